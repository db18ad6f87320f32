"""The protocol without the I/O, shared by tumble.Client and tumble.aio.Client.

A Core frames requests (varint32 length, ClientMessage), takes the bytes
the server sends and splits them into ServerMessages, files replies by
request id, decodes pose frames into each subscription's queue (keeping a
DELTA subscription's baseline) and keeps the names of the bodies it has
seen. The clients only move bytes and wait.

The request builders check their arguments and raise ValueError before
anything is sent.
"""

from __future__ import annotations

import collections
import math
import os
from dataclasses import dataclass
from typing import (Any, Callable, Deque, Dict, Iterable, List, Mapping, Optional, Sequence, Set, Tuple, Union)

import numpy as np
import numpy.typing as npt

from tumble._errors import ConnectionLost, ServerError, StepCutShort
from tumble._poses import DeltaBaseline, Frame, JointArrays, PackedError, decode_full, decode_joints, decode_packed
from tumble.v1 import protocol_pb2 as pb
from tumble.v1 import scene_pb2
from tumble.v1 import types_pb2

DEFAULT_ADDRESS = "127.0.0.1:7400"
CLIENT_NAME = "tumble-python"
MAX_MAGNITUDE = 1e9  # the server's bound on every number a request carries
MAX_STEP_TICKS = 1_000_000
# Frames and events a subscription keeps for its reader; beyond, the oldest
# go (the server's streams are latest-wins too).
SUBSCRIPTION_QUEUE = 1024

BodyLike = Union[int, str]
"""A body: its id (int) or its name (str)."""
Vector = Union[Sequence[float], npt.NDArray[Any]]
"""Three numbers: a list, a tuple or a numpy array."""

_ENCODINGS = {"full": pb.POSE_ENCODING_FULL, "quantized": pb.POSE_ENCODING_QUANTIZED,
              "delta": pb.POSE_ENCODING_DELTA}
_FIELDS = {"all": pb.POSE_FIELDS_POSE_AND_VELOCITY, "pose": pb.POSE_FIELDS_POSE}
EVENT_KINDS = {"spawned": pb.WORLD_EVENT_BODY_SPAWNED, "removed": pb.WORLD_EVENT_BODY_REMOVED,
               "asleep": pb.WORLD_EVENT_BODY_ASLEEP, "awake": pb.WORLD_EVENT_BODY_AWAKE,
               "reset": pb.WORLD_EVENT_WORLD_RESET, "diverged": pb.WORLD_EVENT_BODY_DIVERGED}
_EVENT_NAMES = {value: name for name, value in EVENT_KINDS.items()}
_MOTIONS = {"dynamic": scene_pb2.MOTION_DYNAMIC, "static": scene_pb2.MOTION_STATIC,
            "kinematic": scene_pb2.MOTION_KINEMATIC}
_MOTION_NAMES = {value: name for name, value in _MOTIONS.items()}
_STEP_ENDS = {pb.STEP_END_PAUSE: "pause", pb.STEP_END_RESUME: "resume", pb.STEP_END_RESET: "reset"}


@dataclass(frozen=True)
class Body:
    """One body as ``Client.bodies()`` lists it."""

    id: int
    name: str  # "" when it has none
    shape: str  # "box", "sphere", "capsule", "points", "plane" or "convex"
    size: Tuple[float, ...]  # box: half extents (3); sphere: (radius,); capsule: (radius, half_height); else ()
    motion: str  # "dynamic", "static" or "kinematic"
    mass: float  # kg
    position: npt.NDArray[np.float64]  # m, centre of mass, world frame, (3,)
    orientation: npt.NDArray[np.float64]  # body to world, w x y z, (4,)
    linear_velocity: npt.NDArray[np.float64]  # m/s, (3,)
    angular_velocity: npt.NDArray[np.float64]  # rad/s, (3,)
    asleep: bool  # a dynamic body that sleeps until something touches or pushes it


@dataclass(frozen=True)
class Event:
    """Something that happened to the world, from a subscription with ``events``.

    ``kind`` is "spawned", "removed", "asleep", "awake", "reset" or
    "diverged"; ``body_id`` is 0 and ``body_name`` "" for "reset".
    """

    subscription_id: int
    tick: int  # the first tick whose state shows it
    kind: str
    body_id: int
    body_name: str


@dataclass(frozen=True)
class Welcome:
    """What the server said when the connection opened."""

    server_version: str
    tick_rate_hz: float
    tick: int
    sim_time: float
    body_count: int
    role: str  # "controller" or "observer"


def resolve_address(address: Optional[str]) -> Tuple[str, int]:
    """(host, port) of `address`, else of $TUMBLE_SERVER, else of 127.0.0.1:7400."""
    text = address if address is not None else os.environ.get("TUMBLE_SERVER") or DEFAULT_ADDRESS
    host, sep, port_text = text.rpartition(":")
    if not sep or not host or not port_text.isdigit() or not 0 < int(port_text) < 65536:
        raise ValueError(f"address must be HOST:PORT with a port from 1 to 65535, got {text!r}")
    return host.strip("[]"), int(port_text)


def resolve_token(token: Optional[str]) -> str:
    """`token`, else $TUMBLE_TOKEN, else none."""
    return token if token is not None else os.environ.get("TUMBLE_TOKEN", "")


def check_timeout(timeout: Optional[float]) -> Optional[float]:
    """A timeout in seconds (> 0) or None (wait for ever)."""
    if timeout is None:
        return None
    if isinstance(timeout, bool) or not isinstance(timeout, (int, float)) or not timeout > 0 \
            or not math.isfinite(timeout):
        raise ValueError(f"timeout must be a number of seconds > 0 or None, got {timeout!r}")
    return float(timeout)


# --- arguments ---------------------------------------------------------------

def _number(value: Any, what: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise ValueError(f"{what} must be a number, got {value!r}")
    x = float(value)
    if not math.isfinite(x) or abs(x) > MAX_MAGNITUDE:
        raise ValueError(f"{what} must be finite and at most 1e9 in magnitude, got {x}")
    return x


def _numbers(value: Any, count: int, what: str) -> Tuple[float, ...]:
    if isinstance(value, (str, bytes)) or value is None:
        raise ValueError(f"{what} must be {count} numbers, got {value!r}")
    try:
        items = list(np.asarray(value, dtype=object).reshape(-1)) if isinstance(value, np.ndarray) else list(value)
    except TypeError:
        raise ValueError(f"{what} must be {count} numbers, got {value!r}") from None
    if len(items) != count:
        raise ValueError(f"{what} must be {count} numbers, got {len(items)}")
    return tuple(_number(x, f"{what}[{i}]") for i, x in enumerate(items))


def vec3(value: Vector, what: str) -> types_pb2.Vec3:
    """A Vec3 of three finite numbers; ValueError naming `what` otherwise."""
    x, y, z = _numbers(value, 3, what)
    return types_pb2.Vec3(x=x, y=y, z=z)


def quat(value: Vector, what: str) -> types_pb2.Quat:
    """A Quat of four numbers w, x, y, z of unit length (within 1e-3)."""
    w, x, y, z = _numbers(value, 4, what)
    norm = math.sqrt(w * w + x * x + y * y + z * z)
    if abs(norm - 1.0) > 1e-3:
        raise ValueError(f"{what} must be a unit quaternion [w, x, y, z], got [{w}, {x}, {y}, {z}] of length {norm}")
    return types_pb2.Quat(w=w, x=x, y=y, z=z)


def body_ref(body: BodyLike, what: str = "body") -> pb.BodyRef:
    """A BodyRef: an int is an id, a str a name."""
    if isinstance(body, str):
        if not body:
            raise ValueError(f"{what}: a name must not be empty")
        if len(body.encode()) > 128:
            raise ValueError(f"{what}: a name is at most 128 bytes of UTF-8")
        return pb.BodyRef(name=body)
    if isinstance(body, (int, np.integer)) and not isinstance(body, bool):
        if not 0 <= int(body) <= 0xFFFFFFFF:
            raise ValueError(f"{what}: an id is from 0 to 2^32 - 1, got {int(body)}")
        return pb.BodyRef(id=int(body))
    raise ValueError(f"{what} must be an id (int) or a name (str), got {body!r}")


def _duration(duration: Optional[float], ticks: Optional[int], persistent: bool, target: Any) -> None:
    given = [name for name, value in (("duration", duration), ("ticks", ticks)) if value is not None]
    if persistent:
        given.append("persistent")
    if len(given) > 1:
        raise ValueError(f"give at most one of duration, ticks and persistent, got {' and '.join(given)}")
    if duration is not None:
        seconds = _number(duration, "duration")
        if not 0 < seconds <= 1e6:
            raise ValueError(f"duration must be in (0, 1e6] s, got {seconds}")
        target.seconds = seconds
    if ticks is not None:
        if isinstance(ticks, bool) or not isinstance(ticks, (int, np.integer)) or not 1 <= ticks <= 0xFFFFFFFF:
            raise ValueError(f"ticks must be a whole number from 1 to 2^32 - 1, got {ticks!r}")
        target.ticks = int(ticks)
    target.persistent = bool(persistent)


def _point(message: Any, at: Optional[Vector], local: bool) -> None:
    if at is not None:
        message.point.CopyFrom(vec3(at, "at"))
        message.point_frame = pb.FRAME_BODY if local else pb.FRAME_WORLD
    elif local:
        raise ValueError("local=True needs a point: at=(x, y, z)")


# --- replies -----------------------------------------------------------------

def raise_error(error: pb.Error) -> None:
    """Raises the ServerError an Error message stands for."""
    raise ServerError(pb.ErrorCode.Name(error.code) if error.code in pb.ErrorCode.values() else str(error.code),
                      error.message, error.request_id)


def message_dict(message: Any) -> Dict[str, Any]:
    """A message's fields as a dict: every scalar (defaults too), sub-messages only when present."""
    out: Dict[str, Any] = {}
    for field in message.DESCRIPTOR.fields:
        if field.name == "request_id":
            continue
        if field.message_type is not None and field.label != field.LABEL_REPEATED:
            if message.HasField(field.name):
                out[field.name] = message_dict(getattr(message, field.name))
        else:
            value = getattr(message, field.name)
            out[field.name] = list(value) if field.label == field.LABEL_REPEATED else value
    return out


def _body(info: pb.BodyInfo) -> Body:
    kind = info.shape.WhichOneof("kind") or ""
    size: Tuple[float, ...] = ()
    if kind == "box":
        h = info.shape.box.half_extents
        size = (h.x, h.y, h.z)
    elif kind == "sphere":
        size = (info.shape.sphere.radius,)
    elif kind == "capsule":
        size = (info.shape.capsule.radius, info.shape.capsule.half_height)
    p, q, v, w = info.position, info.orientation, info.linear_velocity, info.angular_velocity
    return Body(info.id, info.name, kind, size, _MOTION_NAMES.get(info.motion, str(info.motion)), info.mass,
                np.array([p.x, p.y, p.z]), np.array([q.w, q.x, q.y, q.z]), np.array([v.x, v.y, v.z]),
                np.array([w.x, w.y, w.z]), info.asleep)


class Subscription:
    """The client's side of one subscription: its decoded frames and events, oldest first."""

    def __init__(self, subscription_id: int, encoding: int, rate_hz: float, joints: bool) -> None:
        self.id = subscription_id
        self.encoding = encoding
        self.rate_hz = rate_hz
        self.joints = joints  # its frames carry every joint's state
        self.items: Deque[Union[Frame, Event]] = collections.deque(maxlen=SUBSCRIPTION_QUEUE)
        self.baseline = DeltaBaseline() if encoding == pb.POSE_ENCODING_DELTA else None
        self.key_frame_wanted = False
        self.key_frame_asked = False
        self.closed = False


# A request ready to go: its ClientMessage kind and message, and what makes
# the result of its reply.
Request = Tuple[str, Any, Callable[[pb.ServerMessage], Any]]


def _ack_tick(reply: pb.ServerMessage) -> int:
    return int(reply.ack.applied_tick)


class Core:
    """One connection's protocol state; see the module's docstring."""

    def __init__(self) -> None:
        self._next_id = 1
        self._buffer = bytearray()
        self._replies: Dict[int, pb.ServerMessage] = {}
        self._ignored: Set[int] = set()  # requests whose replies nobody waits for (KeyFrameRequest)
        self._subscribe_joints: Dict[int, bool] = {}  # unanswered Subscribe requests: whether each asked for joints
        self.subscriptions: Dict[int, Subscription] = {}
        self.names: Dict[int, str] = {}  # every id ever seen with its name: ids are never reused
        self.fatal: Optional[BaseException] = None
        self._checked_ids: Dict[int, npt.NDArray[np.uint32]] = {}
        self._hello_id = 0

    # Framing.

    def frame(self, kind: str, message: Any) -> Tuple[int, bytes]:
        """A request's id and bytes: varint32 length, ClientMessage{request_id, kind}."""
        request_id = self._next_id
        self._next_id += 1
        envelope = pb.ClientMessage(request_id=request_id)
        getattr(envelope, kind).CopyFrom(message)
        if kind == "hello":
            self._hello_id = request_id
        elif kind == "subscribe":
            self._subscribe_joints[request_id] = message.joints
        body = envelope.SerializeToString()
        return request_id, _varint_bytes(len(body)) + body

    def ignore_reply(self, request_id: int) -> None:
        """Drops the reply to `request_id` when it comes."""
        self._ignored.add(request_id)

    def feed(self, data: bytes) -> None:
        """Takes bytes from the server and handles every whole message in them."""
        buffer = self._buffer
        buffer += data
        pos = 0
        end = len(buffer)
        while pos < end:
            length = 0
            shift = 0
            i = pos
            complete = False
            while i < end:
                byte = buffer[i]
                i += 1
                length |= (byte & 0x7F) << shift
                if byte < 0x80:
                    complete = True
                    break
                shift += 7
                if shift > 28:
                    self.fatal = ConnectionLost("the server sent a broken length prefix")
                    raise self.fatal
            if not complete or i + length > end:
                break  # the rest of the message is still on its way
            message = pb.ServerMessage()
            message.ParseFromString(bytes(buffer[i:i + length]))
            pos = i + length
            self._dispatch(message)
        del buffer[:pos]

    def _dispatch(self, message: pb.ServerMessage) -> None:
        kind = message.WhichOneof("kind")
        if kind == "pose_frame":
            self._take_frame(message.pose_frame)
            return
        if kind == "world_event":
            self._take_event(message.world_event)
            return
        if kind is None:
            return
        reply = getattr(message, kind)
        # Welcome carries no request_id: it answers the Hello.
        request_id = self._hello_id if kind == "welcome" else reply.request_id
        if request_id in self._ignored:
            self._ignored.discard(request_id)
            return
        asked_joints = self._subscribe_joints.pop(request_id, False)  # a Subscribe is answered, or an Error
        if kind == "subscribed":
            # Filed now: the subscription's first frame may follow in the same read.
            self._open_subscription(reply, asked_joints)
        if kind == "error" and request_id == 0:
            # An Error that answers nothing comes before the server closes the connection.
            self.fatal = ServerError(pb.ErrorCode.Name(reply.code), reply.message, 0)
            return
        self._replies[request_id] = message

    def reply(self, request_id: int) -> Optional[pb.ServerMessage]:
        """The reply to `request_id` if it has come (taken out), else None."""
        return self._replies.pop(request_id, None)

    # Subscriptions.

    def _take_frame(self, frame: pb.PoseFrame) -> None:
        sub = self.subscriptions.get(frame.subscription_id)
        if sub is None or sub.closed:
            return
        try:
            if sub.baseline is not None:
                arrays = sub.baseline.apply(frame)
                if arrays is None:
                    if not sub.key_frame_asked:
                        sub.key_frame_wanted = True
                    return
                sub.key_frame_asked = False
                arrays = tuple(None if a is None else a.copy() for a in arrays)  # type: ignore[assignment]
            elif frame.encoding == pb.POSE_ENCODING_FULL:
                arrays = decode_full(frame)
            else:
                arrays = decode_packed(frame.packed)
            joints: Optional[JointArrays] = decode_joints(frame) if sub.joints else None
        except PackedError:
            # Dropped: a FULL or QUANTIZED frame stands alone, and a DELTA
            # baseline has already taken this frame's bodies.
            return
        sub.items.append(Frame(frame.tick, frame.sim_time, *arrays, names=self.names,  # type: ignore[misc]
                               subscription_id=frame.subscription_id, joints=joints))

    def _take_event(self, event: pb.WorldEvent) -> None:
        if event.kind == pb.WORLD_EVENT_BODY_SPAWNED:
            self.names[event.body_id] = event.body_name
        sub = self.subscriptions.get(event.subscription_id)
        if sub is None or sub.closed:
            return
        sub.items.append(Event(event.subscription_id, event.tick, _EVENT_NAMES.get(event.kind, str(event.kind)),
                               event.body_id, event.body_name))

    def key_frame_requests(self) -> List[int]:
        """The DELTA subscriptions that need a key frame; each is asked once until one comes."""
        wanted = []
        for sub in self.subscriptions.values():
            if sub.key_frame_wanted and not sub.closed:
                sub.key_frame_wanted = False
                sub.key_frame_asked = True
                wanted.append(sub.id)
        return wanted

    def needs_names(self, frame: Frame, stream: int) -> bool:
        """Whether `frame` holds ids whose names this client has not seen (checked once per set of ids)."""
        checked = self._checked_ids.get(stream)
        if checked is not None and checked.shape == frame.ids.shape and bool(np.array_equal(checked, frame.ids)):
            return False
        names = self.names
        if all(i in names for i in frame.ids.tolist()):
            self._checked_ids[stream] = frame.ids
            return False
        return True

    def took_names(self, frame: Frame, stream: int) -> None:
        """After a listing: ids still unknown (bodies gone since) have no name."""
        for i in frame.ids.tolist():
            self.names.setdefault(i, "")
        self._checked_ids[stream] = frame.ids

    # Requests: each returns (kind, message, result of the reply).

    @staticmethod
    def hello(token: str, client_name: str) -> Request:
        if len(token.encode()) > 256:
            raise ValueError("token is at most 256 bytes")
        if len(client_name.encode()) > 128:
            raise ValueError("client_name is at most 128 bytes")

        def welcome(reply: pb.ServerMessage) -> Welcome:
            w = reply.welcome
            role = {pb.ROLE_CONTROLLER: "controller", pb.ROLE_OBSERVER: "observer"}.get(w.role, str(w.role))
            return Welcome(w.server_version, w.tick_rate_hz, w.tick, w.sim_time, w.body_count, role)

        return "hello", pb.Hello(protocol_version=pb.PROTOCOL_VERSION_CURRENT, client_name=client_name,
                                 token=token), welcome

    def list_page(self, start_id: int) -> Request:
        def page(reply: pb.ServerMessage) -> Tuple[List[Body], int]:
            bodies = [_body(b) for b in reply.body_list.bodies]
            for b in bodies:
                self.names[b.id] = b.name
            return bodies, reply.body_list.next_start_id

        return "list_bodies", pb.ListBodies(start_id=start_id), page

    @staticmethod
    def force(body: BodyLike, force: Vector, at: Optional[Vector], local: bool, duration: Optional[float],
              ticks: Optional[int], persistent: bool) -> Request:
        m = pb.ApplyForce(body=body_ref(body), force=vec3(force, "force"))
        _point(m, at, local)
        _duration(duration, ticks, persistent, m)
        return "apply_force", m, _ack_tick

    @staticmethod
    def torque(body: BodyLike, torque: Vector, duration: Optional[float], ticks: Optional[int],
               persistent: bool) -> Request:
        m = pb.ApplyTorque(body=body_ref(body), torque=vec3(torque, "torque"))
        _duration(duration, ticks, persistent, m)
        return "apply_torque", m, _ack_tick

    @staticmethod
    def impulse(body: BodyLike, impulse: Vector, at: Optional[Vector], local: bool) -> Request:
        m = pb.ApplyImpulse(body=body_ref(body), impulse=vec3(impulse, "impulse"))
        _point(m, at, local)
        return "apply_impulse", m, _ack_tick

    @staticmethod
    def clear(body: Optional[BodyLike]) -> Request:
        m = pb.ClearForces()
        if body is not None:
            m.body.CopyFrom(body_ref(body))
        return "clear_forces", m, _ack_tick

    def spawn(self, name: str, box: Optional[Vector], sphere: Optional[float], capsule: Optional[Vector],
              mass: float, at: Vector, orientation: Optional[Vector], linear_velocity: Optional[Vector],
              angular_velocity: Optional[Vector], motion: str, friction: Optional[float],
              restitution: Optional[float]) -> Request:
        if not isinstance(name, str):
            raise ValueError(f"name must be a str, got {name!r}")
        if name.isdigit() and name.isascii():
            raise ValueError(f"name must not be digits only (it would read as an id), got {name!r}")
        if len(name.encode()) > 128:
            raise ValueError("name is at most 128 bytes of UTF-8")
        shapes = [s for s, v in (("box", box), ("sphere", sphere), ("capsule", capsule)) if v is not None]
        if len(shapes) != 1:
            raise ValueError(f"give exactly one shape: box, sphere or capsule, got {shapes or 'none'}")
        if motion not in _MOTIONS:
            raise ValueError(f"motion must be one of {', '.join(_MOTIONS)}, got {motion!r}")
        spec = scene_pb2.BodySpec(name=name, mass=_number(mass, "mass"), position=vec3(at, "at"),
                                  motion=_MOTIONS[motion])
        if box is not None:
            spec.shape.box.half_extents.CopyFrom(vec3(box, "box"))
        elif sphere is not None:
            spec.shape.sphere.radius = _number(sphere, "sphere")
        else:
            radius, half_height = _numbers(capsule, 2, "capsule")
            spec.shape.capsule.radius = radius
            spec.shape.capsule.half_height = half_height
        if orientation is not None:
            spec.orientation.CopyFrom(quat(orientation, "orientation"))
        if linear_velocity is not None:
            spec.linear_velocity.CopyFrom(vec3(linear_velocity, "linear_velocity"))
        if angular_velocity is not None:
            spec.angular_velocity.CopyFrom(vec3(angular_velocity, "angular_velocity"))
        if friction is not None:
            spec.friction = _number(friction, "friction")
        if restitution is not None:
            spec.restitution = _number(restitution, "restitution")

        def spawned(reply: pb.ServerMessage) -> int:
            self.names[reply.ack.body_id] = name
            return int(reply.ack.body_id)

        return "spawn_body", pb.SpawnBody(body=spec), spawned

    @staticmethod
    def remove(body: BodyLike) -> Request:
        return "remove_body", pb.RemoveBody(body=body_ref(body)), _ack_tick

    @staticmethod
    def set(body: BodyLike, position: Optional[Vector], orientation: Optional[Vector],
            linear_velocity: Optional[Vector], angular_velocity: Optional[Vector]) -> Request:
        m = pb.SetBodyState(body=body_ref(body))
        if position is None and orientation is None and linear_velocity is None and angular_velocity is None:
            raise ValueError("give at least one of position, orientation, linear_velocity and angular_velocity")
        if position is not None:
            m.position.CopyFrom(vec3(position, "position"))
        if orientation is not None:
            m.orientation.CopyFrom(quat(orientation, "orientation"))
        if linear_velocity is not None:
            m.linear_velocity.CopyFrom(vec3(linear_velocity, "linear_velocity"))
        if angular_velocity is not None:
            m.angular_velocity.CopyFrom(vec3(angular_velocity, "angular_velocity"))
        return "set_body_state", m, _ack_tick

    @staticmethod
    def clock(kind: str) -> Request:
        message = {"pause": pb.Pause, "resume": pb.Resume, "reset": pb.Reset}[kind]()
        return kind, message, _ack_tick

    @staticmethod
    def tick_rate(hz: float) -> Request:
        rate = _number(hz, "hz")
        if not 1 <= rate <= 10000:
            raise ValueError(f"hz must be from 1 to 10000, got {rate}")
        return "set_tick_rate", pb.SetTickRate(rate_hz=rate), _ack_tick

    @staticmethod
    def stats() -> Request:
        return "get_stats", pb.GetStats(), lambda reply: message_dict(reply.stats)

    def step(self, n: int, forces: Optional[Mapping[BodyLike, Vector]], torques: Optional[Mapping[BodyLike, Vector]],
             bodies: Optional[Iterable[BodyLike]], fields: str, joints: bool) -> Request:
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or not 1 <= n <= MAX_STEP_TICKS:
            raise ValueError(f"n must be a whole number of ticks from 1 to {MAX_STEP_TICKS}, got {n!r}")
        if fields not in _FIELDS:
            raise ValueError(f"fields must be 'all' or 'pose', got {fields!r}")
        m = pb.Step(ticks=int(n), reply_frame=True, frame_fields=_FIELDS[fields], frame_joints=bool(joints))
        for what, loads, target in (("forces", forces, m.forces), ("torques", torques, m.torques)):
            if loads is None:
                continue
            if not isinstance(loads, Mapping):
                raise ValueError(f"{what} must map bodies to vectors, e.g. {{'crate': (10, 0, 0)}}")
            for body, value in loads.items():
                load = target.add()
                load.body.CopyFrom(body_ref(body, f"{what} key"))
                if what == "forces":
                    load.force.CopyFrom(vec3(value, f"forces[{body!r}]"))
                else:
                    load.torque.CopyFrom(vec3(value, f"torques[{body!r}]"))
        if bodies is not None:
            if isinstance(bodies, (str, int)):
                bodies = [bodies]
            for body in bodies:
                m.frame_bodies.add().CopyFrom(body_ref(body, "bodies"))

        def frame(reply: pb.ServerMessage) -> Frame:
            ack = reply.ack
            result = Frame(ack.frame.tick, ack.frame.sim_time, *decode_full(ack.frame), names=self.names,
                           joints=decode_joints(ack.frame) if joints else None)
            if ack.step_ticks_left:
                raise StepCutShort(result, ack.step_ticks_left, _STEP_ENDS.get(ack.step_ended_by, "request"))
            return result

        return "step", m, frame

    @staticmethod
    def subscribe(bodies: Optional[Iterable[BodyLike]], rate: float, encoding: str, fields: str,
                  events: Union[bool, Iterable[str]], joints: bool) -> Tuple[str, Any]:
        rate_hz = _number(rate, "rate")
        if rate_hz < 0:
            raise ValueError(f"rate must be >= 0 Hz (0: every tick), got {rate_hz}")
        if encoding not in _ENCODINGS:
            raise ValueError(f"encoding must be 'full', 'quantized' or 'delta', got {encoding!r}")
        if fields not in _FIELDS:
            raise ValueError(f"fields must be 'all' or 'pose', got {fields!r}")
        m = pb.Subscribe(rate_hz=rate_hz, encoding=_ENCODINGS[encoding], fields=_FIELDS[fields], joints=bool(joints))
        if bodies is not None:
            if isinstance(bodies, (str, int)):
                bodies = [bodies]
            for body in bodies:
                m.bodies.add().CopyFrom(body_ref(body, "bodies"))
            if not m.bodies:
                raise ValueError("bodies must name at least one body, or be None for every body")
        if events is True:
            m.events.extend(EVENT_KINDS.values())
        elif events is not False and events is not None:
            if isinstance(events, str):
                events = [events]
            for kind in events:
                if kind not in EVENT_KINDS:
                    raise ValueError(f"events holds {kind!r}, not one of {', '.join(EVENT_KINDS)}")
                m.events.append(EVENT_KINDS[kind])
        return "subscribe", m

    def _open_subscription(self, s: pb.Subscribed, joints: bool) -> None:
        self.subscriptions[s.subscription_id] = Subscription(s.subscription_id, s.encoding, s.rate_hz, joints)

    def subscribed(self, reply: pb.ServerMessage) -> Subscription:
        """The subscription a Subscribed reply opened (filed when the reply came)."""
        return self.subscriptions[reply.subscribed.subscription_id]

    @staticmethod
    def check(reply: pb.ServerMessage) -> pb.ServerMessage:
        """`reply`, or the ServerError it holds raised."""
        if reply.WhichOneof("kind") == "error":
            raise_error(reply.error)
        return reply


def _varint_bytes(value: int) -> bytes:
    out = bytearray()
    while value >= 0x80:
        out.append((value & 0x7F) | 0x80)
        value >>= 7
    out.append(value)
    return bytes(out)
