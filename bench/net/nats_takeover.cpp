// nats_takeover: what keeping a world in JetStream (tumbled --nats-state)
// costs and how fast a standby takes it over. It starts three nats-server
// nodes with JetStream routed into one cluster on 127.0.0.1
// (nats_cluster.h) and measures, with real tumbled processes:
//
//  1. Takeover, R times: a leader and a --standby of one world of B
//     spinning cubes; a subscription on node 2 reads the world's pose
//     stream; the leader is SIGKILLed once it has written a checkpoint and
//     a standby waits, after a further delay drawn uniformly from one
//     checkpoint interval (so that kills fall at every phase of the
//     checkpoints and of the lease's renewals), and the time from the kill
//     to the first frame of the new leader (a larger epoch) is one sample. The killed server comes back as the
//     next standby. Every frame's epoch is checked in arrival order: a
//     frame of an older epoch after one of a newer is a stale frame (two
//     publishers). The tick goes back from the last frame of the old
//     leader to the first of the new by what the kill lost.
//  2. Checkpoints, for each size in --sizes: tumbled alone with that many
//     cubes for D seconds, with --nats-state and without it; Stats (over
//     .query, once a second) give each checkpoint's encoded size, the sim
//     thread's capture and the writer's time until JetStream acknowledged
//     it, and the tick's 99th percentile with and without.
//
// It prints one line of key=value fields for the takeover and one per size
// (bench/README.md), the takeover's runs on standard error as they go, and
// exits 3 when a frame did not decode, a takeover did not come or a stale
// frame was seen, 1 when the run could not be set up.
#include <signal.h>
#include <unistd.h>

#include <nats/nats.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "child_process.h"
#include "latency_probe.h"
#include "nats_cluster.h"
#include "tumble/v1/protocol.pb.h"
#include "tumble/v1/world_info.pb.h"
#include "tumble_client/nats_subjects.h"

namespace {

using Clock = std::chrono::steady_clock;

constexpr const char* kWorld = "bench";
constexpr const char* kStream = "q60";

struct Options {
  std::string tumbled;                                // path of the tumbled binary
  std::string nats_server = "/usr/sbin/nats-server";  // path of nats-server
  unsigned runs = 20;
  unsigned bodies = 1000;
  std::vector<unsigned> sizes = {1000, 10000};
  double seconds = 20;
  double checkpoint_interval_s = 1;
  double lease_renew_s = 0.5;
  double lease_timeout_s = 2;
  std::int64_t max_payload = 8 << 20;
};

[[noreturn]] void fail(const std::string& why) {
  std::fprintf(stderr, "nats_takeover: %s\n", why.c_str());
  std::exit(1);
}

std::string number_text(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

double ms_between(Clock::time_point from, Clock::time_point to) {
  return std::chrono::duration<double, std::milli>(to - from).count();
}

// A scene of `count` cubes (0.2 m, 1 kg) on a cubic grid 1 m apart, in no
// gravity, each spinning at 1 rad/s about a tilted axis: the world changes
// every tick (so every interval has a checkpoint), no two bodies ever
// touch, and a checkpoint holds `count` bodies in motion.
std::string spinning_cubes_scene(unsigned count) {
  const auto side = static_cast<unsigned>(std::ceil(std::cbrt(static_cast<double>(count))));
  std::ostringstream out;
  out << R"({"gravity": [0, 0, 0], "bodies": [)";
  for (unsigned i = 0; i < count; ++i) {
    const unsigned x = i % side;
    const unsigned y = (i / side) % side;
    const unsigned z = i / (side * side);
    out << (i == 0 ? "" : ",") << R"({"name": "c)" << i
        << R"(", "shape": {"box": {"half_extents": [0.1, 0.1, 0.1]}}, "mass": 1, "position": [)" << x << ", " << y
        << ", " << z << R"(], "angular_velocity": [0.6, 0.8, 0]})";
  }
  out << "]}";
  return out.str();
}

// One nats.c connection of the benchmark's own.
class NatsClient {
 public:
  explicit NatsClient(const std::string& url) {
    natsStatus status = natsConnection_ConnectTo(&connection_, url.c_str());
    if (status != NATS_OK) fail("connect to NATS at " + url + ": " + natsStatus_GetText(status));
  }
  ~NatsClient() { natsConnection_Destroy(connection_); }
  NatsClient(const NatsClient&) = delete;
  NatsClient& operator=(const NatsClient&) = delete;

  natsConnection* get() { return connection_; }

  // The first reply to `data` on `subject`, or nullopt.
  std::optional<std::string> request(const std::string& subject, const std::string& data,
                                     std::chrono::milliseconds timeout) {
    natsMsg* reply = nullptr;
    if (natsConnection_Request(&reply, connection_, subject.c_str(), data.data(), static_cast<int>(data.size()),
                               timeout.count()) != NATS_OK) {
      return std::nullopt;
    }
    std::string out(natsMsg_GetData(reply), static_cast<std::size_t>(natsMsg_GetDataLength(reply)));
    natsMsg_Destroy(reply);
    return out;
  }

  // Every reply to one request that came within `window`.
  std::vector<std::string> request_all(const std::string& subject, std::chrono::milliseconds window) {
    std::vector<std::string> replies;
    natsInbox* inbox = nullptr;
    natsSubscription* subscription = nullptr;
    if (natsInbox_Create(&inbox) == NATS_OK &&
        natsConnection_SubscribeSync(&subscription, connection_, inbox) == NATS_OK &&
        natsConnection_PublishRequest(connection_, subject.c_str(), inbox, nullptr, 0) == NATS_OK) {
      const Clock::time_point until = Clock::now() + window;
      for (;;) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(until - Clock::now()).count();
        natsMsg* reply = nullptr;
        if (left <= 0 || natsSubscription_NextMsg(&reply, subscription, left) != NATS_OK) break;
        replies.emplace_back(natsMsg_GetData(reply), static_cast<std::size_t>(natsMsg_GetDataLength(reply)));
        natsMsg_Destroy(reply);
      }
    }
    natsSubscription_Destroy(subscription);
    natsInbox_Destroy(inbox);
    return replies;
  }

 private:
  natsConnection* connection_ = nullptr;
};

// Stats of world `world` over its .query subject, or nullopt.
std::optional<tumble::v1::Stats> stats_of(NatsClient& client, const std::string& world) {
  tumble::v1::ClientMessage message;
  message.set_request_id(1);
  message.mutable_get_stats();
  const auto reply = client.request(tumble::client::query_subject(world), message.SerializeAsString(),
                                    std::chrono::milliseconds(1000));
  tumble::v1::ServerMessage answer;
  if (!reply || !answer.ParseFromString(*reply) || !answer.has_stats()) return std::nullopt;
  return answer.stats();
}

// Waits up to `timeout` for Stats that satisfy `ready`.
template <typename Ready>
tumble::v1::Stats wait_for_stats(NatsClient& client, const std::string& world, std::chrono::seconds timeout,
                                 const std::string& what, Ready ready) {
  const Clock::time_point give_up = Clock::now() + timeout;
  for (;;) {
    if (auto stats = stats_of(client, world); stats && ready(*stats)) return *stats;
    if (Clock::now() > give_up) fail("waited " + std::to_string(timeout.count()) + " s for " + what);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

// The standbys of `world` that answer tumble.v1.worlds now.
unsigned standbys_of(NatsClient& client, const std::string& world) {
  unsigned count = 0;
  for (const std::string& reply :
       client.request_all(std::string(tumble::client::kWorldsSubject), std::chrono::milliseconds(300))) {
    tumble::v1::WorldInfo info;
    if (info.ParseFromString(reply) && info.world() == world && info.standby()) ++count;
  }
  return count;
}

// The frames of the world's pose stream, in the order they arrive.
class FrameLog {
 public:
  struct Frame {
    Clock::time_point arrived;
    std::uint64_t tick = 0;
    std::uint64_t epoch = 0;
  };

  FrameLog(NatsClient& client, const std::string& subject) {
    if (natsConnection_Subscribe(&subscription_, client.get(), subject.c_str(), &FrameLog::on_message, this) !=
            NATS_OK ||
        natsSubscription_SetOnCompleteCB(subscription_, &FrameLog::on_complete, this) != NATS_OK ||
        natsSubscription_SetPendingLimits(subscription_, -1, -1) != NATS_OK) {
      fail("subscribing to " + subject);
    }
  }
  ~FrameLog() {
    std::unique_lock lock(mutex_);
    if (natsSubscription_Unsubscribe(subscription_) == NATS_OK) {
      changed_.wait_for(lock, std::chrono::seconds(10), [this] { return complete_; });
    }
    lock.unlock();
    natsSubscription_Destroy(subscription_);
  }
  FrameLog(const FrameLog&) = delete;
  FrameLog& operator=(const FrameLog&) = delete;

  // Waits up to `timeout` for a frame whose epoch satisfies `wanted`; the first such.
  template <typename Wanted>
  std::optional<Frame> wait_for(Wanted wanted, std::chrono::seconds timeout) {
    std::unique_lock lock(mutex_);
    std::optional<Frame> found;
    changed_.wait_for(lock, timeout, [&] {
      for (const Frame& frame : frames_) {
        if (wanted(frame)) {
          found = frame;
          return true;
        }
      }
      return false;
    });
    return found;
  }

  // The last frame of `epoch` received so far.
  std::optional<Frame> last_of(std::uint64_t epoch) {
    std::lock_guard lock(mutex_);
    for (auto it = frames_.rbegin(); it != frames_.rend(); ++it) {
      if (it->epoch == epoch) return *it;
    }
    return std::nullopt;
  }

  // Frames that came after one of a newer epoch, and frames that did not decode.
  std::uint64_t stale() {
    std::lock_guard lock(mutex_);
    return stale_;
  }
  std::uint64_t undecoded() {
    std::lock_guard lock(mutex_);
    return undecoded_;
  }

 private:
  static void on_message(natsConnection*, natsSubscription*, natsMsg* message, void* closure) {
    auto* self = static_cast<FrameLog*>(closure);
    const Clock::time_point arrived = Clock::now();
    tumble::v1::ServerMessage frame;
    const bool decoded =
        frame.ParseFromArray(natsMsg_GetData(message), natsMsg_GetDataLength(message)) && frame.has_pose_frame();
    natsMsg_Destroy(message);
    std::lock_guard lock(self->mutex_);
    if (!decoded) {
      ++self->undecoded_;
      return;
    }
    const std::uint64_t epoch = frame.pose_frame().epoch();
    if (epoch < self->newest_epoch_) ++self->stale_;
    self->newest_epoch_ = std::max(self->newest_epoch_, epoch);
    self->frames_.push_back({arrived, frame.pose_frame().tick(), epoch});
    // Only the recent frames are needed; keep the log small.
    if (self->frames_.size() > 4096) self->frames_.erase(self->frames_.begin(), self->frames_.begin() + 2048);
    self->changed_.notify_all();
  }
  static void on_complete(void* closure) {
    auto* self = static_cast<FrameLog*>(closure);
    std::lock_guard lock(self->mutex_);
    self->complete_ = true;
    self->changed_.notify_all();
  }

  natsSubscription* subscription_ = nullptr;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<Frame> frames_;
  std::uint64_t newest_epoch_ = 0;
  std::uint64_t stale_ = 0;
  std::uint64_t undecoded_ = 0;
  bool complete_ = false;
};

struct TakeoverResult {
  std::vector<double> takeover_ms;
  std::vector<double> ticks_back;
  std::uint64_t first_epoch = 0;
  std::uint64_t last_epoch = 0;
  std::uint64_t stale = 0;
  std::uint64_t undecoded = 0;
  unsigned missing = 0;  // kills after which no new leader published within 30 s
  double tick_rate_hz = 0;
};

TakeoverResult measure_takeovers(const Options& options, tumble::bench::NatsCluster& cluster, const std::string& dir) {
  const std::string scene = dir + "/takeover.json";
  std::ofstream(scene) << spinning_cubes_scene(options.bodies);
  std::vector<std::string> argv = {options.tumbled,
                                   "--listen",
                                   "none",
                                   "--scene",
                                   scene,
                                   "--nats",
                                   cluster.urls(),
                                   "--world",
                                   kWorld,
                                   "--nats-state",
                                   "--checkpoint-interval",
                                   number_text(options.checkpoint_interval_s),
                                   "--lease-renew",
                                   number_text(options.lease_renew_s),
                                   "--lease-timeout",
                                   number_text(options.lease_timeout_s)};
  std::vector<std::string> standby_argv = argv;
  standby_argv.push_back("--standby");

  NatsClient reader(cluster.url(2));
  NatsClient asker(cluster.url(1));
  FrameLog frames(reader, tumble::client::poses_subject(kWorld, kStream));
  natsConnection_Flush(reader.get());

  unsigned started = 0;
  const auto start = [&](const std::vector<std::string>& args) {
    auto process =
        std::make_unique<tumble::bench::ChildProcess>(args, dir + "/tumbled" + std::to_string(started++) + ".log");
    if (!process->started()) fail("cannot start " + options.tumbled);
    return process;
  };
  std::unique_ptr<tumble::bench::ChildProcess> leader = start(argv);
  const auto led =
      frames.wait_for([](const FrameLog::Frame& frame) { return frame.epoch > 0; }, std::chrono::seconds(60));
  if (!led) fail("the first leader published no frame in 60 s");
  TakeoverResult result;
  result.first_epoch = led->epoch;
  std::uint64_t epoch = led->epoch;
  std::unique_ptr<tumble::bench::ChildProcess> standby = start(standby_argv);

  std::mt19937 random(20261206);  // the same phases in every run of the benchmark
  std::uniform_real_distribution<double> phase(0.0, options.checkpoint_interval_s);
  for (unsigned run = 1; run <= options.runs; ++run) {
    // The leader has written a checkpoint of its own, and a standby waits.
    const tumble::v1::Stats led_stats =
        wait_for_stats(asker, kWorld, std::chrono::seconds(60), "a checkpoint of the leader",
                       [](const tumble::v1::Stats& stats) { return stats.checkpoints().written() >= 1; });
    result.tick_rate_hz = led_stats.tick_rate_hz();
    const Clock::time_point give_up = Clock::now() + std::chrono::seconds(60);
    while (standbys_of(asker, kWorld) == 0) {
      if (Clock::now() > give_up) fail("no standby answered in 60 s");
    }
    std::this_thread::sleep_for(std::chrono::duration<double>(phase(random)));
    const Clock::time_point killed = Clock::now();
    ::kill(leader->pid(), SIGKILL);
    const std::uint64_t old_epoch = epoch;
    const auto taken = frames.wait_for([&](const FrameLog::Frame& frame) { return frame.epoch > old_epoch; },
                                       std::chrono::seconds(30));
    leader->stop();
    if (!taken) {
      ++result.missing;
      std::fprintf(stderr, "run %u: no frame of a new leader within 30 s of the kill\n", run);
      break;
    }
    const auto last_old = frames.last_of(old_epoch);
    const double takeover = ms_between(killed, taken->arrived);
    const double back = last_old ? static_cast<double>(last_old->tick) - static_cast<double>(taken->tick) : 0.0;
    result.takeover_ms.push_back(takeover);
    result.ticks_back.push_back(back);
    epoch = taken->epoch;
    std::fprintf(stderr, "run %u: epoch %llu -> %llu, first frame %.0f ms after the kill, tick %llu -> %llu\n", run,
                 static_cast<unsigned long long>(old_epoch), static_cast<unsigned long long>(epoch), takeover,
                 static_cast<unsigned long long>(last_old ? last_old->tick : 0),
                 static_cast<unsigned long long>(taken->tick));
    // The standby leads now; the killed server comes back as the next standby.
    leader = std::move(standby);
    standby = start(standby_argv);
  }
  result.last_epoch = epoch;
  result.stale = frames.stale();
  result.undecoded = frames.undecoded();
  standby->stop();
  leader->stop();
  return result;
}

struct CheckpointResult {
  unsigned bodies = 0;
  std::uint64_t checkpoints = 0;
  std::uint64_t failed = 0;
  std::uint64_t bytes = 0;
  std::vector<double> write_ms;
  std::vector<double> capture_ms;
  double tick_ms_p99 = 0;
  double tick_cpu_ms_p99 = 0;
  double tick_ms_p99_without = 0;
  double tick_cpu_ms_p99_without = 0;
  std::uint64_t overruns = 0;
  std::uint64_t overruns_without = 0;
};

// tumbled alone with `bodies` cubes for the window, with --nats-state or
// without; each checkpoint's figures as Stats gives them once a second.
void run_world(const Options& options, tumble::bench::NatsCluster& cluster, const std::string& dir, unsigned bodies,
               bool keep_state, CheckpointResult* result) {
  const std::string world = "ckpt" + std::to_string(bodies) + (keep_state ? "s" : "n");
  const std::string scene = dir + "/" + world + ".json";
  std::ofstream(scene) << spinning_cubes_scene(bodies);
  std::vector<std::string> argv = {options.tumbled, "--listen",     "none",    "--scene", scene,
                                   "--nats",        cluster.urls(), "--world", world};
  if (keep_state) {
    argv.insert(argv.end(), {"--nats-state", "--checkpoint-interval", number_text(options.checkpoint_interval_s)});
  }
  tumble::bench::ChildProcess tumbled(argv, dir + "/" + world + ".log");
  if (!tumbled.started()) fail("cannot start " + options.tumbled);
  NatsClient client(cluster.url(1));
  // The window begins once the world runs (and has written its first checkpoint).
  const tumble::v1::Stats before =
      wait_for_stats(client, world, std::chrono::seconds(120), "world " + world, [&](const tumble::v1::Stats& stats) {
        return stats.tick() > 0 && (!keep_state || stats.checkpoints().written() >= 1);
      });
  std::uint64_t seen = before.checkpoints().written();
  const Clock::time_point end =
      Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(options.seconds));
  tumble::v1::Stats last = before;
  while (Clock::now() < end) {
    std::this_thread::sleep_for(std::chrono::milliseconds(250));
    const auto stats = stats_of(client, world);
    if (!stats) continue;
    last = *stats;
    if (keep_state && stats->checkpoints().written() > seen) {
      seen = stats->checkpoints().written();
      result->write_ms.push_back(stats->checkpoints().last_write_ms());
      result->capture_ms.push_back(stats->checkpoints().last_capture_ms());
      result->bytes = stats->checkpoints().last_bytes();
    }
  }
  if (keep_state) {
    result->checkpoints = last.checkpoints().written() - before.checkpoints().written();
    result->failed = last.checkpoints().failed();
    result->tick_ms_p99 = last.tick_ms_p99();
    result->tick_cpu_ms_p99 = last.tick_cpu_ms_p99();
    result->overruns = last.overruns() - before.overruns();
  } else {
    result->tick_ms_p99_without = last.tick_ms_p99();
    result->tick_cpu_ms_p99_without = last.tick_cpu_ms_p99();
    result->overruns_without = last.overruns() - before.overruns();
  }
  tumbled.stop();
}

double max_of(const std::vector<double>& values) {
  return values.empty() ? 0.0 : *std::max_element(values.begin(), values.end());
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  CLI::App app{"Takeover time and checkpoint cost of a world kept in a 3-node JetStream cluster"};
  app.add_option("--tumbled", options.tumbled, "Path of the tumbled binary to start")->required();
  app.add_option("--nats-server", options.nats_server, "Path of nats-server")->capture_default_str();
  app.add_option("--runs", options.runs, "R: takeovers to measure (0: none)")
      ->capture_default_str()
      ->check(CLI::Range(0u, 10000u));
  app.add_option("--bodies", options.bodies, "B: cubes in the world of the takeovers")
      ->capture_default_str()
      ->check(CLI::Range(1u, 100000u));
  app.add_option("--sizes", options.sizes, "Cubes in each world whose checkpoints are measured (none: no such run)")
      ->capture_default_str()
      ->check(CLI::Range(1u, 100000u));
  app.add_option("--seconds", options.seconds, "D: seconds of each checkpoint run, with and without --nats-state")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 86400.0));
  app.add_option("--checkpoint-interval", options.checkpoint_interval_s, "tumbled --checkpoint-interval, s")
      ->capture_default_str()
      ->check(CLI::Range(0.05, 3600.0));
  app.add_option("--lease-renew", options.lease_renew_s, "tumbled --lease-renew, s")->capture_default_str();
  app.add_option("--lease-timeout", options.lease_timeout_s, "tumbled --lease-timeout, s")->capture_default_str();
  app.add_option("--max-payload", options.max_payload,
                 "The nodes' max_payload, bytes: a checkpoint must fit in one message")
      ->capture_default_str()
      ->check(CLI::Range(std::int64_t{1} << 20, std::int64_t{64} << 20));
  CLI11_PARSE(app, argc, argv);

  const std::string dir = tumble::bench::make_temp_dir("nats_takeover");
  if (dir.empty()) fail("cannot make a temporary directory");
  tumble::bench::NatsCluster cluster(options.nats_server, dir, {.jetstream = true, .max_payload = options.max_payload});
  if (const std::string why = cluster.start(std::chrono::seconds(60)); !why.empty()) fail(why);

  bool failed = false;
  if (options.runs > 0) {
    const TakeoverResult takeovers = measure_takeovers(options, cluster, dir);
    const double goal_ms = (options.lease_timeout_s + 1) * 1000;
    const auto over_goal = std::count_if(takeovers.takeover_ms.begin(), takeovers.takeover_ms.end(),
                                         [&](double ms) { return ms > goal_ms; });
    const double interval_ticks = options.checkpoint_interval_s * takeovers.tick_rate_hz;
    std::printf(
        "phase=takeover runs=%zu bodies=%u lease_renew_s=%g lease_timeout_s=%g checkpoint_interval_s=%g "
        "takeover_ms_p50=%.0f takeover_ms_max=%.0f takeovers_over_goal=%lld ticks_back_p50=%.0f ticks_back_max=%.0f "
        "checkpoint_interval_ticks=%.0f epoch_first=%llu epoch_last=%llu stale_frames=%llu undecoded=%llu "
        "missing=%u\n",
        takeovers.takeover_ms.size(), options.bodies, options.lease_renew_s, options.lease_timeout_s,
        options.checkpoint_interval_s, tumble::bench::percentile(takeovers.takeover_ms, 0.5),
        max_of(takeovers.takeover_ms), static_cast<long long>(over_goal),
        tumble::bench::percentile(takeovers.ticks_back, 0.5), max_of(takeovers.ticks_back), interval_ticks,
        static_cast<unsigned long long>(takeovers.first_epoch), static_cast<unsigned long long>(takeovers.last_epoch),
        static_cast<unsigned long long>(takeovers.stale), static_cast<unsigned long long>(takeovers.undecoded),
        takeovers.missing);
    std::fflush(stdout);
    failed = takeovers.missing > 0 || takeovers.stale > 0 || takeovers.undecoded > 0;
  }
  for (const unsigned bodies : options.sizes) {
    CheckpointResult result;
    result.bodies = bodies;
    run_world(options, cluster, dir, bodies, false, &result);
    run_world(options, cluster, dir, bodies, true, &result);
    std::printf(
        "phase=checkpoint bodies=%u seconds=%g checkpoints=%llu failed=%llu bytes=%llu write_ms_p50=%.2f "
        "write_ms_max=%.2f capture_ms_p50=%.2f capture_ms_max=%.2f tick_ms_p99=%.3f tick_ms_p99_without=%.3f "
        "tick_cpu_ms_p99=%.3f tick_cpu_ms_p99_without=%.3f overruns=%llu overruns_without=%llu\n",
        bodies, options.seconds, static_cast<unsigned long long>(result.checkpoints),
        static_cast<unsigned long long>(result.failed), static_cast<unsigned long long>(result.bytes),
        tumble::bench::percentile(result.write_ms, 0.5), max_of(result.write_ms),
        tumble::bench::percentile(result.capture_ms, 0.5), max_of(result.capture_ms), result.tick_ms_p99,
        result.tick_ms_p99_without, result.tick_cpu_ms_p99, result.tick_cpu_ms_p99_without,
        static_cast<unsigned long long>(result.overruns), static_cast<unsigned long long>(result.overruns_without));
    std::fflush(stdout);
    failed = failed || result.checkpoints == 0 || result.failed > 0;
  }
  std::error_code ignored;
  std::filesystem::remove_all(dir, ignored);
  nats_CloseAndWait(2000);
  return failed ? 3 : 0;
}
