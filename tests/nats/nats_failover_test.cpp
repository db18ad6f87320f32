// A world kept in JetStream (--nats-state) taken over by a standby: a
// JetStream cluster of three real nats-server processes on loopback, two
// real tumbled for one world, a reader of the world's full stream from
// start to end. Every check is on frames (their epoch, tick and poses) and
// on what the servers answer; the waits are bounded polls.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <fstream>
#include <optional>
#include <thread>

#include "cli_helpers.h"
#include "nats_messages.h"
#include "nats_server_process.h"
#include "nats_test_client.h"
#include "poll_until.h"
#include "process.h"
#include "tumble/v1/protocol.pb.h"
#include "tumble/v1/world_info.pb.h"
#include "tumbled_process.h"

namespace tumble::test {
namespace {

using tumble::v1::ServerMessage;

constexpr std::uint64_t kTicksPerSecond = 240;  // tumbled's default tick rate
constexpr double kCheckpointInterval = 0.25;    // s
constexpr std::uint64_t kCheckpointTicks = 60;  // the same in ticks

// One frame of the full stream: its leader's epoch, tick, sim time, and
// where the crate was.
struct Seen {
  std::uint64_t epoch = 0;
  std::uint64_t tick = 0;
  double sim_time = 0;
  double crate_x = 0;
  double crate_vx = 0;
};

// The frames read so far, in arrival order, as they show body `crate`.
std::vector<Seen> seen_frames(NatsCollector& stream, std::optional<std::uint32_t> crate = std::nullopt) {
  std::vector<Seen> seen;
  for (const NatsMessage& message : stream.messages()) {
    const tumble::v1::PoseFrame frame = parse_server_message(message.data).pose_frame();
    for (int i = 0; i < frame.ids_size(); ++i) {
      if (crate && frame.ids(i) != *crate) continue;
      seen.push_back(
          {frame.epoch(), frame.tick(), frame.sim_time(), frame.positions(3 * i), frame.linear_velocities(3 * i)});
      break;
    }
  }
  return seen;
}

class NatsFailover : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(cluster_.start()) << cluster_.node(0).log() << cluster_.node(1).log() << cluster_.node(2).log();
    dir_ = make_temp_dir();
    std::ofstream(dir_ + "/scene.json") << kFloatingScene;
  }

  // A tumbled for world "lab" that may wait as a standby: not waited for.
  std::unique_ptr<ChildProcess> start_server(const std::string& name, std::vector<std::string> args) {
    std::vector<std::string> argv = {
        tumbled_path(),  "--scene",      dir_ + "/scene.json",    "--listen",
        "127.0.0.1:0",   "--nats",       cluster_.urls(),         "--world",
        "lab",           "--nats-state", "--checkpoint-interval", std::to_string(kCheckpointInterval),
        "--nats-stream", "f=full@60:all"};
    argv.insert(argv.end(), args.begin(), args.end());
    return std::make_unique<ChildProcess>(argv, dir_ + "/" + name + ".log");
  }
  std::string log_of(const std::string& name) const { return read_file(dir_ + "/" + name + ".log"); }

  // What the world's servers answer on tumble.v1.worlds.
  std::vector<tumble::v1::WorldInfo> worlds(NatsTestClient& client) {
    std::vector<tumble::v1::WorldInfo> infos;
    for (const std::string& reply : client.request_many("tumble.v1.worlds", "")) {
      tumble::v1::WorldInfo info;
      if (info.ParseFromString(reply) && info.world() == "lab") infos.push_back(info);
    }
    return infos;
  }

  // Polls until the world has one leader and `standbys` standbys; the leader's WorldInfo.
  std::optional<tumble::v1::WorldInfo> wait_for_roles(NatsTestClient& client, std::size_t standbys) {
    std::optional<tumble::v1::WorldInfo> leader;
    poll_until([&] {
      const auto infos = worlds(client);
      std::size_t leaders = 0;
      std::size_t waiting = 0;
      for (const auto& info : infos) {
        if (info.standby()) {
          ++waiting;
        } else {
          ++leaders;
          leader = info;
        }
      }
      return leaders == 1 && waiting == standbys;
    });
    return leader;
  }

  NatsCluster cluster_{{}, /*jetstream=*/true};
  std::string dir_;
};

// A controller pushing a body about every tick over .rpc, through its own
// connection, on a thread of its own until stopped; it counts how each
// push was answered.
class Pusher {
 public:
  Pusher(const std::string& url, std::string body) : body_(std::move(body)), thread_([this, url] { run(url); }) {}
  ~Pusher() { stop(); }

  void stop() {
    running_ = false;
    if (thread_.joinable()) thread_.join();
  }
  int acked() const { return acked_; }
  int refused() const { return refused_; }        // at once: no server serves the world
  int unanswered() const { return unanswered_; }  // no reply within the request's timeout
  int other_errors() const { return other_errors_; }
  bool connected() const { return connected_; }

 private:
  void run(const std::string& url) {
    NatsTestClient controller(url);
    connected_ = controller.connected();
    for (std::uint64_t id = 1000; running_ && connected_; ++id) {
      // Well under the lease timeout: the push in flight when the leader
      // dies gives up before a standby can lead, so those after it find
      // the world without a leader.
      const auto reply =
          controller.request("tumble.v1.lab.rpc", impulse_request(body_, 1e-4, id), std::chrono::milliseconds(750));
      if (reply) {
        tumble::v1::ServerMessage answer;
        (answer.ParseFromString(*reply) && answer.has_ack() && answer.ack().request_id() == id ? acked_
                                                                                               : other_errors_)++;
      } else if (controller.last_status() == NATS_NO_RESPONDERS) {
        ++refused_;
      } else {
        ++unanswered_;
      }
      // About a tick (1/240 s) between pushes: a load, not a wait for anything.
      std::this_thread::sleep_for(std::chrono::milliseconds(4));
    }
  }

  std::string body_;
  std::atomic<bool> running_{true};
  std::atomic<bool> connected_{false};
  std::atomic<int> acked_{0};
  std::atomic<int> refused_{0};
  std::atomic<int> unanswered_{0};
  std::atomic<int> other_errors_{0};
  std::thread thread_;
};

// Across everything read: epochs never go back (a frame of an older
// leader never follows one of a newer: one publisher at a time).
void expect_one_publisher_at_a_time(const std::vector<Seen>& seen) {
  for (std::size_t i = 1; i < seen.size(); ++i) {
    ASSERT_GE(seen[i].epoch, seen[i - 1].epoch) << "frame " << i << " at tick " << seen[i].tick;
  }
}

TEST_F(NatsFailover, TheStandbyLeadsAfterTheLeaderIsKilledAndTheWorldGoesOnFromItsLastCheckpoint) {
  auto leader = start_server("a", {});
  NatsTestClient client(cluster_.node(1).url());
  ASSERT_TRUE(client.connected());
  const auto first = wait_for_roles(client, 0);
  ASSERT_TRUE(first) << log_of("a");
  ASSERT_GT(first->epoch(), 0u);
  auto standby = start_server("b", {"--standby"});
  ASSERT_TRUE(wait_for_roles(client, 1)) << log_of("b");

  auto stream = client.subscribe("tumble.v1.lab.poses.f");
  ASSERT_TRUE(stream && stream->wait_count(10));
  tumble::v1::ClientMessage list;
  list.set_request_id(2);
  list.mutable_list_bodies();
  const ServerMessage bodies = parse_server_message(*client.request("tumble.v1.lab.rpc", list.SerializeAsString()));
  std::optional<std::uint32_t> crate;
  for (const auto& body : bodies.body_list().bodies()) {
    if (body.name() == "crate") crate = body.id();
  }
  ASSERT_TRUE(crate) << bodies.DebugString();
  // 480 N for one tick on 2 kg: the crate drifts along x at 1 m/s.
  const ServerMessage ack = parse_server_message(*client.request("tumble.v1.lab.rpc", force_request("crate", 480, 1)));
  ASSERT_TRUE(ack.has_ack()) << ack.DebugString();
  ASSERT_TRUE(stream->wait([&](const std::vector<NatsMessage>& messages) {
    return parse_server_message(messages.back().data).pose_frame().tick() >
           ack.ack().applied_tick() + 2 * kTicksPerSecond;
  }));

  // The CLI reads the stream too, through another node, and rides through.
  const std::string cli_out = dir_ + "/subscribe.out";
  ChildProcess cli(
      {tumble_cli_path(), "--nats", cluster_.node(2).url(), "--world", "lab", "--json", "subscribe", "--stream", "f"},
      cli_out, dir_ + "/subscribe.err");
  const auto lines = [&] {
    const std::string text = read_file(cli_out);
    return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
  };
  ASSERT_TRUE(poll_until([&] { return lines() >= 10; })) << read_file(dir_ + "/subscribe.err");

  // Under load: a controller pushes the ball about every tick through node 2.
  Pusher pusher(cluster_.node(2).url(), "ball");
  ASSERT_TRUE(poll_until([&] { return pusher.acked() >= 20; })) << "the leader answers the pushes";

  leader->signal(SIGKILL);
  leader->wait(std::chrono::seconds(10));
  const std::size_t printed_before = lines();
  const auto taken = [&] {
    const auto seen = seen_frames(*stream);
    return !seen.empty() && seen.back().epoch > first->epoch();
  };
  ASSERT_TRUE(poll_until(taken, std::chrono::seconds(20))) << log_of("b");
  // The new leader answers the pushes, too.
  const int acked_at_takeover = pusher.acked();
  EXPECT_TRUE(poll_until([&] { return pusher.acked() >= acked_at_takeover + 20; })) << log_of("b");
  pusher.stop();
  // Every push was answered or refused at once while nobody led the world;
  // only the one in flight when the leader died may have gone unanswered.
  EXPECT_GT(pusher.refused(), 0) << "pushes in the gap are refused, not queued";
  EXPECT_LE(pusher.unanswered(), 1);
  EXPECT_EQ(pusher.other_errors(), 0);
  // A second of the new leader's frames.
  const std::uint64_t resumed_at = seen_frames(*stream).back().tick;
  ASSERT_TRUE(stream->wait([&](const std::vector<NatsMessage>& messages) {
    return parse_server_message(messages.back().data).pose_frame().tick() > resumed_at + kTicksPerSecond;
  }));

  const std::vector<Seen> seen = seen_frames(*stream, crate);
  expect_one_publisher_at_a_time(seen);
  std::uint64_t last_old_tick = 0;
  std::optional<Seen> first_new;
  for (const Seen& frame : seen) {
    if (frame.epoch == first->epoch()) last_old_tick = frame.tick;
    if (frame.epoch > first->epoch() && !first_new) first_new = frame;
  }
  ASSERT_TRUE(first_new);
  // It resumed from the last checkpoint: at most one interval of sim time
  // behind the last frame seen (and half one more for a tick under way).
  EXPECT_GE(first_new->tick + kCheckpointTicks * 3 / 2, last_old_tick);
  // The pushed crate is where its checkpoint put it and drifts on at 1 m/s
  // under the new leader.
  for (const Seen& frame : seen) {
    if (frame.tick <= ack.ack().applied_tick()) continue;
    EXPECT_NEAR(frame.crate_vx, 1.0, 1e-6) << "tick " << frame.tick << " epoch " << frame.epoch;
  }
  const Seen& last = seen.back();
  EXPECT_NEAR(last.crate_x - first_new->crate_x, last.sim_time - first_new->sim_time, 1e-3);

  // The CLI printed the new leader's frames after the old one's (the old is gone).
  EXPECT_TRUE(poll_until([&] { return lines() >= printed_before + 30; })) << read_file(dir_ + "/subscribe.err");
  EXPECT_TRUE(cli.running()) << read_file(dir_ + "/subscribe.err");

  // The new leader answers for the world, with its epoch.
  const auto now = wait_for_roles(client, 0);
  ASSERT_TRUE(now);
  EXPECT_EQ(now->epoch(), seen.back().epoch);
  EXPECT_NE(now->server_id(), first->server_id());
}

TEST_F(NatsFailover, ALeaderStoppedPastTheTimeoutPublishesNothingMoreAndComesBackAsTheStandby) {
  auto a = start_server("a", {});
  NatsTestClient client(cluster_.node(1).url());
  const auto first = wait_for_roles(client, 0);
  ASSERT_TRUE(first) << log_of("a");
  auto b = start_server("b", {"--standby"});
  ASSERT_TRUE(wait_for_roles(client, 1)) << log_of("b");
  auto stream = client.subscribe("tumble.v1.lab.poses.f");
  ASSERT_TRUE(stream && stream->wait_count(10));

  a->signal(SIGSTOP);
  ASSERT_TRUE(poll_until(
      [&] {
        const auto seen = seen_frames(*stream);
        return !seen.empty() && seen.back().epoch > first->epoch();
      },
      std::chrono::seconds(20)))
      << log_of("b");
  a->signal(SIGCONT);
  // a finds its lease taken and starts again as b's standby.
  ASSERT_TRUE(poll_until([&] { return log_of("a").find("starting again as a standby") != std::string::npos; }))
      << log_of("a");
  const auto after = wait_for_roles(client, 1);
  ASSERT_TRUE(after) << log_of("a");
  EXPECT_GT(after->epoch(), first->epoch());
  // Another second of frames: every one from the new leader.
  const std::uint64_t from = seen_frames(*stream).back().tick;
  ASSERT_TRUE(stream->wait([&](const std::vector<NatsMessage>& messages) {
    return parse_server_message(messages.back().data).pose_frame().tick() > from + kTicksPerSecond;
  }));
  const std::vector<Seen> seen = seen_frames(*stream);
  expect_one_publisher_at_a_time(seen);
  EXPECT_EQ(seen.back().epoch, after->epoch());
  EXPECT_TRUE(a->running());
}

}  // namespace
}  // namespace tumble::test
