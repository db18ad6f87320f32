"""The exceptions the client raises besides ValueError and TimeoutError."""

from __future__ import annotations

from typing import Optional


class Error(Exception):
    """The base of the errors tumble raises about the server and the connection."""


class ServerError(Error):
    """The server answered a request with an Error.

    ``code`` is the ErrorCode's name (e.g. ``"UNKNOWN_BODY"``), ``message`` the
    server's sentence and ``request_id`` the id of the request it answers (0
    when the error answers none, e.g. before the connection is closed).
    """

    def __init__(self, code: str, message: str, request_id: int) -> None:
        super().__init__(f"{code}: {message}")
        self.code = code
        self.message = message
        self.request_id = request_id


class ConnectionLost(Error, ConnectionError):
    """The connection to the server closed or failed; the client cannot be used any more."""


class StepCutShort(Error):
    """A Step was ended early by a Pause, Resume or Reset from some client.

    ``frame`` is the state at the tick it reached (None when the Step asked
    for none), ``ticks_left`` the ticks it did not step and ``ended_by`` what
    ended it: ``"pause"``, ``"resume"`` or ``"reset"``.
    """

    def __init__(self, frame: Optional[object], ticks_left: int, ended_by: str) -> None:
        super().__init__(f"the Step was cut short by a {ended_by}, {ticks_left} ticks before its end")
        self.frame = frame
        self.ticks_left = ticks_left
        self.ended_by = ended_by
