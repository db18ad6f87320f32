// Turns a tumble.v1.JointSpec (from a scene file or AddJoint) into the
// physics engine's JointDesc, checking that it describes a joint its type
// takes: a name within string_limits.h, two different known bodies (body_a
// may be the world), finite points within kMaxMagnitude, a nonzero axis,
// limits in order, only the fields of its type (limits and a motor on a
// hinge or slider, a cone on a ball joint, lengths and a spring on a
// distance joint), then whatever physics::World::joint_desc_error refuses.
// Errors name the joint and field as scene files do, e.g.
// "joints[2].limits: the lower limit 1.5 is above the upper limit -1.5".
//
// Pure functions of their arguments; the world and directory are only read.
#pragma once

#include <string>
#include <string_view>

#include "sim/body_directory.h"
#include "sim/status.h"
#include "tumble/physics/joint.h"
#include "tumble/physics/world.h"
#include "tumble/v1/protocol.pb.h"
#include "tumble/v1/scene.pb.h"

namespace tumble::sim {

// What JointSpec.body_a names the world by.
inline constexpr std::string_view kWorldBodyName = "world";

// The type as scene files and the CLI write it ("hinge"); "" for UNSPECIFIED.
const char* joint_type_name(tumble::v1::JointType type);
// The type `name` stands for; JOINT_TYPE_UNSPECIFIED for none.
tumble::v1::JointType joint_type_named(std::string_view name);

// The engine's joint type of a protocol type, and back; false for
// UNSPECIFIED or a value no type has.
bool physics_joint_type(tumble::v1::JointType type, physics::JointType* out);
tumble::v1::JointType wire_joint_type(physics::JointType type);

// What can be judged of `spec` without the world: a known type, a name
// within the limits, both bodies named and different, finite numbers, and
// only the fields its type takes. `where` names the joint, e.g. "joints[2]".
Status check_joint_spec(const tumble::v1::JointSpec& spec, const std::string& where);

// A motor as SetJointMotor or a JointSpec gives it, for a joint of `type`:
// a type with a motor, a speed or a position, a spring only with a
// position, the max_torque of a hinge or the max_force of a slider, all
// finite and forces >= 0. `where` names the motor, e.g. "joints[2].motor".
Status check_joint_motor(const tumble::v1::JointMotorSpec& motor, tumble::v1::JointType type, const std::string& where);

// The engine's motor for a spec check_joint_motor accepts.
physics::JointMotor physics_motor(const tumble::v1::JointMotorSpec& motor);
// The spec of the engine's motor of a joint of `type` (nothing when off).
void wire_motor(const physics::JointMotor& motor, physics::JointType type, tumble::v1::JointMotorSpec* out);

// The body `ref` (JointSpec.body_a or body_b) names: kWorldBodyId for
// "world", the body of that id for decimal digits, else the body of that
// name; kInvalidBodyId when there is none.
physics::BodyId resolve_joint_body(std::string_view ref, const physics::World& world, const BodyDirectory& directory);

// Fills `desc` from `spec` at the bodies' current poses
// (World::set_joint_frames): check_joint_spec, the bodies resolved, the
// defaults filled in (a fixed joint's anchor at body B's centre of mass, a
// ball joint's cone axis towards it, a distance joint's lengths from its
// anchors), then World::joint_desc_error.
Status joint_desc_from_spec(const tumble::v1::JointSpec& spec, const std::string& where, const physics::World& world,
                            const BodyDirectory& directory, physics::JointDesc* desc);

// The joint's state as of the last step (World::joint_state), as the wire
// carries it.
void fill_joint_state(const physics::World& world, physics::JointId id, tumble::v1::JointState* out);

}  // namespace tumble::sim
