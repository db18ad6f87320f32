"""The synchronous client: tumble.connect() and tumble.Client over a blocking socket."""

from __future__ import annotations

import socket
import time
from types import TracebackType
from typing import Any, Iterable, Iterator, List, Mapping, Optional, Type, Union

from tumble._core import (CLIENT_NAME, Body, BodyLike, Core, Event, Request, Subscription as _SubscriptionState,
                          Vector, Welcome, check_timeout, resolve_address, resolve_token)
from tumble._errors import ConnectionLost, StepCutShort
from tumble._poses import Frame
from tumble.v1 import protocol_pb2 as pb

_READ_BYTES = 1 << 20


def connect(address: Optional[str] = None, token: Optional[str] = None, timeout: Optional[float] = 10.0,
            client_name: str = CLIENT_NAME) -> "Client":
    """Connects to tumbled and says Hello; returns the Client.

    `address` is HOST:PORT, by default $TUMBLE_SERVER or 127.0.0.1:7400;
    `token` the access token, by default $TUMBLE_TOKEN; `timeout` the seconds
    to wait for the connection and for each reply (None: for ever). Raises
    ServerError when the server refuses the Hello (e.g. UNAUTHENTICATED),
    ConnectionLost or OSError when it cannot be reached.
    """
    return Client(address, token, timeout, client_name)


class Client:
    """One connection to tumbled; every call sends one request and waits for its reply.

    Use it as a context manager, or call close(). Not for use by several
    threads at once (one connection per thread). Bodies are named by id
    (int) or name (str); vectors are any three numbers (a list, a tuple, a
    numpy array). Bad arguments raise ValueError before anything is sent; a
    request the server refuses raises ServerError; a lost connection
    ConnectionLost; a reply that does not come within the timeout
    TimeoutError.
    """

    def __init__(self, address: Optional[str] = None, token: Optional[str] = None,
                 timeout: Optional[float] = 10.0, client_name: str = CLIENT_NAME) -> None:
        """Connects as connect() does."""
        host, port = resolve_address(address)
        self.timeout = check_timeout(timeout)
        """Seconds to wait for each reply (None: for ever)."""
        self._core = Core()
        hello = Core.hello(resolve_token(token), client_name)
        self._socket: Optional[socket.socket] = socket.create_connection((host, port), timeout=self.timeout)
        try:
            self._socket.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            self._buffer = bytearray(_READ_BYTES)
            self.welcome: Welcome = self._call(hello)
            """What the server said on connecting: its version, tick rate, tick, bodies and this client's role."""
        except BaseException:
            self.close()
            raise

    # Connection.

    def close(self) -> None:
        """Closes the connection; the client cannot be used after. Idempotent."""
        if self._socket is not None:
            try:
                self._socket.close()
            finally:
                self._socket = None
                for sub in self._core.subscriptions.values():
                    sub.closed = True

    def __enter__(self) -> "Client":
        return self

    def __exit__(self, exc_type: Optional[Type[BaseException]], exc: Optional[BaseException],
                 tb: Optional[TracebackType]) -> None:
        self.close()

    def _send(self, data: bytes) -> None:
        if self._socket is None:
            raise ConnectionLost("the client is closed")
        try:
            self._socket.sendall(data)
        except OSError as error:
            self.close()
            raise ConnectionLost(f"the connection to the server failed: {error}") from error

    def _receive(self, deadline: Optional[float]) -> None:
        """Reads once from the socket and hands the bytes to the core."""
        if self._core.fatal is not None:
            self.close()
            raise self._core.fatal
        if self._socket is None:
            raise ConnectionLost("the client is closed")
        if deadline is None:
            self._socket.settimeout(None)
        else:
            left = deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError("no reply from the server in time")
            self._socket.settimeout(left)
        try:
            count = self._socket.recv_into(self._buffer)
        except socket.timeout:
            raise TimeoutError("no reply from the server in time") from None
        except OSError as error:
            self.close()
            raise ConnectionLost(f"the connection to the server failed: {error}") from error
        if count == 0:
            self.close()
            if self._core.fatal is not None:
                raise self._core.fatal
            raise ConnectionLost("the server closed the connection")
        self._core.feed(memoryview(self._buffer)[:count])
        self._ask_key_frames()

    def _ask_key_frames(self) -> None:
        for subscription_id in self._core.key_frame_requests():
            request_id, data = self._core.frame("key_frame_request", pb.KeyFrameRequest(subscription_id=subscription_id))
            self._core.ignore_reply(request_id)
            self._send(data)

    def _deadline(self) -> Optional[float]:
        return None if self.timeout is None else time.monotonic() + self.timeout

    def _wait(self, request_id: int) -> pb.ServerMessage:
        deadline = self._deadline()
        while True:
            reply = self._core.reply(request_id)
            if reply is not None:
                return Core.check(reply)
            self._receive(deadline)

    def _call(self, request: Request) -> Any:
        kind, message, result = request
        request_id, data = self._core.frame(kind, message)
        self._send(data)
        return result(self._wait(request_id))

    def _fill_names(self, frame: Frame, stream: int) -> Frame:
        if self._core.needs_names(frame, stream):
            self.bodies()
            self._core.took_names(frame, stream)
        return frame

    # Reading.

    def bodies(self) -> List[Body]:
        """Every body of the world, in ascending id order (read page by page)."""
        out: List[Body] = []
        start = 0
        while True:
            page, start = self._call(self._core.list_page(start))
            out.extend(page)
            if start == 0:
                return out

    def stats(self) -> dict:  # type: ignore[type-arg]
        """The server's counters (the Stats message as a dict): tick, sim_time, paused, tick_rate_hz, ..."""
        return self._call(Core.stats())  # type: ignore[no-any-return]

    # Bodies.

    def force(self, body: BodyLike, force: Vector, at: Optional[Vector] = None, local: bool = False,
              duration: Optional[float] = None, ticks: Optional[int] = None, persistent: bool = False) -> int:
        """Pushes `body` with `force` (N, world frame); returns the first tick it acts in.

        `at`: the point of application (m; world frame, or the body's with
        local=True), else the centre of mass. It lasts one tick, `duration`
        seconds, `ticks` ticks, or with persistent=True every tick until
        clear().
        """
        return self._call(Core.force(body, force, at, local, duration, ticks, persistent))  # type: ignore[no-any-return]

    def torque(self, body: BodyLike, torque: Vector, duration: Optional[float] = None, ticks: Optional[int] = None,
               persistent: bool = False) -> int:
        """Turns `body` with `torque` (N m, world frame), as force() lasts; returns the first tick it acts in."""
        return self._call(Core.torque(body, torque, duration, ticks, persistent))  # type: ignore[no-any-return]

    def impulse(self, body: BodyLike, impulse: Vector, at: Optional[Vector] = None, local: bool = False) -> int:
        """Changes the momentum of `body` at once by `impulse` (N s), at a point if given; returns the tick that shows it."""
        return self._call(Core.impulse(body, impulse, at, local))  # type: ignore[no-any-return]

    def clear(self, body: Optional[BodyLike] = None) -> int:
        """Ends the timed and persistent forces and torques of `body`, or of every body; returns the first tick without them."""
        return self._call(Core.clear(body))  # type: ignore[no-any-return]

    def spawn(self, name: str, box: Optional[Vector] = None, sphere: Optional[float] = None,
              capsule: Optional[Vector] = None, mass: float = 1.0, at: Vector = (0.0, 0.0, 0.0),
              orientation: Optional[Vector] = None, linear_velocity: Optional[Vector] = None,
              angular_velocity: Optional[Vector] = None, motion: str = "dynamic", friction: Optional[float] = None,
              restitution: Optional[float] = None) -> int:
        """Adds a body and returns its id.

        One shape: `box` (half extents, m), `sphere` (radius, m) or `capsule`
        (radius, half height, m). `mass` kg; `at` its centre, m;
        `orientation` w, x, y, z; velocities m/s and rad/s; `motion`
        "dynamic", "static" or "kinematic"; `friction` (>= 0) and
        `restitution` (0 to 1) default to the server's 0.5 and 0. `name`
        may be "" and must not be digits only.
        """
        return self._call(self._core.spawn(name, box, sphere, capsule, mass, at, orientation,  # type: ignore[no-any-return]
                                           linear_velocity, angular_velocity, motion, friction, restitution))

    def remove(self, body: BodyLike) -> int:
        """Takes `body` out of the world, with its forces; returns the first tick without it."""
        return self._call(Core.remove(body))  # type: ignore[no-any-return]

    def set(self, body: BodyLike, position: Optional[Vector] = None, orientation: Optional[Vector] = None,
            linear_velocity: Optional[Vector] = None, angular_velocity: Optional[Vector] = None) -> int:
        """Replaces the given parts of the state of `body` and wakes it; returns the first tick that shows it."""
        return self._call(Core.set(body, position, orientation, linear_velocity, angular_velocity))  # type: ignore[no-any-return]

    # Clock.

    def pause(self) -> int:
        """Stops the clock (ending a Step under way); returns the tick the world stays at."""
        return self._call(Core.clock("pause"))  # type: ignore[no-any-return]

    def resume(self) -> int:
        """Steps at the tick rate again; returns the first tick stepped."""
        return self._call(Core.clock("resume"))  # type: ignore[no-any-return]

    def reset(self) -> int:
        """Puts the world back to its scene (the clock goes on); returns the first tick that shows it."""
        return self._call(Core.clock("reset"))  # type: ignore[no-any-return]

    def tick_rate(self, hz: float) -> int:
        """Sets the tick rate (1 to 10000 Hz) from the next tick on; returns that tick."""
        return self._call(Core.tick_rate(hz))  # type: ignore[no-any-return]

    def step(self, n: int = 1, forces: Optional[Mapping[BodyLike, Vector]] = None,
             torques: Optional[Mapping[BodyLike, Vector]] = None, bodies: Optional[Iterable[BodyLike]] = None,
             fields: str = "all", joints: bool = False) -> Frame:
        """Steps a paused world `n` ticks and returns the state after the last: one round trip.

        `forces` and `torques` map bodies to vectors (N, N m, world frame)
        that act on each of these `n` ticks and no other. The frame holds
        `bodies` (default: every body), with velocities unless
        fields="pose", and with joints=True every joint's state too
        (Frame.joint_ids ...). The world must be paused (else ServerError
        FAILED_PRECONDITION); a Step another client cuts short with a
        Pause, Resume or Reset raises StepCutShort, which holds the frame
        of the tick it reached.
        """
        try:
            frame: Frame = self._call(self._core.step(n, forces, torques, bodies, fields, joints))
        except StepCutShort as cut:
            if isinstance(cut.frame, Frame):
                self._fill_names(cut.frame, -1)
            raise
        return self._fill_names(frame, -1)

    # Streams.

    def subscribe(self, bodies: Optional[Iterable[BodyLike]] = None, rate: float = 30.0, encoding: str = "full",
                  fields: str = "all", events: Union[bool, Iterable[str]] = False,
                  joints: bool = False) -> "Subscription":
        """Starts a stream of Frames of `bodies` (default: every body) at `rate` Hz (0: every tick).

        `encoding` "full", "quantized" or "delta" (the same arrays, smaller
        on the wire: positions within 0.49 mm, orientations within 0.27
        degrees, velocities within 1/256 m/s and 1/512 rad/s); `fields`
        "all" or "pose" (no velocities); `events` True for every kind of
        Event, or the kinds wanted ("spawned", "removed", "asleep",
        "awake", "reset", "diverged"); `joints` True for every joint's
        state of the world in each frame (Frame.joint_ids ..., float32 on
        the wire in every encoding, whatever `bodies`). The first frame is
        the current state.
        """
        kind, message = Core.subscribe(bodies, rate, encoding, fields, events, joints)
        request_id, data = self._core.frame(kind, message)
        self._send(data)
        return Subscription(self, self._core.subscribed(self._wait(request_id)))


class Subscription:
    """A stream of Frames (and Events, when asked) from one subscription; iterate over it.

    ``next(timeout)`` waits at most `timeout` seconds (TimeoutError), the
    iterator for ever. The client keeps the latest 1024 items a reader has
    not taken; older ones are dropped. Use it as a context manager, or call
    close() to unsubscribe.
    """

    def __init__(self, client: Client, state: _SubscriptionState) -> None:
        """Wraps a subscription the server opened; made by Client.subscribe()."""
        self._client = client
        self._state = state

    @property
    def id(self) -> int:
        """The server's id of the subscription."""
        return self._state.id

    @property
    def rate_hz(self) -> float:
        """The rate the server serves it at (the tick rate over a whole number of ticks)."""
        return self._state.rate_hz

    def next(self, timeout: Optional[float] = None) -> Union[Frame, Event]:
        """The next Frame or Event, waiting at most `timeout` s (None: for ever)."""
        deadline = None if timeout is None else time.monotonic() + check_timeout(timeout)  # type: ignore[operator]
        items = self._state.items
        while not items:
            if self._state.closed:
                raise StopIteration
            self._client._receive(deadline)
        item = items.popleft()
        if isinstance(item, Frame):
            return self._client._fill_names(item, self._state.id)
        return item

    def __iter__(self) -> Iterator[Union[Frame, Event]]:
        return self

    def __next__(self) -> Union[Frame, Event]:
        return self.next()

    def close(self) -> None:
        """Unsubscribes (when the connection is still open); what was not read is dropped."""
        if self._state.closed:
            return
        self._state.closed = True
        self._state.items.clear()
        if self._client._socket is not None:
            self._client._call(("unsubscribe", pb.Unsubscribe(subscription_id=self._state.id), lambda reply: None))

    def __enter__(self) -> "Subscription":
        return self

    def __exit__(self, exc_type: Optional[Type[BaseException]], exc: Optional[BaseException],
                 tb: Optional[TracebackType]) -> None:
        self.close()
