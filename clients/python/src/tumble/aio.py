"""The asynchronous client: the same API as tumble.Client, with async/await.

    async with await tumble.aio.connect("127.0.0.1:7400") as client:
        await client.pause()
        frame = await client.step(1, forces={"crate": (10, 0, 0)})
        async for item in await client.subscribe(rate=30):
            ...

Several tasks may share one Client: each request waits for its own reply
while whichever task reads hands every message to its place.
"""

from __future__ import annotations

import asyncio
import socket
from types import TracebackType
from typing import Any, AsyncIterator, Iterable, List, Mapping, Optional, Type, Union

from tumble._core import (CLIENT_NAME, Body, BodyLike, Core, Event, Request, Subscription as _SubscriptionState,
                          Vector, Welcome, check_timeout, resolve_address, resolve_token)
from tumble._errors import ConnectionLost, StepCutShort
from tumble._poses import Frame
from tumble.v1 import protocol_pb2 as pb

__all__ = ["connect", "Client", "Subscription"]

_READ_BYTES = 1 << 20


async def connect(address: Optional[str] = None, token: Optional[str] = None, timeout: Optional[float] = 10.0,
                  client_name: str = CLIENT_NAME) -> "Client":
    """Connects to tumbled and says Hello, as tumble.connect() does; returns the Client."""
    client = Client()
    await client._open(address, token, timeout, client_name)
    return client


class Client:
    """One connection to tumbled, as tumble.Client, whose methods are coroutines here.

    Make it with ``await tumble.aio.connect(...)``; ``async with`` closes it.
    """

    def __init__(self) -> None:
        """An unconnected client; use tumble.aio.connect()."""
        self.timeout: Optional[float] = None
        """Seconds to wait for each reply (None: for ever)."""
        self.welcome: Optional[Welcome] = None
        """What the server said on connecting."""
        self._core = Core()
        self._reader: Optional[asyncio.StreamReader] = None
        self._writer: Optional[asyncio.StreamWriter] = None
        self._read_lock = asyncio.Lock()
        self._arrived = asyncio.Event()

    async def _open(self, address: Optional[str], token: Optional[str], timeout: Optional[float],
                    client_name: str) -> None:
        host, port = resolve_address(address)
        self.timeout = check_timeout(timeout)
        hello = Core.hello(resolve_token(token), client_name)
        self._reader, self._writer = await asyncio.wait_for(asyncio.open_connection(host, port, limit=_READ_BYTES),
                                                            self.timeout)
        sock = self._writer.get_extra_info("socket")
        if sock is not None:
            sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        try:
            self.welcome = await self._call(hello)
        except BaseException:
            await self.close()
            raise

    async def close(self) -> None:
        """Closes the connection; the client cannot be used after. Idempotent."""
        writer, self._writer = self._writer, None
        for sub in self._core.subscriptions.values():
            sub.closed = True
        self._arrived.set()
        if writer is not None:
            writer.close()
            try:
                await writer.wait_closed()
            except OSError:
                pass

    async def __aenter__(self) -> "Client":
        return self

    async def __aexit__(self, exc_type: Optional[Type[BaseException]], exc: Optional[BaseException],
                        tb: Optional[TracebackType]) -> None:
        await self.close()

    async def _send(self, data: bytes) -> None:
        if self._writer is None:
            raise ConnectionLost("the client is closed")
        try:
            self._writer.write(data)
            await self._writer.drain()
        except OSError as error:
            await self.close()
            raise ConnectionLost(f"the connection to the server failed: {error}") from error

    async def _receive(self) -> None:
        """Reads once (one task at a time) and hands the bytes to the core; others wait for the next read."""
        if self._read_lock.locked():
            # Another task is reading: wait until it has handed something over.
            self._arrived.clear()
            await self._arrived.wait()
            return
        async with self._read_lock:
            try:
                await self._read_once()
            finally:
                self._arrived.set()  # whatever happened, the waiting tasks look again

    async def _read_once(self) -> None:
        """One read from the socket, fed to the core; closes the client on a lost connection."""
        if self._core.fatal is not None:
            await self.close()
            raise self._core.fatal
        if self._reader is None or self._writer is None:
            raise ConnectionLost("the client is closed")
        try:
            data = await self._reader.read(_READ_BYTES)
        except OSError as error:
            await self.close()
            raise ConnectionLost(f"the connection to the server failed: {error}") from error
        if not data:
            await self.close()
            if self._core.fatal is not None:
                raise self._core.fatal
            raise ConnectionLost("the server closed the connection")
        self._core.feed(data)
        for subscription_id in self._core.key_frame_requests():
            request_id, frame = self._core.frame("key_frame_request",
                                                 pb.KeyFrameRequest(subscription_id=subscription_id))
            self._core.ignore_reply(request_id)
            await self._send(frame)

    async def _wait(self, request_id: int) -> pb.ServerMessage:
        async def reply() -> pb.ServerMessage:
            while True:
                message = self._core.reply(request_id)
                if message is not None:
                    return Core.check(message)
                if self._writer is None:
                    raise ConnectionLost("the client is closed")
                await self._receive()

        try:
            return await asyncio.wait_for(reply(), self.timeout)
        except asyncio.TimeoutError:
            raise TimeoutError("no reply from the server in time") from None

    async def _call(self, request: Request) -> Any:
        kind, message, result = request
        request_id, data = self._core.frame(kind, message)
        await self._send(data)
        return result(await self._wait(request_id))

    async def _fill_names(self, frame: Frame, stream: int) -> Frame:
        if self._core.needs_names(frame, stream):
            await self.bodies()
            self._core.took_names(frame, stream)
        return frame

    async def bodies(self) -> List[Body]:
        """Every body of the world, in ascending id order; see tumble.Client.bodies."""
        out: List[Body] = []
        start = 0
        while True:
            page, start = await self._call(self._core.list_page(start))
            out.extend(page)
            if start == 0:
                return out

    async def stats(self) -> dict:  # type: ignore[type-arg]
        """The server's counters as a dict; see tumble.Client.stats."""
        return await self._call(Core.stats())  # type: ignore[no-any-return]

    async def force(self, body: BodyLike, force: Vector, at: Optional[Vector] = None, local: bool = False,
                    duration: Optional[float] = None, ticks: Optional[int] = None, persistent: bool = False) -> int:
        """Pushes a body; see tumble.Client.force."""
        return await self._call(Core.force(body, force, at, local, duration, ticks, persistent))  # type: ignore[no-any-return]

    async def torque(self, body: BodyLike, torque: Vector, duration: Optional[float] = None,
                     ticks: Optional[int] = None, persistent: bool = False) -> int:
        """Turns a body; see tumble.Client.torque."""
        return await self._call(Core.torque(body, torque, duration, ticks, persistent))  # type: ignore[no-any-return]

    async def impulse(self, body: BodyLike, impulse: Vector, at: Optional[Vector] = None, local: bool = False) -> int:
        """Changes a body's momentum at once; see tumble.Client.impulse."""
        return await self._call(Core.impulse(body, impulse, at, local))  # type: ignore[no-any-return]

    async def clear(self, body: Optional[BodyLike] = None) -> int:
        """Ends forces and torques; see tumble.Client.clear."""
        return await self._call(Core.clear(body))  # type: ignore[no-any-return]

    async def spawn(self, name: str, box: Optional[Vector] = None, sphere: Optional[float] = None,
                    capsule: Optional[Vector] = None, mass: float = 1.0, at: Vector = (0.0, 0.0, 0.0),
                    orientation: Optional[Vector] = None, linear_velocity: Optional[Vector] = None,
                    angular_velocity: Optional[Vector] = None, motion: str = "dynamic",
                    friction: Optional[float] = None, restitution: Optional[float] = None) -> int:
        """Adds a body and returns its id; see tumble.Client.spawn."""
        return await self._call(self._core.spawn(name, box, sphere, capsule, mass, at, orientation,  # type: ignore[no-any-return]
                                                 linear_velocity, angular_velocity, motion, friction, restitution))

    async def remove(self, body: BodyLike) -> int:
        """Takes a body out of the world; see tumble.Client.remove."""
        return await self._call(Core.remove(body))  # type: ignore[no-any-return]

    async def set(self, body: BodyLike, position: Optional[Vector] = None, orientation: Optional[Vector] = None,
                  linear_velocity: Optional[Vector] = None, angular_velocity: Optional[Vector] = None) -> int:
        """Replaces parts of a body's state; see tumble.Client.set."""
        return await self._call(Core.set(body, position, orientation, linear_velocity, angular_velocity))  # type: ignore[no-any-return]

    async def pause(self) -> int:
        """Stops the clock; see tumble.Client.pause."""
        return await self._call(Core.clock("pause"))  # type: ignore[no-any-return]

    async def resume(self) -> int:
        """Starts the clock; see tumble.Client.resume."""
        return await self._call(Core.clock("resume"))  # type: ignore[no-any-return]

    async def reset(self) -> int:
        """Puts the world back to its scene; see tumble.Client.reset."""
        return await self._call(Core.clock("reset"))  # type: ignore[no-any-return]

    async def tick_rate(self, hz: float) -> int:
        """Sets the tick rate; see tumble.Client.tick_rate."""
        return await self._call(Core.tick_rate(hz))  # type: ignore[no-any-return]

    async def step(self, n: int = 1, forces: Optional[Mapping[BodyLike, Vector]] = None,
                   torques: Optional[Mapping[BodyLike, Vector]] = None, bodies: Optional[Iterable[BodyLike]] = None,
                   fields: str = "all", joints: bool = False) -> Frame:
        """Steps a paused world and returns the state after the last tick; see tumble.Client.step."""
        try:
            frame: Frame = await self._call(self._core.step(n, forces, torques, bodies, fields, joints))
        except StepCutShort as cut:
            if isinstance(cut.frame, Frame):
                await self._fill_names(cut.frame, -1)
            raise
        return await self._fill_names(frame, -1)

    async def subscribe(self, bodies: Optional[Iterable[BodyLike]] = None, rate: float = 30.0,
                        encoding: str = "full", fields: str = "all", events: Union[bool, Iterable[str]] = False,
                        joints: bool = False) -> "Subscription":
        """Starts a stream of Frames (and Events); see tumble.Client.subscribe. Iterate with ``async for``."""
        kind, message = Core.subscribe(bodies, rate, encoding, fields, events, joints)
        request_id, data = self._core.frame(kind, message)
        await self._send(data)
        return Subscription(self, self._core.subscribed(await self._wait(request_id)))


class Subscription:
    """A stream of Frames and Events; ``async for`` over it, or ``await next(timeout)``."""

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
        """The rate the server serves it at."""
        return self._state.rate_hz

    async def next(self, timeout: Optional[float] = None) -> Union[Frame, Event]:
        """The next Frame or Event, waiting at most `timeout` s (None: for ever; TimeoutError after)."""
        async def take() -> Union[Frame, Event]:
            items = self._state.items
            while not items:
                if self._state.closed:
                    raise StopAsyncIteration
                await self._client._receive()
            item = items.popleft()
            if isinstance(item, Frame):
                return await self._client._fill_names(item, self._state.id)
            return item

        if timeout is None:
            return await take()
        try:
            return await asyncio.wait_for(take(), check_timeout(timeout))
        except asyncio.TimeoutError:
            raise TimeoutError("no frame or event in time") from None

    def __aiter__(self) -> AsyncIterator[Union[Frame, Event]]:
        return self

    async def __anext__(self) -> Union[Frame, Event]:
        return await self.next()

    async def close(self) -> None:
        """Unsubscribes (when the connection is still open)."""
        if self._state.closed:
            return
        self._state.closed = True
        self._state.items.clear()
        if self._client._writer is not None:
            await self._client._call(("unsubscribe", pb.Unsubscribe(subscription_id=self._state.id),
                                      lambda reply: None))

    async def __aenter__(self) -> "Subscription":
        return self

    async def __aexit__(self, exc_type: Optional[Type[BaseException]], exc: Optional[BaseException],
                        tb: Optional[TracebackType]) -> None:
        await self.close()
