// The real tumbled against clients that misbehave: garbage, broken frames,
// silence, floods, clients that never read, hundreds at once, wrong tokens,
// observers that try to push, clients over their rate, connections over the
// limit. Each gets a clear Error or a clean disconnect, and afterwards a
// fresh, well-behaved client is served and the world still steps.
//
// Assertions are on ticks and state; wall-clock bounds are generous, for a
// shared and noisy machine.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <thread>
#include <vector>

#include "cli_helpers.h"
#include "poll_until.h"
#include "raw_client.h"
#include "replies.h"
#include "requests.h"
#include "tumbled_process.h"

namespace tumble::test {
namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;
using std::chrono::seconds;
using tumble::v1::ClientMessage;
using tumble::v1::ServerMessage;

// Zero gravity: a body moves only when a request pushes it. The ball has
// mass 1, so its speed is the sum of the impulses it took.
const char* const kScene = kFloatingScene;

constexpr double kTickRate = 240;

// The crate and a grid of `spheres` spheres 3 m apart, in zero gravity: big
// frames and body lists. The spheres drift and spin all alike, so they stay
// awake (the physics works every tick) and never collide.
std::string sphere_grid(int spheres) {
  std::ostringstream scene;
  scene
      << R"({"gravity": [0, 0, 0], "bodies": [)"
      << R"({"name": "crate", "shape": {"box": {"half_extents": [0.5, 0.5, 0.5]}}, "mass": 2, "position": [0, -100, 0]})";
  for (int i = 0; i < spheres; ++i) {
    scene << R"(, {"name": "s)" << i << R"(", "shape": {"sphere": {"radius": 0.5}}, "mass": 1,)"
          << R"( "position": [)" << 3 * (i % 50) << ", " << 3 * (i / 50) << ", 0],"
          << R"( "linear_velocity": [0, 0, 0.5], "angular_velocity": [0, 1, 0]})";
  }
  scene << "]}";
  return scene.str();
}

ClientMessage hello(const std::string& token = "", const std::string& name = "bad-input-test") {
  ClientMessage m;
  m.set_request_id(1);
  m.mutable_hello()->set_protocol_version(tumble::v1::PROTOCOL_VERSION_CURRENT);
  m.mutable_hello()->set_client_name(name);
  m.mutable_hello()->set_token(token);
  return m;
}

// A request that costs the server almost nothing and gets a small Error.
ClientMessage probe(std::uint64_t id) {
  ClientMessage m;
  m.set_request_id(id);
  m.mutable_unsubscribe()->set_subscription_id(999999);
  return m;
}

std::string describe(const std::optional<ServerMessage>& m) { return m ? m->ShortDebugString() : "nothing"; }

// Sends Hello with `token`; the server's answer.
std::optional<ServerMessage> greet(RawClient& client, const std::string& token = "") {
  if (!client.send(hello(token))) return std::nullopt;
  return client.read();
}

// Sends `request` and reads until its reply.
std::optional<ServerMessage> ask(RawClient& client, const ClientMessage& request, milliseconds timeout = seconds(10)) {
  if (!client.send(request)) return std::nullopt;
  return client.read_until([&](const ServerMessage& m) { return is_reply_to(m, request.request_id()); }, timeout);
}

// Expects an Error of `code` (echoing `request_id`) and then the server closing the connection.
void ExpectRefusedAndClosed(RawClient& client, tumble::v1::ErrorCode code, std::uint64_t request_id = 0) {
  const auto reply = client.read_until([](const ServerMessage& m) { return m.has_error(); });
  ASSERT_TRUE(reply) << "no Error before the connection ended";
  EXPECT_EQ(reply->error().code(), code) << reply->ShortDebugString();
  EXPECT_EQ(reply->error().request_id(), request_id);
  EXPECT_FALSE(reply->error().message().empty());
  EXPECT_TRUE(client.closed_by_server()) << "the server left the connection open";
}

// Reads until every request in [first, last] is answered; the replies by request id.
std::map<std::uint64_t, ServerMessage> replies_to(RawClient& client, std::uint64_t first, std::uint64_t last) {
  std::map<std::uint64_t, ServerMessage> replies;
  const auto deadline = Clock::now() + seconds(30);
  while (replies.size() < last - first + 1 && Clock::now() < deadline) {
    const auto message = client.read(seconds(10));
    if (!message) break;
    for (std::uint64_t id = first; id <= last; ++id) {
      if (is_reply_to(*message, id)) replies.emplace(id, *message);
    }
  }
  return replies;
}

// Sends small requests until one fails: the server has closed the
// connection (a write to a closed peer is reset). Replies are not read, so
// the client stays a non-reader. True if that happened within `timeout`.
bool wait_until_dropped(RawClient& client, milliseconds timeout) {
  const auto deadline = Clock::now() + timeout;
  for (std::uint64_t id = 1000; Clock::now() < deadline; ++id) {
    if (!client.send(probe(id))) return true;
    std::this_thread::sleep_for(milliseconds(100));
  }
  return false;
}

// The server's resident memory, from /proc, in bytes.
std::int64_t resident_bytes(pid_t pid) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stoll(line.substr(6)) * 1024;  // "VmRSS:  1234 kB"
  }
  return -1;
}

// A fresh client is served: it shakes hands, its force is applied after the
// tick the server welcomed it at (the world steps), and its body list
// shows that tick or a later one. The deadline is generous: a server that
// has just dropped a flooding client may still be working through the
// requests it took before, slowly under a sanitizer on a loaded machine.
void ExpectHealthy(const TumbledProcess& server, const std::string& token = "") {
  RawClient client(server.port());
  ASSERT_TRUE(client.connected());
  const auto welcome = greet(client, token);
  ASSERT_TRUE(welcome && welcome->has_welcome()) << describe(welcome) << "\n" << server.log();
  const auto ack = ask(client, force(2, "crate", 1), seconds(30));
  ASSERT_TRUE(ack && ack->has_ack()) << describe(ack);
  EXPECT_GT(ack->ack().applied_tick(), welcome->welcome().tick());
  const auto list = ask(client, list_bodies(3));
  ASSERT_TRUE(list && list->has_body_list()) << describe(list);
  EXPECT_GE(list->body_list().tick(), ack->ack().applied_tick());
}

class BadInput : public ::testing::Test {
 protected:
  // Tokens in the environment would reach every tumbled started here.
  void SetUp() override {
    ::unsetenv("TUMBLE_TOKEN");
    ::unsetenv("TUMBLE_OBSERVER_TOKEN");
  }
};

TEST_F(BadInput, GarbageBeforeHelloIsMalformed) {
  TumbledProcess server(kScene);
  ASSERT_TRUE(server.started()) << server.log();
  {
    // An HTTP request: 'G' reads as a length of 71, and those 71 bytes are no ClientMessage.
    RawClient client(server.port());
    ASSERT_TRUE(
        client.send_bytes("GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nUser-Agent: curl/7.88.1\r\n"
                          "Accept: */*\r\nConnection: keep-alive\r\n\r\n"));
    ExpectRefusedAndClosed(client, tumble::v1::MALFORMED_FRAME);
  }
  {
    // The start of a TLS ClientHello: 0x16 is a length of 22, then field number 0.
    RawClient client(server.port());
    std::string tls("\x16\x03\x01\x02\x00\x01\x00\x01\xfc\x03\x03", 11);
    tls += std::string(40, '\x5a');
    ASSERT_TRUE(client.send_bytes(tls));
    ExpectRefusedAndClosed(client, tumble::v1::MALFORMED_FRAME);
  }
  ExpectHealthy(server);
}

TEST_F(BadInput, GarbageAfterHelloIsMalformed) {
  TumbledProcess server(kScene);
  ASSERT_TRUE(server.started()) << server.log();
  RawClient client(server.port());
  ASSERT_TRUE(greet(client));
  ASSERT_TRUE(client.send_bytes(std::string("\x06\x00\xff\xff\xff\xff\xff", 7)));
  ExpectRefusedAndClosed(client, tumble::v1::MALFORMED_FRAME);
  ExpectHealthy(server);
}

TEST_F(BadInput, TruncatedFrameThenCloseHarmsNobody) {
  TumbledProcess server(kScene);
  ASSERT_TRUE(server.started()) << server.log();
  RawClient watcher(server.port());
  ASSERT_TRUE(greet(watcher));
  const auto subscribed = ask(watcher, subscribe(2, 60));
  ASSERT_TRUE(subscribed && subscribed->has_subscribed());
  {
    RawClient client(server.port());
    ASSERT_TRUE(greet(client));
    const std::string frame = wire::encode_frame(force(2, "crate", 5));
    ASSERT_TRUE(client.send_bytes(frame.substr(0, frame.size() / 2)));  // half a force, then gone
  }
  // The half force was never applied: the crate moves only by ExpectHealthy's
  // 1 N for one tick, 1 N / 2 kg * (1/240) s.
  ExpectHealthy(server);
  const auto list = ask(watcher, list_bodies(3));
  ASSERT_TRUE(list && list->has_body_list());
  int crates = 0;
  for (const auto& body : list->body_list().bodies()) {
    if (body.name() == "crate") {
      EXPECT_NEAR(body.linear_velocity().x(), 1.0 / 480.0, 1e-12);
      ++crates;
    }
  }
  EXPECT_EQ(crates, 1) << "the body list has no crate to check";
  // And the watcher's frames kept coming.
  const auto frame = watcher.read_until([](const ServerMessage& m) { return m.has_pose_frame(); });
  EXPECT_TRUE(frame);
}

TEST_F(BadInput, FourGibibyteLengthPrefixIsRefusedFromThePrefix) {
  TumbledProcess server(kScene);
  ASSERT_TRUE(server.started()) << server.log();
  const std::string four_gib("\x80\x80\x80\x80\x10", 5);  // the varint of 2^32
  for (const bool greeted : {false, true}) {
    RawClient client(server.port());
    if (greeted) {
      ASSERT_TRUE(greet(client));
    }
    ASSERT_TRUE(client.send_bytes(four_gib + std::string(4096, 'x')));
    const auto reply = client.read_until([](const ServerMessage& m) { return m.has_error(); });
    ASSERT_TRUE(reply) << "no Error";
    EXPECT_EQ(reply->error().code(), tumble::v1::FRAME_TOO_LARGE);
    EXPECT_NE(reply->error().message().find("4294967296"), std::string::npos) << reply->error().message();
    EXPECT_TRUE(client.closed_by_server());
  }
  ExpectHealthy(server);
}

TEST_F(BadInput, EnvelopeOfAnUnknownKindIsAnsweredAndTheSessionGoesOn) {
  TumbledProcess server(kScene);
  ASSERT_TRUE(server.started()) << server.log();
  RawClient client(server.port());
  ASSERT_TRUE(greet(client));
  // A well-formed envelope holding only a field this server has never heard of.
  ClientMessage unknown;
  unknown.set_request_id(7);
  unknown.GetReflection()->MutableUnknownFields(&unknown)->AddLengthDelimited(4000, "from the future");
  const auto reply = ask(client, unknown);
  ASSERT_TRUE(reply && reply->has_error()) << describe(reply);
  EXPECT_EQ(reply->error().code(), tumble::v1::UNKNOWN_MESSAGE);
  // The same connection is still served.
  const auto list = ask(client, list_bodies(8));
  ASSERT_TRUE(list && list->has_body_list()) << describe(list);
  ExpectHealthy(server);
}

TEST_F(BadInput, AClientThatNeverSaysHelloIsCutOffAfterTheHandshakeTimeout) {
  TumbledProcess server(kScene, {"--handshake-timeout", "1"});
  ASSERT_TRUE(server.started()) << server.log();
  RawClient silent(server.port());
  ASSERT_TRUE(silent.connected());
  const auto start = Clock::now();
  const auto reply = silent.read(seconds(30));
  const double waited = std::chrono::duration<double>(Clock::now() - start).count();
  ASSERT_TRUE(reply && reply->has_error()) << describe(reply);
  EXPECT_EQ(reply->error().code(), tumble::v1::HANDSHAKE_REQUIRED);
  EXPECT_EQ(reply->error().message(), "no Hello within 1 s of connecting");
  EXPECT_GE(waited, 0.9);
  EXPECT_TRUE(silent.closed_by_server());
  ExpectHealthy(server);
}

TEST_F(BadInput, WrongOrMissingTokenIsUnauthenticated) {
  TumbledProcess server(kScene, {"--token", "ctl-secret", "--observer-token", "obs-secret"});
  ASSERT_TRUE(server.started()) << server.log();
  for (const std::string token : {"", "wrong", "ctl-secre", "ctl-secret2", "obs-secret "}) {
    RawClient client(server.port());
    ASSERT_TRUE(client.send(hello(token)));
    ExpectRefusedAndClosed(client, tumble::v1::UNAUTHENTICATED, 1);
  }
  {
    RawClient controller(server.port());
    const auto welcome = greet(controller, "ctl-secret");
    ASSERT_TRUE(welcome && welcome->has_welcome()) << describe(welcome);
    EXPECT_EQ(welcome->welcome().role(), tumble::v1::ROLE_CONTROLLER);
    RawClient observer(server.port());
    const auto watching = greet(observer, "obs-secret");
    ASSERT_TRUE(watching && watching->has_welcome()) << describe(watching);
    EXPECT_EQ(watching->welcome().role(), tumble::v1::ROLE_OBSERVER);
  }
  // The CLI sends its token in Hello, from --token or TUMBLE_TOKEN.
  const CommandResult without = server.cli({"bodies"});
  EXPECT_EQ(without.exit_code, 1);
  EXPECT_NE(without.err.find("UNAUTHENTICATED"), std::string::npos) << without.err;
  const CommandResult with = server.cli({"--token", "ctl-secret", "bodies"});
  EXPECT_EQ(with.exit_code, 0) << with.err;
  ::setenv("TUMBLE_TOKEN", "ctl-secret", 1);
  const CommandResult from_env = server.cli({"bodies"});
  ::unsetenv("TUMBLE_TOKEN");
  EXPECT_EQ(from_env.exit_code, 0) << from_env.err;

  ExpectHealthy(server, "ctl-secret");
  // The log says who was refused, never what the tokens are.
  const std::string log = server.log();
  EXPECT_NE(log.find("UNAUTHENTICATED"), std::string::npos);
  EXPECT_EQ(log.find("ctl-secret"), std::string::npos);
  EXPECT_EQ(log.find("obs-secret"), std::string::npos);
}

TEST_F(BadInput, TokensComeFromTheEnvironmentToo) {
  ::setenv("TUMBLE_TOKEN", "env-ctl", 1);
  ::setenv("TUMBLE_OBSERVER_TOKEN", "env-obs", 1);
  TumbledProcess server(kScene);
  ::unsetenv("TUMBLE_TOKEN");
  ::unsetenv("TUMBLE_OBSERVER_TOKEN");
  ASSERT_TRUE(server.started()) << server.log();
  RawClient anonymous(server.port());
  ASSERT_TRUE(anonymous.send(hello()));
  ExpectRefusedAndClosed(anonymous, tumble::v1::UNAUTHENTICATED, 1);
  RawClient observer(server.port());
  const auto welcome = greet(observer, "env-obs");
  ASSERT_TRUE(welcome && welcome->has_welcome()) << describe(welcome);
  EXPECT_EQ(welcome->welcome().role(), tumble::v1::ROLE_OBSERVER);
  ExpectHealthy(server, "env-ctl");
}

TEST_F(BadInput, LimitAndTokenFlagsAreChecked) {
  const CommandResult same =
      run_command({tumbled_path(), "--listen", "127.0.0.1:0", "--token", "same", "--observer-token", "same"});
  EXPECT_EQ(same.exit_code, 2);
  EXPECT_NE(same.err.find("must differ"), std::string::npos) << same.err;
  for (const char* flag : {"--max-connections", "--max-commands-per-second", "--handshake-timeout",
                           "--max-undelivered-seconds", "--max-pending-bytes"}) {
    EXPECT_NE(run_command({tumbled_path(), "--listen", "127.0.0.1:0", flag, "0"}).exit_code, 0) << flag;
  }
}

TEST_F(BadInput, WithoutTokensEveryoneControlsAndTheLogSaysSo) {
  TumbledProcess server(kScene);
  ASSERT_TRUE(server.started()) << server.log();
  RawClient client(server.port());
  const auto welcome = greet(client, "any token at all");
  ASSERT_TRUE(welcome && welcome->has_welcome()) << describe(welcome);
  EXPECT_EQ(welcome->welcome().role(), tumble::v1::ROLE_CONTROLLER);
  EXPECT_NE(server.log().find("every client that connects may control the world"), std::string::npos) << server.log();
}

TEST_F(BadInput, AnObserverMayWatchButNotPush) {
  TumbledProcess server(kScene, {"--token", "ctl-secret", "--observer-token", "obs-secret"});
  ASSERT_TRUE(server.started()) << server.log();
  RawClient observer(server.port());
  const auto welcome = greet(observer, "obs-secret");
  ASSERT_TRUE(welcome && welcome->has_welcome()) << describe(welcome);

  ClientMessage torque;
  torque.set_request_id(4);
  torque.mutable_apply_torque()->mutable_body()->set_name("crate");
  torque.mutable_apply_torque()->mutable_torque()->set_y(100);
  ClientMessage pause;
  pause.set_request_id(8);
  pause.mutable_pause();
  ClientMessage reset;
  reset.set_request_id(9);
  reset.mutable_reset();
  for (const ClientMessage& push : {force(2, "crate", 100), impulse(3, "ball", 100), torque, pause, reset}) {
    const auto reply = ask(observer, push);
    ASSERT_TRUE(reply && reply->has_error()) << describe(reply);
    EXPECT_EQ(reply->error().code(), tumble::v1::PERMISSION_DENIED);
    EXPECT_EQ(reply->error().request_id(), push.request_id());
  }
  // The observer is still connected, may read, and nothing moved.
  const auto list = ask(observer, list_bodies(5));
  ASSERT_TRUE(list && list->has_body_list()) << describe(list);
  for (const auto& body : list->body_list().bodies()) {
    EXPECT_EQ(body.linear_velocity().x(), 0.0) << body.name();
    EXPECT_EQ(body.angular_velocity().y(), 0.0) << body.name();
  }
  const auto subscribed = ask(observer, subscribe(6, 30));
  ASSERT_TRUE(subscribed && subscribed->has_subscribed()) << describe(subscribed);
  EXPECT_TRUE(observer.read_until([](const ServerMessage& m) { return m.has_pose_frame(); }));
  ClientMessage unsubscribe;
  unsubscribe.set_request_id(7);
  unsubscribe.mutable_unsubscribe()->set_subscription_id(subscribed->subscribed().subscription_id());
  const auto left = ask(observer, unsubscribe);
  EXPECT_TRUE(left && left->has_ack()) << describe(left);
  ClientMessage get_stats;
  get_stats.set_request_id(10);
  get_stats.mutable_get_stats();
  const auto stats = ask(observer, get_stats);
  ASSERT_TRUE(stats && stats->has_stats()) << describe(stats);
  EXPECT_FALSE(stats->stats().paused());  // the denied Pause did nothing

  // The CLI with the observer's token hears the refusal.
  const CommandResult pushed = server.cli({"--token", "obs-secret", "force", "crate", "--force", "1", "0", "0"});
  EXPECT_EQ(pushed.exit_code, 1);
  EXPECT_NE(pushed.err.find("PERMISSION_DENIED"), std::string::npos) << pushed.err;
  ExpectHealthy(server, "ctl-secret");
}

TEST_F(BadInput, RequestsOverTheRateAreRefusedAndNothingElseHappens) {
  TumbledProcess server(kScene, {"--max-commands-per-second", "20"});
  ASSERT_TRUE(server.started()) << server.log();
  RawClient client(server.port());
  ASSERT_TRUE(greet(client));
  // 100 impulses of 1 N s on the 1 kg ball, all at once.
  constexpr int kSent = 100;
  std::string burst;
  for (std::uint64_t id = 1; id <= kSent; ++id) burst += wire::encode_frame(impulse(id, "ball", 1));
  ASSERT_TRUE(client.send_bytes(burst));
  // Refusals are immediate, acks come from the sim's next tick: collect them all by id.
  const auto replies = replies_to(client, 1, kSent);
  ASSERT_EQ(replies.size(), static_cast<std::size_t>(kSent)) << "some requests got no reply";
  int applied = 0;
  int limited = 0;
  for (const auto& [id, reply] : replies) {
    if (reply.has_ack()) {
      ++applied;
    } else {
      ASSERT_TRUE(reply.has_error()) << reply.ShortDebugString();
      EXPECT_EQ(reply.error().code(), tumble::v1::RATE_LIMITED);
      EXPECT_EQ(reply.error().request_id(), id);
      ++limited;
    }
  }
  EXPECT_GE(applied, 20);  // the burst
  EXPECT_GE(limited, 50);
  EXPECT_EQ(applied + limited, kSent);

  // The connection recovers once tokens come back (one every 50 ms), and
  // only the accepted impulses moved the ball: 1 m/s each.
  std::optional<ServerMessage> list;
  for (std::uint64_t id = 200; id < 300; ++id) {
    list = ask(client, list_bodies(id));
    ASSERT_TRUE(list) << "no reply";
    if (list->has_body_list()) break;
    EXPECT_EQ(list->error().code(), tumble::v1::RATE_LIMITED);
    std::this_thread::sleep_for(milliseconds(100));
  }
  ASSERT_TRUE(list && list->has_body_list()) << "never served again";
  int balls = 0;
  for (const auto& body : list->body_list().bodies()) {
    if (body.name() == "ball") {
      EXPECT_DOUBLE_EQ(body.linear_velocity().x(), applied);
      ++balls;
    }
  }
  EXPECT_EQ(balls, 1) << "the body list has no ball to check";
  EXPECT_NE(server.log().find("refusing the excess"), std::string::npos);
  ExpectHealthy(server);
}

TEST_F(BadInput, ConnectionsOverTheLimitAreRefusedAndTheOthersGoOn) {
  TumbledProcess server(kScene, {"--max-connections", "3"});
  ASSERT_TRUE(server.started()) << server.log();
  std::vector<std::unique_ptr<RawClient>> clients;
  for (int i = 0; i < 3; ++i) {
    clients.push_back(std::make_unique<RawClient>(server.port()));
    ASSERT_TRUE(greet(*clients.back()));
  }
  {
    RawClient extra(server.port());
    ASSERT_TRUE(extra.connected());  // the kernel accepts; the server refuses
    const auto reply = extra.read(seconds(10));
    ASSERT_TRUE(reply && reply->has_error()) << describe(reply);
    EXPECT_EQ(reply->error().code(), tumble::v1::RESOURCE_EXHAUSTED);
    EXPECT_NE(reply->error().message().find("limit of 3 connections"), std::string::npos) << reply->error().message();
    EXPECT_TRUE(extra.closed_by_server());
  }
  // Refusals are counted, and logged as one line a second.
  const auto stats = ask(*clients[0], get_stats(9));
  ASSERT_TRUE(stats && stats->has_stats()) << describe(stats);
  EXPECT_EQ(stats->stats().connections_refused(), 1u);
  EXPECT_TRUE(poll_until([&] {
    return server.log().find("refused 1 connections over the limit of 3 in the last second") != std::string::npos;
  })) << server.log();
  for (std::uint64_t i = 0; i < clients.size(); ++i) {
    const auto list = ask(*clients[i], list_bodies(10 + i));
    EXPECT_TRUE(list && list->has_body_list()) << describe(list);
  }
  // Once one leaves, there is room again (the server notices within moments).
  clients.pop_back();
  bool admitted = false;
  for (int attempt = 0; attempt < 100 && !admitted; ++attempt) {
    RawClient next(server.port());
    const auto welcome = greet(next);
    admitted = welcome && welcome->has_welcome();
    if (!admitted) std::this_thread::sleep_for(milliseconds(100));
  }
  EXPECT_TRUE(admitted);
  ExpectHealthy(server);
}

// 100,000 zero bytes after Hello are 100,000 empty envelopes: the client
// gets the error budget's worth of replies, one RESOURCE_EXHAUSTED and a
// close, a few kilobytes instead of megabytes.
TEST_F(BadInput, AHundredThousandZeroBytesDrawAFewKilobytesAndAClose) {
  TumbledProcess server(kScene);
  ASSERT_TRUE(server.started()) << server.log();
  RawClient flood(server.port());
  ASSERT_TRUE(greet(flood));
  ASSERT_TRUE(flood.send_bytes(std::string(100000, '\0')));
  std::size_t replies = 0;
  std::size_t reply_bytes = 0;
  std::optional<ServerMessage> last;
  while (auto message = flood.read(seconds(10))) {
    ++replies;
    reply_bytes += wire::encode_frame(*message).size();
    last = message;
  }
  EXPECT_TRUE(flood.saw_eof());
  ASSERT_TRUE(last);
  EXPECT_EQ(last->error().code(), tumble::v1::RESOURCE_EXHAUSTED) << describe(last);
  EXPECT_EQ(last->error().message(), "over the limit of 100 errors per second; the connection is closed");
  EXPECT_LE(replies, 121u);
  EXPECT_LT(reply_bytes, 12000u);
  std::cout << "[ figures  ] 100000 zero bytes: " << replies << " replies, " << reply_bytes << " bytes" << std::endl;

  RawClient watcher(server.port());
  ASSERT_TRUE(greet(watcher));
  const auto stats = ask(watcher, get_stats(2));
  ASSERT_TRUE(stats && stats->has_stats()) << describe(stats);
  EXPECT_EQ(stats->stats().clients_closed_for_errors(), 1u);
  ExpectHealthy(server);
}

TEST_F(BadInput, AFrameThatStallsIsCutOffAfterTheFrameTimeout) {
  TumbledProcess server(kScene, {"--frame-timeout", "0.3"});
  ASSERT_TRUE(server.started()) << server.log();
  RawClient staller(server.port());
  ASSERT_TRUE(greet(staller));
  ASSERT_TRUE(staller.send_bytes("\x20partial"));  // announces 32 bytes, sends 7
  ExpectRefusedAndClosed(staller, tumble::v1::MALFORMED_FRAME);
  EXPECT_NE(server.log().find("is still incomplete, over the limit of 0.3 s"), std::string::npos) << server.log();
  ExpectHealthy(server);
}

TEST_F(BadInput, FiveHundredClientsAtOnceAreAllServed) {
  TumbledProcess server(kScene);
  ASSERT_TRUE(server.started()) << server.log();
  constexpr int kThreads = 5;
  constexpr int kPerThread = 100;
  std::vector<std::vector<std::unique_ptr<RawClient>>> groups(kThreads);
  std::atomic<int> greeted{0};
  std::atomic<int> listed{0};
  std::atomic<int> acked{0};
  std::atomic<int> failures{0};
  std::atomic<std::uint64_t> first_tick{0};
  std::atomic<std::uint64_t> last_tick{0};
  const auto start = Clock::now();
  // Each phase runs on every thread at once: all 500 connect and shake hands,
  // then all ask for the bodies, then every fifth pushes the crate.
  const auto run_phase = [&](const std::function<void(std::vector<std::unique_ptr<RawClient>>&, int)>& phase) {
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t) threads.emplace_back([&, t] { phase(groups[static_cast<std::size_t>(t)], t); });
    for (auto& thread : threads) thread.join();
  };
  run_phase([&](std::vector<std::unique_ptr<RawClient>>& group, int t) {
    for (int i = 0; i < kPerThread; ++i) {
      auto client = std::make_unique<RawClient>(server.port());
      const auto welcome = greet(*client, "");
      if (!welcome || !welcome->has_welcome()) {
        ++failures;
        continue;
      }
      if (t == 0 && i == 0) first_tick = welcome->welcome().tick();
      ++greeted;
      group.push_back(std::move(client));
    }
  });
  ASSERT_EQ(greeted.load(), kThreads * kPerThread);
  run_phase([&](std::vector<std::unique_ptr<RawClient>>& group, int) {
    for (auto& client : group) EXPECT_TRUE(client->send(list_bodies(2)));
    for (auto& client : group) {
      const auto list = client->read_until([](const ServerMessage& m) { return is_reply_to(m, 2); }, seconds(30));
      if (list && list->has_body_list() && list->body_list().bodies_size() == 2) {
        ++listed;
      } else {
        ++failures;
      }
    }
  });
  run_phase([&](std::vector<std::unique_ptr<RawClient>>& group, int) {
    for (std::size_t i = 0; i < group.size(); i += 5) EXPECT_TRUE(group[i]->send(force(3, "crate", 1)));
    for (std::size_t i = 0; i < group.size(); i += 5) {
      const auto ack = group[i]->read_until([](const ServerMessage& m) { return is_reply_to(m, 3); }, seconds(30));
      if (ack && ack->has_ack()) {
        ++acked;
        std::uint64_t seen = last_tick.load();
        while (ack->ack().applied_tick() > seen && !last_tick.compare_exchange_weak(seen, ack->ack().applied_tick())) {
        }
      } else {
        ++failures;
      }
    }
  });
  const double took = std::chrono::duration<double>(Clock::now() - start).count();
  EXPECT_EQ(failures.load(), 0);
  EXPECT_EQ(listed.load(), kThreads * kPerThread);
  EXPECT_EQ(acked.load(), kThreads * kPerThread / 5);
  EXPECT_GT(last_tick.load(), first_tick.load()) << "the world did not step";
  std::cout << "[ figures  ] 500 clients: handshake, list and " << acked.load() << " forces in " << took << " s; ticks "
            << first_tick.load() << " -> " << last_tick.load() << std::endl;
  // With all 500 still connected, one more is served.
  ExpectHealthy(server);
}

TEST_F(BadInput, AClientThatStopsReadingIsDisconnectedAfterTheUndeliveredLimit) {
  TumbledProcess server(sphere_grid(400), {"--max-undelivered-seconds", "1"});
  ASSERT_TRUE(server.started()) << server.log();
  RawClient sleeper(server.port());
  ASSERT_TRUE(greet(sleeper));
  ASSERT_TRUE(sleeper.send(subscribe(2, 0)));  // every body, every tick, never read
  EXPECT_TRUE(wait_until_dropped(sleeper, seconds(60))) << server.log();
  EXPECT_NE(server.log().find("still undelivered"), std::string::npos) << server.log();
  ExpectHealthy(server);
}

TEST_F(BadInput, AClientThatLetsRepliesPileUpIsDisconnected) {
  TumbledProcess server(sphere_grid(400), {"--max-pending-bytes", "262144"});
  ASSERT_TRUE(server.started()) << server.log();
  RawClient hoarder(server.port());
  ASSERT_TRUE(greet(hoarder));
  // Body lists of 400 bodies, asked for and never read.
  bool dropped = false;
  for (std::uint64_t id = 2; id < 5000 && !dropped; ++id) {
    dropped = !hoarder.send(list_bodies(id));
    if (id % 20 == 0) std::this_thread::sleep_for(milliseconds(20));
  }
  EXPECT_TRUE(dropped || wait_until_dropped(hoarder, seconds(30)));
  EXPECT_NE(server.log().find("bytes of replies unread"), std::string::npos) << server.log();
  ExpectHealthy(server);
}

// The long one (its own ctest label): a subscriber to every body of a large
// world, every tick, that never reads for 30 s. Frames are latest-wins, so
// the server's memory stays flat while the sim keeps its rate and a reading
// subscriber keeps getting every frame of its own stream. The undelivered
// limit is raised so that latest-wins, not a disconnect, is what is tested.
TEST_F(BadInput, SlowNeverReadingSubscriberForThirtySeconds) {
  constexpr int kBodies = 2000;
  constexpr double kReaderRate = 30;
  constexpr auto kWindow = seconds(30);
  TumbledProcess server(sphere_grid(kBodies), {"--max-undelivered-seconds", "3600"});
  ASSERT_TRUE(server.started()) << server.log();
  const pid_t pid = server.process().pid();

  RawClient sleeper(server.port());
  ASSERT_TRUE(greet(sleeper));
  ASSERT_TRUE(sleeper.send(subscribe(2, 0)));

  RawClient reader(server.port());
  ASSERT_TRUE(greet(reader));
  const auto subscribed = ask(reader, subscribe(2, kReaderRate));
  ASSERT_TRUE(subscribed && subscribed->has_subscribed()) << describe(subscribed);
  const std::uint32_t period = subscribed->subscribed().period_ticks();

  // Warm up (first frames encoded, buffers filled), then take the baseline.
  const auto read_frame = [&]() -> std::optional<std::uint64_t> {
    const auto frame = reader.read_until([](const ServerMessage& m) { return m.has_pose_frame(); }, seconds(10));
    if (!frame) return std::nullopt;
    EXPECT_EQ(frame->pose_frame().ids_size(), kBodies + 1);
    return frame->pose_frame().tick();
  };
  const auto warm_up_end = Clock::now() + seconds(2);
  while (Clock::now() < warm_up_end) ASSERT_TRUE(read_frame()) << "the reader stopped getting frames";
  const std::int64_t baseline = resident_bytes(pid);
  ASSERT_GT(baseline, 0);

  const auto first = read_frame();
  ASSERT_TRUE(first);
  const auto start = Clock::now();
  std::uint64_t last = *first;
  int frames = 0;
  std::int64_t peak = baseline;
  auto next_sample = start;
  while (Clock::now() - start < kWindow) {
    const auto tick = read_frame();
    ASSERT_TRUE(tick) << "the reader stopped getting frames after " << frames;
    ++frames;
    last = *tick;
    if (Clock::now() >= next_sample) {
      peak = std::max(peak, resident_bytes(pid));
      next_sample += milliseconds(500);
    }
  }
  const double wall = std::chrono::duration<double>(Clock::now() - start).count();
  peak = std::max(peak, resident_bytes(pid));

  const double growth_mib = static_cast<double>(peak - baseline) / (1024.0 * 1024.0);
  const double ticks = static_cast<double>(last - *first);
  const double tick_ratio = ticks / (wall * kTickRate);
  const double expected_frames = ticks / period;
  std::cout << "[ figures  ] never-reading subscriber, " << kBodies << " bodies, " << wall << " s: RSS "
            << baseline / (1024 * 1024) << " MiB + " << growth_mib << " MiB at peak; ticks " << ticks << " ("
            << 100 * tick_ratio << "% of " << kTickRate << " Hz); reader frames " << frames << " of " << expected_frames
            << " (" << 100 * frames / expected_frames << "%)" << std::endl;
  EXPECT_LT(growth_mib, 64.0);
  // A server held up by the sleeper would stop stepping (a ratio near 0);
  // other work on a shared machine costs tens of percent, so the floor is low.
  EXPECT_GE(tick_ratio, 0.5);
  EXPECT_GE(static_cast<double>(frames), 0.9 * expected_frames);

  // The sleeper was subscribed all along and never disconnected: when it
  // reads at last, it finds its Subscribed, then gets a reply after at most
  // the few frames the socket buffers hold.
  const auto sleeper_subscribed = sleeper.read_until([](const ServerMessage& m) { return is_reply_to(m, 2); });
  EXPECT_TRUE(sleeper_subscribed && sleeper_subscribed->has_subscribed()) << describe(sleeper_subscribed);
  const auto reply = ask(sleeper, list_bodies(3), seconds(30));
  EXPECT_TRUE(reply && reply->has_body_list()) << describe(reply);
  ExpectHealthy(server);
}

}  // namespace
}  // namespace tumble::test
