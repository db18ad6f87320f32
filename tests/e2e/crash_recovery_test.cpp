// Crash recovery under load, against the real processes: tumbled stepping a
// world of moving bodies while a client pushes one of them at every tick
// and `tumble subscribe --reconnect` prints every tick, with checkpoints
// every second, is killed with SIGKILL and restarted on the same port and
// state file. The world comes back at most one checkpoint interval older
// than the last frame seen, whole and as it was at that tick, and the
// subscriber rides through the restart without exiting.
#include <gtest/gtest.h>

#include <signal.h>

#include <array>
#include <atomic>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "cli_helpers.h"
#include "raw_client.h"
#include "sim/state_file.h"
#include "tumbled_process.h"

namespace tumble::test {
namespace {

using nlohmann::json;
using namespace std::chrono_literals;

// The world steps at 120 Hz and is checkpointed every second: one interval
// is 120 ticks.
constexpr const char* kTickRate = "120";
constexpr double kSecondsPerTick = 1.0 / 120;
constexpr const char* kCheckpointSeconds = "1";
constexpr std::uint64_t kIntervalTicks = 120;

// A kill loses at most one interval, plus this allowance (a quarter
// second): the checkpoint the saver thread was still writing when the kill
// came, whose predecessor is then the one on disk, and the few ticks a late
// sim thread runs back to back to catch up with its clock.
constexpr std::uint64_t kMarginTicks = 30;

// Zero gravity and no contacts, so each body's motion is its own: the
// drifter flies straight at constant velocity, the spinner tumbles about
// all three axes, the pushed box goes back and forth under the load's
// forces (its spin keeps it awake between pushes), and a grid of spheres
// drifting alike keeps the physics busy. The subscriber follows the
// first three.
std::string scene() {
  std::ostringstream text;
  text << R"({"gravity": [0, 0, 0], "bodies": [)"
       << R"({"name": "drifter", "shape": {"sphere": {"radius": 0.5}}, "mass": 1, "position": [-20, 0, 0],)"
       << R"( "linear_velocity": [1, 0.5, -0.25]},)"
       << R"({"name": "spinner", "shape": {"box": {"half_extents": [0.2, 0.4, 0.6]}}, "mass": 3,)"
       << R"( "position": [20, 0, 0], "angular_velocity": [0.3, 2, 0.1]},)"
       << R"({"name": "pushed", "shape": {"box": {"half_extents": [0.5, 0.5, 0.5]}}, "mass": 2,)"
       << R"( "angular_velocity": [0, 1, 0]})";
  for (int i = 0; i < 24; ++i) {
    text << R"(, {"name": "dust)" << i << R"(", "shape": {"sphere": {"radius": 0.3}}, "mass": 1, "position": [)"
         << 2 * (i % 6) - 5 << ", " << 2 * (i / 6) + 10 << R"(, 0], "linear_velocity": [0, 0, 0.3]})";
  }
  text << "]}";
  return text.str();
}

// The drifter's position at `tick`: x0 + v t, from tick 0 on.
std::array<double, 3> drifter_at(std::uint64_t tick) {
  const double t = static_cast<double>(tick) * kSecondsPerTick;
  return {-20 + 1 * t, 0.5 * t, -0.25 * t};
}

// Pushes "pushed" back and forth from a thread of its own: a force of 4 N
// along +x or -x for one tick, each as soon as the last was acknowledged
// (about one per tick). When the server goes away it connects again, until
// destroyed.
class PushingClient {
 public:
  explicit PushingClient(std::uint16_t port) : port_(port), thread_([this] { run(); }) {}
  ~PushingClient() {
    stop_ = true;
    thread_.join();
  }
  PushingClient(const PushingClient&) = delete;
  PushingClient& operator=(const PushingClient&) = delete;

  // Forces the server has acknowledged so far.
  std::uint64_t acked() const { return acked_; }

 private:
  void run() {
    while (!stop_) {
      RawClient client(port_);
      const auto welcome = client.connected() ? client.handshake("pusher") : std::nullopt;
      if (!welcome || !welcome->has_welcome()) {
        std::this_thread::sleep_for(50ms);
        continue;
      }
      std::uint64_t request_id = 1;
      double direction = 1;
      while (!stop_) {
        tumble::v1::ClientMessage push;
        push.set_request_id(++request_id);
        push.mutable_apply_force()->mutable_body()->set_name("pushed");
        push.mutable_apply_force()->mutable_force()->set_x(4 * direction);
        direction = -direction;
        if (!client.send(push)) break;
        const auto reply = client.read(100ms);
        if (reply && reply->has_ack()) ++acked_;
        if (client.saw_eof()) break;
      }
    }
  }

  const std::uint16_t port_;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> acked_{0};
  std::thread thread_;
};

// The frames a subscriber has printed to `path` so far: whole lines only.
std::vector<json> printed_frames(const std::string& path) {
  std::string text = read_file(path);
  const std::size_t end = text.rfind('\n');
  text.resize(end == std::string::npos ? 0 : end + 1);
  return json_lines(text);
}

std::uint64_t tick_of(const json& frame) { return frame.value("tick", std::uint64_t{0}); }

// Polls `done` every 10 ms for up to `limit`; true once it holds.
bool wait_until(const std::function<bool()>& done, std::chrono::seconds limit = 60s) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < deadline) {
    if (done()) return true;
    std::this_thread::sleep_for(10ms);
  }
  return done();
}

double norm(double x, double y, double z) { return std::sqrt(x * x + y * y + z * z); }

// Expects a frame's body to show the saved body within what it can have
// moved in `gap` ticks (float32 rounding when the frame is of the saved
// tick itself).
void expect_frame_shows(const json& body, const tumble::v1::SavedBody& saved, std::uint64_t gap) {
  const tumble::v1::BodySpec& spec = saved.spec();
  const double speed = norm(spec.linear_velocity().x(), spec.linear_velocity().y(), spec.linear_velocity().z());
  const double spin = norm(spec.angular_velocity().x(), spec.angular_velocity().y(), spec.angular_velocity().z());
  // A push changes the speed by 4 N / 2 kg per tick; a free tumble keeps |w| within a factor of 2 here.
  const double reach = (speed + 0.02 * static_cast<double>(gap)) * static_cast<double>(gap) * kSecondsPerTick;
  const double turn = spin * static_cast<double>(gap) * kSecondsPerTick;  // |dq/dt| = |w| / 2, doubled for the tumble
  const std::array<double, 3> position = {spec.position().x(), spec.position().y(), spec.position().z()};
  const std::array<double, 4> orientation = {spec.orientation().w(), spec.orientation().x(), spec.orientation().y(),
                                             spec.orientation().z()};
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_NEAR(body["position"][k].get<double>(), position[k], reach + 1e-5 * (1 + std::abs(position[k])))
        << body << " " << gap << " ticks from the checkpoint";
  }
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_NEAR(body["orientation"][k].get<double>(), orientation[k], turn + 1e-6)
        << body << " " << gap << " ticks from the checkpoint";
  }
}

TEST(CrashRecovery, AKilledServerComesBackAtMostOneCheckpointOlderAndSubscribersRideThrough) {
  const std::string dir = make_temp_dir();
  const std::string state_path = dir + "/world.state";
  const std::vector<std::string> flags = {"--tick-rate",           kTickRate,         "--state", state_path,
                                          "--checkpoint-interval", kCheckpointSeconds};
  auto first = std::make_unique<TumbledProcess>(scene(), flags);
  ASSERT_TRUE(first->started()) << first->log();
  const std::uint16_t port = first->port();
  PushingClient pusher(port);

  const std::string out_path = dir + "/subscriber.out";
  const std::string err_path = dir + "/subscriber.err";
  ChildProcess subscriber({tumble_cli_path(), "--server", first->server(), "--json", "subscribe", "--bodies",
                           "drifter,spinner,pushed", "--rate", "0", "--reconnect", "--reconnect-max-wait", "0.2"},
                          out_path, err_path);
  ASSERT_TRUE(subscriber.started());

  // A couple of intervals, then a fresh checkpoint, then the kill half an
  // interval of ticks after it: between two checkpoints, so that the world
  // comes back visibly older than the last frame.
  std::uint64_t first_tick = 0;
  ASSERT_TRUE(wait_until([&] {
    const auto frames = printed_frames(out_path);
    if (frames.empty()) return false;
    first_tick = tick_of(frames.front());
    return tick_of(frames.back()) >= first_tick + 2 * kIntervalTicks && checkpoint_tick(state_path) > 0;
  })) << "no frames or no checkpoint\n"
      << first->log() << read_file(err_path);
  const std::uint64_t earlier_checkpoint = checkpoint_tick(state_path);
  std::uint64_t fresh_checkpoint = 0;
  ASSERT_TRUE(wait_until([&] {
    fresh_checkpoint = checkpoint_tick(state_path);
    return fresh_checkpoint > earlier_checkpoint;
  })) << "no checkpoint after tick "
      << earlier_checkpoint;
  ASSERT_TRUE(wait_until([&] {
    const auto frames = printed_frames(out_path);
    return !frames.empty() && tick_of(frames.back()) >= fresh_checkpoint + kIntervalTicks / 2;
  }));
  const std::uint64_t acked_before_kill = pusher.acked();
  first->process().signal(SIGKILL);
  ASSERT_EQ(first->process().wait(10s), 128 + SIGKILL);
  const std::size_t printed_at_kill = printed_frames(out_path).size();
  EXPECT_GT(acked_before_kill, kIntervalTicks) << "the load pushed at least an interval's worth of times";

  // What the restart will resume: the last checkpoint that reached the disk whole.
  tumble::v1::WorldState saved;
  bool exists = false;
  ASSERT_TRUE(sim::read_state_file(state_path, &saved, &exists).ok());
  ASSERT_TRUE(exists);
  const std::uint64_t restored_tick = saved.tick();
  EXPECT_GE(restored_tick, fresh_checkpoint) << "a checkpoint on disk before the kill was lost";

  // The same port (the acceptor sets SO_REUSEADDR, so the old connections
  // in TIME_WAIT do not block it), the same state file; the scene file is
  // only the fallback for a first start, so an empty one proves nothing is
  // taken from it.
  first.reset();
  TumbledProcess second(R"({"bodies": []})", flags, port);
  ASSERT_TRUE(second.started()) << second.log();
  EXPECT_NE(second.log().find("from " + state_path + ", at tick " + std::to_string(restored_tick)), std::string::npos)
      << second.log();

  // The subscriber comes back and prints half an interval of new frames.
  std::vector<json> frames;
  std::size_t restart_at = 0;  // index of the first frame from the restarted server
  ASSERT_TRUE(wait_until([&] {
    frames = printed_frames(out_path);
    for (restart_at = 1; restart_at < frames.size(); ++restart_at) {
      if (tick_of(frames[restart_at]) < tick_of(frames[restart_at - 1])) break;
    }
    return restart_at < frames.size() && tick_of(frames.back()) >= tick_of(frames[restart_at]) + kIntervalTicks / 2;
  })) << "the subscriber did not come back with frames\n"
      << read_file(err_path) << second.log();
  EXPECT_TRUE(subscriber.running()) << "the subscriber exited\n" << read_file(err_path);
  subscriber.signal(SIGINT);
  EXPECT_EQ(subscriber.wait(30s), 0) << "Ctrl-C ends a reconnecting subscriber with success";

  // (a) At most one interval (plus the margin) older than the last frame
  // seen before the kill, and not newer.
  const std::uint64_t last_seen = tick_of(frames[restart_at - 1]);
  EXPECT_GE(restart_at, printed_at_kill) << "every frame printed before the kill came before the restart";
  EXPECT_LE(restored_tick, last_seen);
  EXPECT_LE(last_seen - restored_tick, kIntervalTicks + kMarginTicks)
      << "restored tick " << restored_tick << ", last tick seen " << last_seen;

  // (b) The restored world is the scene's bodies, ids and names and all,
  // as they were at that tick: the frame the subscriber printed closest to
  // it shows the same poses (to float32, or within what the bodies can
  // move in the ticks between), and the drifter is where its velocity took it.
  const json list = run_json(second, {"bodies"});
  ASSERT_EQ(list["bodies"].size(), 27u) << list;
  EXPECT_EQ(body(list, "drifter")["id"], 0);
  EXPECT_EQ(body(list, "spinner")["id"], 1);
  EXPECT_EQ(body(list, "pushed")["id"], 2);
  EXPECT_EQ(body(list, "dust23")["id"], 26);
  ASSERT_EQ(saved.bodies_size(), 27);
  std::map<std::string, const tumble::v1::SavedBody*> saved_by_name;
  for (const tumble::v1::SavedBody& b : saved.bodies()) saved_by_name[b.spec().name()] = &b;
  const json* closest = nullptr;
  std::uint64_t gap = 0;
  for (std::size_t i = 0; i < restart_at; ++i) {
    const std::uint64_t t = tick_of(frames[i]);
    const std::uint64_t distance = t > restored_tick ? t - restored_tick : restored_tick - t;
    if (closest == nullptr || distance < gap) {
      closest = &frames[i];
      gap = distance;
    }
  }
  ASSERT_NE(closest, nullptr);
  ASSERT_LE(gap, 4u) << "the stream skipped the ticks around the checkpoint";
  for (const char* name : {"drifter", "spinner", "pushed"}) {
    ASSERT_EQ(saved_by_name.count(name), 1u) << name;
    expect_frame_shows(body(*closest, name), *saved_by_name[name], gap);
  }
  for (const json& frame : frames) {
    const std::array<double, 3> expected = drifter_at(tick_of(frame));
    const json& drifter = body(frame, "drifter");
    for (std::size_t k = 0; k < 3; ++k) {
      ASSERT_NEAR(drifter["position"][k].get<double>(), expected[k], 1e-4) << frame;
    }
  }

  // (c) Frames from both servers on stdout and nothing else; the tick goes
  // back once, to the restored tick or a little after it (the restarted
  // server steps while the subscriber reconnects), then on one at a time.
  for (const json& frame : frames) ASSERT_TRUE(frame.is_object() && frame.contains("tick")) << frame;
  const std::uint64_t resumed_at = tick_of(frames[restart_at]);
  EXPECT_GE(resumed_at, restored_tick);
  EXPECT_LT(resumed_at, last_seen);
  for (std::size_t i = restart_at + 1; i < frames.size(); ++i) {
    EXPECT_GT(tick_of(frames[i]), tick_of(frames[i - 1])) << "the tick went back a second time";
  }
  const std::string notes = read_file(err_path);
  EXPECT_NE(notes.find("; reconnecting in "), std::string::npos) << notes;
  const std::string back = "tumble: reconnected to " + second.server() + " at tick ";
  const std::size_t at = notes.find(back);
  ASSERT_NE(at, std::string::npos) << notes;
  const std::uint64_t listed_at = std::stoull(notes.substr(at + back.size()));
  EXPECT_GE(listed_at, restored_tick) << notes;
  EXPECT_LE(listed_at, resumed_at) << notes;
  for (const std::string& line : lines_of(notes)) EXPECT_EQ(line.rfind("tumble: ", 0), 0u) << line;
}

}  // namespace
}  // namespace tumble::test
