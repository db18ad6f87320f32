// The limits on text from clients and files, and where each path applies them.
#include <gtest/gtest.h>

#include <string>

#include "sim/body_spec.h"
#include "sim/request_check.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"
#include "sim/string_limits.h"

namespace tumble::sim {
namespace {

using tumble::v1::ClientMessage;

TEST(StringLimits, BodyNamesUpToTheLimitAreAccepted) {
  EXPECT_TRUE(check_body_name("", "body.name").ok());
  EXPECT_TRUE(check_body_name("crate", "body.name").ok());
  EXPECT_TRUE(check_body_name("7up", "body.name").ok());
  EXPECT_TRUE(check_body_name(std::string(kMaxBodyNameBytes, 'n'), "body.name").ok());
}

TEST(StringLimits, ErrorsNameTheFieldAndTheLimit) {
  EXPECT_EQ(check_body_name(std::string(129, 'n'), "bodies[2].name").message(),
            "bodies[2].name: 129 bytes, over the limit of 128 bytes");
  EXPECT_EQ(check_body_name(std::string(1000000, 'n'), "body.name").message(),
            "body.name: 1000000 bytes, over the limit of 128 bytes");
  EXPECT_EQ(check_text_length(std::string(257, 't'), "Hello.token", kMaxTokenBytes).message(),
            "Hello.token: 257 bytes, over the limit of 256 bytes");
}

TEST(StringLimits, NamesOfDigitsOnlyAreRefusedBecauseTheyReadAsIds) {
  EXPECT_EQ(check_body_name("123", "body.name").message(),
            "body.name: '123' is digits only, which clients read as a body id; a name needs another character");
  EXPECT_FALSE(check_body_name("0", "body.name").ok());
}

ClientMessage spawn(const std::string& name) {
  ClientMessage message;
  auto* body = message.mutable_spawn_body()->mutable_body();
  body->set_name(name);
  body->mutable_shape()->mutable_sphere()->set_radius(0.5);
  body->set_mass(1);
  return message;
}

// Why check_request refuses `message`, or "accepted".
std::string refusal(const ClientMessage& message) {
  const auto error = check_request(message);
  return error ? error->message : "accepted";
}

TEST(StringLimits, EveryRequestPathChecksNames) {
  EXPECT_EQ(refusal(spawn("rock")), "accepted");
  EXPECT_EQ(refusal(spawn(std::string(200, 'r'))), "body.name: 200 bytes, over the limit of 128 bytes");
  EXPECT_EQ(refusal(spawn("42")),
            "body.name: '42' is digits only, which clients read as a body id; a name needs another character");

  ClientMessage remove;
  remove.mutable_remove_body()->mutable_body()->set_name(std::string(1000, 'r'));
  EXPECT_EQ(refusal(remove), "body.name: 1000 bytes, over the limit of 128 bytes");
  ClientMessage subscribe;
  subscribe.mutable_subscribe()->add_bodies()->set_name(std::string(129, 's'));
  EXPECT_EQ(refusal(subscribe), "body.name: 129 bytes, over the limit of 128 bytes");
}

TEST(StringLimits, HelloStringsAreBounded) {
  tumble::v1::Hello hello;
  hello.set_client_name(std::string(128, 'c'));
  hello.set_token(std::string(256, 't'));
  EXPECT_FALSE(check_hello(hello));
  hello.set_client_name(std::string(129, 'c'));
  auto error = check_hello(hello);
  ASSERT_TRUE(error);
  EXPECT_EQ(error->code, tumble::v1::INVALID_ARGUMENT);
  EXPECT_EQ(error->message, "Hello.client_name: 129 bytes, over the limit of 128 bytes");
  hello.set_token(std::string(257, 't'));
  error = check_hello(hello);
  ASSERT_TRUE(error);
  EXPECT_EQ(error->code, tumble::v1::UNAUTHENTICATED);
  EXPECT_EQ(error->message, "Hello.token: 257 bytes, over the limit of 256 bytes");
}

TEST(StringLimits, SceneFilesAndSpawnsThatSkipTheRequestCheckAreRefusedToo) {
  // A scene: refused with the body's path.
  tumble::v1::Scene scene;
  ASSERT_TRUE(parse_scene_json(R"({"bodies": [{"name": "ok", "shape": {"sphere": {"radius": 1}}, "mass": 1},
      {"name": "2024", "shape": {"sphere": {"radius": 1}}, "mass": 1}]})",
                               &scene)
                  .ok());
  std::unique_ptr<Simulation> sim;
  const Status status = Simulation::create(scene, SimConfig{}, &sim);
  EXPECT_EQ(status.message(),
            "bodies[1].name: '2024' is digits only, which clients read as a body id; a name needs another character");

  // A spawn handed to the sim directly (as a journal's replay does).
  ASSERT_TRUE(Simulation::create(tumble::v1::Scene{}, SimConfig{}, &sim).ok());
  tumble::v1::ServerMessage reply;
  sim->submit(Command{spawn(std::string(300, 'x')), [&](tumble::v1::ServerMessage m) { reply = std::move(m); }});
  sim->run_tick();
  EXPECT_EQ(reply.error().message(), "body.name: 300 bytes, over the limit of 128 bytes");
  EXPECT_EQ(sim->body_count(), 0u);
}

TEST(StringLimits, AnUnknownFieldOfAHugeNameIsQuotedEscapedAndBounded) {
  tumble::v1::Scene scene;
  // ESC (written \u001b in the JSON), then 504 more bytes: 96 escaped bytes are kept.
  const std::string key = R"(\u001b[31m)" + std::string(500, 'k');
  const Status status = parse_scene_json(R"({"bodies": [{")" + key + R"(": 1}]})", &scene);
  EXPECT_EQ(status.message(), "bodies[0]: unknown field '\\x1b[31m" + std::string(88, 'k') + "...(412 more bytes)'");
}

}  // namespace
}  // namespace tumble::sim
