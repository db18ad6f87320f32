// tumbled serving a world over NATS, end to end: a real tumbled process
// and a real nats-server on loopback ports; every assertion is on what
// arrives over NATS (and TCP), on ticks and sequences, never on wall time.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <fstream>
#include <map>
#include <optional>

#include "cli_helpers.h"
#include "nats_messages.h"
#include "nats_server_process.h"
#include "nats_test_client.h"
#include "poll_until.h"
#include "process.h"
#include "tumble/v1/protocol.pb.h"
#include "tumble/v1/world_info.pb.h"
#include "tumbled_process.h"
#include "wire/quantized_poses.h"

namespace tumble::test {
namespace {

using tumble::v1::ClientMessage;
using tumble::v1::ServerMessage;

class NatsWorld : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_TRUE(nats_.start()) << nats_.log(); }

  std::unique_ptr<TumbledProcess> start_tumbled(std::vector<std::string> args = {}) {
    std::vector<std::string> all = {"--nats", nats_.url(), "--world", "lab"};
    all.insert(all.end(), args.begin(), args.end());
    auto tumbled = std::make_unique<TumbledProcess>(kFloatingScene, all);
    EXPECT_TRUE(tumbled->started()) << tumbled->log();
    return tumbled;
  }

  // The one world that answers tumble.v1.worlds.
  static tumble::v1::WorldInfo only_world(NatsTestClient& client) {
    const std::vector<std::string> replies = client.request_many("tumble.v1.worlds", "");
    EXPECT_EQ(replies.size(), 1u);
    tumble::v1::WorldInfo info;
    EXPECT_TRUE(!replies.empty() && info.ParseFromString(replies[0]));
    return info;
  }

  // The Stats reply over .rpc once the link is up.
  bool wait_connected(NatsTestClient& client) {
    return poll_until([&] {
      auto reply = client.request("tumble.v1.lab.rpc", stats_request(1), std::chrono::milliseconds(500));
      return reply && parse_server_message(*reply).stats().nats().connected();
    });
  }

  NatsServerProcess nats_;
};

TEST_F(NatsWorld, TheWorldsRequestIsAnsweredWithItsStreamsAndSubjects) {
  auto tumbled = start_tumbled({"--nats-stream", "f30=full@30:all", "--nats-stream", "d60=delta@60"});
  NatsTestClient client(nats_.url());
  ASSERT_TRUE(wait_connected(client));
  const tumble::v1::WorldInfo info = only_world(client);
  EXPECT_EQ(info.world(), "lab");
  EXPECT_EQ(info.bodies(), 2u);
  EXPECT_GT(info.tick_rate_hz(), 0);
  EXPECT_EQ(info.rpc_subject(), "tumble.v1.lab.rpc");
  EXPECT_EQ(info.events_subject(), "tumble.v1.lab.events");
  EXPECT_FALSE(info.server_id().empty());
  ASSERT_EQ(info.streams_size(), 2);
  EXPECT_EQ(info.streams(0).name(), "f30");
  EXPECT_EQ(info.streams(0).subject(), "tumble.v1.lab.poses.f30");
  EXPECT_EQ(info.streams(0).encoding(), tumble::v1::POSE_ENCODING_FULL);
  EXPECT_EQ(info.streams(0).fields(), tumble::v1::POSE_FIELDS_POSE_AND_VELOCITY);
  EXPECT_EQ(info.streams(1).encoding(), tumble::v1::POSE_ENCODING_DELTA);
  EXPECT_DOUBLE_EQ(info.streams(1).key_interval_s(), 1.0);
  EXPECT_DOUBLE_EQ(info.streams(1).rest_key_interval_s(), 30.0);
}

TEST_F(NatsWorld, AForceOverRpcIsAckedAndMovesTheBodyInTheNextFullFrame) {
  auto tumbled = start_tumbled({"--nats-stream", "f=full@60:all"});
  NatsTestClient client(nats_.url());
  ASSERT_TRUE(wait_connected(client));
  auto frames = client.subscribe("tumble.v1.lab.poses.f");
  ASSERT_TRUE(frames);
  auto reply = client.request("tumble.v1.lab.rpc", force_request("crate", 240, 7));
  ASSERT_TRUE(reply) << client.error();
  const ServerMessage ack = parse_server_message(*reply);
  ASSERT_TRUE(ack.has_ack()) << ack.DebugString();
  EXPECT_EQ(ack.ack().request_id(), 7u);
  const std::uint64_t applied = ack.ack().applied_tick();
  EXPECT_GT(applied, 0u);
  // A frame of a tick after the force shows the crate moving along +x.
  ASSERT_TRUE(frames->wait([&](const std::vector<NatsMessage>& messages) {
    for (const NatsMessage& m : messages) {
      const ServerMessage frame = parse_server_message(m.data);
      if (frame.pose_frame().tick() > applied) return true;
    }
    return false;
  }));
  for (const NatsMessage& m : frames->messages()) {
    const tumble::v1::PoseFrame frame = parse_server_message(m.data).pose_frame();
    if (frame.tick() <= applied) continue;
    ASSERT_GE(frame.linear_velocities_size(), 3);
    // The crate is body 1 of the floating scene: first in the frame.
    EXPECT_GT(frame.linear_velocities(0), 0.0f) << "tick " << frame.tick();
    break;
  }
}

TEST_F(NatsWorld, APayloadThatIsNotAClientMessageGetsAnErrorAndChangesNothing) {
  auto tumbled = start_tumbled({"--nats-stream", "f=full@60:all"});
  NatsTestClient client(nats_.url());
  ASSERT_TRUE(wait_connected(client));
  auto reply = client.request("tumble.v1.lab.rpc", std::string("\xff\xff\xff\x0f garbage", 12));
  ASSERT_TRUE(reply) << client.error();
  const ServerMessage error = parse_server_message(*reply);
  ASSERT_TRUE(error.has_error());
  EXPECT_EQ(error.error().code(), tumble::v1::INVALID_ARGUMENT);
  EXPECT_NE(error.error().message().find("not a ClientMessage"), std::string::npos);
  // The world is as it was: both bodies still at rest in the floating scene.
  auto frames = client.subscribe("tumble.v1.lab.poses.f");
  ASSERT_TRUE(frames && frames->wait_count(1));
  const tumble::v1::PoseFrame frame = parse_server_message(frames->messages()[0].data).pose_frame();
  ASSERT_EQ(frame.ids_size(), 2);
  for (int i = 0; i < frame.linear_velocities_size(); ++i) EXPECT_EQ(frame.linear_velocities(i), 0.0f);
}

TEST_F(NatsWorld, SubscribeOverRpcIsRefusedNamingThePoseSubject) {
  auto tumbled = start_tumbled();
  NatsTestClient client(nats_.url());
  ASSERT_TRUE(wait_connected(client));
  ClientMessage subscribe;
  subscribe.set_request_id(3);
  subscribe.mutable_subscribe()->set_rate_hz(10);
  auto reply = client.request("tumble.v1.lab.rpc", subscribe.SerializeAsString());
  ASSERT_TRUE(reply);
  const ServerMessage error = parse_server_message(*reply);
  ASSERT_TRUE(error.has_error());
  EXPECT_EQ(error.error().request_id(), 3u);
  EXPECT_EQ(error.error().code(), tumble::v1::INVALID_ARGUMENT);
  EXPECT_NE(error.error().message().find("tumble.v1.lab.poses.q60"), std::string::npos) << error.error().message();
}

TEST_F(NatsWorld, StatsOverRpcAndTcpReportTheLink) {
  auto tumbled = start_tumbled();
  NatsTestClient client(nats_.url());
  ASSERT_TRUE(wait_connected(client));
  const ServerMessage stats = parse_server_message(*client.request("tumble.v1.lab.rpc", stats_request(5)));
  EXPECT_EQ(stats.stats().request_id(), 5u);
  EXPECT_TRUE(stats.stats().nats().connected());
  EXPECT_EQ(stats.stats().nats().world(), "lab");
  EXPECT_EQ(stats.stats().nats().server_url(), nats_.url());
  EXPECT_GT(stats.stats().nats().messages_out(), 0u);
  EXPECT_GT(stats.stats().nats().requests_in(), 0u);
  const CommandResult tcp = tumbled->cli({"--json", "stats"});
  EXPECT_EQ(tcp.exit_code, 0) << tcp.err;
}

TEST_F(NatsWorld, ListBodiesOverRpcIsPaged) {
  auto tumbled = start_tumbled();
  NatsTestClient client(nats_.url());
  ASSERT_TRUE(wait_connected(client));
  ClientMessage list;
  list.set_request_id(9);
  list.mutable_list_bodies()->set_max_bodies(1);
  const ServerMessage first = parse_server_message(*client.request("tumble.v1.lab.rpc", list.SerializeAsString()));
  ASSERT_TRUE(first.has_body_list()) << first.DebugString();
  ASSERT_EQ(first.body_list().bodies_size(), 1);
  EXPECT_GT(first.body_list().next_start_id(), 0u);
  list.mutable_list_bodies()->set_start_id(first.body_list().next_start_id());
  const ServerMessage second = parse_server_message(*client.request("tumble.v1.lab.rpc", list.SerializeAsString()));
  ASSERT_EQ(second.body_list().bodies_size(), 1);
  EXPECT_NE(second.body_list().bodies(0).id(), first.body_list().bodies(0).id());
}

TEST_F(NatsWorld, FramesCarryConsecutiveSequencesAndDeltaKeyFramesComeAtTheRestIntervalThenAtTheMovingOne) {
  // The floating scene is at rest (no gravity) until the force.
  auto tumbled = start_tumbled({"--nats-stream", "q=quantized@60", "--nats-stream", "d=delta@60", "--nats-key-interval",
                                "0.25", "--nats-rest-key-interval", "1"});
  NatsTestClient client(nats_.url());
  auto quantized = client.subscribe("tumble.v1.lab.poses.q");
  auto delta = client.subscribe("tumble.v1.lab.poses.d");
  ASSERT_TRUE(quantized && delta);
  // 2.5 s of sim time at rest, then a push that leaves the crate drifting.
  ASSERT_TRUE(delta->wait_count(150));
  const ServerMessage ack = parse_server_message(*client.request("tumble.v1.lab.rpc", force_request("crate", 100, 1)));
  ASSERT_TRUE(ack.has_ack()) << ack.DebugString();
  const std::uint64_t pushed = ack.ack().applied_tick();
  // Frames until 2 s of sim time after the ack.
  const double push_time = parse_server_message(delta->messages().back().data).pose_frame().sim_time();
  ASSERT_TRUE(delta->wait([&](const std::vector<NatsMessage>& messages) {
    return parse_server_message(messages.back().data).pose_frame().sim_time() >= push_time + 2;
  }));
  for (auto* collector : {quantized.get(), delta.get()}) {
    const std::vector<NatsMessage> messages = collector->messages();
    for (std::size_t i = 1; i < messages.size(); ++i) {
      EXPECT_EQ(parse_server_message(messages[i].data).pose_frame().sequence(),
                parse_server_message(messages[i - 1].data).pose_frame().sequence() + 1);
    }
  }
  // Key frames 1 s of sim time apart before the push, 0.25 s apart after it.
  std::vector<double> resting_keys;
  std::vector<double> moving_keys;
  std::size_t changes = 0;
  for (const NatsMessage& m : delta->messages()) {
    const tumble::v1::PoseFrame frame = parse_server_message(m.data).pose_frame();
    EXPECT_EQ(frame.encoding(), tumble::v1::POSE_ENCODING_DELTA);
    if (!frame.key_frame()) {
      ++changes;
    } else if (frame.tick() <= pushed) {
      resting_keys.push_back(frame.sim_time());
    } else {
      moving_keys.push_back(frame.sim_time());
    }
  }
  ASSERT_GE(resting_keys.size(), 2u);
  ASSERT_GE(moving_keys.size(), 5u);
  EXPECT_GT(changes, resting_keys.size() + moving_keys.size());
  for (std::size_t i = 1; i < resting_keys.size(); ++i) {
    EXPECT_NEAR(resting_keys[i] - resting_keys[i - 1], 1.0, 1.0 / 60 + 1e-9);
  }
  for (std::size_t i = 1; i < moving_keys.size(); ++i) {
    EXPECT_NEAR(moving_keys[i] - moving_keys[i - 1], 0.25, 1.0 / 60 + 1e-9);
  }
}

TEST_F(NatsWorld, AKeyRequestAnswersTheLatestFrameWholeWithItsSequence) {
  auto tumbled = start_tumbled({"--nats-stream", "d=delta@60", "--nats-key-interval", "100"});
  NatsTestClient client(nats_.url());
  auto delta = client.subscribe("tumble.v1.lab.poses.d");
  ASSERT_TRUE(delta && delta->wait_count(3));
  auto reply = client.request("tumble.v1.lab.key.d", "");
  ASSERT_TRUE(reply) << client.error();
  const tumble::v1::PoseFrame key = parse_server_message(*reply).pose_frame();
  EXPECT_TRUE(key.key_frame());
  EXPECT_GT(key.sequence(), 1u);
  const auto poses = wire::decode_quantized_poses(key.packed());
  ASSERT_TRUE(poses);
  EXPECT_EQ(poses->bodies.size(), 2u);
  // A change numbered sequence + 1 follows on the stream.
  EXPECT_TRUE(delta->wait([&](const std::vector<NatsMessage>& messages) {
    for (const NatsMessage& m : messages) {
      if (parse_server_message(m.data).pose_frame().sequence() == key.sequence() + 1) return true;
    }
    return false;
  }));
}

// A plank on a hinge from the world, level, so it swings.
const char* const kHingeScene = R"({"bodies": [
    {"name": "plank", "shape": {"box": {"half_extents": [0.5, 0.05, 0.05]}}, "mass": 2, "position": [0.5, 2, 0]}],
  "joints": [
    {"name": "hinge", "type": "hinge", "body_a": "world", "body_b": "plank", "anchor": [0, 2, 0], "axis": [0, 0, 1]}]})";

TEST_F(NatsWorld, AStreamWithJointsCarriesTheirStateInEveryFrameAndInItsKeyAnswer) {
  TumbledProcess tumbled(kHingeScene, {"--nats", nats_.url(), "--world", "lab", "--nats-stream", "dj=delta@60:joints",
                                       "--nats-stream", "f=full@60"});
  ASSERT_TRUE(tumbled.started()) << tumbled.log();
  NatsTestClient client(nats_.url());
  ASSERT_TRUE(wait_connected(client));
  const tumble::v1::WorldInfo info = only_world(client);
  ASSERT_EQ(info.streams_size(), 2);
  EXPECT_TRUE(info.streams(0).joints());
  EXPECT_FALSE(info.streams(1).joints());

  auto with_joints = client.subscribe("tumble.v1.lab.poses.dj");
  auto without = client.subscribe("tumble.v1.lab.poses.f");
  ASSERT_TRUE(with_joints && without);
  ASSERT_TRUE(with_joints->wait_count(5) && without->wait_count(2));
  // Every frame, key or change, has the hinge's state; the plank swings.
  double fastest = 0;
  for (const NatsMessage& m : with_joints->messages()) {
    const tumble::v1::PoseFrame frame = parse_server_message(m.data).pose_frame();
    ASSERT_EQ(frame.joint_ids_size(), 1) << "sequence " << frame.sequence();
    EXPECT_EQ(frame.joint_ids(0), 0u);
    ASSERT_EQ(frame.joint_speeds_size(), 1);
    fastest = std::max(fastest, static_cast<double>(std::abs(frame.joint_speeds(0))));
  }
  EXPECT_GT(fastest, 0.1);
  for (const NatsMessage& m : without->messages())
    EXPECT_EQ(parse_server_message(m.data).pose_frame().joint_ids_size(), 0);

  // The key answer is the latest frame whole: its joints are that frame's.
  auto reply = client.request("tumble.v1.lab.key.dj", "");
  ASSERT_TRUE(reply) << client.error();
  const tumble::v1::PoseFrame key = parse_server_message(*reply).pose_frame();
  ASSERT_EQ(key.joint_ids_size(), 1);
  ASSERT_TRUE(with_joints->wait([&](const std::vector<NatsMessage>& messages) {
    for (const NatsMessage& m : messages) {
      if (parse_server_message(m.data).pose_frame().sequence() == key.sequence()) return true;
    }
    return false;
  }));
  for (const NatsMessage& m : with_joints->messages()) {
    const tumble::v1::PoseFrame frame = parse_server_message(m.data).pose_frame();
    if (frame.sequence() != key.sequence()) continue;
    EXPECT_EQ(frame.tick(), key.tick());
    EXPECT_EQ(frame.joint_positions(0), key.joint_positions(0));
    EXPECT_EQ(frame.joint_speeds(0), key.joint_speeds(0));
  }
}

TEST_F(NatsWorld, QueryAnswersReadsAsAnObserverAndRefusesCommandsChangingNothing) {
  auto tumbled = start_tumbled({"--nats-stream", "f=full@60:all"});
  NatsTestClient client(nats_.url());
  ASSERT_TRUE(wait_connected(client));
  ClientMessage hello;
  hello.set_request_id(1);
  hello.mutable_hello()->set_protocol_version(tumble::v1::PROTOCOL_VERSION_CURRENT);
  const ServerMessage welcome = parse_server_message(*client.request("tumble.v1.lab.query", hello.SerializeAsString()));
  ASSERT_TRUE(welcome.has_welcome()) << welcome.DebugString();
  EXPECT_EQ(welcome.welcome().role(), tumble::v1::ROLE_OBSERVER);

  ClientMessage list;
  list.set_request_id(2);
  list.mutable_list_bodies();
  const ServerMessage bodies = parse_server_message(*client.request("tumble.v1.lab.query", list.SerializeAsString()));
  ASSERT_EQ(bodies.body_list().bodies_size(), 2) << bodies.DebugString();
  EXPECT_EQ(bodies.body_list().bodies(0).name(), "crate");

  const ServerMessage refused =
      parse_server_message(*client.request("tumble.v1.lab.query", force_request("crate", 240, 3)));
  ASSERT_TRUE(refused.has_error()) << refused.DebugString();
  EXPECT_EQ(refused.error().request_id(), 3u);
  EXPECT_EQ(refused.error().code(), tumble::v1::PERMISSION_DENIED);
  EXPECT_NE(refused.error().message().find("tumble.v1.lab.rpc"), std::string::npos) << refused.error().message();
  // Nothing moved: a frame after the refusal shows both bodies at rest.
  auto frames = client.subscribe("tumble.v1.lab.poses.f");
  ASSERT_TRUE(frames && frames->wait_count(2));
  const tumble::v1::PoseFrame frame = parse_server_message(frames->messages()[1].data).pose_frame();
  ASSERT_EQ(frame.linear_velocities_size(), 6);
  for (int i = 0; i < frame.linear_velocities_size(); ++i) EXPECT_EQ(frame.linear_velocities(i), 0.0f);
}

TEST_F(NatsWorld, TwoTumbledOfOneWorldAnswerAnRpcOnce) {
  auto first = start_tumbled();
  auto second = start_tumbled();
  NatsTestClient client(nats_.url());
  ASSERT_TRUE(wait_connected(client));
  // Both are there: two replies to the worlds request.
  ASSERT_TRUE(poll_until([&] { return client.request_many("tumble.v1.worlds", "").size() == 2; }));
  const std::vector<std::string> replies = client.request_many("tumble.v1.lab.rpc", stats_request(11));
  EXPECT_EQ(replies.size(), 1u);
}

TEST(NatsWorldStart, TumbledStartedWhileNatsIsDownServesTcpAndConnectsLater) {
  NatsServerProcess nats;
  TumbledProcess tumbled(kFloatingScene, {"--nats", nats.url(), "--world", "late"});
  ASSERT_TRUE(tumbled.started()) << tumbled.log();
  EXPECT_TRUE(poll_until([&] { return tumbled.log().find("NATS link down") != std::string::npos; })) << tumbled.log();
  const CommandResult bodies = tumbled.cli({"bodies"});
  EXPECT_EQ(bodies.exit_code, 0) << bodies.err;
  ASSERT_TRUE(nats.start()) << nats.log();
  NatsTestClient client(nats.url());
  EXPECT_TRUE(poll_until([&] {
    auto reply = client.request("tumble.v1.late.rpc", stats_request(1), std::chrono::milliseconds(500));
    return reply && parse_server_message(*reply).stats().nats().connected();
  })) << tumbled.log();
  EXPECT_NE(tumbled.log().find("NATS link up"), std::string::npos);
}

TEST(NatsWorldStart, CredentialsTheServerRefusesEndTumbledAtStartInOneLineNamingTheFlag) {
  NatsServerProcess nats("authorization { users = [ { user: tumbled, password: right-pass } ] }");
  ASSERT_TRUE(nats.start()) << nats.log();
  const std::string scene = make_temp_dir() + "/scene.json";
  std::ofstream(scene) << kFloatingScene;
  const std::string url = "nats://tumbled:wrong-pass@127.0.0.1:" + std::to_string(nats.port());
  const CommandResult result =
      run_command({tumbled_path(), "--scene", scene, "--listen", "127.0.0.1:0", "--nats", url, "--world", "lab"});
  EXPECT_EQ(result.exit_code, 1) << result.out << result.err;
  const std::string said = result.out + result.err;
  EXPECT_NE(said.find("--nats: the NATS server refused the user, password, token or credentials"), std::string::npos)
      << said;
  EXPECT_EQ(said.find("wrong-pass"), std::string::npos) << "the password is not shown: " << said;
}

TEST(NatsWorldStart, WithListenNoneTheWorldIsServedOverNatsAlone) {
  NatsServerProcess nats;
  ASSERT_TRUE(nats.start()) << nats.log();
  const std::string dir = make_temp_dir();
  std::ofstream(dir + "/scene.json") << kFloatingScene;
  ChildProcess tumbled(
      {tumbled_path(), "--scene", dir + "/scene.json", "--listen", "none", "--nats", nats.url(), "--world", "solo"},
      dir + "/tumbled.log");
  NatsTestClient client(nats.url());
  ASSERT_TRUE(client.connected()) << client.error();
  std::optional<std::string> reply;
  ASSERT_TRUE(poll_until([&] {
    reply = client.request("tumble.v1.solo.rpc", stats_request(2), std::chrono::milliseconds(500));
    return reply.has_value();
  })) << read_file(dir + "/tumbled.log");
  EXPECT_TRUE(parse_server_message(*reply).stats().nats().connected());
  const std::string log = read_file(dir + "/tumbled.log");
  EXPECT_EQ(log.find("listening on"), std::string::npos) << "no TCP or HTTP listener: " << log;
  // SIGTERM ends it cleanly, as with listeners.
  tumbled.signal(SIGTERM);
  EXPECT_EQ(tumbled.wait(std::chrono::seconds(20)), 0) << read_file(dir + "/tumbled.log");
}

// 60 spheres: a FULL frame with velocities is about 3.5 kB, a QUANTIZED one
// under 1 kB.
std::string sixty_spheres() {
  std::string scene = R"({"gravity": [0, 0, 0], "bodies": [)";
  for (int i = 0; i < 60; ++i) {
    if (i > 0) scene += ", ";
    scene += R"({"shape": {"sphere": {"radius": 0.25}}, "mass": 1, "position": [)" + std::to_string(i) +
             R"(, 0, 0], "linear_velocity": [0, 1, 0]})";
  }
  return scene + "]}";
}

TEST(NatsWorldPayload, AFrameOverTheServersMaxPayloadIsNotPublishedAndTheOtherStreamsGoOn) {
  NatsServerProcess nats("max_payload: 2048");
  ASSERT_TRUE(nats.start()) << nats.log();
  TumbledProcess tumbled(sixty_spheres(), {"--nats", nats.url(), "--world", "lab", "--nats-stream", "big=full@30:all",
                                           "--nats-stream", "small=quantized@30"});
  ASSERT_TRUE(tumbled.started()) << tumbled.log();
  NatsTestClient client(nats.url());
  auto big = client.subscribe("tumble.v1.lab.poses.big");
  auto small = client.subscribe("tumble.v1.lab.poses.small");
  ASSERT_TRUE(big && small);
  ASSERT_TRUE(small->wait_count(10)) << tumbled.log();
  // The small stream's frames are consecutive: the refused ones cost it nothing.
  const std::vector<NatsMessage> frames = small->messages();
  for (std::size_t i = 1; i < frames.size(); ++i) {
    EXPECT_EQ(parse_server_message(frames[i].data).pose_frame().sequence(),
              parse_server_message(frames[i - 1].data).pose_frame().sequence() + 1);
  }
  const auto poses = wire::decode_quantized_poses(parse_server_message(frames.back().data).pose_frame().packed());
  ASSERT_TRUE(poses);
  EXPECT_EQ(poses->bodies.size(), 60u);
  EXPECT_TRUE(big->messages().empty()) << "no frame over 2048 bytes reaches NATS";
  const ServerMessage stats = parse_server_message(*client.request("tumble.v1.lab.rpc", stats_request(4)));
  EXPECT_GT(stats.stats().nats().frames_dropped(), 0u);
  EXPECT_TRUE(poll_until([&] {
    return tumbled.log().find("over the server's max payload of 2048") != std::string::npos;
  })) << tumbled.log();
  // TCP is served as ever.
  EXPECT_EQ(tumbled.cli({"bodies"}).exit_code, 0);
}

// A certificate authority and a certificate for 127.0.0.1 it signed, made
// with /usr/bin/openssl (Debian's openssl package) in `dir`: ca.pem, server.pem, server.key. False on failure.
bool make_certificates(const std::string& dir) {
  const std::vector<std::vector<std::string>> steps = {
      {"/usr/bin/openssl", "req", "-x509", "-newkey", "rsa:2048", "-nodes", "-keyout", dir + "/ca.key", "-out",
       dir + "/ca.pem", "-days", "2", "-subj", "/CN=tumble test CA"},
      {"/usr/bin/openssl", "req", "-newkey", "rsa:2048", "-nodes", "-keyout", dir + "/server.key", "-out",
       dir + "/server.csr", "-subj", "/CN=127.0.0.1"},
      {"/usr/bin/openssl", "x509", "-req", "-in", dir + "/server.csr", "-CA", dir + "/ca.pem", "-CAkey",
       dir + "/ca.key", "-CAcreateserial", "-out", dir + "/server.pem", "-days", "2", "-extfile", dir + "/san.ext"}};
  std::ofstream(dir + "/san.ext") << "subjectAltName=IP:127.0.0.1\n";
  for (const auto& step : steps) {
    const CommandResult result = run_command(step);
    if (result.exit_code != 0) {
      ADD_FAILURE() << step[0] << " " << step[1] << ": " << result.err;
      return false;
    }
  }
  return true;
}

TEST(NatsWorldTls, OverTlsTumbledServesWhenItTrustsTheServerAndSaysWhyNotWhenItDoesNot) {
  const std::string dir = make_temp_dir();
  ASSERT_TRUE(make_certificates(dir));
  NatsServerProcess nats("tls { cert_file: \"" + dir + "/server.pem\", key_file: \"" + dir + "/server.key\" }");
  ASSERT_TRUE(nats.start()) << nats.log();
  const std::string url = "tls://127.0.0.1:" + std::to_string(nats.port());
  std::ofstream(dir + "/scene.json") << kFloatingScene;

  // Not trusting the test CA: one line naming the flag and the check that failed.
  const CommandResult untrusted = run_command(
      {tumbled_path(), "--scene", dir + "/scene.json", "--listen", "127.0.0.1:0", "--nats", url, "--world", "lab"});
  EXPECT_EQ(untrusted.exit_code, 1);
  EXPECT_NE((untrusted.out + untrusted.err).find("--nats: SSL Error (SSL handshake error"), std::string::npos)
      << untrusted.out << untrusted.err;

  // Trusting it (OpenSSL's SSL_CERT_FILE, which children inherit): served, and the CLI reads it too.
  ASSERT_EQ(setenv("SSL_CERT_FILE", (dir + "/ca.pem").c_str(), 1), 0);
  TumbledProcess tumbled(kFloatingScene, {"--nats", url, "--world", "lab"});
  ASSERT_TRUE(tumbled.started()) << tumbled.log();
  CommandResult worlds;
  EXPECT_TRUE(poll_until([&] {
    worlds = run_command({tumble_cli_path(), "--nats", url, "--json", "worlds"});
    return worlds.exit_code == 0 && worlds.out.find("\"lab\"") != std::string::npos;
  })) << worlds.out
      << worlds.err << tumbled.log();
  const CommandResult bodies = run_command({tumble_cli_path(), "--nats", url, "--world", "lab", "bodies"});
  EXPECT_EQ(bodies.exit_code, 0) << bodies.err;
  EXPECT_NE(bodies.out.find("crate"), std::string::npos) << bodies.out;
  unsetenv("SSL_CERT_FILE");
}

}  // namespace
}  // namespace tumble::test
