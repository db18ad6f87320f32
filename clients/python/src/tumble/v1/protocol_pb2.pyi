from tumble.v1 import types_pb2 as _types_pb2
from tumble.v1 import scene_pb2 as _scene_pb2
from google.protobuf.internal import containers as _containers
from google.protobuf.internal import enum_type_wrapper as _enum_type_wrapper
from google.protobuf import descriptor as _descriptor
from google.protobuf import message as _message
from typing import ClassVar as _ClassVar, Iterable as _Iterable, Mapping as _Mapping, Optional as _Optional, Union as _Union

DESCRIPTOR: _descriptor.FileDescriptor
ERROR_CODE_UNSPECIFIED: ErrorCode
FAILED_PRECONDITION: ErrorCode
FRAME_BODY: Frame
FRAME_TOO_LARGE: ErrorCode
FRAME_WORLD: Frame
HANDSHAKE_REQUIRED: ErrorCode
INTERNAL: ErrorCode
INVALID_ARGUMENT: ErrorCode
MALFORMED_FRAME: ErrorCode
PERMISSION_DENIED: ErrorCode
POSE_ENCODING_DELTA: PoseEncoding
POSE_ENCODING_FULL: PoseEncoding
POSE_ENCODING_QUANTIZED: PoseEncoding
POSE_FIELDS_POSE: PoseFields
POSE_FIELDS_POSE_AND_VELOCITY: PoseFields
PROTOCOL_VERSION_CURRENT: ProtocolVersion
PROTOCOL_VERSION_UNSPECIFIED: ProtocolVersion
RATE_LIMITED: ErrorCode
RESOURCE_EXHAUSTED: ErrorCode
ROLE_CONTROLLER: Role
ROLE_OBSERVER: Role
ROLE_UNSPECIFIED: Role
STEP_END_COMPLETED: StepEnd
STEP_END_PAUSE: StepEnd
STEP_END_RESET: StepEnd
STEP_END_RESUME: StepEnd
STEP_END_UNSPECIFIED: StepEnd
UNAUTHENTICATED: ErrorCode
UNKNOWN_BODY: ErrorCode
UNKNOWN_JOINT: ErrorCode
UNKNOWN_MESSAGE: ErrorCode
UNKNOWN_SUBSCRIPTION: ErrorCode
UNSUPPORTED_VERSION: ErrorCode
WORLD_EVENT_BODY_ASLEEP: WorldEventKind
WORLD_EVENT_BODY_AWAKE: WorldEventKind
WORLD_EVENT_BODY_DIVERGED: WorldEventKind
WORLD_EVENT_BODY_REMOVED: WorldEventKind
WORLD_EVENT_BODY_SPAWNED: WorldEventKind
WORLD_EVENT_JOINT_ADDED: WorldEventKind
WORLD_EVENT_JOINT_BROKEN: WorldEventKind
WORLD_EVENT_JOINT_REMOVED: WorldEventKind
WORLD_EVENT_KIND_UNSPECIFIED: WorldEventKind
WORLD_EVENT_WORLD_RESET: WorldEventKind

class Ack(_message.Message):
    __slots__ = ["applied_tick", "body_id", "frame", "joint_id", "request_id", "step_ended_by", "step_ticks_left"]
    APPLIED_TICK_FIELD_NUMBER: _ClassVar[int]
    BODY_ID_FIELD_NUMBER: _ClassVar[int]
    FRAME_FIELD_NUMBER: _ClassVar[int]
    JOINT_ID_FIELD_NUMBER: _ClassVar[int]
    REQUEST_ID_FIELD_NUMBER: _ClassVar[int]
    STEP_ENDED_BY_FIELD_NUMBER: _ClassVar[int]
    STEP_TICKS_LEFT_FIELD_NUMBER: _ClassVar[int]
    applied_tick: int
    body_id: int
    frame: PoseFrame
    joint_id: int
    request_id: int
    step_ended_by: StepEnd
    step_ticks_left: int
    def __init__(self, request_id: _Optional[int] = ..., applied_tick: _Optional[int] = ..., body_id: _Optional[int] = ..., step_ticks_left: _Optional[int] = ..., step_ended_by: _Optional[_Union[StepEnd, str]] = ..., joint_id: _Optional[int] = ..., frame: _Optional[_Union[PoseFrame, _Mapping]] = ...) -> None: ...

class AddJoint(_message.Message):
    __slots__ = ["joint"]
    JOINT_FIELD_NUMBER: _ClassVar[int]
    joint: _scene_pb2.JointSpec
    def __init__(self, joint: _Optional[_Union[_scene_pb2.JointSpec, _Mapping]] = ...) -> None: ...

class ApplyForce(_message.Message):
    __slots__ = ["body", "force", "persistent", "point", "point_frame", "seconds", "ticks"]
    BODY_FIELD_NUMBER: _ClassVar[int]
    FORCE_FIELD_NUMBER: _ClassVar[int]
    PERSISTENT_FIELD_NUMBER: _ClassVar[int]
    POINT_FIELD_NUMBER: _ClassVar[int]
    POINT_FRAME_FIELD_NUMBER: _ClassVar[int]
    SECONDS_FIELD_NUMBER: _ClassVar[int]
    TICKS_FIELD_NUMBER: _ClassVar[int]
    body: BodyRef
    force: _types_pb2.Vec3
    persistent: bool
    point: _types_pb2.Vec3
    point_frame: Frame
    seconds: float
    ticks: int
    def __init__(self, body: _Optional[_Union[BodyRef, _Mapping]] = ..., force: _Optional[_Union[_types_pb2.Vec3, _Mapping]] = ..., point: _Optional[_Union[_types_pb2.Vec3, _Mapping]] = ..., point_frame: _Optional[_Union[Frame, str]] = ..., seconds: _Optional[float] = ..., ticks: _Optional[int] = ..., persistent: bool = ...) -> None: ...

class ApplyImpulse(_message.Message):
    __slots__ = ["body", "impulse", "point", "point_frame"]
    BODY_FIELD_NUMBER: _ClassVar[int]
    IMPULSE_FIELD_NUMBER: _ClassVar[int]
    POINT_FIELD_NUMBER: _ClassVar[int]
    POINT_FRAME_FIELD_NUMBER: _ClassVar[int]
    body: BodyRef
    impulse: _types_pb2.Vec3
    point: _types_pb2.Vec3
    point_frame: Frame
    def __init__(self, body: _Optional[_Union[BodyRef, _Mapping]] = ..., impulse: _Optional[_Union[_types_pb2.Vec3, _Mapping]] = ..., point: _Optional[_Union[_types_pb2.Vec3, _Mapping]] = ..., point_frame: _Optional[_Union[Frame, str]] = ...) -> None: ...

class ApplyTorque(_message.Message):
    __slots__ = ["body", "persistent", "seconds", "ticks", "torque"]
    BODY_FIELD_NUMBER: _ClassVar[int]
    PERSISTENT_FIELD_NUMBER: _ClassVar[int]
    SECONDS_FIELD_NUMBER: _ClassVar[int]
    TICKS_FIELD_NUMBER: _ClassVar[int]
    TORQUE_FIELD_NUMBER: _ClassVar[int]
    body: BodyRef
    persistent: bool
    seconds: float
    ticks: int
    torque: _types_pb2.Vec3
    def __init__(self, body: _Optional[_Union[BodyRef, _Mapping]] = ..., torque: _Optional[_Union[_types_pb2.Vec3, _Mapping]] = ..., seconds: _Optional[float] = ..., ticks: _Optional[int] = ..., persistent: bool = ...) -> None: ...

class BodyInfo(_message.Message):
    __slots__ = ["angular_velocity", "asleep", "id", "linear_velocity", "mass", "motion", "name", "orientation", "position", "shape"]
    ANGULAR_VELOCITY_FIELD_NUMBER: _ClassVar[int]
    ASLEEP_FIELD_NUMBER: _ClassVar[int]
    ID_FIELD_NUMBER: _ClassVar[int]
    LINEAR_VELOCITY_FIELD_NUMBER: _ClassVar[int]
    MASS_FIELD_NUMBER: _ClassVar[int]
    MOTION_FIELD_NUMBER: _ClassVar[int]
    NAME_FIELD_NUMBER: _ClassVar[int]
    ORIENTATION_FIELD_NUMBER: _ClassVar[int]
    POSITION_FIELD_NUMBER: _ClassVar[int]
    SHAPE_FIELD_NUMBER: _ClassVar[int]
    angular_velocity: _types_pb2.Vec3
    asleep: bool
    id: int
    linear_velocity: _types_pb2.Vec3
    mass: float
    motion: _scene_pb2.Motion
    name: str
    orientation: _types_pb2.Quat
    position: _types_pb2.Vec3
    shape: _scene_pb2.Shape
    def __init__(self, id: _Optional[int] = ..., name: _Optional[str] = ..., shape: _Optional[_Union[_scene_pb2.Shape, _Mapping]] = ..., mass: _Optional[float] = ..., position: _Optional[_Union[_types_pb2.Vec3, _Mapping]] = ..., orientation: _Optional[_Union[_types_pb2.Quat, _Mapping]] = ..., linear_velocity: _Optional[_Union[_types_pb2.Vec3, _Mapping]] = ..., angular_velocity: _Optional[_Union[_types_pb2.Vec3, _Mapping]] = ..., asleep: bool = ..., motion: _Optional[_Union[_scene_pb2.Motion, str]] = ...) -> None: ...

class BodyList(_message.Message):
    __slots__ = ["bodies", "next_start_id", "request_id", "tick", "total_bodies"]
    BODIES_FIELD_NUMBER: _ClassVar[int]
    NEXT_START_ID_FIELD_NUMBER: _ClassVar[int]
    REQUEST_ID_FIELD_NUMBER: _ClassVar[int]
    TICK_FIELD_NUMBER: _ClassVar[int]
    TOTAL_BODIES_FIELD_NUMBER: _ClassVar[int]
    bodies: _containers.RepeatedCompositeFieldContainer[BodyInfo]
    next_start_id: int
    request_id: int
    tick: int
    total_bodies: int
    def __init__(self, request_id: _Optional[int] = ..., tick: _Optional[int] = ..., bodies: _Optional[_Iterable[_Union[BodyInfo, _Mapping]]] = ..., next_start_id: _Optional[int] = ..., total_bodies: _Optional[int] = ...) -> None: ...

class BodyRef(_message.Message):
    __slots__ = ["id", "name"]
    ID_FIELD_NUMBER: _ClassVar[int]
    NAME_FIELD_NUMBER: _ClassVar[int]
    id: int
    name: str
    def __init__(self, id: _Optional[int] = ..., name: _Optional[str] = ...) -> None: ...

class Checkpoints(_message.Message):
    __slots__ = ["capture_ms_max", "destination", "failed", "interval_s", "last_bytes", "last_capture_ms", "last_tick", "last_write_ms", "write_ms_max", "written"]
    CAPTURE_MS_MAX_FIELD_NUMBER: _ClassVar[int]
    DESTINATION_FIELD_NUMBER: _ClassVar[int]
    FAILED_FIELD_NUMBER: _ClassVar[int]
    INTERVAL_S_FIELD_NUMBER: _ClassVar[int]
    LAST_BYTES_FIELD_NUMBER: _ClassVar[int]
    LAST_CAPTURE_MS_FIELD_NUMBER: _ClassVar[int]
    LAST_TICK_FIELD_NUMBER: _ClassVar[int]
    LAST_WRITE_MS_FIELD_NUMBER: _ClassVar[int]
    WRITE_MS_MAX_FIELD_NUMBER: _ClassVar[int]
    WRITTEN_FIELD_NUMBER: _ClassVar[int]
    capture_ms_max: float
    destination: str
    failed: int
    interval_s: float
    last_bytes: int
    last_capture_ms: float
    last_tick: int
    last_write_ms: float
    write_ms_max: float
    written: int
    def __init__(self, destination: _Optional[str] = ..., interval_s: _Optional[float] = ..., written: _Optional[int] = ..., failed: _Optional[int] = ..., last_tick: _Optional[int] = ..., last_bytes: _Optional[int] = ..., last_write_ms: _Optional[float] = ..., write_ms_max: _Optional[float] = ..., last_capture_ms: _Optional[float] = ..., capture_ms_max: _Optional[float] = ...) -> None: ...

class ClearForces(_message.Message):
    __slots__ = ["body"]
    BODY_FIELD_NUMBER: _ClassVar[int]
    body: BodyRef
    def __init__(self, body: _Optional[_Union[BodyRef, _Mapping]] = ...) -> None: ...

class ClientMessage(_message.Message):
    __slots__ = ["add_joint", "apply_force", "apply_impulse", "apply_torque", "clear_forces", "get_stats", "hello", "key_frame_request", "list_bodies", "list_joints", "pause", "remove_body", "remove_joint", "request_id", "reset", "resume", "set_body_state", "set_joint_motor", "set_tick_rate", "spawn_body", "step", "subscribe", "unsubscribe"]
    ADD_JOINT_FIELD_NUMBER: _ClassVar[int]
    APPLY_FORCE_FIELD_NUMBER: _ClassVar[int]
    APPLY_IMPULSE_FIELD_NUMBER: _ClassVar[int]
    APPLY_TORQUE_FIELD_NUMBER: _ClassVar[int]
    CLEAR_FORCES_FIELD_NUMBER: _ClassVar[int]
    GET_STATS_FIELD_NUMBER: _ClassVar[int]
    HELLO_FIELD_NUMBER: _ClassVar[int]
    KEY_FRAME_REQUEST_FIELD_NUMBER: _ClassVar[int]
    LIST_BODIES_FIELD_NUMBER: _ClassVar[int]
    LIST_JOINTS_FIELD_NUMBER: _ClassVar[int]
    PAUSE_FIELD_NUMBER: _ClassVar[int]
    REMOVE_BODY_FIELD_NUMBER: _ClassVar[int]
    REMOVE_JOINT_FIELD_NUMBER: _ClassVar[int]
    REQUEST_ID_FIELD_NUMBER: _ClassVar[int]
    RESET_FIELD_NUMBER: _ClassVar[int]
    RESUME_FIELD_NUMBER: _ClassVar[int]
    SET_BODY_STATE_FIELD_NUMBER: _ClassVar[int]
    SET_JOINT_MOTOR_FIELD_NUMBER: _ClassVar[int]
    SET_TICK_RATE_FIELD_NUMBER: _ClassVar[int]
    SPAWN_BODY_FIELD_NUMBER: _ClassVar[int]
    STEP_FIELD_NUMBER: _ClassVar[int]
    SUBSCRIBE_FIELD_NUMBER: _ClassVar[int]
    UNSUBSCRIBE_FIELD_NUMBER: _ClassVar[int]
    add_joint: AddJoint
    apply_force: ApplyForce
    apply_impulse: ApplyImpulse
    apply_torque: ApplyTorque
    clear_forces: ClearForces
    get_stats: GetStats
    hello: Hello
    key_frame_request: KeyFrameRequest
    list_bodies: ListBodies
    list_joints: ListJoints
    pause: Pause
    remove_body: RemoveBody
    remove_joint: RemoveJoint
    request_id: int
    reset: Reset
    resume: Resume
    set_body_state: SetBodyState
    set_joint_motor: SetJointMotor
    set_tick_rate: SetTickRate
    spawn_body: SpawnBody
    step: Step
    subscribe: Subscribe
    unsubscribe: Unsubscribe
    def __init__(self, request_id: _Optional[int] = ..., hello: _Optional[_Union[Hello, _Mapping]] = ..., apply_force: _Optional[_Union[ApplyForce, _Mapping]] = ..., apply_torque: _Optional[_Union[ApplyTorque, _Mapping]] = ..., apply_impulse: _Optional[_Union[ApplyImpulse, _Mapping]] = ..., list_bodies: _Optional[_Union[ListBodies, _Mapping]] = ..., subscribe: _Optional[_Union[Subscribe, _Mapping]] = ..., unsubscribe: _Optional[_Union[Unsubscribe, _Mapping]] = ..., spawn_body: _Optional[_Union[SpawnBody, _Mapping]] = ..., remove_body: _Optional[_Union[RemoveBody, _Mapping]] = ..., set_body_state: _Optional[_Union[SetBodyState, _Mapping]] = ..., clear_forces: _Optional[_Union[ClearForces, _Mapping]] = ..., pause: _Optional[_Union[Pause, _Mapping]] = ..., resume: _Optional[_Union[Resume, _Mapping]] = ..., step: _Optional[_Union[Step, _Mapping]] = ..., reset: _Optional[_Union[Reset, _Mapping]] = ..., set_tick_rate: _Optional[_Union[SetTickRate, _Mapping]] = ..., get_stats: _Optional[_Union[GetStats, _Mapping]] = ..., key_frame_request: _Optional[_Union[KeyFrameRequest, _Mapping]] = ..., add_joint: _Optional[_Union[AddJoint, _Mapping]] = ..., remove_joint: _Optional[_Union[RemoveJoint, _Mapping]] = ..., set_joint_motor: _Optional[_Union[SetJointMotor, _Mapping]] = ..., list_joints: _Optional[_Union[ListJoints, _Mapping]] = ...) -> None: ...

class Error(_message.Message):
    __slots__ = ["code", "message", "request_id"]
    CODE_FIELD_NUMBER: _ClassVar[int]
    MESSAGE_FIELD_NUMBER: _ClassVar[int]
    REQUEST_ID_FIELD_NUMBER: _ClassVar[int]
    code: ErrorCode
    message: str
    request_id: int
    def __init__(self, request_id: _Optional[int] = ..., code: _Optional[_Union[ErrorCode, str]] = ..., message: _Optional[str] = ...) -> None: ...

class GetStats(_message.Message):
    __slots__ = []
    def __init__(self) -> None: ...

class Hello(_message.Message):
    __slots__ = ["client_name", "protocol_version", "token"]
    CLIENT_NAME_FIELD_NUMBER: _ClassVar[int]
    PROTOCOL_VERSION_FIELD_NUMBER: _ClassVar[int]
    TOKEN_FIELD_NUMBER: _ClassVar[int]
    client_name: str
    protocol_version: int
    token: str
    def __init__(self, protocol_version: _Optional[int] = ..., client_name: _Optional[str] = ..., token: _Optional[str] = ...) -> None: ...

class JointInfo(_message.Message):
    __slots__ = ["anchor_a", "anchor_b", "axis", "body_a", "body_a_name", "body_b", "body_b_name", "break_force", "break_torque", "collide_connected", "cone_limit", "friction", "id", "length", "limits", "max_length", "min_length", "motor", "name", "spring", "state", "type"]
    ANCHOR_A_FIELD_NUMBER: _ClassVar[int]
    ANCHOR_B_FIELD_NUMBER: _ClassVar[int]
    AXIS_FIELD_NUMBER: _ClassVar[int]
    BODY_A_FIELD_NUMBER: _ClassVar[int]
    BODY_A_NAME_FIELD_NUMBER: _ClassVar[int]
    BODY_B_FIELD_NUMBER: _ClassVar[int]
    BODY_B_NAME_FIELD_NUMBER: _ClassVar[int]
    BREAK_FORCE_FIELD_NUMBER: _ClassVar[int]
    BREAK_TORQUE_FIELD_NUMBER: _ClassVar[int]
    COLLIDE_CONNECTED_FIELD_NUMBER: _ClassVar[int]
    CONE_LIMIT_FIELD_NUMBER: _ClassVar[int]
    FRICTION_FIELD_NUMBER: _ClassVar[int]
    ID_FIELD_NUMBER: _ClassVar[int]
    LENGTH_FIELD_NUMBER: _ClassVar[int]
    LIMITS_FIELD_NUMBER: _ClassVar[int]
    MAX_LENGTH_FIELD_NUMBER: _ClassVar[int]
    MIN_LENGTH_FIELD_NUMBER: _ClassVar[int]
    MOTOR_FIELD_NUMBER: _ClassVar[int]
    NAME_FIELD_NUMBER: _ClassVar[int]
    SPRING_FIELD_NUMBER: _ClassVar[int]
    STATE_FIELD_NUMBER: _ClassVar[int]
    TYPE_FIELD_NUMBER: _ClassVar[int]
    anchor_a: _types_pb2.Vec3
    anchor_b: _types_pb2.Vec3
    axis: _types_pb2.Vec3
    body_a: int
    body_a_name: str
    body_b: int
    body_b_name: str
    break_force: float
    break_torque: float
    collide_connected: bool
    cone_limit: float
    friction: float
    id: int
    length: float
    limits: _scene_pb2.JointLimits
    max_length: float
    min_length: float
    motor: _scene_pb2.JointMotorSpec
    name: str
    spring: _scene_pb2.JointSpring
    state: JointState
    type: _scene_pb2.JointType
    def __init__(self, id: _Optional[int] = ..., name: _Optional[str] = ..., type: _Optional[_Union[_scene_pb2.JointType, str]] = ..., body_a: _Optional[int] = ..., body_a_name: _Optional[str] = ..., body_b: _Optional[int] = ..., body_b_name: _Optional[str] = ..., anchor_a: _Optional[_Union[_types_pb2.Vec3, _Mapping]] = ..., anchor_b: _Optional[_Union[_types_pb2.Vec3, _Mapping]] = ..., axis: _Optional[_Union[_types_pb2.Vec3, _Mapping]] = ..., limits: _Optional[_Union[_scene_pb2.JointLimits, _Mapping]] = ..., cone_limit: _Optional[float] = ..., length: _Optional[float] = ..., min_length: _Optional[float] = ..., max_length: _Optional[float] = ..., spring: _Optional[_Union[_scene_pb2.JointSpring, _Mapping]] = ..., motor: _Optional[_Union[_scene_pb2.JointMotorSpec, _Mapping]] = ..., break_force: _Optional[float] = ..., break_torque: _Optional[float] = ..., collide_connected: bool = ..., state: _Optional[_Union[JointState, _Mapping]] = ..., friction: _Optional[float] = ...) -> None: ...

class JointList(_message.Message):
    __slots__ = ["joints", "next_start_id", "request_id", "tick", "total_joints"]
    JOINTS_FIELD_NUMBER: _ClassVar[int]
    NEXT_START_ID_FIELD_NUMBER: _ClassVar[int]
    REQUEST_ID_FIELD_NUMBER: _ClassVar[int]
    TICK_FIELD_NUMBER: _ClassVar[int]
    TOTAL_JOINTS_FIELD_NUMBER: _ClassVar[int]
    joints: _containers.RepeatedCompositeFieldContainer[JointInfo]
    next_start_id: int
    request_id: int
    tick: int
    total_joints: int
    def __init__(self, request_id: _Optional[int] = ..., tick: _Optional[int] = ..., joints: _Optional[_Iterable[_Union[JointInfo, _Mapping]]] = ..., next_start_id: _Optional[int] = ..., total_joints: _Optional[int] = ...) -> None: ...

class JointRef(_message.Message):
    __slots__ = ["id", "name"]
    ID_FIELD_NUMBER: _ClassVar[int]
    NAME_FIELD_NUMBER: _ClassVar[int]
    id: int
    name: str
    def __init__(self, id: _Optional[int] = ..., name: _Optional[str] = ...) -> None: ...

class JointState(_message.Message):
    __slots__ = ["force", "id", "motor_impulse", "position", "speed", "torque"]
    FORCE_FIELD_NUMBER: _ClassVar[int]
    ID_FIELD_NUMBER: _ClassVar[int]
    MOTOR_IMPULSE_FIELD_NUMBER: _ClassVar[int]
    POSITION_FIELD_NUMBER: _ClassVar[int]
    SPEED_FIELD_NUMBER: _ClassVar[int]
    TORQUE_FIELD_NUMBER: _ClassVar[int]
    force: _types_pb2.Vec3
    id: int
    motor_impulse: float
    position: float
    speed: float
    torque: _types_pb2.Vec3
    def __init__(self, id: _Optional[int] = ..., position: _Optional[float] = ..., speed: _Optional[float] = ..., force: _Optional[_Union[_types_pb2.Vec3, _Mapping]] = ..., torque: _Optional[_Union[_types_pb2.Vec3, _Mapping]] = ..., motor_impulse: _Optional[float] = ...) -> None: ...

class KeyFrameRequest(_message.Message):
    __slots__ = ["subscription_id"]
    SUBSCRIPTION_ID_FIELD_NUMBER: _ClassVar[int]
    subscription_id: int
    def __init__(self, subscription_id: _Optional[int] = ...) -> None: ...

class ListBodies(_message.Message):
    __slots__ = ["max_bodies", "start_id"]
    MAX_BODIES_FIELD_NUMBER: _ClassVar[int]
    START_ID_FIELD_NUMBER: _ClassVar[int]
    max_bodies: int
    start_id: int
    def __init__(self, start_id: _Optional[int] = ..., max_bodies: _Optional[int] = ...) -> None: ...

class ListJoints(_message.Message):
    __slots__ = ["max_joints", "start_id"]
    MAX_JOINTS_FIELD_NUMBER: _ClassVar[int]
    START_ID_FIELD_NUMBER: _ClassVar[int]
    max_joints: int
    start_id: int
    def __init__(self, start_id: _Optional[int] = ..., max_joints: _Optional[int] = ...) -> None: ...

class NatsLink(_message.Message):
    __slots__ = ["bytes_out", "connected", "frames_dropped", "messages_out", "reconnects", "requests_in", "server_url", "world"]
    BYTES_OUT_FIELD_NUMBER: _ClassVar[int]
    CONNECTED_FIELD_NUMBER: _ClassVar[int]
    FRAMES_DROPPED_FIELD_NUMBER: _ClassVar[int]
    MESSAGES_OUT_FIELD_NUMBER: _ClassVar[int]
    RECONNECTS_FIELD_NUMBER: _ClassVar[int]
    REQUESTS_IN_FIELD_NUMBER: _ClassVar[int]
    SERVER_URL_FIELD_NUMBER: _ClassVar[int]
    WORLD_FIELD_NUMBER: _ClassVar[int]
    bytes_out: int
    connected: bool
    frames_dropped: int
    messages_out: int
    reconnects: int
    requests_in: int
    server_url: str
    world: str
    def __init__(self, connected: bool = ..., server_url: _Optional[str] = ..., messages_out: _Optional[int] = ..., bytes_out: _Optional[int] = ..., reconnects: _Optional[int] = ..., requests_in: _Optional[int] = ..., frames_dropped: _Optional[int] = ..., world: _Optional[str] = ...) -> None: ...

class Pause(_message.Message):
    __slots__ = []
    def __init__(self) -> None: ...

class PoseFrame(_message.Message):
    __slots__ = ["angular_velocities", "encoding", "epoch", "ids", "joint_ids", "joint_motor_impulses", "joint_positions", "joint_speeds", "key_frame", "linear_velocities", "orientations", "packed", "positions", "removed_ids", "sequence", "sim_time", "subscription_id", "tick"]
    ANGULAR_VELOCITIES_FIELD_NUMBER: _ClassVar[int]
    ENCODING_FIELD_NUMBER: _ClassVar[int]
    EPOCH_FIELD_NUMBER: _ClassVar[int]
    IDS_FIELD_NUMBER: _ClassVar[int]
    JOINT_IDS_FIELD_NUMBER: _ClassVar[int]
    JOINT_MOTOR_IMPULSES_FIELD_NUMBER: _ClassVar[int]
    JOINT_POSITIONS_FIELD_NUMBER: _ClassVar[int]
    JOINT_SPEEDS_FIELD_NUMBER: _ClassVar[int]
    KEY_FRAME_FIELD_NUMBER: _ClassVar[int]
    LINEAR_VELOCITIES_FIELD_NUMBER: _ClassVar[int]
    ORIENTATIONS_FIELD_NUMBER: _ClassVar[int]
    PACKED_FIELD_NUMBER: _ClassVar[int]
    POSITIONS_FIELD_NUMBER: _ClassVar[int]
    REMOVED_IDS_FIELD_NUMBER: _ClassVar[int]
    SEQUENCE_FIELD_NUMBER: _ClassVar[int]
    SIM_TIME_FIELD_NUMBER: _ClassVar[int]
    SUBSCRIPTION_ID_FIELD_NUMBER: _ClassVar[int]
    TICK_FIELD_NUMBER: _ClassVar[int]
    angular_velocities: _containers.RepeatedScalarFieldContainer[float]
    encoding: PoseEncoding
    epoch: int
    ids: _containers.RepeatedScalarFieldContainer[int]
    joint_ids: _containers.RepeatedScalarFieldContainer[int]
    joint_motor_impulses: _containers.RepeatedScalarFieldContainer[float]
    joint_positions: _containers.RepeatedScalarFieldContainer[float]
    joint_speeds: _containers.RepeatedScalarFieldContainer[float]
    key_frame: bool
    linear_velocities: _containers.RepeatedScalarFieldContainer[float]
    orientations: _containers.RepeatedScalarFieldContainer[float]
    packed: bytes
    positions: _containers.RepeatedScalarFieldContainer[float]
    removed_ids: _containers.RepeatedScalarFieldContainer[int]
    sequence: int
    sim_time: float
    subscription_id: int
    tick: int
    def __init__(self, subscription_id: _Optional[int] = ..., tick: _Optional[int] = ..., sim_time: _Optional[float] = ..., ids: _Optional[_Iterable[int]] = ..., positions: _Optional[_Iterable[float]] = ..., orientations: _Optional[_Iterable[float]] = ..., linear_velocities: _Optional[_Iterable[float]] = ..., angular_velocities: _Optional[_Iterable[float]] = ..., encoding: _Optional[_Union[PoseEncoding, str]] = ..., packed: _Optional[bytes] = ..., key_frame: bool = ..., removed_ids: _Optional[_Iterable[int]] = ..., sequence: _Optional[int] = ..., epoch: _Optional[int] = ..., joint_ids: _Optional[_Iterable[int]] = ..., joint_positions: _Optional[_Iterable[float]] = ..., joint_speeds: _Optional[_Iterable[float]] = ..., joint_motor_impulses: _Optional[_Iterable[float]] = ...) -> None: ...

class RemoveBody(_message.Message):
    __slots__ = ["body"]
    BODY_FIELD_NUMBER: _ClassVar[int]
    body: BodyRef
    def __init__(self, body: _Optional[_Union[BodyRef, _Mapping]] = ...) -> None: ...

class RemoveJoint(_message.Message):
    __slots__ = ["joint"]
    JOINT_FIELD_NUMBER: _ClassVar[int]
    joint: JointRef
    def __init__(self, joint: _Optional[_Union[JointRef, _Mapping]] = ...) -> None: ...

class Reset(_message.Message):
    __slots__ = []
    def __init__(self) -> None: ...

class Resume(_message.Message):
    __slots__ = []
    def __init__(self) -> None: ...

class ServerMessage(_message.Message):
    __slots__ = ["ack", "body_list", "error", "joint_list", "pose_frame", "stats", "subscribed", "welcome", "world_event"]
    ACK_FIELD_NUMBER: _ClassVar[int]
    BODY_LIST_FIELD_NUMBER: _ClassVar[int]
    ERROR_FIELD_NUMBER: _ClassVar[int]
    JOINT_LIST_FIELD_NUMBER: _ClassVar[int]
    POSE_FRAME_FIELD_NUMBER: _ClassVar[int]
    STATS_FIELD_NUMBER: _ClassVar[int]
    SUBSCRIBED_FIELD_NUMBER: _ClassVar[int]
    WELCOME_FIELD_NUMBER: _ClassVar[int]
    WORLD_EVENT_FIELD_NUMBER: _ClassVar[int]
    ack: Ack
    body_list: BodyList
    error: Error
    joint_list: JointList
    pose_frame: PoseFrame
    stats: Stats
    subscribed: Subscribed
    welcome: Welcome
    world_event: WorldEvent
    def __init__(self, welcome: _Optional[_Union[Welcome, _Mapping]] = ..., ack: _Optional[_Union[Ack, _Mapping]] = ..., error: _Optional[_Union[Error, _Mapping]] = ..., body_list: _Optional[_Union[BodyList, _Mapping]] = ..., subscribed: _Optional[_Union[Subscribed, _Mapping]] = ..., pose_frame: _Optional[_Union[PoseFrame, _Mapping]] = ..., stats: _Optional[_Union[Stats, _Mapping]] = ..., world_event: _Optional[_Union[WorldEvent, _Mapping]] = ..., joint_list: _Optional[_Union[JointList, _Mapping]] = ...) -> None: ...

class SetBodyState(_message.Message):
    __slots__ = ["angular_velocity", "body", "linear_velocity", "orientation", "position"]
    ANGULAR_VELOCITY_FIELD_NUMBER: _ClassVar[int]
    BODY_FIELD_NUMBER: _ClassVar[int]
    LINEAR_VELOCITY_FIELD_NUMBER: _ClassVar[int]
    ORIENTATION_FIELD_NUMBER: _ClassVar[int]
    POSITION_FIELD_NUMBER: _ClassVar[int]
    angular_velocity: _types_pb2.Vec3
    body: BodyRef
    linear_velocity: _types_pb2.Vec3
    orientation: _types_pb2.Quat
    position: _types_pb2.Vec3
    def __init__(self, body: _Optional[_Union[BodyRef, _Mapping]] = ..., position: _Optional[_Union[_types_pb2.Vec3, _Mapping]] = ..., orientation: _Optional[_Union[_types_pb2.Quat, _Mapping]] = ..., linear_velocity: _Optional[_Union[_types_pb2.Vec3, _Mapping]] = ..., angular_velocity: _Optional[_Union[_types_pb2.Vec3, _Mapping]] = ...) -> None: ...

class SetJointMotor(_message.Message):
    __slots__ = ["joint", "motor"]
    JOINT_FIELD_NUMBER: _ClassVar[int]
    MOTOR_FIELD_NUMBER: _ClassVar[int]
    joint: JointRef
    motor: _scene_pb2.JointMotorSpec
    def __init__(self, joint: _Optional[_Union[JointRef, _Mapping]] = ..., motor: _Optional[_Union[_scene_pb2.JointMotorSpec, _Mapping]] = ...) -> None: ...

class SetTickRate(_message.Message):
    __slots__ = ["rate_hz"]
    RATE_HZ_FIELD_NUMBER: _ClassVar[int]
    rate_hz: float
    def __init__(self, rate_hz: _Optional[float] = ...) -> None: ...

class SpawnBody(_message.Message):
    __slots__ = ["body"]
    BODY_FIELD_NUMBER: _ClassVar[int]
    body: _scene_pb2.BodySpec
    def __init__(self, body: _Optional[_Union[_scene_pb2.BodySpec, _Mapping]] = ...) -> None: ...

class Stats(_message.Message):
    __slots__ = ["bodies", "bodies_asleep", "bodies_awake", "bodies_diverged", "bytes_sent", "checkpoints", "clients", "clients_closed_for_errors", "connections_refused", "nats", "overruns", "paused", "real_time_factor", "request_id", "sim_time", "tick", "tick_cpu_ms_p50", "tick_cpu_ms_p99", "tick_ms_p50", "tick_ms_p99", "tick_rate_hz", "tick_start_late_ms_p50", "tick_start_late_ms_p99"]
    BODIES_ASLEEP_FIELD_NUMBER: _ClassVar[int]
    BODIES_AWAKE_FIELD_NUMBER: _ClassVar[int]
    BODIES_DIVERGED_FIELD_NUMBER: _ClassVar[int]
    BODIES_FIELD_NUMBER: _ClassVar[int]
    BYTES_SENT_FIELD_NUMBER: _ClassVar[int]
    CHECKPOINTS_FIELD_NUMBER: _ClassVar[int]
    CLIENTS_CLOSED_FOR_ERRORS_FIELD_NUMBER: _ClassVar[int]
    CLIENTS_FIELD_NUMBER: _ClassVar[int]
    CONNECTIONS_REFUSED_FIELD_NUMBER: _ClassVar[int]
    NATS_FIELD_NUMBER: _ClassVar[int]
    OVERRUNS_FIELD_NUMBER: _ClassVar[int]
    PAUSED_FIELD_NUMBER: _ClassVar[int]
    REAL_TIME_FACTOR_FIELD_NUMBER: _ClassVar[int]
    REQUEST_ID_FIELD_NUMBER: _ClassVar[int]
    SIM_TIME_FIELD_NUMBER: _ClassVar[int]
    TICK_CPU_MS_P50_FIELD_NUMBER: _ClassVar[int]
    TICK_CPU_MS_P99_FIELD_NUMBER: _ClassVar[int]
    TICK_FIELD_NUMBER: _ClassVar[int]
    TICK_MS_P50_FIELD_NUMBER: _ClassVar[int]
    TICK_MS_P99_FIELD_NUMBER: _ClassVar[int]
    TICK_RATE_HZ_FIELD_NUMBER: _ClassVar[int]
    TICK_START_LATE_MS_P50_FIELD_NUMBER: _ClassVar[int]
    TICK_START_LATE_MS_P99_FIELD_NUMBER: _ClassVar[int]
    bodies: int
    bodies_asleep: int
    bodies_awake: int
    bodies_diverged: int
    bytes_sent: int
    checkpoints: Checkpoints
    clients: int
    clients_closed_for_errors: int
    connections_refused: int
    nats: NatsLink
    overruns: int
    paused: bool
    real_time_factor: float
    request_id: int
    sim_time: float
    tick: int
    tick_cpu_ms_p50: float
    tick_cpu_ms_p99: float
    tick_ms_p50: float
    tick_ms_p99: float
    tick_rate_hz: float
    tick_start_late_ms_p50: float
    tick_start_late_ms_p99: float
    def __init__(self, request_id: _Optional[int] = ..., tick: _Optional[int] = ..., sim_time: _Optional[float] = ..., paused: bool = ..., tick_rate_hz: _Optional[float] = ..., real_time_factor: _Optional[float] = ..., tick_ms_p50: _Optional[float] = ..., tick_ms_p99: _Optional[float] = ..., overruns: _Optional[int] = ..., bodies: _Optional[int] = ..., bodies_awake: _Optional[int] = ..., bodies_asleep: _Optional[int] = ..., clients: _Optional[int] = ..., bytes_sent: _Optional[int] = ..., tick_cpu_ms_p50: _Optional[float] = ..., tick_cpu_ms_p99: _Optional[float] = ..., tick_start_late_ms_p50: _Optional[float] = ..., tick_start_late_ms_p99: _Optional[float] = ..., bodies_diverged: _Optional[int] = ..., connections_refused: _Optional[int] = ..., clients_closed_for_errors: _Optional[int] = ..., nats: _Optional[_Union[NatsLink, _Mapping]] = ..., checkpoints: _Optional[_Union[Checkpoints, _Mapping]] = ...) -> None: ...

class Step(_message.Message):
    __slots__ = ["forces", "frame_bodies", "frame_fields", "frame_joints", "reply_frame", "ticks", "torques"]
    FORCES_FIELD_NUMBER: _ClassVar[int]
    FRAME_BODIES_FIELD_NUMBER: _ClassVar[int]
    FRAME_FIELDS_FIELD_NUMBER: _ClassVar[int]
    FRAME_JOINTS_FIELD_NUMBER: _ClassVar[int]
    REPLY_FRAME_FIELD_NUMBER: _ClassVar[int]
    TICKS_FIELD_NUMBER: _ClassVar[int]
    TORQUES_FIELD_NUMBER: _ClassVar[int]
    forces: _containers.RepeatedCompositeFieldContainer[ApplyForce]
    frame_bodies: _containers.RepeatedCompositeFieldContainer[BodyRef]
    frame_fields: PoseFields
    frame_joints: bool
    reply_frame: bool
    ticks: int
    torques: _containers.RepeatedCompositeFieldContainer[ApplyTorque]
    def __init__(self, ticks: _Optional[int] = ..., forces: _Optional[_Iterable[_Union[ApplyForce, _Mapping]]] = ..., torques: _Optional[_Iterable[_Union[ApplyTorque, _Mapping]]] = ..., reply_frame: bool = ..., frame_bodies: _Optional[_Iterable[_Union[BodyRef, _Mapping]]] = ..., frame_fields: _Optional[_Union[PoseFields, str]] = ..., frame_joints: bool = ...) -> None: ...

class Subscribe(_message.Message):
    __slots__ = ["bodies", "encoding", "events", "fields", "joints", "rate_hz"]
    BODIES_FIELD_NUMBER: _ClassVar[int]
    ENCODING_FIELD_NUMBER: _ClassVar[int]
    EVENTS_FIELD_NUMBER: _ClassVar[int]
    FIELDS_FIELD_NUMBER: _ClassVar[int]
    JOINTS_FIELD_NUMBER: _ClassVar[int]
    RATE_HZ_FIELD_NUMBER: _ClassVar[int]
    bodies: _containers.RepeatedCompositeFieldContainer[BodyRef]
    encoding: PoseEncoding
    events: _containers.RepeatedScalarFieldContainer[WorldEventKind]
    fields: PoseFields
    joints: bool
    rate_hz: float
    def __init__(self, bodies: _Optional[_Iterable[_Union[BodyRef, _Mapping]]] = ..., rate_hz: _Optional[float] = ..., fields: _Optional[_Union[PoseFields, str]] = ..., events: _Optional[_Iterable[_Union[WorldEventKind, str]]] = ..., encoding: _Optional[_Union[PoseEncoding, str]] = ..., joints: bool = ...) -> None: ...

class Subscribed(_message.Message):
    __slots__ = ["encoding", "period_ticks", "position_step", "rate_hz", "request_id", "subscription_id"]
    ENCODING_FIELD_NUMBER: _ClassVar[int]
    PERIOD_TICKS_FIELD_NUMBER: _ClassVar[int]
    POSITION_STEP_FIELD_NUMBER: _ClassVar[int]
    RATE_HZ_FIELD_NUMBER: _ClassVar[int]
    REQUEST_ID_FIELD_NUMBER: _ClassVar[int]
    SUBSCRIPTION_ID_FIELD_NUMBER: _ClassVar[int]
    encoding: PoseEncoding
    period_ticks: int
    position_step: float
    rate_hz: float
    request_id: int
    subscription_id: int
    def __init__(self, request_id: _Optional[int] = ..., subscription_id: _Optional[int] = ..., period_ticks: _Optional[int] = ..., rate_hz: _Optional[float] = ..., encoding: _Optional[_Union[PoseEncoding, str]] = ..., position_step: _Optional[float] = ...) -> None: ...

class Unsubscribe(_message.Message):
    __slots__ = ["subscription_id"]
    SUBSCRIPTION_ID_FIELD_NUMBER: _ClassVar[int]
    subscription_id: int
    def __init__(self, subscription_id: _Optional[int] = ...) -> None: ...

class Welcome(_message.Message):
    __slots__ = ["body_count", "protocol_version", "role", "server_version", "sim_time", "tick", "tick_rate_hz"]
    BODY_COUNT_FIELD_NUMBER: _ClassVar[int]
    PROTOCOL_VERSION_FIELD_NUMBER: _ClassVar[int]
    ROLE_FIELD_NUMBER: _ClassVar[int]
    SERVER_VERSION_FIELD_NUMBER: _ClassVar[int]
    SIM_TIME_FIELD_NUMBER: _ClassVar[int]
    TICK_FIELD_NUMBER: _ClassVar[int]
    TICK_RATE_HZ_FIELD_NUMBER: _ClassVar[int]
    body_count: int
    protocol_version: int
    role: Role
    server_version: str
    sim_time: float
    tick: int
    tick_rate_hz: float
    def __init__(self, protocol_version: _Optional[int] = ..., server_version: _Optional[str] = ..., tick_rate_hz: _Optional[float] = ..., tick: _Optional[int] = ..., sim_time: _Optional[float] = ..., body_count: _Optional[int] = ..., role: _Optional[_Union[Role, str]] = ...) -> None: ...

class WorldEvent(_message.Message):
    __slots__ = ["body_id", "body_name", "joint_body_a", "joint_id", "joint_name", "kind", "subscription_id", "tick"]
    BODY_ID_FIELD_NUMBER: _ClassVar[int]
    BODY_NAME_FIELD_NUMBER: _ClassVar[int]
    JOINT_BODY_A_FIELD_NUMBER: _ClassVar[int]
    JOINT_ID_FIELD_NUMBER: _ClassVar[int]
    JOINT_NAME_FIELD_NUMBER: _ClassVar[int]
    KIND_FIELD_NUMBER: _ClassVar[int]
    SUBSCRIPTION_ID_FIELD_NUMBER: _ClassVar[int]
    TICK_FIELD_NUMBER: _ClassVar[int]
    body_id: int
    body_name: str
    joint_body_a: int
    joint_id: int
    joint_name: str
    kind: WorldEventKind
    subscription_id: int
    tick: int
    def __init__(self, subscription_id: _Optional[int] = ..., tick: _Optional[int] = ..., kind: _Optional[_Union[WorldEventKind, str]] = ..., body_id: _Optional[int] = ..., body_name: _Optional[str] = ..., joint_id: _Optional[int] = ..., joint_name: _Optional[str] = ..., joint_body_a: _Optional[int] = ...) -> None: ...

class ProtocolVersion(int, metaclass=_enum_type_wrapper.EnumTypeWrapper):
    __slots__ = []

class Frame(int, metaclass=_enum_type_wrapper.EnumTypeWrapper):
    __slots__ = []

class PoseFields(int, metaclass=_enum_type_wrapper.EnumTypeWrapper):
    __slots__ = []

class WorldEventKind(int, metaclass=_enum_type_wrapper.EnumTypeWrapper):
    __slots__ = []

class PoseEncoding(int, metaclass=_enum_type_wrapper.EnumTypeWrapper):
    __slots__ = []

class Role(int, metaclass=_enum_type_wrapper.EnumTypeWrapper):
    __slots__ = []

class StepEnd(int, metaclass=_enum_type_wrapper.EnumTypeWrapper):
    __slots__ = []

class ErrorCode(int, metaclass=_enum_type_wrapper.EnumTypeWrapper):
    __slots__ = []
