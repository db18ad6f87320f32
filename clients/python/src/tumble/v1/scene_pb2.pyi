from tumble.v1 import types_pb2 as _types_pb2
from google.protobuf.internal import containers as _containers
from google.protobuf.internal import enum_type_wrapper as _enum_type_wrapper
from google.protobuf import descriptor as _descriptor
from google.protobuf import message as _message
from typing import ClassVar as _ClassVar, Iterable as _Iterable, Mapping as _Mapping, Optional as _Optional, Union as _Union

DESCRIPTOR: _descriptor.FileDescriptor
JOINT_TYPE_BALL: JointType
JOINT_TYPE_DISTANCE: JointType
JOINT_TYPE_FIXED: JointType
JOINT_TYPE_HINGE: JointType
JOINT_TYPE_SLIDER: JointType
JOINT_TYPE_UNSPECIFIED: JointType
MOTION_DYNAMIC: Motion
MOTION_KINEMATIC: Motion
MOTION_STATIC: Motion

class BodySpec(_message.Message):
    __slots__ = ["angular_velocity", "friction", "linear_velocity", "mass", "motion", "name", "orientation", "position", "restitution", "shape"]
    ANGULAR_VELOCITY_FIELD_NUMBER: _ClassVar[int]
    FRICTION_FIELD_NUMBER: _ClassVar[int]
    LINEAR_VELOCITY_FIELD_NUMBER: _ClassVar[int]
    MASS_FIELD_NUMBER: _ClassVar[int]
    MOTION_FIELD_NUMBER: _ClassVar[int]
    NAME_FIELD_NUMBER: _ClassVar[int]
    ORIENTATION_FIELD_NUMBER: _ClassVar[int]
    POSITION_FIELD_NUMBER: _ClassVar[int]
    RESTITUTION_FIELD_NUMBER: _ClassVar[int]
    SHAPE_FIELD_NUMBER: _ClassVar[int]
    angular_velocity: _types_pb2.Vec3
    friction: float
    linear_velocity: _types_pb2.Vec3
    mass: float
    motion: Motion
    name: str
    orientation: _types_pb2.Quat
    position: _types_pb2.Vec3
    restitution: float
    shape: Shape
    def __init__(self, name: _Optional[str] = ..., shape: _Optional[_Union[Shape, _Mapping]] = ..., mass: _Optional[float] = ..., position: _Optional[_Union[_types_pb2.Vec3, _Mapping]] = ..., orientation: _Optional[_Union[_types_pb2.Quat, _Mapping]] = ..., linear_velocity: _Optional[_Union[_types_pb2.Vec3, _Mapping]] = ..., angular_velocity: _Optional[_Union[_types_pb2.Vec3, _Mapping]] = ..., motion: _Optional[_Union[Motion, str]] = ..., friction: _Optional[float] = ..., restitution: _Optional[float] = ...) -> None: ...

class Box(_message.Message):
    __slots__ = ["half_extents"]
    HALF_EXTENTS_FIELD_NUMBER: _ClassVar[int]
    half_extents: _types_pb2.Vec3
    def __init__(self, half_extents: _Optional[_Union[_types_pb2.Vec3, _Mapping]] = ...) -> None: ...

class Capsule(_message.Message):
    __slots__ = ["half_height", "radius"]
    HALF_HEIGHT_FIELD_NUMBER: _ClassVar[int]
    RADIUS_FIELD_NUMBER: _ClassVar[int]
    half_height: float
    radius: float
    def __init__(self, radius: _Optional[float] = ..., half_height: _Optional[float] = ...) -> None: ...

class Convex(_message.Message):
    __slots__ = ["points"]
    POINTS_FIELD_NUMBER: _ClassVar[int]
    points: _containers.RepeatedCompositeFieldContainer[_types_pb2.Vec3]
    def __init__(self, points: _Optional[_Iterable[_Union[_types_pb2.Vec3, _Mapping]]] = ...) -> None: ...

class JointLimits(_message.Message):
    __slots__ = ["lower", "upper"]
    LOWER_FIELD_NUMBER: _ClassVar[int]
    UPPER_FIELD_NUMBER: _ClassVar[int]
    lower: float
    upper: float
    def __init__(self, lower: _Optional[float] = ..., upper: _Optional[float] = ...) -> None: ...

class JointMotorSpec(_message.Message):
    __slots__ = ["damping_ratio", "hertz", "max_force", "max_torque", "position", "speed"]
    DAMPING_RATIO_FIELD_NUMBER: _ClassVar[int]
    HERTZ_FIELD_NUMBER: _ClassVar[int]
    MAX_FORCE_FIELD_NUMBER: _ClassVar[int]
    MAX_TORQUE_FIELD_NUMBER: _ClassVar[int]
    POSITION_FIELD_NUMBER: _ClassVar[int]
    SPEED_FIELD_NUMBER: _ClassVar[int]
    damping_ratio: float
    hertz: float
    max_force: float
    max_torque: float
    position: float
    speed: float
    def __init__(self, speed: _Optional[float] = ..., position: _Optional[float] = ..., hertz: _Optional[float] = ..., damping_ratio: _Optional[float] = ..., max_torque: _Optional[float] = ..., max_force: _Optional[float] = ...) -> None: ...

class JointSpec(_message.Message):
    __slots__ = ["anchor", "anchor_b", "axis", "body_a", "body_b", "break_force", "break_torque", "collide_connected", "cone_limit", "friction", "length", "limits", "max_length", "min_length", "motor", "name", "spring", "type"]
    ANCHOR_B_FIELD_NUMBER: _ClassVar[int]
    ANCHOR_FIELD_NUMBER: _ClassVar[int]
    AXIS_FIELD_NUMBER: _ClassVar[int]
    BODY_A_FIELD_NUMBER: _ClassVar[int]
    BODY_B_FIELD_NUMBER: _ClassVar[int]
    BREAK_FORCE_FIELD_NUMBER: _ClassVar[int]
    BREAK_TORQUE_FIELD_NUMBER: _ClassVar[int]
    COLLIDE_CONNECTED_FIELD_NUMBER: _ClassVar[int]
    CONE_LIMIT_FIELD_NUMBER: _ClassVar[int]
    FRICTION_FIELD_NUMBER: _ClassVar[int]
    LENGTH_FIELD_NUMBER: _ClassVar[int]
    LIMITS_FIELD_NUMBER: _ClassVar[int]
    MAX_LENGTH_FIELD_NUMBER: _ClassVar[int]
    MIN_LENGTH_FIELD_NUMBER: _ClassVar[int]
    MOTOR_FIELD_NUMBER: _ClassVar[int]
    NAME_FIELD_NUMBER: _ClassVar[int]
    SPRING_FIELD_NUMBER: _ClassVar[int]
    TYPE_FIELD_NUMBER: _ClassVar[int]
    anchor: _types_pb2.Vec3
    anchor_b: _types_pb2.Vec3
    axis: _types_pb2.Vec3
    body_a: str
    body_b: str
    break_force: float
    break_torque: float
    collide_connected: bool
    cone_limit: float
    friction: float
    length: float
    limits: JointLimits
    max_length: float
    min_length: float
    motor: JointMotorSpec
    name: str
    spring: JointSpring
    type: JointType
    def __init__(self, name: _Optional[str] = ..., type: _Optional[_Union[JointType, str]] = ..., body_a: _Optional[str] = ..., body_b: _Optional[str] = ..., anchor: _Optional[_Union[_types_pb2.Vec3, _Mapping]] = ..., anchor_b: _Optional[_Union[_types_pb2.Vec3, _Mapping]] = ..., axis: _Optional[_Union[_types_pb2.Vec3, _Mapping]] = ..., limits: _Optional[_Union[JointLimits, _Mapping]] = ..., cone_limit: _Optional[float] = ..., length: _Optional[float] = ..., min_length: _Optional[float] = ..., max_length: _Optional[float] = ..., spring: _Optional[_Union[JointSpring, _Mapping]] = ..., motor: _Optional[_Union[JointMotorSpec, _Mapping]] = ..., break_force: _Optional[float] = ..., break_torque: _Optional[float] = ..., collide_connected: bool = ..., friction: _Optional[float] = ...) -> None: ...

class JointSpring(_message.Message):
    __slots__ = ["damping_ratio", "hertz"]
    DAMPING_RATIO_FIELD_NUMBER: _ClassVar[int]
    HERTZ_FIELD_NUMBER: _ClassVar[int]
    damping_ratio: float
    hertz: float
    def __init__(self, hertz: _Optional[float] = ..., damping_ratio: _Optional[float] = ...) -> None: ...

class Plane(_message.Message):
    __slots__ = ["normal", "offset"]
    NORMAL_FIELD_NUMBER: _ClassVar[int]
    OFFSET_FIELD_NUMBER: _ClassVar[int]
    normal: _types_pb2.Vec3
    offset: float
    def __init__(self, normal: _Optional[_Union[_types_pb2.Vec3, _Mapping]] = ..., offset: _Optional[float] = ...) -> None: ...

class PointMasses(_message.Message):
    __slots__ = ["masses", "positions"]
    MASSES_FIELD_NUMBER: _ClassVar[int]
    POSITIONS_FIELD_NUMBER: _ClassVar[int]
    masses: _containers.RepeatedScalarFieldContainer[float]
    positions: _containers.RepeatedCompositeFieldContainer[_types_pb2.Vec3]
    def __init__(self, masses: _Optional[_Iterable[float]] = ..., positions: _Optional[_Iterable[_Union[_types_pb2.Vec3, _Mapping]]] = ...) -> None: ...

class Scene(_message.Message):
    __slots__ = ["bodies", "gravity", "joints"]
    BODIES_FIELD_NUMBER: _ClassVar[int]
    GRAVITY_FIELD_NUMBER: _ClassVar[int]
    JOINTS_FIELD_NUMBER: _ClassVar[int]
    bodies: _containers.RepeatedCompositeFieldContainer[BodySpec]
    gravity: _types_pb2.Vec3
    joints: _containers.RepeatedCompositeFieldContainer[JointSpec]
    def __init__(self, gravity: _Optional[_Union[_types_pb2.Vec3, _Mapping]] = ..., bodies: _Optional[_Iterable[_Union[BodySpec, _Mapping]]] = ..., joints: _Optional[_Iterable[_Union[JointSpec, _Mapping]]] = ...) -> None: ...

class Shape(_message.Message):
    __slots__ = ["box", "capsule", "convex", "plane", "points", "sphere"]
    BOX_FIELD_NUMBER: _ClassVar[int]
    CAPSULE_FIELD_NUMBER: _ClassVar[int]
    CONVEX_FIELD_NUMBER: _ClassVar[int]
    PLANE_FIELD_NUMBER: _ClassVar[int]
    POINTS_FIELD_NUMBER: _ClassVar[int]
    SPHERE_FIELD_NUMBER: _ClassVar[int]
    box: Box
    capsule: Capsule
    convex: Convex
    plane: Plane
    points: PointMasses
    sphere: Sphere
    def __init__(self, box: _Optional[_Union[Box, _Mapping]] = ..., sphere: _Optional[_Union[Sphere, _Mapping]] = ..., capsule: _Optional[_Union[Capsule, _Mapping]] = ..., points: _Optional[_Union[PointMasses, _Mapping]] = ..., plane: _Optional[_Union[Plane, _Mapping]] = ..., convex: _Optional[_Union[Convex, _Mapping]] = ...) -> None: ...

class Sphere(_message.Message):
    __slots__ = ["radius"]
    RADIUS_FIELD_NUMBER: _ClassVar[int]
    radius: float
    def __init__(self, radius: _Optional[float] = ...) -> None: ...

class Motion(int, metaclass=_enum_type_wrapper.EnumTypeWrapper):
    __slots__ = []

class JointType(int, metaclass=_enum_type_wrapper.EnumTypeWrapper):
    __slots__ = []
