#include "latency_probe.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <thread>

#include "tumble_client/pose_sample.h"
#include "tumble_client/pose_stream.h"
#include "wire/quantized_poses.h"

namespace tumble::bench {
namespace {

using Clock = std::chrono::steady_clock;

// The change under way, shared by the controller and the watcher.
struct Pending {
  std::mutex mutex;
  std::condition_variable seen_changed;
  bool waiting = false;  // a change was sent and not yet seen
  double value = 0;      // the value being waited for: m/s or m along x
  Clock::time_point sent;
  Clock::time_point arrived;  // of the first frame that showed it
  std::uint64_t tick = 0;     // of that frame
};

// The probe's x velocity or x position as `frame` carries it; nullopt when
// the frame does not hold the probe (a DELTA change where it did not move)
// or cannot be read (the stream's own check reports that).
std::optional<double> probe_value(const tumble::v1::PoseFrame& frame, std::uint32_t probe, ProbeSignal signal) {
  if (frame.encoding() == tumble::v1::POSE_ENCODING_FULL) {
    auto sample = client::unpack_pose_frame(frame);
    if (!sample) return std::nullopt;
    for (const client::BodyPose& body : sample->bodies) {
      if (body.id != probe) continue;
      return signal == ProbeSignal::velocity ? body.linear_velocity[0] : body.position[0];
    }
    return std::nullopt;
  }
  // QUANTIZED, and DELTA's own bodies (a key frame's all, a change's moved ones).
  const auto poses = wire::decode_quantized_poses(frame.packed());
  if (!poses) return std::nullopt;
  const auto it = std::find_if(poses->bodies.begin(), poses->bodies.end(),
                               [&](const wire::QuantizedBody& body) { return body.id == probe; });
  if (it == poses->bodies.end()) return std::nullopt;
  return signal == ProbeSignal::velocity ? wire::linear_velocity_of(*it)[0]
                                         : wire::position_of(*it, poses->step_exponent)[0];
}

// Reads the watcher's frames until `stop`, checking each as a client does
// (PoseStream) and stamping the first that shows the pending change. False
// when the stream broke.
bool watch(client::Transport& watcher, std::uint32_t probe, ProbeSignal signal, Pending& pending,
           const std::atomic<bool>& stop) {
  client::PoseStream stream;
  while (!stop.load()) {
    auto message = watcher.next_message(std::chrono::milliseconds(100));
    if (!message) {
      if (message.failure().kind == client::FailureKind::timeout) continue;
      return false;
    }
    if (!message->has_pose_frame()) continue;
    const Clock::time_point arrived = Clock::now();
    const tumble::v1::PoseFrame& frame = message->pose_frame();
    if (!stream.apply(frame)) return false;
    const std::optional<double> seen = probe_value(frame, probe, signal);
    if (!seen) continue;
    std::lock_guard lock(pending.mutex);
    if (!pending.waiting || std::abs(*seen - pending.value) > 0.01) continue;
    pending.arrived = arrived;
    pending.tick = frame.tick();
    pending.waiting = false;
    pending.seen_changed.notify_all();
  }
  return true;
}

// The request that makes change number `step` (1, 2, ...), and the value
// the watcher waits for: each different from the last, and the probe kept
// far from everything.
tumble::v1::SetBodyState change(std::uint32_t probe, ProbeSignal signal, int step, double& value) {
  tumble::v1::SetBodyState set;
  set.mutable_body()->set_id(probe);
  set.mutable_position()->set_y(5);
  if (signal == ProbeSignal::velocity) {
    value = 0.5 * (1 + step % 8);  // 0.5 .. 4 m/s
    set.mutable_position()->set_x(-100);
    set.mutable_linear_velocity()->set_x(value);
  } else {
    value = -100 + 0.25 * (1 + step % 8);  // -99.75 .. -98 m, at rest
    set.mutable_position()->set_x(value);
    set.mutable_linear_velocity()->set_x(0);
  }
  return set;
}

}  // namespace

LatencyResult measure_latency(const LoadTarget& target, std::uint32_t probe, double watch_rate_hz,
                              tumble::v1::PoseEncoding encoding, Clock::time_point start, Clock::time_point end) {
  client::Connection controller = connect_or_exit(target, "net_load-latency-controller");
  client::Connection watcher = connect_or_exit(target, "net_load-latency-watcher");
  tumble::v1::Subscribe request;
  request.add_bodies()->set_id(probe);
  request.set_rate_hz(watch_rate_hz);
  request.set_fields(tumble::v1::POSE_FIELDS_POSE_AND_VELOCITY);
  request.set_encoding(encoding);
  auto subscribed = watcher.subscribe(request, std::chrono::seconds(10));
  if (!subscribed) exit_with("subscribe the latency watcher", subscribed.failure());
  return measure_latency_over(controller, watcher, probe, ProbeSignal::velocity, start, end);
}

LatencyResult measure_latency_over(client::Transport& controller, client::Transport& watcher, std::uint32_t probe,
                                   ProbeSignal signal, Clock::time_point start, Clock::time_point end) {
  LatencyResult result;
  Pending pending;
  std::atomic<bool> stop{false};
  std::atomic<bool> watcher_broke{false};
  std::thread watching([&] { watcher_broke = !watch(watcher, probe, signal, pending, stop); });

  for (int step = 1; Clock::now() + std::chrono::milliseconds(200) < end && !watcher_broke; ++step) {
    double value = 0;
    const tumble::v1::SetBodyState set = change(probe, signal, step, value);
    {
      std::lock_guard lock(pending.mutex);
      pending.waiting = true;
      pending.value = value;
      pending.sent = Clock::now();
    }
    auto ack = controller.set_body_state(set, std::chrono::seconds(10));
    if (!ack) ++result.errors;
    {
      std::unique_lock lock(pending.mutex);
      if (pending.seen_changed.wait_for(lock, std::chrono::seconds(2), [&] { return !pending.waiting; })) {
        LatencySample sample;
        sample.sent_s = std::chrono::duration<double>(pending.sent - start).count();
        sample.latency_ms = std::chrono::duration<double, std::milli>(pending.arrived - pending.sent).count();
        sample.applied_tick = ack ? ack->applied_tick() : 0;
        sample.visible_tick = pending.tick;
        result.samples.push_back(sample);
        result.latencies_ms.push_back(sample.latency_ms);
      } else {
        ++result.lost;
        pending.waiting = false;
      }
    }
    // 20 ms plus 0..49 ms in steps of 7 ms, which is prime to the pause's
    // length: about 20 changes a second, each sent at another phase of the tick.
    std::this_thread::sleep_for(std::chrono::milliseconds(20 + (7 * step) % 50));
  }
  stop = true;
  watching.join();
  if (watcher_broke) ++result.errors;
  return result;
}

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const auto rank = static_cast<std::size_t>(std::ceil(p * static_cast<double>(values.size())));
  return values[std::min(std::max<std::size_t>(rank, 1) - 1, values.size() - 1)];
}

}  // namespace tumble::bench
