// A DELTA stream over NATS read the way `tumble --nats` reads it (the
// client library's NatsConnection, SequenceGate and PoseStream), held
// against a FULL stream of the same world published from the same
// snapshots: every frame a reader shows must be the world at that tick,
// within the quantization grid, whether it joined late or fell so far
// behind that frames were dropped on its way.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "nats_messages.h"
#include "nats_server_process.h"
#include "nats_test_client.h"
#include "tumble_client/nats_connection.h"
#include "tumble_client/pose_sample.h"
#include "tumble_client/pose_stream.h"
#include "tumbled_process.h"

namespace tumble::test {
namespace {

using client::NatsConnection;
using client::PoseSample;

// Two bodies drifting and spinning in zero gravity: every frame differs
// from the one before, so a change applied to the wrong baseline shows.
constexpr const char* kDriftingScene = R"({"gravity": [0, 0, 0], "bodies": [
    {"name": "crate", "shape": {"box": {"half_extents": [0.5, 0.5, 0.5]}}, "mass": 2,
     "linear_velocity": [2, 0, 0], "angular_velocity": [0, 0, 1]},
    {"name": "ball", "shape": {"sphere": {"radius": 0.5}}, "mass": 1, "position": [0, 0, 50],
     "linear_velocity": [0, 0.5, 0], "angular_velocity": [1, 0, 0]}]})";

// Half a cell of the 1/1024 m grid, with room for float32 rounding.
constexpr double kPositionError = 1e-3;
// |q1 . q2| of two orientations the smallest-three grid cannot tell apart.
constexpr double kOrientationDot = 1 - 1e-5;

// What a frame shows, where the test can find it again: sequence and
// whether it stands alone.
struct Shown {
  PoseSample sample;
  std::uint64_t sequence = 0;
  bool key_frame = false;
};

class DeltaReaders : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(nats_.start()) << nats_.log();
    // No scheduled key frame after the first: a reader out of step comes
    // back only by asking.
    tumbled_ = std::make_unique<TumbledProcess>(
        kDriftingScene, std::vector<std::string>{"--nats", nats_.url(), "--world", "lab", "--nats-stream", "f=full@240",
                                                 "--nats-stream", "d=delta@240", "--nats-key-interval", "1000"});
    ASSERT_TRUE(tumbled_->started()) << tumbled_->log();
    observer_ = std::make_unique<NatsTestClient>(nats_.url());
    full_ = observer_->subscribe("tumble.v1.lab.poses.f");
    raw_delta_ = observer_->subscribe("tumble.v1.lab.poses.d");
    ASSERT_TRUE(full_ && raw_delta_) << observer_->error();
    ASSERT_TRUE(full_->wait_count(1)) << tumbled_->log();
  }

  // A reader of stream d, subscribed.
  std::unique_ptr<NatsConnection> reader() {
    client::NatsOptions options;
    options.servers = {nats_.url()};
    options.world = "lab";
    options.stream = "d";
    auto connection = NatsConnection::connect(options, std::chrono::seconds(10));
    EXPECT_TRUE(connection) << connection.failure().message;
    if (!connection) return nullptr;
    auto subscribed = connection->subscribe(tumble::v1::Subscribe{}, std::chrono::seconds(10));
    EXPECT_TRUE(subscribed) << subscribed.failure().message;
    if (!subscribed) return nullptr;
    return std::make_unique<NatsConnection>(std::move(connection).value());
  }

  // The next frame `connection` shows, decoded by `stream`.
  Shown next(NatsConnection& connection, client::PoseStream& stream) {
    auto message = connection.next_message(std::chrono::seconds(20));
    EXPECT_TRUE(message) << message.failure().message;
    if (!message || !message->has_pose_frame()) return {};
    const tumble::v1::PoseFrame& frame = message->pose_frame();
    auto sample = stream.decode(frame);
    EXPECT_TRUE(sample) << sample.failure().message;
    if (!sample) return {};
    return Shown{*sample, frame.sequence(), frame.key_frame()};
  }

  // The FULL stream's frame of `tick`, waited for; a test failure when the
  // stream passed that tick without one.
  PoseSample full_at(std::uint64_t tick) {
    const bool arrived = full_->wait([&](const std::vector<NatsMessage>& messages) {
      return !messages.empty() && parse_server_message(messages.back().data).pose_frame().tick() >= tick;
    });
    EXPECT_TRUE(arrived) << "no FULL frame up to tick " << tick;
    for (NatsMessage& m : full_->take()) {
      auto sample = client::unpack_pose_frame(parse_server_message(m.data).pose_frame());
      if (sample) full_by_tick_[sample->tick] = *sample;
    }
    const auto it = full_by_tick_.find(tick);
    EXPECT_NE(it, full_by_tick_.end()) << "the FULL stream has no frame of tick " << tick;
    return it == full_by_tick_.end() ? PoseSample{} : it->second;
  }

  // Every body of `shown` where the FULL frame of its tick has it.
  void expect_as_full(const Shown& shown) {
    const PoseSample full = full_at(shown.sample.tick);
    ASSERT_EQ(shown.sample.bodies.size(), full.bodies.size()) << "tick " << shown.sample.tick;
    for (std::size_t i = 0; i < full.bodies.size(); ++i) {
      const client::BodyPose& a = shown.sample.bodies[i];
      const client::BodyPose& b = full.bodies[i];
      ASSERT_EQ(a.id, b.id);
      for (std::size_t k = 0; k < 3; ++k) {
        EXPECT_NEAR(a.position[k], b.position[k], kPositionError)
            << "body " << a.id << " at tick " << shown.sample.tick << ", sequence " << shown.sequence;
      }
      double dot = 0;
      for (std::size_t k = 0; k < 4; ++k) dot += double(a.orientation[k]) * double(b.orientation[k]);
      EXPECT_GE(std::abs(dot), kOrientationDot) << "body " << a.id << " at tick " << shown.sample.tick;
    }
  }

  // The next `count` frames shown after `tick`: each later than the one
  // before, each as the FULL frame of its tick.
  void expect_next_as_full(NatsConnection& connection, client::PoseStream& stream, std::uint64_t tick, int count) {
    for (int i = 0; i < count; ++i) {
      const Shown shown = next(connection, stream);
      EXPECT_GT(shown.sample.tick, tick);
      tick = shown.sample.tick;
      expect_as_full(shown);
    }
  }

  NatsServerProcess nats_;
  std::unique_ptr<TumbledProcess> tumbled_;
  std::unique_ptr<NatsTestClient> observer_;  // reads the FULL stream and counts the DELTA one
  std::unique_ptr<NatsCollector> full_;
  std::unique_ptr<NatsCollector> raw_delta_;
  std::map<std::uint64_t, PoseSample> full_by_tick_;
};

TEST_F(DeltaReaders, ALateJoinerShowsTheWorldFromTheKeyFrameItAsksFor) {
  // Long after the stream's only scheduled key frame.
  ASSERT_TRUE(raw_delta_->wait_count(60));
  auto connection = reader();
  ASSERT_TRUE(connection);
  client::PoseStream stream;
  const Shown first = next(*connection, stream);
  EXPECT_TRUE(first.key_frame) << "a late joiner shows nothing before the key frame it asked for";
  EXPECT_GT(first.sequence, 60u);
  expect_as_full(first);
  // Later frames may include another key frame: a change published while
  // the key reply was on its way can overtake it, and the reader asks again.
  expect_next_as_full(*connection, stream, first.sample.tick, 30);
}

TEST_F(DeltaReaders, AReaderThatFellBehindShowsNothingWrongAndComesBackByItsKeyRequest) {
  auto connection = reader();
  ASSERT_TRUE(connection);
  client::PoseStream stream;
  Shown last;
  for (int i = 0; i < 5; ++i) {
    last = next(*connection, stream);
    expect_as_full(last);
  }
  // Not reading while more frames are published than the reader queues
  // (256): the oldest are dropped, and what is left does not follow on.
  const std::size_t published = raw_delta_->messages().size();
  ASSERT_TRUE(raw_delta_->wait_count(published + 400)) << tumbled_->log();
  const Shown back = next(*connection, stream);
  EXPECT_TRUE(back.key_frame) << "after a gap, the first frame shown is the key frame asked for";
  EXPECT_GT(back.sequence, last.sequence + 1);
  expect_as_full(back);
  expect_next_as_full(*connection, stream, back.sample.tick, 30);
}

}  // namespace
}  // namespace tumble::test
