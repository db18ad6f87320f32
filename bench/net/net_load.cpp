// net_load: a load generator for tumbled's pose streams. It spawns a world
// of B spheres (a fraction of them spinning in place, the rest at rest),
// opens S subscribers at R Hz in one encoding, and after D seconds prints
// one line: bytes per body per frame, frames received against expected,
// force-to-visible latency and the server's overruns (see README.md).
//
// Latency: a controller sets a probe body's velocity to a new value every
// 100 to 150 ms (varied, so the changes fall at every phase of the frame
// period); a watcher subscribed to the probe alone, at the same rate and
// encoding, timestamps the first frame that shows it. The figure includes
// the wait for the next frame (up to one period), as a client sees it.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "tumble_client/connection.h"
#include "tumble_client/endpoint.h"
#include "tumble_client/pose_stream.h"

namespace {

using Clock = std::chrono::steady_clock;
using tumble::client::Connection;

struct Options {
  std::string server = "127.0.0.1:7400";
  std::string token;
  unsigned subscribers = 8;
  unsigned bodies = 1000;
  double rate_hz = 30;
  std::string encoding = "full";
  double seconds = 10;
  double moving = 0.1;  // fraction of the bodies that spin
};

// What one subscriber counted.
struct Tally {
  std::uint64_t frames = 0;
  std::uint64_t bytes = 0;        // PoseFrame messages as framed on the wire
  std::uint64_t body_slots = 0;   // bodies the frames stood for (after completion)
};

[[noreturn]] void fail(const std::string& what, const tumble::client::Failure& failure) {
  std::fprintf(stderr, "net_load: %s: %s\n", what.c_str(), failure.message.c_str());
  std::exit(1);
}

Connection connect(const Options& options, const std::string& name) {
  auto endpoint = tumble::client::parse_endpoint(options.server);
  if (!endpoint) fail("server", endpoint.failure());
  auto connection = Connection::connect(*endpoint, name, options.token, std::chrono::seconds(10));
  if (!connection) fail("connect", connection.failure());
  return std::move(*connection);
}

tumble::v1::PoseEncoding encoding_of(const std::string& name) {
  if (name == "quantized") return tumble::v1::POSE_ENCODING_QUANTIZED;
  if (name == "delta") return tumble::v1::POSE_ENCODING_DELTA;
  return tumble::v1::POSE_ENCODING_FULL;
}

// Bytes of a message with its varint length prefix.
std::uint64_t framed_size(const tumble::v1::ServerMessage& message) {
  const std::size_t body = message.ByteSizeLong();
  std::size_t prefix = 1;
  for (std::size_t rest = body >> 7; rest > 0; rest >>= 7) ++prefix;
  return body + prefix;
}

// Spawns the world: spheres on a 0.5 m grid, every 1/moving-th one spinning;
// retries the spawns the server's request rate refuses. Returns the probe's id.
std::uint32_t spawn_world(Connection& controller, const Options& options) {
  const auto side = static_cast<unsigned>(std::ceil(std::sqrt(static_cast<double>(options.bodies))));
  const unsigned spin_every = options.moving > 0 ? static_cast<unsigned>(std::lround(1 / options.moving)) : 0;
  for (unsigned i = 0; i <= options.bodies; ++i) {
    tumble::v1::BodySpec spec;
    spec.mutable_shape()->mutable_sphere()->set_radius(0.2);
    spec.set_mass(1);
    if (i == options.bodies) {  // the probe, far from the others
      spec.set_name("net_load_probe");
      spec.mutable_position()->set_x(-100);
    } else {
      spec.mutable_position()->set_x(100 + 0.5 * (i % side));
      spec.mutable_position()->set_y(0.5 * (i / side));
      if (spin_every > 0 && i % spin_every == 0) spec.mutable_angular_velocity()->set_z(1);
    }
    for (;;) {
      auto ack = controller.spawn_body(spec, std::chrono::seconds(10));
      if (ack) {
        if (i == options.bodies) return ack->body_id();
        break;
      }
      if (ack.failure().code != tumble::v1::RATE_LIMITED) fail("spawn", ack.failure());
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
  return 0;
}

void subscribe_all(Connection& connection, const Options& options, std::optional<std::uint32_t> only,
                   tumble::v1::PoseFields fields) {
  tumble::v1::Subscribe request;
  request.set_rate_hz(options.rate_hz);
  request.set_fields(fields);
  request.set_encoding(encoding_of(options.encoding));
  if (only) request.add_bodies()->set_id(*only);
  auto subscribed = connection.subscribe(request, std::chrono::seconds(10));
  if (!subscribed) fail("subscribe", subscribed.failure());
}

// One subscriber: counts frames and bytes until `end`.
Tally run_subscriber(const Options& options, unsigned index, Clock::time_point start, Clock::time_point end) {
  Connection connection = connect(options, "net_load-" + std::to_string(index));
  subscribe_all(connection, options, std::nullopt, tumble::v1::POSE_FIELDS_POSE);
  tumble::client::PoseStream stream;
  Tally tally;
  while (Clock::now() < end) {
    auto message = connection.next_message(std::chrono::milliseconds(100));
    if (!message) {
      if (message.failure().kind == tumble::client::FailureKind::timeout) continue;
      fail("subscriber", message.failure());
    }
    if (!message->has_pose_frame()) continue;
    auto sample = stream.decode(message->pose_frame());
    if (!sample) fail("decode", sample.failure());
    if (Clock::now() < start) continue;  // the key frame and the warm-up are not counted
    ++tally.frames;
    tally.bytes += framed_size(*message);
    tally.body_slots += sample->bodies.size();
  }
  return tally;
}

// Sets the probe's x velocity to a new value every 100 to 150 ms and times
// the first frame showing each; returns the latencies in ms.
std::vector<double> measure_latency(const Options& options, std::uint32_t probe, Clock::time_point end) {
  Connection controller = connect(options, "net_load-controller");
  Connection watcher = connect(options, "net_load-watcher");
  subscribe_all(watcher, options, probe, tumble::v1::POSE_FIELDS_POSE_AND_VELOCITY);
  tumble::client::PoseStream stream;
  std::vector<double> latencies;
  for (int step = 1; Clock::now() + std::chrono::milliseconds(200) < end; ++step) {
    // Cycles through 0.5 .. 4 m/s, each different from the last, and puts
    // the probe back to its start so that it never reaches the others.
    const double speed = 0.5 * (1 + step % 8);
    tumble::v1::SetBodyState set;
    set.mutable_body()->set_id(probe);
    set.mutable_position()->set_x(-100);
    set.mutable_linear_velocity()->set_x(speed);
    const Clock::time_point sent = Clock::now();
    auto ack = controller.set_body_state(set, std::chrono::seconds(10));
    if (!ack) fail("set probe velocity", ack.failure());
    // A change not seen within 2 s is lost: it shows in latency_samples only.
    const Clock::time_point give_up = sent + std::chrono::seconds(2);
    while (Clock::now() < give_up) {
      auto message = watcher.next_message(std::chrono::milliseconds(100));
      if (!message) {
        if (message.failure().kind == tumble::client::FailureKind::timeout) continue;
        fail("watcher", message.failure());
      }
      if (!message->has_pose_frame()) continue;
      auto sample = stream.decode(message->pose_frame());
      if (!sample) fail("decode", sample.failure());
      if (sample->bodies.empty()) continue;
      const double seen = static_cast<double>(sample->bodies[0].linear_velocity[0]);
      if (std::abs(seen - speed) > 0.01) continue;
      latencies.push_back(std::chrono::duration<double, std::milli>(Clock::now() - sent).count());
      break;
    }
    // 100 ms plus 0..49 ms in steps of 7 ms, which is prime to the pause's length.
    std::this_thread::sleep_for(std::chrono::milliseconds(100 + (7 * step) % 50));
  }
  return latencies;
}

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const auto index = static_cast<std::size_t>(std::ceil(p * static_cast<double>(values.size()))) - 1;
  return values[std::min(index, values.size() - 1)];
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  CLI::App app{"Load generator for tumbled's pose streams"};
  app.add_option("--server", options.server, "tumbled to load, HOST:PORT")->capture_default_str();
  app.add_option("--token", options.token, "Controller token, when the server asks for one");
  app.add_option("--subscribers", options.subscribers, "S: subscribers")
      ->capture_default_str()
      ->check(CLI::Range(1u, 10000u));
  app.add_option("--bodies", options.bodies, "B: spheres to spawn")
      ->capture_default_str()
      ->check(CLI::Range(1u, 1000000u));
  app.add_option("--rate", options.rate_hz, "R: frames per second per subscriber")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 10000.0));
  app.add_option("--encoding", options.encoding, "full, quantized or delta")
      ->capture_default_str()
      ->check(CLI::IsMember({"full", "quantized", "delta"}));
  app.add_option("--seconds", options.seconds, "D: measured seconds")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 3600.0));
  app.add_option("--moving", options.moving, "Fraction of the bodies that spin")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  CLI11_PARSE(app, argc, argv);

  Connection controller = connect(options, "net_load");
  const std::uint32_t probe = spawn_world(controller, options);
  auto before = controller.get_stats(std::chrono::seconds(10));
  if (!before) fail("stats", before.failure());

  // One second of warm-up for the connections and the key frames, then D measured.
  const Clock::time_point start = Clock::now() + std::chrono::seconds(1);
  const Clock::time_point end =
      start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(options.seconds));
  std::vector<Tally> tallies(options.subscribers);
  std::vector<std::thread> threads;
  for (unsigned i = 0; i < options.subscribers; ++i) {
    threads.emplace_back([&, i] { tallies[i] = run_subscriber(options, i, start, end); });
  }
  std::vector<double> latencies;
  threads.emplace_back([&] { latencies = measure_latency(options, probe, end); });
  for (std::thread& thread : threads) thread.join();

  auto after = controller.get_stats(std::chrono::seconds(10));
  if (!after) fail("stats", after.failure());
  Tally total;
  for (const Tally& tally : tallies) {
    total.frames += tally.frames;
    total.bytes += tally.bytes;
    total.body_slots += tally.body_slots;
  }
  // The server rounds the rate to the tick rate over a whole number of ticks.
  const double period_ticks = std::max(1.0, std::round(after->tick_rate_hz() / options.rate_hz));
  const double expected = options.seconds * after->tick_rate_hz() / period_ticks * options.subscribers;
  std::printf(
      "encoding=%s subscribers=%u bodies=%u rate_hz=%g seconds=%g bytes_per_body_frame=%.2f frames=%llu "
      "frames_expected=%.0f latency_samples=%zu latency_ms_p50=%.1f latency_ms_p99=%.1f overruns=%llu\n",
      options.encoding.c_str(), options.subscribers, options.bodies, options.rate_hz, options.seconds,
      total.body_slots > 0 ? static_cast<double>(total.bytes) / static_cast<double>(total.body_slots) : 0.0,
      static_cast<unsigned long long>(total.frames), expected, latencies.size(), percentile(latencies, 0.5),
      percentile(latencies, 0.99), static_cast<unsigned long long>(after->overruns() - before->overruns()));
  return 0;
}
