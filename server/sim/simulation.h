// The simulation: one World stepped at a fixed rate on a thread of its own,
// fed by a queue of commands and publishing snapshots of the poses.
//
// Tick n ends at the absolute deadline t0 + n * dt on the steady clock, so
// the rate does not drift. At each tick the sim thread drains the command
// queue and applies the commands, steps the world once, and, when a
// subscription is due, publishes a Snapshot. A tick that finishes late is
// followed at once by the next; a sim that falls more than
// max_catch_up_ticks behind skips the missed ticks and counts them as
// overruns. The sim thread never waits on anything but its clock.
//
// Thread: submit(), request_snapshot(), set_publish_periods() and the
// read-only accessors may be called from any thread. run_tick() is for tests
// and replays that step without the clock, and only while not started.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "physics/world.h"
#include "sim/body_directory.h"
#include "sim/command.h"
#include "sim/snapshot.h"
#include "sim/status.h"
#include "sim/timed_loads.h"
#include "tumble/v1/scene.pb.h"

namespace tumble::sim {

struct SimConfig {
  double tick_rate_hz = 240;
  std::uint32_t max_catch_up_ticks = 8;  // late ticks run back to back before the rest are skipped
};

// Receives each published snapshot on the sim thread; must not block.
using SnapshotListener = std::function<void(std::shared_ptr<const Snapshot>)>;

class Simulation {
 public:
  // Builds the world of `scene`; fails with a message naming the body and
  // field when the scene does not describe a valid world.
  static Status create(const tumble::v1::Scene& scene, const SimConfig& config,
                       std::unique_ptr<Simulation>* out);
  ~Simulation();

  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  // Set before start(); called with each published snapshot.
  void set_snapshot_listener(SnapshotListener listener);

  // Starts the sim thread.
  void start();
  // Stops and joins the sim thread. Idempotent.
  void stop();

  // Queues a checked request; it is applied at the start of the next tick
  // and its reply handed to command.reply.
  void submit(Command command);

  // Makes the next tick publish a snapshot whatever the periods are.
  void request_snapshot();

  // The periods, in ticks, of the active subscriptions: a snapshot is
  // published after every tick that one of them divides.
  void set_publish_periods(std::vector<std::uint32_t> periods);

  // Applies queued commands, steps once and publishes if due.
  void run_tick();

  double tick_rate_hz() const { return config_.tick_rate_hz; }
  std::uint64_t tick() const { return tick_.load(std::memory_order_relaxed); }
  double sim_time() const { return sim_time_.load(std::memory_order_relaxed); }
  std::uint32_t body_count() const { return body_count_.load(std::memory_order_relaxed); }
  // Ticks skipped because the sim fell too far behind its clock.
  std::uint64_t overruns() const { return overruns_.load(std::memory_order_relaxed); }

  // The current names and shapes of the bodies.
  std::shared_ptr<const BodyDirectory> directory() const;

  // The world, for tests that run the sim with run_tick(); not while started.
  const physics::World& world() const { return world_; }

 private:
  explicit Simulation(const SimConfig& config);

  void run_loop();
  void apply(Command& command);
  tumble::v1::ServerMessage apply_force(const tumble::v1::ClientMessage& message);
  tumble::v1::ServerMessage apply_torque(const tumble::v1::ClientMessage& message);
  tumble::v1::ServerMessage apply_impulse(const tumble::v1::ClientMessage& message);
  tumble::v1::ServerMessage list_bodies(const tumble::v1::ClientMessage& message) const;
  void publish();
  bool publish_due();
  std::uint32_t duration_ticks(bool has_seconds, double seconds, bool has_ticks, std::uint32_t ticks) const;

  const SimConfig config_;
  const double dt_;  // s, 1 / tick rate

  // Sim thread state.
  physics::World world_;
  TimedLoads loads_;
  std::shared_ptr<const BodyDirectory> directory_;
  std::vector<Command> draining_;
  std::vector<std::uint32_t> periods_;  // the sim thread's copy of publish_periods_
  std::uint64_t next_tick_ = 0;         // sim-thread copy of tick_
  SnapshotListener listener_;

  // Shared with other threads.
  CommandQueue commands_;
  std::mutex periods_mutex_;
  std::vector<std::uint32_t> publish_periods_;
  bool periods_changed_ = false;
  std::atomic<bool> snapshot_requested_{false};
  std::atomic<std::uint64_t> tick_{0};
  std::atomic<double> sim_time_{0};
  std::atomic<std::uint32_t> body_count_{0};
  std::atomic<std::uint64_t> overruns_{0};

  mutable std::mutex directory_mutex_;
  std::shared_ptr<const BodyDirectory> shared_directory_;  // guarded; directory_ as other threads see it

  std::mutex run_mutex_;
  std::condition_variable run_wakeup_;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace tumble::sim
