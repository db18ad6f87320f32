#include "output.h"

#include <cmath>
#include <sstream>

#include <gtest/gtest.h>

namespace tumble::cli {
namespace {

client::PoseSample two_body_sample() {
  client::PoseSample sample;
  sample.subscription_id = 3;
  sample.tick = 1234;
  sample.sim_time = 5.1416;
  client::BodyPose crate;
  crate.id = 4;
  crate.position = {1.f, 2.5f, -3.f};
  crate.orientation = {0.5f, 0.1f, 0.2f, 0.3f};
  crate.linear_velocity = {0.25f, 0.f, -0.5f};
  crate.angular_velocity = {0.f, 1.5f, 0.f};
  client::BodyPose other;
  other.id = 9;
  other.position = {-1.f, -2.f, -0.00001f};
  other.orientation = {1.f, 0.f, 0.f, 0.f};
  other.linear_velocity = {7.f, 8.f, 9.f};
  other.angular_velocity = {-0.125f, 0.f, 0.f};
  sample.bodies = {crate, other};
  return sample;
}

tumble::v1::BodyList four_body_list() {
  tumble::v1::BodyList list;
  list.set_request_id(2);
  list.set_tick(77);
  auto* crate = list.add_bodies();
  crate->set_id(4);
  crate->set_name("crate");
  crate->mutable_shape()->mutable_box()->mutable_half_extents()->set_x(0.5);
  crate->set_mass(12.5);
  crate->mutable_position()->set_y(1.25);
  crate->mutable_orientation()->set_w(0.5);
  crate->mutable_orientation()->set_x(0.25);
  crate->mutable_orientation()->set_y(-0.25);
  crate->mutable_orientation()->set_z(0.75);
  crate->mutable_linear_velocity()->set_x(3);
  crate->mutable_linear_velocity()->set_y(4);
  crate->mutable_angular_velocity()->set_z(-2);
  auto* ball = list.add_bodies();
  ball->set_id(10);
  ball->set_name("ball");
  ball->mutable_shape()->mutable_sphere()->set_radius(0.1);
  ball->set_mass(1);
  ball->mutable_orientation()->set_w(1);
  ball->set_asleep(true);
  auto* turntable = list.add_bodies();
  turntable->set_id(11);
  turntable->set_name("turntable");
  turntable->mutable_shape()->mutable_box()->mutable_half_extents()->set_x(1);
  turntable->set_motion(tumble::v1::MOTION_KINEMATIC);
  turntable->mutable_orientation()->set_w(1);
  turntable->mutable_angular_velocity()->set_y(0.5);
  auto* ground = list.add_bodies();
  ground->set_id(12);
  ground->mutable_shape()->mutable_plane()->mutable_normal()->set_y(1);
  ground->set_motion(tumble::v1::MOTION_STATIC);
  ground->mutable_orientation()->set_w(1);
  return list;
}

TEST(PoseSampleJson, ExactValuesNamesAndQuaternionOrder) {
  const BodyNames names = {{4, "crate"}, {5, "unused"}};
  const std::string line = json_line(pose_sample_json(two_body_sample(), names));
  ASSERT_FALSE(line.empty());
  EXPECT_EQ(line.back(), '\n');
  EXPECT_EQ(line.find('\n'), line.size() - 1);
  EXPECT_EQ(line.rfind("{\"tick\": 1234, \"time\": 5.1416, \"bodies\": [{\"id\": 4, \"name\": \"crate\", ", 0), 0u)
      << line;

  const nlohmann::json json = nlohmann::json::parse(line);
  EXPECT_EQ(json.size(), 3u);
  EXPECT_EQ(json["tick"], 1234);
  EXPECT_EQ(json["time"], 5.1416);
  ASSERT_EQ(json["bodies"].size(), 2u);

  const nlohmann::json& crate = json["bodies"][0];
  EXPECT_EQ(crate.size(), 6u);
  EXPECT_EQ(crate["id"], 4);
  EXPECT_EQ(crate["name"], "crate");
  EXPECT_EQ(crate["position"], nlohmann::json::array({1.0, 2.5, -3.0}));
  // [w, x, y, z], floats written as their shortest decimals.
  EXPECT_EQ(crate["orientation"], nlohmann::json::array({0.5, 0.1, 0.2, 0.3}));
  EXPECT_EQ(crate["linear_velocity"], nlohmann::json::array({0.25, 0.0, -0.5}));
  EXPECT_EQ(crate["angular_velocity"], nlohmann::json::array({0.0, 1.5, 0.0}));

  const nlohmann::json& other = json["bodies"][1];
  EXPECT_EQ(other["id"], 9);
  EXPECT_EQ(other["name"], "");  // not in the list of names
  EXPECT_EQ(other["orientation"], nlohmann::json::array({1.0, 0.0, 0.0, 0.0}));
  EXPECT_EQ(other["position"][2], -1e-05);
  EXPECT_EQ(other["angular_velocity"][0], -0.125);
}

TEST(PoseSampleJson, NonFiniteValuesBecomeNull) {
  client::PoseSample sample = two_body_sample();
  sample.bodies[0].position[1] = std::nanf("");
  const nlohmann::json json = nlohmann::json::parse(json_line(pose_sample_json(sample, {})));
  EXPECT_TRUE(json["bodies"][0]["position"][1].is_null());
  EXPECT_EQ(json["bodies"][0]["position"][0], 1.0);
}

TEST(PoseSampleText, JointsFollowTheBodiesOneLineEach) {
  client::PoseSample sample = two_body_sample();
  sample.joints = {{3, 0.25f, -0.5f, 0.0f}, {7, 1.5f, 0.0f, 0.125f}};
  const std::string text = format_pose_sample(sample, {});
  EXPECT_NE(text.find("\n  joint #3  position 0.250  speed -0.500  motor impulse 0.000\n"
                      "  joint #7  position 1.500  speed 0.000  motor impulse 0.125\n"),
            std::string::npos)
      << text;
  const nlohmann::json json = nlohmann::json::parse(json_line(pose_sample_json(sample, {})));
  ASSERT_EQ(json["joints"].size(), 2u);
  EXPECT_EQ(json["joints"][1]["id"], 7);
  EXPECT_EQ(json["joints"][0]["speed"], -0.5);
  EXPECT_EQ(json["joints"][1]["motor_impulse"], 0.125);
  EXPECT_FALSE(nlohmann::json::parse(json_line(pose_sample_json(two_body_sample(), {}))).contains("joints"));
}

TEST(PoseSampleText, HeaderAndOneLinePerBody) {
  const std::string text = format_pose_sample(two_body_sample(), {{4, "crate"}});
  std::istringstream lines(text);
  std::string header, first, second, extra;
  std::getline(lines, header);
  std::getline(lines, first);
  std::getline(lines, second);
  EXPECT_FALSE(std::getline(lines, extra));
  EXPECT_EQ(header, "tick 1234  t=5.142s");
  EXPECT_EQ(first,
            "  crate  pos (1.000, 2.500, -3.000)  quat [0.5000, 0.1000, 0.2000, 0.3000]  v (0.250, 0.000, -0.500)"
            "  w (0.000, 1.500, 0.000)");
  // Unnamed bodies show their id; names are padded to one width; a value
  // that rounds to zero has no minus sign.
  EXPECT_EQ(second,
            "  #9     pos (-1.000, -2.000, 0.000)  quat [1.0000, 0.0000, 0.0000, 0.0000]  v (7.000, 8.000, 9.000)"
            "  w (-0.125, 0.000, 0.000)");
}

TEST(BodyListJson, EveryField) {
  const nlohmann::json json = nlohmann::json::parse(json_line(body_list_json(four_body_list())));
  EXPECT_EQ(json["tick"], 77);
  ASSERT_EQ(json["bodies"].size(), 4u);
  const nlohmann::json& crate = json["bodies"][0];
  EXPECT_EQ(crate["id"], 4);
  EXPECT_EQ(crate["name"], "crate");
  EXPECT_EQ(crate["shape"], "box");
  EXPECT_EQ(crate["motion"], "dynamic");
  EXPECT_EQ(crate["mass"], 12.5);
  EXPECT_EQ(crate["position"], nlohmann::json::array({0.0, 1.25, 0.0}));
  EXPECT_EQ(crate["orientation"], nlohmann::json::array({0.5, 0.25, -0.25, 0.75}));
  EXPECT_EQ(crate["linear_velocity"], nlohmann::json::array({3.0, 4.0, 0.0}));
  EXPECT_EQ(crate["angular_velocity"], nlohmann::json::array({0.0, 0.0, -2.0}));
  EXPECT_EQ(crate["asleep"], false);
  EXPECT_EQ(json["bodies"][1]["shape"], "sphere");
  EXPECT_EQ(json["bodies"][1]["asleep"], true);
  EXPECT_EQ(json["bodies"][2]["motion"], "kinematic");
  EXPECT_EQ(json["bodies"][3]["motion"], "static");
  EXPECT_EQ(json["bodies"][3]["shape"], "plane");

  tumble::v1::BodyList shapeless;
  shapeless.add_bodies()->set_id(1);
  EXPECT_TRUE(nlohmann::json::parse(json_line(body_list_json(shapeless)))["bodies"][0]["shape"].is_null());
}

TEST(BodyTable, AlignedColumnsWithTheNumbers) {
  const std::string table = format_body_table(four_body_list());
  std::istringstream lines(table);
  std::string header, crate, ball, turntable, ground, extra;
  std::getline(lines, header);
  std::getline(lines, crate);
  std::getline(lines, ball);
  std::getline(lines, turntable);
  std::getline(lines, ground);
  EXPECT_FALSE(std::getline(lines, extra));

  EXPECT_EQ(header, "ID  NAME       SHAPE   MOTION     MASS (kg)  POSITION (m)           SPEED (m/s)  ASLEEP");
  EXPECT_EQ(crate, " 4  crate      box     dynamic       12.500  (0.000, 1.250, 0.000)        5.000  no");
  EXPECT_EQ(ball, "10  ball       sphere  dynamic        1.000  (0.000, 0.000, 0.000)        0.000  yes");
  EXPECT_EQ(turntable, "11  turntable  box     kinematic      0.000  (0.000, 0.000, 0.000)        0.000  no");
  EXPECT_EQ(ground, "12  #12        plane   static         0.000  (0.000, 0.000, 0.000)        0.000  no");
}

TEST(BodyTable, EmptyWorldIsJustTheHeader) {
  tumble::v1::BodyList empty;
  EXPECT_EQ(format_body_table(empty), "ID  NAME  SHAPE  MOTION  MASS (kg)  POSITION (m)  SPEED (m/s)  ASLEEP\n");
}

TEST(Ack, TextAndJson) {
  tumble::v1::Ack ack;
  ack.set_request_id(2);
  ack.set_applied_tick(1234);
  EXPECT_EQ(format_ack(ack), "applied at tick 1234\n");
  EXPECT_EQ(json_line(ack_json(ack)), "{\"applied_tick\": 1234, \"request_id\": 2}\n");
}

TEST(BodyNames, FromBodyList) {
  const BodyNames names = body_names(four_body_list());
  ASSERT_EQ(names.size(), 4u);
  EXPECT_EQ(names.at(4), "crate");
  EXPECT_EQ(names.at(10), "ball");
  EXPECT_EQ(names.at(11), "turntable");
  EXPECT_EQ(names.at(12), "");
}

TEST(JsonLine, SpacedLikeTheDocumentationAndEscaped) {
  Json value = Json::object();
  value["a"] = Json::array({1, 2.5, nullptr});
  value["b:c"] = "x, \"y\"";
  value["d"] = Json::object();
  value["e"] = Json::array();
  EXPECT_EQ(json_line(value), "{\"a\": [1, 2.5, null], \"b:c\": \"x, \\\"y\\\"\", \"d\": {}, \"e\": []}\n");
}

TEST(JsonLine, InvalidUtf8IsReplacedNotThrown) {
  Json value = Json::object();
  value["name"] = std::string("bad\xff");
  std::string line;
  EXPECT_NO_THROW(line = json_line(value));
  EXPECT_TRUE(nlohmann::json::accept(line)) << line;
}

}  // namespace
}  // namespace tumble::cli
