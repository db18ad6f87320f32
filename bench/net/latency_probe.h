// Force-to-visible latency: how long after a client sends a command that
// changes a body the first frame showing the change reaches a subscriber.
//
// A controller changes the probe body every 20 to 70 ms (varied, so that
// the sends fall at every phase of the tick), and a watcher on a
// connection of its own, already subscribed to a stream that shows the
// probe, reads frames on its own thread and stamps the first one that
// shows the change. The figure is the tick's wait (a command is applied at
// the start of the next tick, up to one tick period away), the wait for a
// tick on which the watcher's stream is due, the step, the frame's
// encoding and its trip to the watcher, as a client sees them.
//
// The change is one of two (ProbeSignal): a new velocity along x with the
// probe put back at its start (the watcher's stream must carry
// velocities), or a new position along x at rest (any stream of poses, such
// as a pose-only stream of every body over NATS; a DELTA frame carries the
// probe only when it moved).
//
// measure_latency() does it over TCP with a watcher subscribed to the probe
// alone; measure_latency_over() over any two transports, e.g. a request on
// a world's NATS .rpc subject and a NATS pose stream.
#pragma once

#include <chrono>
#include <cstdint>
#include <vector>

#include "load_connection.h"
#include "tumble/v1/protocol.pb.h"
#include "tumble_client/transport.h"

namespace tumble::bench {

// What the controller changes, and what the watcher looks for.
enum class ProbeSignal {
  velocity,  // 0.5 to 4 m/s along x, the position put back at (-100, 5, 0)
  position,  // x from -99.75 to -98 m in steps of 0.25, at rest
};

// One change seen: when it was sent and how long until a frame showed it.
struct LatencySample {
  double sent_s = 0;               // seconds after the measurement's start
  double latency_ms = 0;           // send to the arrival of the first frame showing it
  std::uint64_t applied_tick = 0;  // the tick the server applied it at (its Ack); 0 when the Ack failed
  std::uint64_t visible_tick = 0;  // the tick of the first frame showing it
};

struct LatencyResult {
  std::vector<double> latencies_ms;    // one per change seen
  std::vector<LatencySample> samples;  // the same changes, in the order they were sent
  std::uint64_t lost = 0;              // changes not seen within 2 s
  std::uint64_t errors = 0;            // failed requests or a broken watcher stream
};

// Over TCP: connects a controller and a watcher to `target`, subscribes the
// watcher to the probe alone at `watch_rate_hz` (the tick rate: a frame
// every tick) with velocities in `encoding`, and measures the velocity
// signal from `start` until `end`.
LatencyResult measure_latency(const LoadTarget& target, std::uint32_t probe, double watch_rate_hz,
                              tumble::v1::PoseEncoding encoding, std::chrono::steady_clock::time_point start,
                              std::chrono::steady_clock::time_point end);

// Over `controller` (its requests change the probe) and `watcher` (already
// subscribed to a stream that holds the probe and shows `signal`), from
// `start` until `end`. Each is used on one thread only: the watcher on one
// of its own.
LatencyResult measure_latency_over(client::Transport& controller, client::Transport& watcher, std::uint32_t probe,
                                   ProbeSignal signal, std::chrono::steady_clock::time_point start,
                                   std::chrono::steady_clock::time_point end);

// The p-th quantile (0 < p <= 1) of `values`, nearest rank; 0 when empty.
double percentile(std::vector<double> values, double p);

}  // namespace tumble::bench
