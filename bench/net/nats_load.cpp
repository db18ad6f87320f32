// nats_load: the NATS fan-out benchmark. It starts three nats-server nodes
// routed into one cluster on 127.0.0.1 (nats_cluster.h) and tumbled as a
// real process publishing one pose stream into node 0 (--nats), spawns one
// of net_load's worlds into it (load_world.h, over tumbled's TCP port),
// and reads the stream with S subscriptions spread over the three nodes
// (nats_fanout.h), at nice 10 like net_load's subscribers. Over D seconds
// of ticks it measures the readers' frames (those of the measured ticks
// received up to 2 s after the last, against those published; sequence
// gaps), bytes per subscriber, the force-to-visible latency of a change
// sent as a request on the world's .rpc subject and seen in the same
// stream (latency_probe.h, on node 1), tumbled's tick (GetStats over .rpc)
// and the CPU of tumbled, of the three nats-server processes and of
// itself. It prints one line of key=value fields (bench/README.md), and
// exits 3 when a message did not decode or a request failed, 1 when the
// run could not be set up.
#include <unistd.h>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "child_process.h"
#include "latency_probe.h"
#include "load_world.h"
#include "measured_window.h"
#include "nats_cluster.h"
#include "nats_fanout.h"
#include "process_cpu.h"
#include "thread_priority.h"
#include "tumble_client/nats_connection.h"
#include "tumble_client/nats_subjects.h"

namespace {

using Clock = std::chrono::steady_clock;

constexpr const char* kWorld = "bench";
constexpr const char* kStream = "load";
// How long after the measured ticks their last frames may still arrive and count.
constexpr std::chrono::seconds kGrace{2};

struct Options {
  std::string tumbled;                                // path of the tumbled binary
  std::string nats_server = "/usr/sbin/nats-server";  // path of nats-server
  std::vector<std::string> tumbled_args;              // more arguments for tumbled
  std::string world = "field";
  unsigned bodies = 10000;
  double moving = 0.1;
  bool kinematic_movers = false;
  unsigned subscribers = 1;
  unsigned connections = 30;
  unsigned delivery_threads = 8;
  double rate_hz = 60;
  std::string encoding = "delta";
  double key_interval_s = 1;
  double rest_key_interval_s = 30;
  double seconds = 20;
  bool settle = false;
  bool no_latency = false;
  unsigned spawners = 16;
  int subscriber_nice = 10;
  bool subscriber_idle = false;
  int pending_frames = 64;
  int nats_server_nice = 0;
};

[[noreturn]] void fail(const std::string& why) {
  std::fprintf(stderr, "nats_load: %s\n", why.c_str());
  std::exit(1);
}

// tumbled's TCP port, once it has written it to `port_file`.
std::uint16_t wait_for_port(tumble::bench::ChildProcess& tumbled, const std::string& port_file,
                            const std::string& log) {
  const Clock::time_point give_up = Clock::now() + std::chrono::seconds(30);
  for (;;) {
    const std::string text = tumble::bench::read_text(port_file);
    if (!text.empty() && text.back() == '\n') return static_cast<std::uint16_t>(std::stoul(text));
    if (!tumbled.running() || Clock::now() > give_up) fail("tumbled did not start:\n" + tumble::bench::read_text(log));
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

// A connection to the world over NATS through `url`, reading the benchmark's stream.
tumble::client::NatsConnection connect_world(const std::string& url, const std::string& name) {
  tumble::client::NatsOptions options;
  options.servers = {url};
  options.world = kWorld;
  options.stream = kStream;
  options.client_name = name;
  auto connection = tumble::client::NatsConnection::connect(options, std::chrono::seconds(10));
  if (!connection) fail("connect to NATS at " + url + ": " + connection.failure().message);
  return std::move(*connection);
}

tumble::v1::Stats stats_or_exit(tumble::client::Transport& controller) {
  auto stats = controller.get_stats(std::chrono::seconds(10));
  if (!stats) fail("stats over .rpc: " + stats.failure().message);
  return *stats;
}

// Stats once tumbled answers on .rpc with its NATS link up (at most 30 s).
tumble::v1::Stats wait_for_world(tumble::client::Transport& controller) {
  const Clock::time_point give_up = Clock::now() + std::chrono::seconds(30);
  for (;;) {
    auto stats = controller.get_stats(std::chrono::seconds(2));
    if (stats && stats->nats().connected()) return *stats;
    if (Clock::now() > give_up) {
      fail("tumbled did not answer over NATS: " + (stats ? std::string("link down") : stats.failure().message));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
}

std::string percent_text(std::optional<double> before, std::optional<double> after, double wall) {
  if (!before || !after) return "-";
  char text[32];
  std::snprintf(text, sizeof text, "%.0f", tumble::bench::cpu_percent(*after - *before, wall));
  return text;
}

// `value` as %g prints it: 60, 0.5.
std::string number_text(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

// CPU seconds of the three nats-server nodes, each; nullopt for a node that cannot be read.
std::vector<std::optional<double>> nats_cpu(const tumble::bench::NatsCluster& cluster) {
  std::vector<std::optional<double>> out;
  for (std::size_t i = 0; i < tumble::bench::NatsCluster::kNodes; ++i) {
    out.push_back(tumble::bench::process_cpu_seconds(cluster.pid(i)));
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  CLI::App app{"The NATS fan-out benchmark: tumbled publishing one pose stream into a 3-node nats-server cluster"};
  app.add_option("--tumbled", options.tumbled, "Path of the tumbled binary to start")->required();
  app.add_option("--nats-server", options.nats_server, "Path of nats-server")->capture_default_str();
  app.add_option("--tumbled-arg", options.tumbled_args, "One more argument for tumbled (repeatable)");
  app.add_option("--world", options.world, "field or cubes (net_load's worlds; bench/README.md)")
      ->capture_default_str()
      ->check(CLI::IsMember({"field", "cubes"}));
  app.add_option("--bodies", options.bodies, "B: bodies to spawn")
      ->capture_default_str()
      ->check(CLI::Range(1u, 1000000u));
  app.add_option("--moving", options.moving, "field: the fraction of the bodies that spin")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  app.add_flag("--kinematic-movers", options.kinematic_movers, "field: the spinning bodies are kinematic");
  app.add_option("--subscribers", options.subscribers, "S: subscriptions to the stream")
      ->capture_default_str()
      ->check(CLI::Range(1u, 100000u));
  app.add_option("--connections", options.connections,
                 "C: nats.c connections the subscriptions share, spread over the three nodes (at most S)")
      ->capture_default_str()
      ->check(CLI::Range(1u, 10000u));
  app.add_option("--delivery-threads", options.delivery_threads, "T: threads that run the subscriptions' callbacks")
      ->capture_default_str()
      ->check(CLI::Range(1u, 1000u));
  app.add_option("--rate", options.rate_hz, "The stream's frames per second")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 10000.0));
  app.add_option("--encoding", options.encoding, "The stream's encoding: full, quantized or delta")
      ->capture_default_str()
      ->check(CLI::IsMember({"full", "quantized", "delta"}));
  app.add_option("--key-interval", options.key_interval_s,
                 "tumbled --nats-key-interval: sim seconds between key frames")
      ->capture_default_str()
      ->check(CLI::Range(0.01, 3600.0));
  app.add_option("--rest-key-interval", options.rest_key_interval_s,
                 "tumbled --nats-rest-key-interval: the same while nothing moves (raised to --key-interval)")
      ->capture_default_str()
      ->check(CLI::Range(0.01, 3600.0));
  app.add_option("--seconds", options.seconds, "D: measured seconds")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 86400.0));
  app.add_flag("--settle", options.settle, "Measure once the bodies that come to rest are asleep");
  app.add_flag("--no-latency", options.no_latency,
               "Move no probe and measure no latency, so that a world at rest stays at rest for the window");
  app.add_option("--spawners", options.spawners, "Connections that spawn the world at once")
      ->capture_default_str()
      ->check(CLI::Range(1u, 256u));
  app.add_option("--subscriber-nice", options.subscriber_nice, "Nice value of the subscriptions' nats.c threads")
      ->capture_default_str()
      ->check(CLI::Range(0, 19));
  app.add_flag("--subscriber-idle", options.subscriber_idle, "Run the subscriptions' nats.c threads under SCHED_IDLE");
  app.add_option("--pending-frames", options.pending_frames,
                 "Frames one subscription may have waiting in nats.c; past it nats.c drops what comes")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000000));
  app.add_option("--nats-server-nice", options.nats_server_nice,
                 "Nice value of the three nats-server processes (standing for servers on other machines)")
      ->capture_default_str()
      ->check(CLI::Range(0, 19));
  CLI11_PARSE(app, argc, argv);

  const std::string dir = tumble::bench::make_temp_dir("nats_load");
  if (dir.empty()) fail("cannot make a temporary directory");

  tumble::bench::NatsCluster cluster(options.nats_server, dir, {.nice = options.nats_server_nice});
  if (const std::string why = cluster.start(std::chrono::seconds(30)); !why.empty()) fail(why);

  const std::string tumbled_log = dir + "/tumbled.log";
  std::vector<std::string> tumbled_argv = {
      options.tumbled,
      "--listen",
      "127.0.0.1:0",
      "--port-file",
      dir + "/port",
      "--nats",
      cluster.urls(),
      "--world",
      kWorld,
      "--nats-stream",
      std::string(kStream) + "=" + options.encoding + "@" + number_text(options.rate_hz),
      "--nats-key-interval",
      number_text(options.key_interval_s),
      "--nats-rest-key-interval",
      number_text(std::max(options.rest_key_interval_s, options.key_interval_s))};
  tumbled_argv.insert(tumbled_argv.end(), options.tumbled_args.begin(), options.tumbled_args.end());
  tumble::bench::ChildProcess tumbled(tumbled_argv, tumbled_log);
  if (!tumbled.started()) fail("cannot start " + options.tumbled);
  tumble::bench::LoadTarget target;
  target.server = "127.0.0.1:" + std::to_string(wait_for_port(tumbled, dir + "/port", tumbled_log));

  // Requests and the latency watcher through node 1: a route away from
  // tumbled's node 0, as for two thirds of the subscriptions.
  tumble::client::NatsConnection controller = connect_world(cluster.url(1), "nats_load-controller");
  wait_for_world(controller);
  if (auto paused = controller.pause(std::chrono::seconds(10)); !paused) fail("pause: " + paused.failure().message);
  tumble::bench::WorldOptions world_options;
  world_options.layout =
      options.world == "cubes" ? tumble::bench::WorldLayout::cubes : tumble::bench::WorldLayout::field;
  world_options.bodies = options.bodies;
  world_options.moving = options.moving;
  world_options.kinematic_movers = options.kinematic_movers;
  const tumble::bench::LoadWorld world = tumble::bench::spawn_world(target, world_options, options.spawners);

  // The subscriptions' nats.c threads are made on a thread of lower
  // priority, and inherit it.
  tumble::bench::MeasuredTicks window;
  tumble::bench::MeasuredWindow wall_window;
  tumble::bench::NatsFanoutOptions fanout_options;
  for (std::size_t i = 0; i < tumble::bench::NatsCluster::kNodes; ++i)
    fanout_options.node_urls.push_back(cluster.url(i));
  fanout_options.subject = tumble::client::poses_subject(kWorld, kStream);
  fanout_options.subscriptions = options.subscribers;
  fanout_options.connections = std::min(options.connections, options.subscribers);
  fanout_options.delivery_threads = options.delivery_threads;
  fanout_options.pending_messages = options.pending_frames;
  std::unique_ptr<tumble::bench::NatsFanout> fanout;
  std::thread([&] {
    tumble::bench::set_thread_priority(options.subscriber_nice, options.subscriber_idle, "nats_load");
    fanout = std::make_unique<tumble::bench::NatsFanout>(fanout_options, window, wall_window);
  }).join();
  if (!fanout->error().empty()) fail(fanout->error());
  tumble::client::NatsConnection watcher = connect_world(cluster.url(1), "nats_load-latency-watcher");
  if (auto subscribed = watcher.subscribe(tumble::v1::Subscribe{}, std::chrono::seconds(10)); !subscribed) {
    fail("subscribe the latency watcher: " + subscribed.failure().message);
  }

  if (auto resumed = controller.resume(std::chrono::seconds(10)); !resumed)
    fail("resume: " + resumed.failure().message);
  if (options.settle) {
    const Clock::time_point give_up = Clock::now() + std::chrono::seconds(60);
    while (stats_or_exit(controller).bodies_asleep() < world.resting) {
      if (Clock::now() > give_up) fail("the bodies did not come to rest within 60 s");
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
  }
  // Every subscription holds a whole frame: the stream's next key frame,
  // which a world at rest sends only every rest interval.
  const Clock::time_point give_up = Clock::now() + std::chrono::seconds(20) +
                                    std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(
                                        std::max(options.rest_key_interval_s, options.key_interval_s)));
  while (fanout->ready() < options.subscribers && Clock::now() < give_up) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  const unsigned ready = fanout->ready();

  // The measured ticks: D seconds of the sim from the next tick on. Their
  // frames count whenever they arrive, until kGrace after the last.
  const tumble::v1::Stats before = stats_or_exit(controller);
  const std::uint64_t first_tick = before.tick() + 1;
  const auto window_ticks = static_cast<std::uint64_t>(std::llround(options.seconds * before.tick_rate_hz()));
  window.set(first_tick, first_tick + window_ticks);
  const std::optional<double> tumbled_cpu_before = tumble::bench::process_cpu_seconds(tumbled.pid());
  const std::vector<std::optional<double>> nats_cpu_before = nats_cpu(cluster);
  const std::optional<double> own_cpu_before = tumble::bench::process_cpu_seconds(getpid());
  const Clock::time_point start = Clock::now();
  const Clock::time_point end =
      start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(options.seconds));
  wall_window.set(start, end);
  const tumble::bench::LatencyResult latency =
      options.no_latency ? tumble::bench::LatencyResult{}
                         : tumble::bench::measure_latency_over(controller, watcher, world.probe,
                                                               tumble::bench::ProbeSignal::position, start, end);
  std::this_thread::sleep_until(end);
  tumble::v1::Stats after = stats_or_exit(controller);
  // Until the server has stepped the last measured tick (it may be behind its clock).
  for (const Clock::time_point stop_waiting = Clock::now() + std::chrono::seconds(10);
       after.tick() < first_tick + window_ticks && Clock::now() < stop_waiting;) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    after = stats_or_exit(controller);
  }
  const double wall = std::chrono::duration<double>(Clock::now() - start).count();
  const std::optional<double> tumbled_cpu_after = tumble::bench::process_cpu_seconds(tumbled.pid());
  const std::vector<std::optional<double>> nats_cpu_after = nats_cpu(cluster);
  const std::optional<double> own_cpu_after = tumble::bench::process_cpu_seconds(getpid());
  std::this_thread::sleep_for(kGrace);
  fanout->close();

  // The three nodes' CPU, each and summed ("-" when a node could not be read).
  std::string nats_nodes_text;
  std::optional<double> nats_before = 0.0, nats_after = 0.0;
  for (std::size_t i = 0; i < nats_cpu_before.size(); ++i) {
    nats_nodes_text += (i == 0 ? "" : "/") + percent_text(nats_cpu_before[i], nats_cpu_after[i], wall);
    if (!nats_cpu_before[i] || !nats_cpu_after[i]) {
      nats_before.reset();
    } else if (nats_before) {
      *nats_before += *nats_cpu_before[i];
      *nats_after += *nats_cpu_after[i];
    }
  }
  const std::string nats_cpu_text = percent_text(nats_before, nats_after, wall);

  tumble::bench::StreamTally total;
  double min_frames = std::numeric_limits<double>::max();
  for (const tumble::bench::StreamTally& tally : fanout->tallies()) {
    total.frames += tally.frames;
    total.bytes += tally.bytes;
    total.wire_bytes += tally.wire_bytes;
    total.shown += tally.shown;
    total.body_slots += tally.body_slots;
    total.gaps += tally.gaps;
    total.missed += tally.missed;
    total.errors += tally.errors;
    total.handled_in_window += tally.handled_in_window;
    min_frames = std::min(min_frames, static_cast<double>(tally.frames));
  }
  const tumble::bench::NatsClientEvents events = fanout->events();
  // tumbled rounds the rate to a whole number of ticks.
  const double period_ticks = std::max(1.0, std::round(after.tick_rate_hz() / options.rate_hz));
  const double expected_each = std::round(static_cast<double>(window_ticks) / period_ticks);
  const double subscribers = options.subscribers;
  std::vector<double> latency_ticks;
  for (const tumble::bench::LatencySample& sample : latency.samples) {
    if (sample.applied_tick > 0 && sample.visible_tick >= sample.applied_tick) {
      latency_ticks.push_back(static_cast<double>(sample.visible_tick - sample.applied_tick));
    }
  }
  const std::uint64_t errors = total.errors + latency.errors;
  const auto kbit_per_s = [&](std::uint64_t bytes) {
    return static_cast<double>(bytes) * 8 / 1000 / options.seconds / subscribers;
  };
  std::printf(
      "transport=nats world=%s encoding=%s subscribers=%u connections=%u bodies=%u rate_hz=%g tick_rate_hz=%g "
      "seconds=%g key_interval_s=%g rest_key_interval_s=%g subscribers_ready=%u "
      "bytes_per_body_frame=%.2f kbit_per_s_per_subscriber=%.1f wire_kbit_per_s_per_subscriber=%.1f "
      "frames=%llu frames_expected=%.0f frames_min_percent=%.1f frames_mean_percent=%.2f frames_shown=%llu "
      "frames_handled_per_s=%.0f "
      "gaps=%llu frames_missed=%llu slow_consumer_errors=%llu client_dropped=%llu disconnects=%llu reconnects=%llu "
      "latency_samples=%zu latency_lost=%llu latency_ms_p50=%.2f latency_ms_p99=%.2f latency_ticks_p50=%.0f "
      "latency_ticks_p99=%.0f "
      "overruns=%llu ticks=%llu tick_ms_p50=%.2f tick_ms_p99=%.2f tick_cpu_ms_p99=%.2f tick_late_ms_p50=%.2f "
      "tick_late_ms_p99=%.2f nats_frames_dropped=%llu tumbled_nats_messages_out=%llu tumbled_nats_kbit_per_s=%.1f "
      "server_cpu_percent=%s nats_cpu_percent=%s nats_cpu_percent_nodes=%s load_cpu_percent=%s errors=%llu\n",
      options.world.c_str(), options.encoding.c_str(), options.subscribers, fanout_options.connections, options.bodies,
      options.rate_hz, after.tick_rate_hz(), options.seconds, options.key_interval_s,
      std::max(options.rest_key_interval_s, options.key_interval_s), ready,
      total.body_slots > 0 ? static_cast<double>(total.bytes) / static_cast<double>(total.body_slots) : 0.0,
      kbit_per_s(total.bytes), kbit_per_s(total.wire_bytes), static_cast<unsigned long long>(total.frames),
      expected_each * subscribers, 100 * min_frames / expected_each,
      100 * static_cast<double>(total.frames) / (expected_each * subscribers),
      static_cast<unsigned long long>(total.shown), static_cast<double>(total.handled_in_window) / options.seconds,
      static_cast<unsigned long long>(total.gaps), static_cast<unsigned long long>(total.missed),
      static_cast<unsigned long long>(events.slow_consumer), static_cast<unsigned long long>(events.dropped),
      static_cast<unsigned long long>(events.disconnects), static_cast<unsigned long long>(events.reconnects),
      latency.latencies_ms.size(), static_cast<unsigned long long>(latency.lost),
      tumble::bench::percentile(latency.latencies_ms, 0.5), tumble::bench::percentile(latency.latencies_ms, 0.99),
      tumble::bench::percentile(latency_ticks, 0.5), tumble::bench::percentile(latency_ticks, 0.99),
      static_cast<unsigned long long>(after.overruns() - before.overruns()),
      static_cast<unsigned long long>(after.tick() - before.tick()), after.tick_ms_p50(), after.tick_ms_p99(),
      after.tick_cpu_ms_p99(), after.tick_start_late_ms_p50(), after.tick_start_late_ms_p99(),
      static_cast<unsigned long long>(after.nats().frames_dropped() - before.nats().frames_dropped()),
      static_cast<unsigned long long>(after.nats().messages_out() - before.nats().messages_out()),
      static_cast<double>(after.nats().bytes_out() - before.nats().bytes_out()) * 8 / 1000 / wall,
      percent_text(tumbled_cpu_before, tumbled_cpu_after, wall).c_str(), nats_cpu_text.c_str(), nats_nodes_text.c_str(),
      percent_text(own_cpu_before, own_cpu_after, wall).c_str(), static_cast<unsigned long long>(errors));
  std::fflush(stdout);
  tumbled.stop();
  std::error_code ignored;
  std::filesystem::remove_all(dir, ignored);
  return errors == 0 ? 0 : 3;
}
