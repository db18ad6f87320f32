// The joint subcommands of tumble: joints, joint add, joint remove and
// motor as parsed, the requests they make, and what they print.
#include <gtest/gtest.h>

#include "command_line_helpers.h"
#include "output.h"
#include "requests.h"

namespace tumble::cli {
namespace {

using testing::expect_usage_error;
using testing::parse_command;

TEST(JointCommands, JointAddTakesTheTypeBodiesAndOnlyTheFieldsGiven) {
  const auto command = parse_command<JointAddCommand>({"joint",    "add",
                                                       "door",     "--hinge",
                                                       "world",    "7",
                                                       "--anchor", "0",
                                                       "1",        "0",
                                                       "--axis",   "0",
                                                       "1",        "0",
                                                       "--limits", "-1.5",
                                                       "1.5",      "--break-torque",
                                                       "30",       "--friction",
                                                       "0.4",      "--collide-connected"});
  const tumble::v1::JointSpec spec = make_joint_spec(command);
  EXPECT_EQ(spec.name(), "door");
  EXPECT_EQ(spec.type(), tumble::v1::JOINT_TYPE_HINGE);
  EXPECT_EQ(spec.body_a(), "world");
  EXPECT_EQ(spec.body_b(), "7");
  EXPECT_EQ(spec.anchor().y(), 1);
  EXPECT_EQ(spec.axis().y(), 1);
  EXPECT_EQ(spec.limits().lower(), -1.5);
  EXPECT_EQ(spec.limits().upper(), 1.5);
  EXPECT_EQ(spec.break_torque(), 30);
  EXPECT_EQ(spec.friction(), 0.4);
  EXPECT_TRUE(spec.collide_connected());
  EXPECT_FALSE(spec.has_break_force());
  EXPECT_FALSE(spec.has_cone_limit());
  EXPECT_FALSE(spec.has_anchor_b());

  const tumble::v1::JointSpec rope = make_joint_spec(
      parse_command<JointAddCommand>({"joint", "add", "", "--distance", "world", "bob", "--anchor", "0", "2", "0",
                                      "--anchor-b", "1", "2", "0", "--min-length", "0", "--max-length", "1"}));
  EXPECT_EQ(rope.type(), tumble::v1::JOINT_TYPE_DISTANCE);
  EXPECT_EQ(rope.anchor_b().x(), 1);
  EXPECT_TRUE(rope.has_min_length());
  EXPECT_EQ(rope.max_length(), 1);
  EXPECT_FALSE(rope.has_length());
  EXPECT_FALSE(rope.has_friction());
}

TEST(JointCommands, JointAddNeedsExactlyOneTypeAndTwoBodies) {
  expect_usage_error({"joint", "add", "j", "world", "crate"});
  expect_usage_error({"joint", "add", "j", "--ball", "--fixed", "world", "crate"});
  expect_usage_error({"joint", "add", "j", "--ball", "world"});
  expect_usage_error({"joint", "add", "42", "--ball", "world", "crate"});
  expect_usage_error({"joint"});
}

TEST(JointCommands, MotorTakesADriveWithItsLimitOrOff) {
  const auto speed = parse_command<MotorCommand>({"motor", "hinge", "--speed", "0.5", "--max-torque", "20"});
  EXPECT_EQ(speed.joint.name(), "hinge");
  const tumble::v1::SetJointMotor request = make_set_joint_motor(speed);
  EXPECT_EQ(request.motor().speed(), 0.5);
  EXPECT_EQ(request.motor().max_torque(), 20);
  EXPECT_FALSE(request.motor().has_max_force());

  const auto position = parse_command<MotorCommand>(
      {"motor", "3", "--position", "0.2", "--hertz", "4", "--damping-ratio", "0.7", "--max-force", "50"});
  EXPECT_EQ(position.joint.id(), 3u);
  EXPECT_EQ(position.motor->position(), 0.2);
  EXPECT_EQ(position.motor->hertz(), 4);
  EXPECT_EQ(position.motor->damping_ratio(), 0.7);
  EXPECT_EQ(position.motor->max_force(), 50);

  const auto off = parse_command<MotorCommand>({"motor", "hinge", "--off"});
  EXPECT_FALSE(off.motor.has_value());
  EXPECT_FALSE(make_set_joint_motor(off).has_motor());

  expect_usage_error({"motor", "hinge"});
  expect_usage_error({"motor", "hinge", "--speed", "1"});
  expect_usage_error({"motor", "hinge", "--speed", "1", "--position", "1", "--max-torque", "1"});
  expect_usage_error({"motor", "hinge", "--off", "--speed", "1"});
  expect_usage_error({"motor", "hinge", "--speed", "1", "--hertz", "2", "--max-torque", "1"});
}

TEST(JointCommands, JointsAndRemoveParse) {
  parse_command<JointsCommand>({"joints"});
  EXPECT_EQ(parse_command<JointRemoveCommand>({"joint", "remove", "rope"}).joint.name(), "rope");
  EXPECT_EQ(parse_command<JointRemoveCommand>({"joint", "remove", "12"}).joint.id(), 12u);
}

tumble::v1::JointList a_joint_list() {
  tumble::v1::JointList list;
  list.set_tick(99);
  auto* joint = list.add_joints();
  joint->set_id(0);
  joint->set_name("door");
  joint->set_type(tumble::v1::JOINT_TYPE_HINGE);
  joint->set_body_a(0xfffffffe);
  joint->set_body_a_name("world");
  joint->set_body_b(3);
  joint->mutable_limits()->set_lower(-1);
  joint->mutable_limits()->set_upper(1);
  joint->mutable_motor()->set_speed(0.5);
  joint->mutable_motor()->set_max_torque(20);
  joint->set_friction(1.5);
  joint->mutable_state()->set_position(0.25);
  joint->mutable_state()->set_speed(0.5);
  return list;
}

TEST(JointOutput, TheTableShowsTypeBodiesStateAndMotor) {
  EXPECT_EQ(format_joint_table(a_joint_list()),
            "ID  NAME  TYPE   BODY A  BODY B  POSITION  SPEED  MOTOR\n"
            " 0  door  hinge  world   #3         0.250  0.500  speed 0.500 max 20.000\n");
}

TEST(JointOutput, JsonCarriesEveryField) {
  const Json json = joint_list_json(a_joint_list());
  EXPECT_EQ(json["tick"], 99);
  const Json& joint = json["joints"][0];
  EXPECT_EQ(joint["type"], "hinge");
  EXPECT_EQ(joint["body_a"], nullptr);
  EXPECT_EQ(joint["body_b"], 3);
  EXPECT_EQ(joint["limits"], Json::array({-1.0, 1.0}));
  EXPECT_EQ(joint["cone_limit"], nullptr);
  EXPECT_EQ(joint["motor"]["speed"], 0.5);
  EXPECT_EQ(joint["motor"]["max_torque"], 20.0);
  EXPECT_EQ(joint["break_force"], nullptr);
  EXPECT_EQ(joint["friction"], 1.5);
  EXPECT_EQ(joint["state"]["position"], 0.25);
}

TEST(JointOutput, JointEventsNameTheJointAndItsBodies) {
  tumble::v1::WorldEvent event;
  event.set_tick(7);
  event.set_kind(tumble::v1::WORLD_EVENT_JOINT_BROKEN);
  event.set_joint_id(2);
  event.set_joint_name("rope");
  event.set_joint_body_a(0xfffffffe);
  event.set_body_id(5);
  EXPECT_EQ(format_world_event(event), "tick 7  joint-broken  rope (#2)  world - #5\n");
  EXPECT_EQ(json_line(world_event_json(event)),
            "{\"event\": \"joint-broken\", \"tick\": 7, \"joint_id\": 2, \"joint_name\": \"rope\", \"body_a\": null, "
            "\"body_b\": 5}\n");
  tumble::v1::Ack ack;
  ack.set_joint_id(4);
  ack.set_applied_tick(10);
  EXPECT_EQ(format_joint_added(ack), "added joint 4 at tick 10\n");
  EXPECT_EQ(ack_json(ack)["joint_id"], 4);
}

}  // namespace
}  // namespace tumble::cli
