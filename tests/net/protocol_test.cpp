// The protocol on a real socket: handshake, requests and replies, pose
// streams, and bad input that must get a clear error and harm nobody else.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "poll_until.h"
#include "protocol_checks.h"
#include "raw_client.h"
#include "replies.h"
#include "requests.h"
#include "test_scenes.h"
#include "test_server.h"

namespace tumble::test {
namespace {

using tumble::v1::ClientMessage;
using tumble::v1::ServerMessage;

class ProtocolTest : public ::testing::Test {
 protected:
  TestServer server_{kCrateAndBallScene};
};

TEST_F(ProtocolTest, HelloIsAnsweredByWelcome) {
  RawClient client(server_.port());
  ASSERT_TRUE(client.connected());
  const auto welcome = client.handshake();
  ASSERT_TRUE(welcome && welcome->has_welcome()) << (welcome ? welcome->DebugString() : "no reply");
  EXPECT_EQ(welcome->welcome().protocol_version(), 1u);
  EXPECT_DOUBLE_EQ(welcome->welcome().tick_rate_hz(), 240);
  EXPECT_EQ(welcome->welcome().body_count(), 2u);
  EXPECT_EQ(welcome->welcome().server_version(), "test");
}

TEST_F(ProtocolTest, FirstMessageMustBeHello) {
  RawClient client(server_.port());
  ASSERT_TRUE(client.send(force(5, "crate", 1)));
  const auto reply = client.read();
  ASSERT_TRUE(reply && reply->has_error());
  EXPECT_EQ(reply->error().code(), tumble::v1::HANDSHAKE_REQUIRED);
  EXPECT_EQ(reply->error().request_id(), 5u);
  EXPECT_TRUE(client.closed_by_server());
}

TEST_F(ProtocolTest, OtherProtocolVersionsAreRefused) {
  RawClient client(server_.port());
  ClientMessage hello;
  hello.mutable_hello()->set_protocol_version(99);
  ASSERT_TRUE(client.send(hello));
  const auto reply = client.read();
  ASSERT_TRUE(reply && reply->has_error());
  EXPECT_EQ(reply->error().code(), tumble::v1::UNSUPPORTED_VERSION);
  EXPECT_NE(reply->error().message().find("99"), std::string::npos);
  EXPECT_TRUE(client.closed_by_server());
}

TEST_F(ProtocolTest, ForceIsAckedWithTheTickItTookEffect) {
  RawClient client(server_.port());
  ASSERT_TRUE(client.handshake());
  const std::uint64_t before = server_.sim().tick();
  ASSERT_TRUE(client.send(force(42, "crate", 10)));
  const auto reply = client.read_until([](const ServerMessage& m) { return is_reply_to(m, 42); });
  ASSERT_TRUE(reply && reply->has_ack()) << (reply ? reply->DebugString() : "no reply");
  EXPECT_GT(reply->ack().applied_tick(), before);
}

TEST_F(ProtocolTest, SubscriberGetsTheCurrentStateAtOnceThenFramesAtItsRate) {
  RawClient client(server_.port());
  ASSERT_TRUE(client.handshake());
  ASSERT_TRUE(client.send(subscribe(7, 60, {"ball"})));
  const auto subscribed = client.read();
  ASSERT_TRUE(subscribed && subscribed->has_subscribed()) << (subscribed ? subscribed->DebugString() : "none");
  EXPECT_EQ(subscribed->subscribed().request_id(), 7u);
  EXPECT_EQ(subscribed->subscribed().period_ticks(), 4u);
  EXPECT_DOUBLE_EQ(subscribed->subscribed().rate_hz(), 60);

  std::vector<std::uint64_t> ticks;
  for (int i = 0; i < 5; ++i) {
    const auto frame = client.read();
    ASSERT_TRUE(frame && frame->has_pose_frame());
    const auto& f = frame->pose_frame();
    EXPECT_EQ(f.subscription_id(), subscribed->subscribed().subscription_id());
    ASSERT_EQ(f.ids_size(), 1);
    ASSERT_EQ(f.positions_size(), 3);
    ASSERT_EQ(f.orientations_size(), 4);
    ASSERT_EQ(f.linear_velocities_size(), 3);
    ASSERT_EQ(f.angular_velocities_size(), 3);
    EXPECT_FLOAT_EQ(f.positions(0), 3.0f);
    EXPECT_FLOAT_EQ(f.orientations(0), 1.0f);
    EXPECT_NEAR(f.sim_time(), static_cast<double>(f.tick()) / 240.0, 1e-9);
    ticks.push_back(f.tick());
  }
  // After the first frame, frames fall on multiples of the period.
  for (std::size_t i = 1; i < ticks.size(); ++i) {
    EXPECT_EQ(ticks[i] % 4, 0u) << "tick " << ticks[i];
    EXPECT_GT(ticks[i], ticks[i - 1]);
  }
}

TEST_F(ProtocolTest, StreamsOfOtherBodiesAndRatesEachGetTheirOwnBodies) {
  // The sim copies into a snapshot only the bodies the streams due at its
  // tick read: every frame must still hold exactly its stream's bodies,
  // with the values a frame of every body shows at that tick.
  RawClient client(server_.port());
  ASSERT_TRUE(client.handshake());
  ASSERT_TRUE(client.send(impulse(1, "ball", 2)));  // the ball moves along x at 2 m/s
  const auto pushed = client.read_until([](const ServerMessage& m) { return is_reply_to(m, 1); });
  ASSERT_TRUE(pushed && pushed->has_ack());
  // The step of the applied tick already moves it (semi-implicit Euler).
  const std::uint64_t applied = pushed->ack().applied_tick();
  std::map<std::uint32_t, std::vector<std::uint32_t>> expected_ids;  // by subscription id
  const auto add = [&](std::uint64_t id, double rate_hz, std::initializer_list<const char*> names,
                       std::vector<std::uint32_t> ids) {
    ASSERT_TRUE(client.send(subscribe(id, rate_hz, names)));
    const auto reply = client.read_until([&](const ServerMessage& m) { return is_reply_to(m, id); });
    ASSERT_TRUE(reply && reply->has_subscribed());
    expected_ids[reply->subscribed().subscription_id()] = std::move(ids);
  };
  add(2, 240, {"ball"}, {1});
  add(3, 60, {}, {0, 1});
  add(4, 120, {"crate"}, {0});
  ASSERT_EQ(expected_ids.size(), 3u);

  std::map<std::uint32_t, std::vector<std::uint64_t>> ticks;  // by subscription id
  std::map<std::uint64_t, float> ball_x;                      // by tick, from any stream
  for (int i = 0; i < 60; ++i) {
    const auto message = client.read_until([](const ServerMessage& m) { return m.has_pose_frame(); });
    ASSERT_TRUE(message);
    const auto& frame = message->pose_frame();
    const auto expected = expected_ids.find(frame.subscription_id());
    ASSERT_NE(expected, expected_ids.end());
    const std::vector<std::uint32_t> ids(frame.ids().begin(), frame.ids().end());
    EXPECT_EQ(ids, expected->second) << "subscription " << frame.subscription_id() << ", tick " << frame.tick();
    ticks[frame.subscription_id()].push_back(frame.tick());
    for (int k = 0; k < frame.ids_size(); ++k) {
      if (frame.ids(k) != 1) continue;
      const float x = frame.positions(3 * k);
      const auto [seen, inserted] = ball_x.emplace(frame.tick(), x);
      EXPECT_EQ(seen->second, x) << "the ball at tick " << frame.tick() << " in two streams";
      if (!inserted) continue;
      const double steps = static_cast<double>(frame.tick() + 1 - applied);
      EXPECT_NEAR(x, 3.0 + 2.0 * steps / 240.0, 1e-5) << "tick " << frame.tick() << ", applied at " << applied;
    }
  }
  for (const auto& [id, seen] : ticks) {
    EXPECT_GE(seen.size(), 2u) << "subscription " << id;
    for (std::size_t k = 1; k < seen.size(); ++k) EXPECT_GT(seen[k], seen[k - 1]) << "subscription " << id;
  }
}

TEST(FanOut, InSlicesEverySessionGetsEveryFrameAndEventInOrder) {
  // A fan-out handed to one session a turn, with requests read in between:
  // each subscriber still sees its frames in tick order, and the removal
  // of a body before the first frame without it.
  std::string scene = R"({"gravity": [0, 0, 0], "bodies": [)";
  for (int i = 0; i < 60; ++i) {
    scene += std::string(i > 0 ? "," : "") + R"({"shape": {"sphere": {"radius": 0.2}}, "mass": 1, "position": [)" +
             std::to_string(i) + ", 0, 0]}";
  }
  scene += "]}";
  net::ServerConfig config;
  config.fanout_slice = std::chrono::microseconds(0);
  TestServer server(scene, 240, config);

  std::vector<std::unique_ptr<RawClient>> subscribers;
  for (int i = 0; i < 12; ++i) {
    subscribers.push_back(std::make_unique<RawClient>(server.port()));
    RawClient& client = *subscribers.back();
    ASSERT_TRUE(client.handshake());
    ClientMessage request = subscribe(1, 240, {});  // a frame every tick
    request.mutable_subscribe()->add_events(tumble::v1::WORLD_EVENT_BODY_REMOVED);
    ASSERT_TRUE(client.send(request));
    ASSERT_TRUE(client.read_until([](const ServerMessage& m) { return is_reply_to(m, 1); }));
  }
  RawClient controller(server.port());
  ASSERT_TRUE(controller.handshake());
  ClientMessage remove;
  remove.set_request_id(2);
  remove.mutable_remove_body()->mutable_body()->set_id(7);
  ASSERT_TRUE(controller.send(remove));
  const auto ack = controller.read_until([](const ServerMessage& m) { return is_reply_to(m, 2); });
  ASSERT_TRUE(ack && ack->has_ack()) << (ack ? ack->DebugString() : "no reply");
  const std::uint64_t removed_at = ack->ack().applied_tick();

  for (auto& client : subscribers) {
    std::uint64_t last_tick = 0;
    bool saw_event = false;
    int frames_after = 0;
    while (frames_after < 3) {
      const auto message =
          client->read_until([](const ServerMessage& m) { return m.has_pose_frame() || m.has_world_event(); });
      ASSERT_TRUE(message);
      if (message->has_world_event()) {
        EXPECT_EQ(message->world_event().body_id(), 7u);
        EXPECT_EQ(message->world_event().tick(), removed_at);
        saw_event = true;
        continue;
      }
      const auto& frame = message->pose_frame();
      EXPECT_GT(frame.tick(), last_tick);
      last_tick = frame.tick();
      const bool has_seven = std::find(frame.ids().begin(), frame.ids().end(), 7u) != frame.ids().end();
      if (saw_event) {
        EXPECT_GE(frame.tick(), removed_at) << "a frame from before the removal came after it";
      }
      if (frame.tick() < removed_at) {
        EXPECT_EQ(frame.ids_size(), 60);
        EXPECT_TRUE(has_seven);
        continue;
      }
      EXPECT_TRUE(saw_event) << "the removal comes before the frame of tick " << frame.tick();
      EXPECT_EQ(frame.ids_size(), 59);
      EXPECT_FALSE(has_seven);
      ++frames_after;
    }
  }
}

TEST_F(ProtocolTest, AForceShowsInTheFrameOfItsAppliedTick) {
  RawClient client(server_.port());
  ASSERT_TRUE(client.handshake());
  expect_impulse_shows_from_its_applied_tick(client);
}

TEST_F(ProtocolTest, UnknownBodyGetsAnErrorAndTheSessionGoesOn) {
  RawClient client(server_.port());
  ASSERT_TRUE(client.handshake());
  ASSERT_TRUE(client.send(force(3, "ghost", 1)));
  const auto reply = client.read_until([](const ServerMessage& m) { return is_reply_to(m, 3); });
  ASSERT_TRUE(reply && reply->has_error());
  EXPECT_EQ(reply->error().code(), tumble::v1::UNKNOWN_BODY);
  EXPECT_EQ(reply->error().message(), "no body 'ghost' in the world");

  ASSERT_TRUE(client.send(subscribe(4, 30, {"ghost"})));
  const auto sub = client.read_until([](const ServerMessage& m) { return is_reply_to(m, 4); });
  ASSERT_TRUE(sub && sub->has_error());
  EXPECT_EQ(sub->error().code(), tumble::v1::UNKNOWN_BODY);

  ASSERT_TRUE(client.send(force(5, "crate", 1)));
  const auto ok = client.read_until([](const ServerMessage& m) { return is_reply_to(m, 5); });
  ASSERT_TRUE(ok && ok->has_ack());
}

TEST_F(ProtocolTest, NaNForceGetsInvalidArgumentAndTheSessionGoesOn) {
  RawClient client(server_.port());
  ASSERT_TRUE(client.handshake());
  ASSERT_TRUE(client.send(force(8, "crate", std::numeric_limits<double>::quiet_NaN())));
  const auto reply = client.read_until([](const ServerMessage& m) { return is_reply_to(m, 8); });
  ASSERT_TRUE(reply && reply->has_error());
  EXPECT_EQ(reply->error().code(), tumble::v1::INVALID_ARGUMENT);
  ASSERT_TRUE(client.send(force(9, "crate", 1)));
  const auto ok = client.read_until([](const ServerMessage& m) { return is_reply_to(m, 9); });
  ASSERT_TRUE(ok && ok->has_ack());
  EXPECT_TRUE(std::isfinite(server_.sim().tick()));
}

TEST_F(ProtocolTest, AnEmptyEnvelopeIsAnUnknownMessage) {
  RawClient client(server_.port());
  ASSERT_TRUE(client.handshake());
  ClientMessage empty;
  empty.set_request_id(11);
  ASSERT_TRUE(client.send(empty));
  const auto reply = client.read_until([](const ServerMessage& m) { return is_reply_to(m, 11); });
  ASSERT_TRUE(reply && reply->has_error());
  EXPECT_EQ(reply->error().code(), tumble::v1::UNKNOWN_MESSAGE);
}

// Bad input on one connection: a clear error, that connection closed, and a
// subscriber on another connection keeps receiving frames throughout.
class BadInputTest : public ProtocolTest {
 protected:
  void SetUp() override {
    ASSERT_TRUE(watcher_.handshake());
    ASSERT_TRUE(watcher_.send(subscribe(1, 60)));
    ASSERT_TRUE(watcher_.read_until([](const ServerMessage& m) { return m.has_subscribed(); }));
  }

  void ExpectWatcherStillServed() {
    std::uint64_t first = 0;
    for (int i = 0; i < 3; ++i) {
      const auto frame = watcher_.read_until([](const ServerMessage& m) { return m.has_pose_frame(); });
      ASSERT_TRUE(frame) << "the other subscriber stopped receiving frames";
      if (i == 0) first = frame->pose_frame().tick();
      if (i == 2) {
        EXPECT_GT(frame->pose_frame().tick(), first);
      }
    }
  }

  RawClient watcher_{server_.port()};
};

TEST_F(BadInputTest, GarbageBytesGetMalformedFrameAndAClose) {
  RawClient client(server_.port());
  ASSERT_TRUE(client.handshake());
  // A length of 6 followed by six bytes that are no protobuf message (field 0 is invalid).
  ASSERT_TRUE(client.send_bytes(std::string("\x06\x00\xff\xff\xff\xff\xff", 7)));
  const auto reply = client.read();
  ASSERT_TRUE(reply && reply->has_error());
  EXPECT_EQ(reply->error().code(), tumble::v1::MALFORMED_FRAME);
  EXPECT_TRUE(client.closed_by_server());
  ExpectWatcherStillServed();
}

TEST_F(BadInputTest, OversizedFrameIsRefusedWithoutReadingIt) {
  RawClient client(server_.port());
  ASSERT_TRUE(client.handshake());
  // Announce 4 GiB and send a little of it: the server must refuse from the prefix alone.
  ASSERT_TRUE(client.send_bytes(std::string("\x80\x80\x80\x80\x10", 5) + std::string(1000, 'x')));
  const auto reply = client.read();
  ASSERT_TRUE(reply && reply->has_error());
  EXPECT_EQ(reply->error().code(), tumble::v1::FRAME_TOO_LARGE);
  EXPECT_NE(reply->error().message().find("4294967296"), std::string::npos) << reply->error().message();
  EXPECT_TRUE(client.closed_by_server());
  ExpectWatcherStillServed();
}

TEST_F(BadInputTest, FrameJustOverTheLimitIsRefused) {
  RawClient client(server_.port());
  ASSERT_TRUE(client.handshake());
  ClientMessage big;
  big.set_request_id(2);
  big.mutable_hello()->set_client_name(std::string(wire::kDefaultMaxFrameBytes, 'n'));
  ASSERT_TRUE(client.send(big));
  const auto reply = client.read();
  ASSERT_TRUE(reply && reply->has_error());
  EXPECT_EQ(reply->error().code(), tumble::v1::FRAME_TOO_LARGE);
  EXPECT_TRUE(client.closed_by_server());
  ExpectWatcherStillServed();
}

TEST_F(BadInputTest, BadVarintPrefixIsMalformed) {
  RawClient client(server_.port());
  ASSERT_TRUE(client.handshake());
  ASSERT_TRUE(client.send_bytes(std::string(12, '\xff')));
  const auto reply = client.read();
  ASSERT_TRUE(reply && reply->has_error());
  EXPECT_EQ(reply->error().code(), tumble::v1::MALFORMED_FRAME);
  EXPECT_TRUE(client.closed_by_server());
  ExpectWatcherStillServed();
}

TEST_F(BadInputTest, AClientThatVanishesMidFrameHarmsNobody) {
  {
    RawClient client(server_.port());
    ASSERT_TRUE(client.handshake());
    ASSERT_TRUE(client.send(subscribe(2, 0)));
    ASSERT_TRUE(client.send_bytes("\x40partial"));
  }  // closed without reading
  ExpectWatcherStillServed();
  RawClient next(server_.port());
  EXPECT_TRUE(next.handshake());
}

// This process's resident memory, in bytes: the in-process server's, since
// the test itself holds nothing that grows.
std::size_t resident_bytes() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stoul(line.substr(6)) * 1024;  // "VmRSS:   1234 kB"
  }
  ADD_FAILURE() << "no VmRSS in /proc/self/status";
  return 0;
}

// Waits until `sim` has stepped to `tick`; false if it does not within a minute.
bool reach_tick(sim::Simulation& sim, std::uint64_t tick) {
  return poll_until([&] { return sim.tick() >= tick; }, std::chrono::seconds(60));
}

TEST(NeverReadingClientTest, AClientThatNeverReadsDoesNotGrowTheServer) {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  // AddressSanitizer keeps freed memory resident in its quarantine (256 MB
  // by default) and ThreadSanitizer shadows what is allocated, so there the
  // resident set is not the server's: the plain build measures this.
  GTEST_SKIP() << "resident memory is not the server's under a sanitizer";
#endif
  // 400 bodies, every tick, to a client that never reads: about 12 kB a
  // frame, 240 frames a second. Frames are latest-wins, so once the socket
  // buffers are full the server holds one frame for this client however
  // long it waits. A server that queued every frame would grow by some
  // 3 MB a second.
  TestServer server(row_of_spheres(400));
  RawClient watcher(server.port());
  ASSERT_TRUE(watcher.handshake());
  ASSERT_TRUE(watcher.send(subscribe(1, 60, {"s0"})));
  ASSERT_TRUE(watcher.read_until([](const ServerMessage& m) { return m.has_subscribed(); }));

  RawClient sleeper(server.port());
  ASSERT_TRUE(sleeper.handshake());
  ASSERT_TRUE(sleeper.send(subscribe(2, 0)));
  const std::uint64_t start = server.sim().tick();
  // A second to fill the socket buffers and settle the allocator, then
  // three seconds of frames the client does not take.
  ASSERT_TRUE(reach_tick(server.sim(), start + 240));
  const std::size_t settled = resident_bytes();
  ASSERT_TRUE(reach_tick(server.sim(), start + 960));
  const std::size_t later = resident_bytes();
  // 720 frames queued would be over 8 MB; a bounded server stays within
  // the allocator's noise.
  EXPECT_LT(later, settled + (std::size_t{2} << 20)) << "grew from " << settled << " to " << later << " bytes";

  // And the other subscriber is served throughout.
  std::uint64_t first = 0;
  for (int i = 0; i < 3; ++i) {
    const auto frame = watcher.read_until([](const ServerMessage& m) { return m.has_pose_frame(); });
    ASSERT_TRUE(frame) << "the other subscriber stopped receiving frames";
    if (i == 0) first = frame->pose_frame().tick();
    if (i == 2) {
      EXPECT_GT(frame->pose_frame().tick(), first);
    }
  }
}

}  // namespace
}  // namespace tumble::test
