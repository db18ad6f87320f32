// Joints above the engine: the scene file's joints and their errors, the
// joint requests and their events, and joints carried exactly by saved
// worlds, journals and Reset.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sim/journal.h"
#include "sim/replay.h"
#include "sim/request_check.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"
#include "sim/snapshot.h"
#include "sim_driver.h"
#include "temp_dir.h"

namespace tumble::sim {
namespace {

using tumble::v1::ClientMessage;
using tumble::v1::ServerMessage;

// The bodies the joints of these tests join: far apart, in zero gravity
// unless a test says otherwise, so no contact is ever made.
constexpr const char* kBodies = R"(
    {"name": "door", "shape": {"box": {"half_extents": [0.5, 1, 0.05]}}, "mass": 10, "position": [0.5, 1, 0]},
    {"name": "bob", "shape": {"sphere": {"radius": 0.1}}, "mass": 1, "position": [1, 2, 0]},
    {"name": "upper", "shape": {"capsule": {"radius": 0.1, "half_height": 0.3}}, "mass": 2, "position": [5, 1.5, 0]},
    {"name": "lower", "shape": {"capsule": {"radius": 0.1, "half_height": 0.3}}, "mass": 2, "position": [5, 0.5, 0]},
    {"name": "cart", "shape": {"box": {"half_extents": [0.3, 0.2, 0.2]}}, "mass": 3, "position": [10, 0.5, 0]},
    {"name": "a", "shape": {"sphere": {"radius": 0.2}}, "mass": 1, "position": [15, 0, 0]},
    {"name": "b", "shape": {"sphere": {"radius": 0.2}}, "mass": 1, "position": [15, 1, 0]})";

// The joints of the README's example, one of each type, the ball joint
// and the slider with friction.
constexpr const char* kJoints = R"(
    {"name": "door-hinge", "type": "hinge", "body_a": "world", "body_b": "door",
     "anchor": [0, 1, 0], "axis": [0, 1, 0], "limits": [-1.5, 1.5],
     "motor": {"speed": 0.5, "max_torque": 20}},
    {"name": "rope", "type": "distance", "body_a": "world", "body_b": "bob",
     "anchor_a": [0, 2, 0], "anchor_b": [1, 2, 0], "min_length": 0, "max_length": 1},
    {"type": "ball", "body_a": "upper", "body_b": "lower", "anchor": [5, 1, 0], "cone_limit": 0.8,
     "friction": 0.5},
    {"type": "slider", "body_a": "world", "body_b": "cart", "anchor": [10, 0.5, 0], "axis": [1, 0, 0],
     "limits": [-2, 2], "friction": 2},
    {"type": "fixed", "body_a": "a", "body_b": "b"})";

std::string scene_with(const std::string& joints, const char* gravity = "[0, 0, 0]") {
  return std::string(R"({"gravity": )") + gravity + R"(, "bodies": [)" + kBodies + R"(], "joints": [)" + joints + "]}";
}

ClientMessage add_joint(const std::string& spec_json) {
  // The spec as a scene file writes it, read through the scene parser.
  tumble::v1::Scene scene;
  const Status status = parse_scene_json(R"({"joints": [)" + spec_json + "]}", &scene);
  EXPECT_TRUE(status.ok()) << status.message();
  ClientMessage message;
  *message.mutable_add_joint()->mutable_joint() = scene.joints(0);
  return message;
}

ClientMessage remove_joint(const std::string& name) {
  ClientMessage message;
  message.mutable_remove_joint()->mutable_joint()->set_name(name);
  return message;
}

ClientMessage list_joints() {
  ClientMessage message;
  message.mutable_list_joints();
  return message;
}

ClientMessage speed_motor(const std::string& joint, double speed, double max_torque) {
  ClientMessage message;
  auto* m = message.mutable_set_joint_motor();
  m->mutable_joint()->set_name(joint);
  m->mutable_motor()->set_speed(speed);
  m->mutable_motor()->set_max_torque(max_torque);
  return message;
}

// "CODE: message" of an Error reply, or "ack" for an Ack.
std::string outcome(const ServerMessage& reply) {
  if (reply.has_ack()) return "ack";
  return tumble::v1::ErrorCode_Name(reply.error().code()) + ": " + reply.error().message();
}

// The kinds and joints of the joint events, in order.
std::vector<std::pair<WorldEventKind, physics::JointId>> joint_events(const std::vector<WorldEvent>& events) {
  std::vector<std::pair<WorldEventKind, physics::JointId>> out;
  for (const WorldEvent& event : events) {
    if (event.joint != physics::kInvalidJointId) out.emplace_back(event.kind, event.joint);
  }
  return out;
}

TEST(SceneJoints, EachTypeLoadsWithItsFields) {
  auto sim = make_sim(scene_with(kJoints));
  const physics::World& world = sim->world();
  ASSERT_EQ(world.joint_count(), 5u);
  const physics::JointDesc& hinge = world.joint_desc(world.joint_id_at(0));
  EXPECT_EQ(hinge.type, physics::JointType::hinge);
  EXPECT_EQ(hinge.body_a, physics::kWorldBodyId);
  EXPECT_TRUE(hinge.limits_enabled);
  EXPECT_EQ(hinge.lower, -1.5);
  EXPECT_EQ(hinge.motor.mode, physics::JointMotor::Mode::speed);
  EXPECT_EQ(hinge.motor.max_force, 20);
  const physics::JointDesc& rope = world.joint_desc(world.joint_id_at(1));
  EXPECT_EQ(rope.type, physics::JointType::distance);
  EXPECT_EQ(rope.min_length, 0);
  EXPECT_EQ(rope.max_length, 1);
  EXPECT_EQ(rope.length, 1);  // the anchors' distance, within the limits
  const physics::JointDesc& ball = world.joint_desc(world.joint_id_at(2));
  EXPECT_EQ(ball.cone_limit, 0.8);
  EXPECT_EQ(ball.friction, 0.5);
  // The cone axis points from the anchor to the lower body's centre: -y.
  const physics::Vec3 cone_axis = world.orientation(ball.body_a) * (ball.local_basis_a * physics::Vec3::UnitX());
  EXPECT_TRUE(cone_axis.isApprox(physics::Vec3(0, -1, 0), 1e-12)) << cone_axis.transpose();
  EXPECT_EQ(world.joint_desc(world.joint_id_at(3)).upper, 2);
  EXPECT_EQ(world.joint_desc(world.joint_id_at(3)).friction, 2);
  EXPECT_EQ(hinge.friction, 0) << "none when absent";
  // A fixed joint's anchor defaults to body B's centre.
  const physics::JointDesc& fixed = world.joint_desc(world.joint_id_at(4));
  EXPECT_TRUE(fixed.local_anchor_b.isZero(1e-12)) << fixed.local_anchor_b.transpose();
}

TEST(SceneJoints, ScenesWithoutJointsStillLoad) {
  EXPECT_EQ(load_error(R"({"bodies": [{"shape": {"sphere": {"radius": 1}}, "mass": 1}]})"), "");
}

TEST(SceneJoints, BadJointsStopTheLoadNamingTheJointAndField) {
  const std::pair<std::string, std::string> cases[] = {
      {R"({"type": "hinge", "body_a": "world", "body_b": "nobody", "anchor": [0, 0, 0]})",
       "joints[0].body_b: no body 'nobody' in the world"},
      {R"({"type": "ball", "body_a": "door", "body_b": "door", "anchor": [0, 0, 0]})",
       "joints[0].body_b: 'door' is body_a too; a joint joins two different bodies"},
      {R"({"type": "ball", "body_a": "0", "body_b": "door", "anchor": [0, 0, 0]})",
       "joints[0].body_b: 'door' is body 0, body_a too; a joint joins two different bodies"},
      {R"({"name": "h", "type": "hinge", "body_a": "world", "body_b": "door", "anchor": [0, 0, 0],
           "axis": [0, 0, 0]})",
       "joints[0].axis: must not be zero (joint 'h')"},
      {R"({"name": "h", "type": "hinge", "body_a": "world", "body_b": "door", "anchor": [0, 0, 0],
           "limits": [1.5, -1.5]})",
       "joints[0].limits: the lower limit 1.5 is above the upper limit -1.5 (joint 'h')"},
      {R"({"type": "hinge", "body_a": "world", "body_b": "door", "anchor": [0, 0, 0], "stiffness": 1})",
       "joints[0]: unknown field 'stiffness'"},
      {R"({"type": "weld", "body_a": "world", "body_b": "door"})",
       "joints[0].type: unknown joint type 'weld'; expected ball, hinge, slider, fixed or distance"},
      {R"({"type": "ball", "body_a": "world", "body_b": "door", "anchor": [0, 0, 0],
           "motor": {"speed": 1, "max_torque": 1}})",
       "joints[0].motor: a ball joint has no motor"},
      {R"({"type": "hinge", "body_a": "world", "body_b": "door", "anchor": [0, 0, 0],
           "motor": {"speed": 1, "max_force": 1}})",
       "joints[0].motor.max_force: a hinge joint's motor takes max_torque"},
      {R"({"type": "hinge", "body_a": "world", "body_b": "door", "anchor": [0, 1e400, 0]})",
       "not valid JSON: number overflow parsing '1e400'"},
      {R"({"type": "hinge", "body_a": "world", "body_b": "door"})", "joints[0]: missing field 'anchor'"},
      {R"({"type": "distance", "body_a": "world", "body_b": "bob", "anchor": [0, 0, 0]})",
       "joints[0].anchor: a distance joint takes anchor_a and anchor_b"},
      {R"({"type": "fixed", "body_a": "a", "body_b": "b", "axis": [1, 0, 0]})",
       "joints[0].axis: a fixed joint has no axis"},
      {R"({"type": "ball", "body_a": "world", "body_b": "door", "anchor": [0, 0, 0], "cone_limit": 4})",
       "joints[0].cone_limit: not within (0, pi]"},
      {R"({"type": "fixed", "body_a": "b", "body_b": "world"})", "joints[0].body_b: only body_a may be the world"},
      {R"({"type": "fixed", "body_a": "a", "body_b": "b", "friction": 1})",
       "joints[0].friction: a fixed joint has no friction"},
      {R"({"type": "hinge", "body_a": "world", "body_b": "door", "anchor": [0, 0, 0], "friction": -1})",
       "joints[0].friction: -1 is below 0"},
  };
  for (const auto& [joint, message] : cases) EXPECT_EQ(load_error(scene_with(joint)), message) << joint;
  EXPECT_EQ(load_error(scene_with(R"({"name": "j", "type": "fixed", "body_a": "a", "body_b": "b"},
                                     {"name": "j", "type": "fixed", "body_a": "upper", "body_b": "lower"})")),
            "joints[1].name: 'j' is used by another joint");
}

TEST(JointRequests, AddListDriveAndRemoveAJoint) {
  Driver driver(make_sim(scene_with("")));
  const ServerMessage added = driver.request(add_joint(
      R"({"name": "h", "type": "hinge", "body_a": "world", "body_b": "door", "anchor": [0, 1, 0], "axis": [0, 1, 0],
          "limits": [-1, 1], "friction": 5})"));
  ASSERT_EQ(outcome(added), "ack");
  ASSERT_TRUE(added.ack().has_joint_id());
  const physics::JointId id = added.ack().joint_id();
  EXPECT_TRUE(driver.world().contains_joint(id));

  ASSERT_EQ(outcome(driver.request(speed_motor("h", 1, 50))), "ack");
  driver.run(60);
  const ServerMessage listed = driver.request(list_joints());
  ASSERT_TRUE(listed.has_joint_list());
  ASSERT_EQ(listed.joint_list().joints_size(), 1);
  const tumble::v1::JointInfo& info = listed.joint_list().joints(0);
  EXPECT_EQ(info.id(), id);
  EXPECT_EQ(info.name(), "h");
  EXPECT_EQ(info.type(), tumble::v1::JOINT_TYPE_HINGE);
  EXPECT_EQ(info.body_a_name(), "world");
  EXPECT_EQ(info.body_b_name(), "door");
  EXPECT_NEAR(info.anchor_a().y(), 1, 1e-12);
  EXPECT_NEAR(info.axis().y(), 1, 1e-12);
  EXPECT_EQ(info.limits().upper(), 1);
  EXPECT_EQ(info.motor().speed(), 1);
  EXPECT_EQ(info.motor().max_torque(), 50);
  EXPECT_EQ(info.friction(), 5);
  EXPECT_GT(info.state().position(), 0.1) << "the motor turns the door, against the friction";
  EXPECT_NEAR(info.state().speed(), 1, 0.05);

  ClientMessage off;
  off.mutable_set_joint_motor()->mutable_joint()->set_id(id);
  ASSERT_EQ(outcome(driver.request(off)), "ack");
  EXPECT_EQ(driver.world().joint_desc(id).motor.mode, physics::JointMotor::Mode::off);

  ASSERT_EQ(outcome(driver.request(remove_joint("h"))), "ack");
  EXPECT_FALSE(driver.world().contains_joint(id));
  EXPECT_EQ(outcome(driver.request(remove_joint("h"))), "UNKNOWN_JOINT: no joint 'h' in the world");
  const std::vector<std::pair<WorldEventKind, physics::JointId>> expected = {{WorldEventKind::joint_added, id},
                                                                             {WorldEventKind::joint_removed, id}};
  EXPECT_EQ(joint_events(driver.events()), expected);
}

TEST(JointRequests, BadInputIsRefusedAndChangesNothing) {
  Driver driver(make_sim(scene_with(R"({"name": "ball", "type": "ball", "body_a": "upper", "body_b": "lower",
                                        "anchor": [5, 1, 0]})")));
  const std::pair<ClientMessage, std::string> cases[] = {
      {add_joint(R"({"type": "hinge", "body_a": "world", "body_b": "ghost", "anchor": [0, 0, 0]})"),
       "UNKNOWN_BODY: joint.body_b: no body 'ghost' in the world"},
      {add_joint(R"({"type": "hinge", "body_a": "world", "body_b": "door", "anchor": [0, 0, 0],
                     "limits": [2, 1]})"),
       "INVALID_ARGUMENT: joint.limits: the lower limit 2 is above the upper limit 1"},
      {add_joint(R"({"type": "slider", "body_a": "cart", "body_b": "cart", "anchor": [0, 0, 0]})"),
       "INVALID_ARGUMENT: joint.body_b: 'cart' is body_a too; a joint joins two different bodies"},
      {add_joint(R"({"type": "fixed", "body_a": "a", "body_b": "b", "motor": {"speed": 1, "max_force": 1}})"),
       "INVALID_ARGUMENT: joint.motor: a fixed joint has no motor"},
      {add_joint(R"({"name": "ball", "type": "fixed", "body_a": "a", "body_b": "b"})"),
       "INVALID_ARGUMENT: joint.name: 'ball' is used by another joint"},
      {speed_motor("ball", 1, 1),
       "INVALID_ARGUMENT: joint 'ball' is a ball joint, which has no motor; only a hinge or a slider has one"},
      {speed_motor("nothing", 1, 1), "UNKNOWN_JOINT: no joint 'nothing' in the world"},
  };
  for (const auto& [message, expected] : cases) {
    EXPECT_EQ(outcome(driver.request(message)), expected) << message.ShortDebugString();
  }
  // A NaN, which no scene file can hold.
  ClientMessage nan = add_joint(R"({"type": "ball", "body_a": "world", "body_b": "door", "anchor": [0, 0, 0]})");
  nan.mutable_add_joint()->mutable_joint()->mutable_anchor()->set_y(std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(outcome(driver.request(nan)), "INVALID_ARGUMENT: joint.anchor.y: nan m is outside -1e9 .. 1e9 m");
  ClientMessage nan_motor = speed_motor("ball", std::numeric_limits<double>::quiet_NaN(), 1);
  EXPECT_EQ(outcome(driver.request(nan_motor)).rfind("INVALID_ARGUMENT: motor.speed must be a finite number", 0), 0u);
  EXPECT_EQ(driver.world().joint_count(), 1u);
  EXPECT_TRUE(joint_events(driver.events()).empty());
}

TEST(JointRequests, RemovingABodyRemovesItsJointsWithEventsFirst) {
  Driver driver(make_sim(scene_with(kJoints)));
  ClientMessage remove;
  remove.mutable_remove_body()->mutable_body()->set_name("door");
  ASSERT_EQ(outcome(driver.request(remove)), "ack");
  EXPECT_EQ(driver.world().joint_count(), 4u);
  ASSERT_EQ(driver.events().size(), 2u);
  EXPECT_EQ(driver.events()[0].kind, WorldEventKind::joint_removed);
  EXPECT_EQ(driver.events()[0].name, "door-hinge");
  EXPECT_EQ(driver.events()[0].body_a, physics::kWorldBodyId);
  EXPECT_EQ(driver.events()[1].kind, WorldEventKind::body_removed);
}

TEST(JointRequests, AJointPulledBeyondItsBreakForceBreaksWithEvents) {
  Driver driver(make_sim(scene_with(
      R"({"name": "weak", "type": "distance", "body_a": "world", "body_b": "bob", "anchor_a": [1, 3, 0],
          "anchor_b": [1, 2, 0], "break_force": 5})",
      "[0, -9.81, 0]")));
  driver.run(30);  // the bob weighs 9.81 N
  EXPECT_EQ(driver.world().joint_count(), 0u);
  const std::vector<std::pair<WorldEventKind, physics::JointId>> expected = {{WorldEventKind::joint_broken, 0},
                                                                             {WorldEventKind::joint_removed, 0}};
  EXPECT_EQ(joint_events(driver.events()), expected);
}

TEST(JointRequests, ResetBringsBackTheScenesJointsAndDropsTheRest) {
  Driver driver(make_sim(scene_with(kJoints)));
  ASSERT_EQ(outcome(driver.request(remove_joint("rope"))), "ack");
  const ServerMessage added = driver.request(
      add_joint(R"({"name": "extra", "type": "ball", "body_a": "world", "body_b": "cart", "anchor": [10, 1, 0]})"));
  ASSERT_EQ(outcome(added), "ack");
  EXPECT_EQ(added.ack().joint_id(), 5u);
  driver.events().clear();
  ClientMessage reset;
  reset.mutable_reset();
  ASSERT_EQ(outcome(driver.request(reset)), "ack");
  EXPECT_EQ(driver.world().joint_count(), 5u);
  EXPECT_TRUE(driver.world().contains_joint(1));
  EXPECT_FALSE(driver.world().contains_joint(5));
  EXPECT_EQ(driver.world().next_joint_id(), 6u) << "ids handed out are not handed out again";
  const std::vector<std::pair<WorldEventKind, physics::JointId>> expected = {{WorldEventKind::joint_removed, 5},
                                                                             {WorldEventKind::joint_added, 1}};
  EXPECT_EQ(joint_events(driver.events()), expected);
}

// Every body's state and every joint's impulses, bit for bit.
void expect_same_bits(const physics::World& a, const physics::World& b) {
  ASSERT_EQ(a.body_count(), b.body_count());
  for (std::size_t i = 0; i < a.body_count(); ++i) {
    const physics::BodyId id = a.body_id_at(i);
    ASSERT_EQ(b.body_id_at(i), id);
    EXPECT_EQ(a.position(id), b.position(id)) << id;
    EXPECT_EQ(a.orientation(id).coeffs(), b.orientation(id).coeffs()) << id;
    EXPECT_EQ(a.linear_momentum(id), b.linear_momentum(id)) << id;
    EXPECT_EQ(a.angular_momentum(id), b.angular_momentum(id)) << id;
    EXPECT_EQ(a.is_awake(id), b.is_awake(id)) << id;
  }
  ASSERT_EQ(a.joint_count(), b.joint_count());
  EXPECT_EQ(a.next_joint_id(), b.next_joint_id());
  for (std::size_t i = 0; i < a.joint_count(); ++i) {
    const physics::JointId id = a.joint_id_at(i);
    ASSERT_EQ(b.joint_id_at(i), id);
    const physics::JointImpulses& x = a.joint_impulses(id);
    const physics::JointImpulses& y = b.joint_impulses(id);
    EXPECT_EQ(x.linear, y.linear) << id;
    EXPECT_EQ(x.angular, y.angular) << id;
    EXPECT_EQ(x.lower, y.lower) << id;
    EXPECT_EQ(x.upper, y.upper) << id;
    EXPECT_EQ(x.motor, y.motor) << id;
    EXPECT_EQ(x.spring, y.spring) << id;
    EXPECT_EQ(x.friction, y.friction) << id;
    EXPECT_EQ(a.joint_desc(id).friction, b.joint_desc(id).friction) << id;
  }
}

TEST(JointState, ARestoredWorldContinuesBitIdentically) {
  Driver original(make_sim(scene_with(kJoints, "[0, -9.81, 0]")));
  ASSERT_EQ(outcome(original.request(add_joint(
                R"({"name": "spring", "type": "distance", "body_a": "cart", "body_b": "a", "anchor_a": [10, 0.5, 0],
                    "anchor_b": [15, 0, 0], "min_length": 4, "max_length": 6, "spring": {"hertz": 2}})"))),
            "ack");
  ASSERT_EQ(outcome(original.request(remove_joint("rope"))), "ack");
  original.run(120);
  tumble::v1::WorldState state;
  original.sim().capture(&state);
  ASSERT_EQ(state.joints_size(), 5);
  // Through the bytes, as a state file holds it.
  tumble::v1::WorldState read;
  ASSERT_TRUE(read.ParseFromString(state.SerializeAsString()));
  std::unique_ptr<Simulation> restored_sim;
  const Status status = Simulation::create_from_state(read, SimConfig{}, &restored_sim);
  ASSERT_TRUE(status.ok()) << status.message();
  Driver restored(std::move(restored_sim));
  expect_same_bits(original.world(), restored.world());
  original.run(240);
  restored.run(240);
  expect_same_bits(original.world(), restored.world());
  EXPECT_EQ(outcome(restored.request(remove_joint("spring"))), "ack") << "the names come back too";
}

TEST(JointState, BodiesSavedAsleepOnTheirJointsRestoreAsleep) {
  // A rope from the world to a ball resting on the floor, run until the
  // ball sleeps.
  Driver original(make_sim(R"({"gravity": [0, -9.81, 0], "bodies": [
      {"name": "floor", "static": true, "shape": {"plane": {"normal": [0, 1, 0], "offset": 0}}},
      {"name": "ball", "shape": {"sphere": {"radius": 0.25}}, "mass": 1, "position": [0, 0.25, 0]}],
    "joints": [{"name": "rope", "type": "distance", "body_a": "world", "body_b": "ball",
                "anchor_a": [0, 1.25, 0], "anchor_b": [0, 0.25, 0], "min_length": 0, "max_length": 2}]})"));
  const physics::BodyId ball = original.world().body_id_at(1);
  for (int i = 0; i < 20 && original.world().is_awake(ball); ++i) original.run(60);
  ASSERT_FALSE(original.world().is_awake(ball));
  tumble::v1::WorldState state;
  original.sim().capture(&state);
  std::unique_ptr<Simulation> restored_sim;
  const Status status = Simulation::create_from_state(state, SimConfig{}, &restored_sim);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_FALSE(restored_sim->world().is_awake(ball));
}

TEST(JointState, DamagedJointsAreRefused) {
  Driver original(make_sim(scene_with(kJoints)));
  tumble::v1::WorldState good;
  original.sim().capture(&good);
  const auto error = [&](void (*damage)(tumble::v1::WorldState&)) {
    tumble::v1::WorldState state = good;
    damage(state);
    std::unique_ptr<Simulation> sim;
    return Simulation::create_from_state(state, SimConfig{}, &sim).message();
  };
  EXPECT_EQ(error([](tumble::v1::WorldState& s) { s.mutable_joints(1)->set_body_b(99); }),
            "joints[1].body_b: no body 99");
  EXPECT_EQ(error([](tumble::v1::WorldState& s) { s.mutable_joints(1)->set_id(2); }),
            "joints[2].id: 2 is used by another joint");
  EXPECT_EQ(error([](tumble::v1::WorldState& s) { s.set_next_joint_id(3); }),
            "joints[3].id: 3 is not below next_joint_id");
  EXPECT_EQ(error([](tumble::v1::WorldState& s) {
              s.mutable_joints(0)->set_motor_impulse(std::numeric_limits<double>::infinity());
            }),
            "joints[0]: its impulses must be finite");
  EXPECT_EQ(error([](tumble::v1::WorldState& s) { s.mutable_joints(0)->mutable_local_basis_a()->set_w(2); }),
            "joints[0]: its frames' rotations must be unit quaternions");
  EXPECT_EQ(error([](tumble::v1::WorldState& s) { s.mutable_joints(3)->set_upper(-5); }),
            "joints[3].limits: lower above upper");
}

TEST(JointReplay, AJournalWithJointsReplaysToTheSameWorld) {
  TempDir dir;
  const std::string scene_json = scene_with(kJoints, "[0, -9.81, 0]");
  tumble::v1::Scene scene;
  ASSERT_TRUE(parse_scene_json(scene_json, &scene).ok());
  tumble::v1::JournalHeader header;
  *header.mutable_scene() = scene;
  header.set_format_version(kJournalFormat);
  header.set_tick_rate_hz(240);
  JournalWriter journal;
  ASSERT_TRUE(journal.open(dir.file("run.journal"), header).ok());
  Driver recorded(make_sim(scene_json));
  recorded.sim().set_journal(&journal);
  recorded.run(10);
  ASSERT_EQ(outcome(recorded.request(add_joint(
                R"({"name": "tie", "type": "distance", "body_a": "door", "body_b": "cart", "anchor_a": [0.5, 1, 0],
                    "anchor_b": [10, 0.5, 0]})"))),
            "ack");
  recorded.run(30);
  ASSERT_EQ(outcome(recorded.request(speed_motor("door-hinge", -2, 100))), "ack");
  ASSERT_EQ(outcome(recorded.request(remove_joint("rope"))), "ack");
  recorded.run(50);
  recorded.sim().stop();

  JournalReader reader;
  const Status opened = reader.open(dir.file("run.journal"));
  ASSERT_TRUE(opened.ok()) << opened.message();
  Driver replayed(make_sim(scene_json));
  ReplaySummary summary;
  const Status status = replay_journal(reader, replayed.sim(), &summary);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_EQ(summary.commands, 3u);
  expect_same_bits(recorded.world(), replayed.world());
}

// Snapshots carry every joint's state, by id, while a stream asks for
// joints, and none once no stream does.
TEST(JointSnapshots, CarryEveryJointsStateWhileAStreamWantsThem) {
  Driver driver(make_sim(scene_with(kJoints, "[0, -9.81, 0]")));
  std::vector<std::shared_ptr<const Snapshot>> snapshots;
  driver.sim().add_snapshot_listener([&](std::shared_ptr<const Snapshot> s) { snapshots.push_back(std::move(s)); });
  driver.sim().set_publish_interest({PublishInterest{1, true, {}, true}}, 64);
  driver.run(3);
  ASSERT_FALSE(snapshots.empty());
  const Snapshot& with = *snapshots.back();
  ASSERT_TRUE(with.has_joints);
  const physics::World& world = driver.world();
  ASSERT_EQ(with.joint_ids, (std::vector<physics::JointId>{0, 1, 2, 3, 4}));
  ASSERT_EQ(with.joint_positions.size(), 5u);
  for (std::size_t i = 0; i < with.joint_ids.size(); ++i) {
    const physics::JointState state = world.joint_state(with.joint_ids[i]);
    EXPECT_EQ(with.joint_positions[i], state.position) << i;
    EXPECT_EQ(with.joint_speeds[i], state.speed) << i;
    EXPECT_EQ(with.joint_motor_impulses[i], state.motor_impulse) << i;
  }
  EXPECT_NE(with.joint_motor_impulses[0], 0) << "the door's motor drives it";
  EXPECT_TRUE(with.covers(true, {}, true));

  driver.sim().set_publish_interest({PublishInterest{1, true, {}, false}}, 64);
  driver.run(1);
  const Snapshot& without = *snapshots.back();
  EXPECT_FALSE(without.has_joints);
  EXPECT_TRUE(without.joint_ids.empty());
  EXPECT_FALSE(without.covers(true, {}, true)) << "a stream of joints waits for a snapshot with them";
  EXPECT_TRUE(without.covers(true, {}, false));
}

}  // namespace
}  // namespace tumble::sim
