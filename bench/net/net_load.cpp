// net_load: a load generator for tumbled's pose streams. It spawns a world
// (bench/net/load_world.h) into a running tumbled, opens S subscribers to
// its B bodies at R Hz, and measures on the client side, over D seconds:
// bytes per body per frame, frames received against expected, the
// force-to-visible latency (bench/net/latency_probe.h), and from the server
// its overruns (GetStats) and CPU (/proc, when it runs on this machine).
// Optionally it also sends world-changing requests at a fixed rate
// (bench/net/command_load.h). The subscribers share a few threads, each
// waiting on its share of their sockets at once (--subscriber-threads),
// at a lower priority (--subscriber-nice, or --subscriber-idle): on one
// machine with the server they would otherwise take the cores that
// clients elsewhere would not. It prints one line of key=value fields
// (bench/README.md), and exits 3 when any request or stream failed.
#include <poll.h>
#include <sys/types.h>
#include <unistd.h>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "command_load.h"
#include "latency_probe.h"
#include "load_connection.h"
#include "load_world.h"
#include "measured_window.h"
#include "process_cpu.h"
#include "stall_watch.h"
#include "thread_priority.h"
#include "tumble_client/pose_stream.h"

namespace {

using Clock = std::chrono::steady_clock;
using tumble::bench::LoadTarget;

struct Options {
  LoadTarget target;
  std::string world = "field";
  unsigned subscribers = 8;
  unsigned bodies = 1000;
  double rate_hz = 30;
  std::string encoding = "full";
  double seconds = 10;
  double moving = 0.1;
  bool kinematic_movers = false;
  bool settle = false;
  double commands_per_second = 0;
  pid_t server_pid = 0;
  unsigned spawners = 16;
  int subscriber_nice = 10;
  unsigned subscriber_threads = 25;
  bool subscriber_idle = false;
  std::string latency_log;   // a CSV of every latency sample; none when empty
  bool stall_watch = false;  // watch for stalls of the machine (stall_watch.h)
  double probe_rate_hz = 0;  // the latency watcher's stream; 0: the tick rate
};

using Window = tumble::bench::MeasuredWindow;

// What one subscriber counted inside the window.
struct Tally {
  std::uint64_t frames = 0;
  std::uint64_t bytes = 0;        // PoseFrame messages as framed on the wire
  std::uint64_t body_slots = 0;   // bodies the frames stood for (DELTA: after completion)
  double max_bytes_per_body = 0;  // of the largest frame for its bodies
  std::uint64_t errors = 0;       // a stream that broke or did not decode
};

tumble::v1::PoseEncoding encoding_of(const std::string& name, unsigned index) {
  // "mixed": the subscribers take full, quantized and delta in turn.
  const std::string chosen = name == "mixed" ? std::string(index % 3 == 0   ? "full"
                                                           : index % 3 == 1 ? "quantized"
                                                                            : "delta")
                                             : name;
  if (chosen == "quantized") return tumble::v1::POSE_ENCODING_QUANTIZED;
  if (chosen == "delta") return tumble::v1::POSE_ENCODING_DELTA;
  return tumble::v1::POSE_ENCODING_FULL;
}

// Bytes of a message with its varint length prefix.
std::uint64_t framed_size(const tumble::v1::ServerMessage& message) {
  const std::size_t body = message.ByteSizeLong();
  std::size_t prefix = 1;
  for (std::size_t rest = body >> 7; rest > 0; rest >>= 7) ++prefix;
  return body + prefix;
}

// One subscriber: its connection, what it holds of its stream, and what
// it counted.
struct Subscriber {
  unsigned index = 0;
  tumble::client::Connection connection;
  tumble::client::PoseStream stream;
  bool first = true;  // no frame yet
  bool broken = false;
  Tally tally;
};

// Takes one message a subscriber received: checks a frame and applies a
// DELTA one (PoseStream::apply) without converting the values to floats
// (the load generator shares the machine with the server), reports in
// through `ready` at the first, and counts it inside the window.
void take_message(Subscriber& subscriber, const tumble::v1::ServerMessage& message, std::atomic<unsigned>& ready,
                  const Window& window) {
  if (!message.has_pose_frame()) return;
  const Clock::time_point arrived = Clock::now();
  auto count = subscriber.stream.apply(message.pose_frame());
  if (!count) {
    std::fprintf(stderr, "net_load: subscriber %u: %s\n", subscriber.index, count.failure().message.c_str());
    ++subscriber.tally.errors;
    subscriber.broken = true;
    return;
  }
  if (subscriber.first) {
    subscriber.first = false;
    ++ready;
  }
  if (!window.contains(arrived)) return;
  const std::uint64_t bytes = framed_size(message);
  Tally& tally = subscriber.tally;
  ++tally.frames;
  tally.bytes += bytes;
  tally.body_slots += *count;
  if (*count > 0) {
    tally.max_bytes_per_body =
        std::max(tally.max_bytes_per_body, static_cast<double>(bytes) / static_cast<double>(*count));
  }
}

// The subscribers `indices`, on the calling thread: each subscribes to
// `bodies`, then one loop waits on all their sockets at once (poll(2)) and
// takes what arrived on each, as a client program serving many streams
// would, until the window ends. Their tallies go to `tallies`.
void run_subscribers(const Options& options, const std::vector<unsigned>& indices,
                     const std::vector<std::uint32_t>& bodies, std::atomic<unsigned>& ready, const Window& window,
                     std::vector<Tally>& tallies) {
  tumble::bench::set_thread_priority(options.subscriber_nice, options.subscriber_idle, "net_load");
  std::vector<Subscriber> subscribers;
  subscribers.reserve(indices.size());
  for (const unsigned index : indices) {
    tumble::client::Connection connection =
        tumble::bench::connect_or_exit(options.target, "net_load-" + std::to_string(index));
    tumble::v1::Subscribe request;
    request.set_rate_hz(options.rate_hz);
    request.set_fields(tumble::v1::POSE_FIELDS_POSE);
    request.set_encoding(encoding_of(options.encoding, index));
    for (const std::uint32_t id : bodies) request.add_bodies()->set_id(id);
    auto subscribed = connection.subscribe(request, std::chrono::seconds(30));
    if (!subscribed) tumble::bench::exit_with("subscribe", subscribed.failure());
    subscribers.push_back(Subscriber{index, std::move(connection), {}, true, false, {}});
  }

  std::vector<pollfd> sockets;
  while (!window.over(Clock::now())) {
    // Everything that has arrived (a subscribe may have queued frames),
    // then wait for more on every socket still open.
    sockets.clear();
    for (Subscriber& subscriber : subscribers) {
      while (!subscriber.broken) {
        auto message = subscriber.connection.poll_message();
        if (message) {
          take_message(subscriber, *message, ready, window);
          continue;
        }
        if (message.failure().kind != tumble::client::FailureKind::timeout) {
          std::fprintf(stderr, "net_load: subscriber %u: %s\n", subscriber.index, message.failure().message.c_str());
          ++subscriber.tally.errors;
          subscriber.broken = true;
        }
        break;
      }
      if (!subscriber.broken) sockets.push_back(pollfd{subscriber.connection.native_handle(), POLLIN, 0});
    }
    if (sockets.empty()) break;
    ::poll(sockets.data(), sockets.size(), 100);
  }
  for (Subscriber& subscriber : subscribers) {
    if (subscriber.first) ++ready;  // never got going: do not hold the others up
    tallies[subscriber.index] = subscriber.tally;
  }
}

tumble::v1::Stats stats_or_exit(tumble::client::Connection& controller) {
  auto stats = controller.get_stats(std::chrono::seconds(10));
  if (!stats) tumble::bench::exit_with("stats", stats.failure());
  return *stats;
}

// Waits until the bodies that come to rest are asleep (at most 60 s).
void settle(tumble::client::Connection& controller, unsigned resting) {
  const Clock::time_point give_up = Clock::now() + std::chrono::seconds(60);
  while (stats_or_exit(controller).bodies_asleep() < resting) {
    if (Clock::now() > give_up) {
      std::fprintf(stderr, "net_load: the bodies did not come to rest within 60 s\n");
      std::exit(1);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  CLI::App app{"Load generator for tumbled's pose streams"};
  app.add_option("--server", options.target.server, "tumbled to load, HOST:PORT")->capture_default_str();
  app.add_option("--token", options.target.token, "Controller token, when the server asks for one");
  app.add_option("--world", options.world, "field or cubes, for a world with gravity; see bench/README.md")
      ->capture_default_str()
      ->check(CLI::IsMember({"field", "cubes"}));
  app.add_option("--subscribers", options.subscribers, "S: subscribers")
      ->capture_default_str()
      ->check(CLI::Range(1u, 10000u));
  app.add_option("--bodies", options.bodies, "B: bodies to spawn and follow")
      ->capture_default_str()
      ->check(CLI::Range(1u, 1000000u));
  app.add_option("--rate", options.rate_hz, "R: frames per second per subscriber")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 10000.0));
  app.add_option("--encoding", options.encoding, "full, quantized, delta, or mixed (the three in turn)")
      ->capture_default_str()
      ->check(CLI::IsMember({"full", "quantized", "delta", "mixed"}));
  app.add_option("--seconds", options.seconds, "D: measured seconds")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 86400.0));
  app.add_option("--moving", options.moving, "field: the fraction of the bodies that spin")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  app.add_flag("--kinematic-movers", options.kinematic_movers,
               "field: the spinning bodies are kinematic (driven, not simulated)");
  app.add_flag("--settle", options.settle, "Measure once the bodies that come to rest are asleep, not from the start");
  app.add_option("--commands-per-second", options.commands_per_second,
                 "Also send this many forces, impulses and sets a second")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 10000.0));
  app.add_option("--server-pid", options.server_pid, "tumbled's process id, to report its CPU")
      ->check(CLI::Range(1, std::numeric_limits<int>::max()));
  app.add_option("--spawners", options.spawners, "Connections that spawn the world at once")
      ->capture_default_str()
      ->check(CLI::Range(1u, 256u));
  app.add_option("--subscriber-threads", options.subscriber_threads,
                 "Threads the subscribers share, each waiting on its share of their sockets at once "
                 "(as many as --subscribers: a thread each)")
      ->capture_default_str()
      ->check(CLI::Range(1u, 10000u));
  app.add_option("--subscriber-nice", options.subscriber_nice,
                 "Nice value of the subscribers' threads: they stand for clients on other machines, so by default "
                 "they take only the CPU the server leaves; the latency probe keeps the process's")
      ->capture_default_str()
      ->check(CLI::Range(0, 19));
  app.add_flag("--subscriber-idle", options.subscriber_idle,
               "Run the subscribers' threads under SCHED_IDLE (Linux): a core only when the server and the probe "
               "want none, the nearest one machine comes to clients on others");
  app.add_option("--latency-log", options.latency_log,
                 "Write every latency sample to this file, a CSV line each: sent_s (seconds into the window), "
                 "latency_ms, applied_tick (the server's tick that applied the change), in_stall (with "
                 "--stall-watch: 1 when the sample spans a stall of the machine)");
  app.add_flag("--stall-watch", options.stall_watch,
               "Watch every CPU for stalls of the machine itself (a SCHED_FIFO thread a CPU waking every 1 ms; "
               "needs root or RLIMIT_RTPRIO 90) and report them and the latency samples they touch");
  app.add_option("--probe-rate", options.probe_rate_hz,
                 "Rate of the latency watcher's stream of the probe, Hz (default: the tick rate, a frame every "
                 "tick; the subscribers' rate puts the probe's frames on their ticks, as over NATS)")
      ->check(CLI::Range(0.1, 10000.0));
  CLI11_PARSE(app, argc, argv);

  if (options.stall_watch) {
    if (const std::string refusal = tumble::bench::stall_watch_refusal(); !refusal.empty()) {
      std::fprintf(stderr, "net_load: --stall-watch: %s\n", refusal.c_str());
      return 2;
    }
  }

  // Opened first, so that a path it cannot write fails before any load.
  std::FILE* latency_log = nullptr;
  if (!options.latency_log.empty()) {
    latency_log = std::fopen(options.latency_log.c_str(), "w");
    if (latency_log == nullptr) {
      std::perror(("net_load: " + options.latency_log).c_str());
      return 1;
    }
  }

  tumble::client::Connection controller = tumble::bench::connect_or_exit(options.target, "net_load");
  // Paused while the world is built and the subscribers join, so that the
  // measured window starts with the world as it was spawned.
  if (auto paused = controller.pause(std::chrono::seconds(10)); !paused) {
    tumble::bench::exit_with("pause", paused.failure());
  }
  tumble::bench::WorldOptions world_options;
  world_options.layout =
      options.world == "cubes" ? tumble::bench::WorldLayout::cubes : tumble::bench::WorldLayout::field;
  world_options.bodies = options.bodies;
  world_options.moving = options.moving;
  world_options.kinematic_movers = options.kinematic_movers;
  const tumble::bench::LoadWorld world = tumble::bench::spawn_world(options.target, world_options, options.spawners);

  Window window;
  std::atomic<unsigned> ready{0};
  std::vector<Tally> tallies(options.subscribers);
  std::vector<std::thread> threads;
  const unsigned subscriber_threads = std::min(options.subscriber_threads, options.subscribers);
  std::vector<std::vector<unsigned>> shares(subscriber_threads);
  for (unsigned i = 0; i < options.subscribers; ++i) shares[i % subscriber_threads].push_back(i);
  for (const std::vector<unsigned>& share : shares) {
    threads.emplace_back([&, share] { run_subscribers(options, share, world.bodies, ready, window, tallies); });
  }
  while (ready.load() < options.subscribers) std::this_thread::sleep_for(std::chrono::milliseconds(10));

  if (auto resumed = controller.resume(std::chrono::seconds(10)); !resumed) {
    tumble::bench::exit_with("resume", resumed.failure());
  }
  if (options.settle) settle(controller, world.resting);
  const tumble::v1::Stats before = stats_or_exit(controller);
  const std::optional<double> server_cpu_before =
      options.server_pid > 0 ? tumble::bench::process_cpu_seconds(options.server_pid) : std::nullopt;
  const std::optional<double> own_cpu_before = tumble::bench::process_cpu_seconds(getpid());
  const Clock::time_point start = Clock::now();
  const Clock::time_point end =
      start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(options.seconds));
  window.set(start, end);

  tumble::bench::LatencyResult latency;
  threads.emplace_back([&] {
    const double probe_rate_hz = options.probe_rate_hz > 0 ? options.probe_rate_hz : before.tick_rate_hz();
    latency = tumble::bench::measure_latency(options.target, world.probe, probe_rate_hz,
                                             encoding_of(options.encoding, 0), start, end);
  });
  std::vector<tumble::bench::Stall> stalls;
  std::string stall_error;
  if (options.stall_watch) {
    // Until the latency probe's last change has had time to show.
    threads.emplace_back([&] {
      try {
        stalls = tumble::bench::watch_stalls(start, end + std::chrono::seconds(1));
      } catch (const std::exception& e) {
        stall_error = e.what();
      }
    });
  }
  tumble::bench::CommandTally commands;
  if (options.commands_per_second > 0) {
    threads.emplace_back([&] {
      commands = tumble::bench::run_commands(options.target, world.bodies, options.commands_per_second, end);
    });
  }
  for (std::thread& thread : threads) thread.join();

  // CPU over the window and the moments the threads took to end after it
  // (a read's timeout, the latency probe's last change): the same wall time for both processes.
  const double wall = std::chrono::duration<double>(Clock::now() - start).count();
  const tumble::v1::Stats after = stats_or_exit(controller);
  const auto cpu_over_window = [&](std::optional<double> before_seconds, pid_t pid) -> std::string {
    const std::optional<double> now = tumble::bench::process_cpu_seconds(pid);
    if (!before_seconds || !now) return "-";
    char text[32];
    std::snprintf(text, sizeof text, "%.0f", tumble::bench::cpu_percent(*now - *before_seconds, wall));
    return text;
  };
  const std::string server_cpu = options.server_pid > 0 ? cpu_over_window(server_cpu_before, options.server_pid) : "-";
  const std::string own_cpu = cpu_over_window(own_cpu_before, getpid());

  Tally total;
  double min_frames = std::numeric_limits<double>::max();
  for (const Tally& tally : tallies) {
    total.frames += tally.frames;
    total.bytes += tally.bytes;
    total.body_slots += tally.body_slots;
    total.errors += tally.errors;
    total.max_bytes_per_body = std::max(total.max_bytes_per_body, tally.max_bytes_per_body);
    min_frames = std::min(min_frames, static_cast<double>(tally.frames));
  }
  // The server rounds the rate to a whole number of ticks.
  const double period_ticks = std::max(1.0, std::round(after.tick_rate_hz() / options.rate_hz));
  const double expected_each = options.seconds * after.tick_rate_hz() / period_ticks;
  const std::uint64_t errors = total.errors + latency.errors + commands.errors + (stall_error.empty() ? 0 : 1);
  if (!stall_error.empty()) std::fprintf(stderr, "net_load: %s\n", stall_error.c_str());
  // Each sample's span, from its send to the frame that showed it.
  std::vector<bool> in_stall(latency.samples.size(), false);
  const double goal_ms = 1000 / after.tick_rate_hz() + 2;
  std::size_t slow = 0, slow_in_stall = 0;
  std::vector<double> outside_stalls_ms;  // the server's path alone: samples no stall of the machine touched
  for (std::size_t i = 0; i < latency.samples.size(); ++i) {
    const tumble::bench::LatencySample& sample = latency.samples[i];
    in_stall[i] = tumble::bench::overlaps_stall(stalls, sample.sent_s, sample.sent_s + sample.latency_ms / 1000);
    if (!in_stall[i]) outside_stalls_ms.push_back(sample.latency_ms);
    if (sample.latency_ms > goal_ms) {
      ++slow;
      if (in_stall[i]) ++slow_in_stall;
    }
  }
  std::printf(
      "world=%s encoding=%s subscribers=%u bodies=%u rate_hz=%g tick_rate_hz=%g seconds=%g "
      "bytes_per_body_frame=%.2f bytes_per_body_frame_max=%.2f kbit_per_s_per_subscriber=%.1f "
      "frames=%llu frames_expected=%.0f frames_min_percent=%.1f "
      "latency_samples=%zu latency_lost=%llu latency_ms_p50=%.2f latency_ms_p99=%.2f latency_goal_ms=%.2f "
      "overruns=%llu ticks=%llu tick_ms_p50=%.2f tick_ms_p99=%.2f tick_cpu_ms_p99=%.2f tick_late_ms_p50=%.2f "
      "tick_late_ms_p99=%.2f "
      "server_cpu_percent=%s load_cpu_percent=%s commands=%llu errors=%llu",
      options.world.c_str(), options.encoding.c_str(), options.subscribers, options.bodies, options.rate_hz,
      after.tick_rate_hz(), options.seconds,
      total.body_slots > 0 ? static_cast<double>(total.bytes) / static_cast<double>(total.body_slots) : 0.0,
      total.max_bytes_per_body, static_cast<double>(total.bytes) * 8 / 1000 / options.seconds / options.subscribers,
      static_cast<unsigned long long>(total.frames), expected_each * options.subscribers,
      100 * min_frames / expected_each, latency.latencies_ms.size(), static_cast<unsigned long long>(latency.lost),
      tumble::bench::percentile(latency.latencies_ms, 0.5), tumble::bench::percentile(latency.latencies_ms, 0.99),
      goal_ms, static_cast<unsigned long long>(after.overruns() - before.overruns()),
      static_cast<unsigned long long>(after.tick() - before.tick()), after.tick_ms_p50(), after.tick_ms_p99(),
      after.tick_cpu_ms_p99(), after.tick_start_late_ms_p50(), after.tick_start_late_ms_p99(), server_cpu.c_str(),
      own_cpu.c_str(), static_cast<unsigned long long>(commands.sent), static_cast<unsigned long long>(errors));
  if (options.stall_watch) {
    const tumble::bench::StallFigures figures = tumble::bench::stall_figures(stalls);
    // Whole hundredths of a millisecond, printed exactly.
    std::printf(
        " stalls=%zu stall_ms_max=%lld.%02lld stall_ms_total=%lld.%02lld latency_over_goal=%zu "
        "latency_over_goal_in_stall=%zu latency_in_stall=%zu latency_ms_p99_outside_stalls=%.2f",
        figures.count, static_cast<long long>(figures.longest_cms / 100),
        static_cast<long long>(figures.longest_cms % 100), static_cast<long long>(figures.total_cms / 100),
        static_cast<long long>(figures.total_cms % 100), slow, slow_in_stall,
        latency.samples.size() - outside_stalls_ms.size(), tumble::bench::percentile(outside_stalls_ms, 0.99));
  }
  std::printf("\n");
  if (latency_log != nullptr) {
    std::fprintf(latency_log, options.stall_watch ? "sent_s,latency_ms,applied_tick,in_stall\n"
                                                  : "sent_s,latency_ms,applied_tick\n");
    for (std::size_t i = 0; i < latency.samples.size(); ++i) {
      const tumble::bench::LatencySample& sample = latency.samples[i];
      std::fprintf(latency_log, "%.6f,%.3f,%llu", sample.sent_s, sample.latency_ms,
                   static_cast<unsigned long long>(sample.applied_tick));
      if (options.stall_watch) std::fprintf(latency_log, ",%d", in_stall[i] ? 1 : 0);
      std::fprintf(latency_log, "\n");
    }
    if (std::fclose(latency_log) != 0) {
      std::perror(("net_load: " + options.latency_log).c_str());
      return 1;
    }
  }
  return errors == 0 ? 0 : 3;
}
