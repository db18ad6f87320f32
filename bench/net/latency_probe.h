// Force-to-visible latency: how long after a client sends a command that
// changes a body the first frame showing the change reaches a subscriber.
//
// A controller sets the probe body's velocity to a new value (cycling
// through 0.5 to 4 m/s along x, and putting it back at its start) every 20
// to 70 ms, varied so that the sends fall at every phase of the tick. A
// watcher on a connection of its own, subscribed to the probe alone at the
// tick rate (a frame every tick), reads frames on its own thread and stamps
// the first one whose velocity is the new one. The figure is the tick's
// wait (a command is applied at the start of the next tick, up to one tick
// period away), the step, the frame's encoding and the trip over the
// socket, as a client sees them; the goal is one tick + 2 ms.
#pragma once

#include <chrono>
#include <cstdint>
#include <vector>

#include "load_connection.h"
#include "tumble/v1/protocol.pb.h"

namespace tumble::bench {

// One change seen: when it was sent and how long until a frame showed it.
struct LatencySample {
  double sent_s = 0;               // seconds after the measurement's start
  double latency_ms = 0;           // send to the arrival of the first frame showing it
  std::uint64_t applied_tick = 0;  // the tick the server applied it at (its Ack); 0 when the Ack failed
};

struct LatencyResult {
  std::vector<double> latencies_ms;    // one per change seen
  std::vector<LatencySample> samples;  // the same changes, in the order they were sent
  std::uint64_t lost = 0;              // changes not seen within 2 s
  std::uint64_t errors = 0;            // failed requests or a broken watcher stream
};

// Runs from `start` until `end`. `tick_rate_hz` is the server's; the
// watcher's stream is in `encoding`.
LatencyResult measure_latency(const LoadTarget& target, std::uint32_t probe, double tick_rate_hz,
                              tumble::v1::PoseEncoding encoding, std::chrono::steady_clock::time_point start,
                              std::chrono::steady_clock::time_point end);

// The p-th quantile (0 < p <= 1) of `values`, nearest rank; 0 when empty.
double percentile(std::vector<double> values, double p);

}  // namespace tumble::bench
