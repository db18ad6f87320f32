"""Pose frames: the Frame a client hands out, and the decoding of the three
encodings (FULL float32 arrays, QUANTIZED and DELTA ``packed`` bytes) into
the same numpy arrays, vectorised over the bodies; and of the joints' states
a frame carries when asked, float32 arrays in every encoding.

The layout of ``packed`` is docs/protocol.md's "Pose encodings"
(proto/wire/quantized_poses.h): varints n, flags and k; n zigzag varints of
id differences; with n > 0 three zigzag varints of origin cell, three bytes
of bit widths, then a bit stream, least significant bit first, of per-body
records of fixed width (cell offsets, 32 bits of smallest-three orientation,
with velocities 6 x 16 bits), padded to a byte.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Dict, Iterator, List, Optional, Tuple, TypeVar, Union

import numpy as np
import numpy.typing as npt

from tumble.v1 import protocol_pb2 as pb

FloatArray = npt.NDArray[np.float64]
IdArray = npt.NDArray[np.uint32]
JointArrays = Tuple[IdArray, FloatArray, FloatArray, FloatArray]
"""The joints' ids, positions, speeds and motor impulses, one row each, as a Frame holds them."""

# proto/wire/quantized_poses.h and smallest_three.h.
_LINEAR_VELOCITY_STEP = 1.0 / 128
_ANGULAR_VELOCITY_STEP = 1.0 / 256
_VELOCITY_BITS = 16
_ZERO_LEVEL = 511
_SQRT2 = math.sqrt(2.0)
# For a largest component at index i (w, x, y, z order), the indices of the
# other three in the order they are stored.
# Below this many bodies a FULL frame's repeated fields are read directly:
# cheaper than numpy's fixed cost per call.
_FEW_BODIES = 32
_OTHERS = np.array([[1, 2, 3], [0, 2, 3], [0, 1, 3], [0, 1, 2]], dtype=np.intp)


@dataclass(frozen=True)
class BodyState:
    """One body's state in a Frame: arrays of a single row of the frame's."""

    id: int
    name: str
    position: FloatArray  # m, (3,)
    orientation: FloatArray  # (4,), w x y z
    linear_velocity: Optional[FloatArray]  # m/s, (3,); None without velocities
    angular_velocity: Optional[FloatArray]  # rad/s, (3,); None without velocities


class Frame:
    """The state of a set of bodies at one tick, bodies in ascending id order.

    ``ids`` is uint32 (N,), ``positions`` float64 (N, 3) in m,
    ``orientations`` (N, 4) as w, x, y, z, ``linear_velocities`` and
    ``angular_velocities`` (N, 3) in m/s and rad/s, or None when the
    subscription or Step asked for poses only. ``frame["crate"]`` or
    ``frame[3]`` gives one body (a BodyState); ``len(frame)`` is N.

    With joints asked for, every joint of the world at that tick, in
    ascending id order: ``joint_ids`` uint32 (J,), and float64 (J,)
    ``joint_positions`` (hinge angle in rad, slider position or distance
    joint length in m, ball joint's angle from its axis in rad),
    ``joint_speeds`` (their rates, rad/s or m/s) and
    ``joint_motor_impulses`` (the motor's impulse over the last step, N m s
    or N s); all four None when the subscription or Step did not ask for
    joints. The values were float32 on the wire, whatever the encoding.

    The arrays are the frame's own: change them freely.
    """

    __slots__ = ("tick", "time", "ids", "positions", "orientations", "linear_velocities", "angular_velocities",
                 "joint_ids", "joint_positions", "joint_speeds", "joint_motor_impulses", "subscription_id", "_names",
                 "_index")

    def __init__(self, tick: int, time: float, ids: IdArray, positions: FloatArray, orientations: FloatArray,
                 linear_velocities: Optional[FloatArray], angular_velocities: Optional[FloatArray],
                 names: Dict[int, str], subscription_id: int = 0, joints: Optional[JointArrays] = None) -> None:
        """Makes a frame of arrays already in ascending id order; `names` maps ids to names (shared, read only).

        `joints`: the joints' (ids, positions, speeds, motor impulses) in
        ascending id order, or None when they were not asked for.
        """
        self.tick = tick
        """The tick whose state this is."""
        self.time = time
        """Sim time at that tick, s."""
        self.ids = ids
        self.positions = positions
        self.orientations = orientations
        self.linear_velocities = linear_velocities
        self.angular_velocities = angular_velocities
        self.joint_ids: Optional[IdArray] = None if joints is None else joints[0]
        self.joint_positions: Optional[FloatArray] = None if joints is None else joints[1]
        self.joint_speeds: Optional[FloatArray] = None if joints is None else joints[2]
        self.joint_motor_impulses: Optional[FloatArray] = None if joints is None else joints[3]
        self.subscription_id = subscription_id
        """The subscription it came from; 0 for a Step's frame."""
        self._names = names
        self._index: Optional[Dict[int, int]] = None

    @property
    def names(self) -> List[str]:
        """The bodies' names, in the order of ``ids`` ("" for a body without one)."""
        names = self._names
        return [names.get(i, "") for i in self.ids.tolist()]

    def __len__(self) -> int:
        return int(self.ids.shape[0])

    def __contains__(self, body: object) -> bool:
        try:
            self.index(body)  # type: ignore[arg-type]
        except KeyError:
            return False
        return True

    def index(self, body: Union[int, str]) -> int:
        """The row of a body, by id or name; KeyError when the frame does not hold it."""
        if self._index is None:
            self._index = {int(i): row for row, i in enumerate(self.ids.tolist())}
        if isinstance(body, str):
            for body_id, name in self._names.items():
                if name == body and body_id in self._index:
                    return self._index[body_id]
            raise KeyError(f"no body named {body!r} in this frame")
        if isinstance(body, (int, np.integer)) and not isinstance(body, bool):
            try:
                return self._index[int(body)]
            except KeyError:
                raise KeyError(f"no body with id {int(body)} in this frame") from None
        raise KeyError(f"a body is an id (int) or a name (str), not {type(body).__name__}")

    def __getitem__(self, body: Union[int, str]) -> BodyState:
        row = self.index(body)
        body_id = int(self.ids[row])
        lin = None if self.linear_velocities is None else self.linear_velocities[row].copy()
        ang = None if self.angular_velocities is None else self.angular_velocities[row].copy()
        return BodyState(body_id, self._names.get(body_id, ""), self.positions[row].copy(),
                         self.orientations[row].copy(), lin, ang)

    def __iter__(self) -> Iterator[BodyState]:
        return (self[int(i)] for i in self.ids)

    def __repr__(self) -> str:
        return f"Frame(tick={self.tick}, time={self.time:g}, bodies={len(self)})"


Arrays = Tuple[IdArray, FloatArray, FloatArray, Optional[FloatArray], Optional[FloatArray]]
_ById = TypeVar("_ById", Arrays, JointArrays)


def _sorted_by_id(arrays: _ById) -> _ById:
    ids = arrays[0]
    if ids.shape[0] < 2 or bool(np.all(ids[1:] > ids[:-1])):
        return arrays
    order = np.argsort(ids, kind="stable")
    return tuple(None if a is None else a[order] for a in arrays)  # type: ignore[return-value]


def decode_full(frame: pb.PoseFrame) -> Arrays:
    """The arrays of a FULL frame's float32 fields, as float64, in ascending id order.

    Read from the frame's encoding with numpy (packed varints and little-endian
    float32), not element by element from protobuf's repeated fields, which
    costs a Python object per number.
    """
    n = len(frame.ids)
    if n <= _FEW_BODIES:
        ids = np.array(frame.ids, dtype=np.uint32)
        lin: Optional[FloatArray] = None
        ang: Optional[FloatArray] = None
        if len(frame.linear_velocities) or len(frame.angular_velocities):
            lin = np.array(frame.linear_velocities, dtype=np.float64).reshape(n, 3)
            ang = np.array(frame.angular_velocities, dtype=np.float64).reshape(n, 3)
        return _sorted_by_id((ids, np.array(frame.positions, dtype=np.float64).reshape(n, 3),
                              np.array(frame.orientations, dtype=np.float64).reshape(n, 4), lin, ang))
    data = frame.SerializeToString()
    buf = np.frombuffer(data, dtype=np.uint8)
    spans: Dict[int, Tuple[int, int]] = {}
    pos = 0
    while pos < len(data):
        key, pos = _varint(data, pos)
        wire_type = key & 7
        if wire_type == 2:
            length, pos = _varint(data, pos)
            spans[key >> 3] = (pos, length)
            pos += length
        elif wire_type == 0:
            _, pos = _varint(data, pos)
        elif wire_type == 1:
            pos += 8
        elif wire_type == 5:
            pos += 4
        else:
            raise PackedError(f"a PoseFrame field of wire type {wire_type}")
    start, length = spans.get(4, (0, 0))
    region = buf[start:start + length]
    ids, _ = _varints(region, 0, int(np.count_nonzero(region < 0x80)))
    if ids.shape[0] != n:
        raise PackedError(f"the ids of a FULL frame decode to {ids.shape[0]} where it holds {n}")

    def floats(field: int, width: int) -> Optional[FloatArray]:
        start, length = spans.get(field, (0, 0))
        if length != 4 * width * n:
            if length == 0 and (field >= 7 or n == 0):
                return None
            raise PackedError(f"field {field} of a FULL frame holds {length} bytes for {n} bodies")
        return np.frombuffer(data, dtype="<f4", count=width * n, offset=start).astype(np.float64).reshape(n, width)

    positions = floats(5, 3)
    orientations = floats(6, 4)
    positions = np.zeros((n, 3)) if positions is None else positions
    orientations = np.zeros((n, 4)) if orientations is None else orientations
    lin, ang = floats(7, 3), floats(8, 3)
    if (lin is None) != (ang is None):
        lin = np.zeros((n, 3)) if lin is None else lin
        ang = np.zeros((n, 3)) if ang is None else ang
    return _sorted_by_id((ids.astype(np.uint32), positions, orientations, lin, ang))


class PackedError(ValueError):
    """A frame does not follow the layout: its ``packed`` bytes, its FULL arrays or its joints."""


def decode_joints(frame: pb.PoseFrame) -> JointArrays:
    """The joints' (ids, positions, speeds, motor impulses) a frame carries, in ascending id order.

    The same four float32 fields in every encoding, a DELTA frame's whole.
    Raises PackedError when the four do not hold one value per joint.
    """
    ids = np.array(frame.joint_ids, dtype=np.uint32)
    positions = np.array(frame.joint_positions, dtype=np.float64)
    speeds = np.array(frame.joint_speeds, dtype=np.float64)
    motor_impulses = np.array(frame.joint_motor_impulses, dtype=np.float64)
    if not ids.shape[0] == positions.shape[0] == speeds.shape[0] == motor_impulses.shape[0]:
        raise PackedError(f"a frame's joints hold {ids.shape[0]} ids, {positions.shape[0]} positions, "
                          f"{speeds.shape[0]} speeds and {motor_impulses.shape[0]} motor impulses")
    return _sorted_by_id((ids, positions, speeds, motor_impulses))


def _varint(data: bytes, pos: int) -> Tuple[int, int]:
    value = 0
    shift = 0
    while True:
        if pos >= len(data) or shift > 63:
            raise PackedError("a varint is cut short")
        byte = data[pos]
        pos += 1
        value |= (byte & 0x7F) << shift
        if byte < 0x80:
            return value, pos
        shift += 7


def _unzigzag(value: int) -> int:
    return (value >> 1) ^ -(value & 1)


def _varints(buf: npt.NDArray[np.uint8], pos: int, count: int) -> Tuple[npt.NDArray[np.uint64], int]:
    """`count` varints from buf[pos:], decoded together; and the position after them."""
    if count == 0:
        return np.zeros(0, dtype=np.uint64), pos
    region = buf[pos:]
    ends = np.flatnonzero(region < 0x80)
    if ends.shape[0] < count:
        raise PackedError("the ids are cut short")
    ends = ends[:count]
    end = int(ends[-1]) + 1
    data = region[:end].astype(np.uint64)
    starts = np.empty(count, dtype=np.intp)
    starts[0] = 0
    starts[1:] = ends[:-1] + 1
    # Each byte's place in its varint: 7 bits more per byte after the first.
    group = np.repeat(np.arange(count), ends - starts + 1)
    place = np.arange(end) - starts[group]
    if place.max() > 9:
        raise PackedError("a varint is longer than ten bytes")
    values = np.bitwise_or.reduceat((data & 0x7F) << (7 * place).astype(np.uint64), starts)
    return values, pos + end


def _fields(bits: npt.NDArray[np.uint8], offset: int, width: int) -> npt.NDArray[np.uint64]:
    """The unsigned field of `width` bits at `offset` of each row of a (n, bits) array."""
    n = bits.shape[0]
    if width == 0:
        return np.zeros(n, dtype=np.uint64)
    weights = np.left_shift(np.uint64(1), np.arange(width, dtype=np.uint64))
    return bits[:, offset:offset + width].astype(np.uint64) @ weights


def unpack_smallest_three(packed: npt.NDArray[np.uint64]) -> FloatArray:
    """Unit quaternions (n, 4), w x y z, from their 32-bit smallest-three codes (wire/smallest_three.h)."""
    n = packed.shape[0]
    largest = (packed & np.uint64(3)).astype(np.intp)
    levels = np.stack([(packed >> np.uint64(s)) & np.uint64(1023) for s in (2, 12, 22)], axis=1)
    small = (levels.astype(np.float64) - _ZERO_LEVEL) / (_ZERO_LEVEL * _SQRT2)
    q = np.empty((n, 4), dtype=np.float64)
    rows = np.arange(n)
    q[rows[:, None], _OTHERS[largest]] = small
    squares = np.einsum("ij,ij->i", small, small)
    q[rows, largest] = np.sqrt(np.maximum(0.0, 1.0 - squares))
    q /= np.linalg.norm(q, axis=1)[:, None]
    return q


def decode_packed(packed: bytes) -> Arrays:
    """The arrays of a QUANTIZED or DELTA frame's ``packed`` bytes, in ascending id order.

    Raises PackedError when the bytes do not follow the layout.
    """
    pos = 0
    n, pos = _varint(packed, pos)
    flags, pos = _varint(packed, pos)
    exponent, pos = _varint(packed, pos)
    if n > len(packed) or exponent > 64:
        raise PackedError(f"a count of {n} bodies or a step of 2^-{exponent} m that the bytes cannot hold")
    velocities = bool(flags & 1)
    buf = np.frombuffer(packed, dtype=np.uint8)
    coded, pos = _varints(buf, pos, n)
    signed = (coded >> np.uint64(1)).astype(np.int64) ^ -(coded & np.uint64(1)).astype(np.int64)
    id_values = np.cumsum(signed)
    if n and (id_values.min() < 0 or id_values.max() > 0xFFFFFFFF):
        raise PackedError("an id outside 0 .. 2^32 - 1")
    ids = id_values.astype(np.uint32)
    if n == 0:
        if pos != len(packed):
            raise PackedError("bytes left over after an empty frame")
        empty3 = np.zeros((0, 3))
        return ids, empty3, np.zeros((0, 4)), (empty3.copy() if velocities else None), \
            (empty3.copy() if velocities else None)
    origin = []
    for _ in range(3):
        value, pos = _varint(packed, pos)
        origin.append(_unzigzag(value))
    if pos + 3 > len(packed):
        raise PackedError("the bit widths are cut short")
    widths = list(packed[pos:pos + 3])
    pos += 3
    if max(widths) > 63:
        raise PackedError(f"a bit width over 63: {widths}")
    record = sum(widths) + 32 + (6 * _VELOCITY_BITS if velocities else 0)
    total = record * n
    if (total + 7) // 8 != len(packed) - pos:
        raise PackedError(f"{len(packed) - pos} bytes of bodies where {n} bodies of {record} bits take "
                          f"{(total + 7) // 8}")
    bits = np.unpackbits(buf[pos:], bitorder="little")[:total].reshape(n, record)
    step = math.ldexp(1.0, -exponent)
    positions = np.empty((n, 3), dtype=np.float64)
    offset = 0
    for axis in range(3):
        cells = _fields(bits, offset, widths[axis]).astype(np.int64) + origin[axis]
        positions[:, axis] = cells.astype(np.float64) * step
        offset += widths[axis]
    orientations = unpack_smallest_three(_fields(bits, offset, 32))
    offset += 32
    lin: Optional[FloatArray] = None
    ang: Optional[FloatArray] = None
    if velocities:
        levels = np.stack([_fields(bits, offset + k * _VELOCITY_BITS, _VELOCITY_BITS) for k in range(6)], axis=1)
        signed_levels = levels.astype(np.uint16).view(np.int16).astype(np.float64)
        lin = signed_levels[:, :3] * _LINEAR_VELOCITY_STEP
        ang = signed_levels[:, 3:] * _ANGULAR_VELOCITY_STEP
    return _sorted_by_id((ids, positions, orientations, lin, ang))


class DeltaBaseline:
    """What a client holds of a DELTA subscription: the bodies of the last frame it took in.

    ``apply`` takes a frame and returns the whole state it stands for, or
    None when it cannot (a change without a key frame before it, or bytes
    that do not decode): the caller then asks for a key frame.
    """

    def __init__(self) -> None:
        """An empty baseline: only a key frame can start it."""
        self.arrays: Optional[Arrays] = None

    def apply(self, frame: pb.PoseFrame) -> Optional[Arrays]:
        """The state after `frame`, or None when a key frame is needed."""
        try:
            change = decode_packed(frame.packed)
        except PackedError:
            self.arrays = None
            return None
        if frame.key_frame:
            self.arrays = change
            return change
        base = self.arrays
        if base is None or (base[3] is None) != (change[3] is None):
            return None
        base_ids = base[0]
        removed = np.array(frame.removed_ids, dtype=np.uint32)
        keep = ~np.isin(base_ids, change[0])
        if removed.shape[0]:
            keep &= ~np.isin(base_ids, removed)
        merged = tuple(None if b is None else np.concatenate([b[keep], c])  # type: ignore[index]
                       for b, c in zip(base, change))
        self.arrays = _sorted_by_id(merged)  # type: ignore[type-var, assignment]
        return self.arrays
