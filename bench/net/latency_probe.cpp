#include "latency_probe.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "tumble_client/pose_stream.h"

namespace tumble::bench {
namespace {

using Clock = std::chrono::steady_clock;

// The change under way, shared by the controller and the watcher.
struct Pending {
  std::mutex mutex;
  std::condition_variable seen_changed;
  bool waiting = false;  // a change was sent and not yet seen
  double speed = 0;      // m/s along x, the value being waited for
  Clock::time_point sent;
  Clock::time_point arrived;  // of the first frame that showed it
};

// Reads the watcher's frames until `stop`, stamping the first that shows
// the pending change. False when the stream broke.
bool watch(client::Connection& watcher, Pending& pending, const std::atomic<bool>& stop) {
  client::PoseStream stream;
  while (!stop.load()) {
    auto message = watcher.next_message(std::chrono::milliseconds(100));
    if (!message) {
      if (message.failure().kind == client::FailureKind::timeout) continue;
      return false;
    }
    if (!message->has_pose_frame()) continue;
    const Clock::time_point arrived = Clock::now();
    auto sample = stream.decode(message->pose_frame());
    if (!sample) return false;
    if (sample->bodies.empty()) continue;
    const double seen = static_cast<double>(sample->bodies[0].linear_velocity[0]);
    std::lock_guard lock(pending.mutex);
    if (!pending.waiting || std::abs(seen - pending.speed) > 0.01) continue;
    pending.arrived = arrived;
    pending.waiting = false;
    pending.seen_changed.notify_all();
  }
  return true;
}

}  // namespace

LatencyResult measure_latency(const LoadTarget& target, std::uint32_t probe, double tick_rate_hz,
                              tumble::v1::PoseEncoding encoding, Clock::time_point start, Clock::time_point end) {
  client::Connection controller = connect_or_exit(target, "net_load-latency-controller");
  client::Connection watcher = connect_or_exit(target, "net_load-latency-watcher");
  tumble::v1::Subscribe request;
  request.add_bodies()->set_id(probe);
  request.set_rate_hz(tick_rate_hz);  // period: one tick
  request.set_fields(tumble::v1::POSE_FIELDS_POSE_AND_VELOCITY);
  request.set_encoding(encoding);
  auto subscribed = watcher.subscribe(request, std::chrono::seconds(10));
  if (!subscribed) exit_with("subscribe the latency watcher", subscribed.failure());

  LatencyResult result;
  Pending pending;
  std::atomic<bool> stop{false};
  std::atomic<bool> watcher_broke{false};
  std::thread watching([&] { watcher_broke = !watch(watcher, pending, stop); });

  for (int step = 1; Clock::now() + std::chrono::milliseconds(200) < end && !watcher_broke; ++step) {
    // 0.5 .. 4 m/s, each different from the last; back to the start so that
    // the probe stays far from everything.
    const double speed = 0.5 * (1 + step % 8);
    tumble::v1::SetBodyState set;
    set.mutable_body()->set_id(probe);
    set.mutable_position()->set_x(-100);
    set.mutable_position()->set_y(5);
    set.mutable_linear_velocity()->set_x(speed);
    {
      std::lock_guard lock(pending.mutex);
      pending.waiting = true;
      pending.speed = speed;
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
