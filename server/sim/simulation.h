// The simulation: one World stepped at a fixed rate on a thread of its own,
// fed by a queue of commands and publishing snapshots of the poses and the
// events of each tick.
//
// Tick n ends at the absolute deadline t0 + n * dt on the steady clock, so
// the rate does not drift. At each tick the sim thread drains the command
// queue and applies the commands (sim/command_handlers.cpp), steps the
// world once, and, when a subscription is due, publishes a Snapshot of the
// bodies the due subscriptions read (sim/publish_plan.h). A tick that
// finishes late is followed at once by the next; a sim that falls more than
// max_catch_up_ticks behind skips the missed ticks and counts them as
// overruns (sim/tick_loop.h). The sim thread never waits on anything but
// its clock. The journal and checkpoints: sim/run_record.h.
//
// Paused, the loop keeps its cadence and keeps applying commands, but does
// not step: the tick stays put. A request submitted while paused wakes the
// loop for a pass at once (TickLoop::wake), so a lockstep client's Step is
// taken up as it arrives, not up to a tick period later. A Step request
// then runs its ticks back to back (at most one tick period of wall time
// per pass, so commands are still served between bursts), with its own
// forces and torques, and may be answered with the frame of its last tick. A Pause, Resume or Reset ends a Step under
// way, which is answered then with the tick it reached; so a Step runs only
// while paused, and a paused world's tick moves only through a Step. An
// edit of the world while paused is published at once as an out-of-band
// snapshot of the current tick.
//
// The tick and sim time only ever grow: Reset puts the bodies back but not
// the clock, and SetTickRate changes dt from the next tick on.
//
// Several consumers may read the sim side by side (the network front, a
// NATS link): each adds its listeners, and each states its own publish
// interest and sleep-event wish as a source of its own; the sim publishes
// for the union of the sources and hands every snapshot and event batch to
// every listener, which takes what it needs. The sim knows nothing of who
// they are.
//
// Thread: submit(), resolve(), request_snapshot(), set_publish_interest(),
// set_sleep_events_wanted(), add_publish_source() and the read-only
// accessors may be called from any thread. run_tick() is for tests and
// replays that step without the clock, and only while not started. The
// listeners and the stats hooks are added before start().
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "sim/body_directory.h"
#include "sim/body_loads.h"
#include "sim/command.h"
#include "sim/joint_directory.h"
#include "sim/journal.h"
#include "sim/publish_interest.h"
#include "sim/publish_plan.h"
#include "sim/run_record.h"
#include "sim/sleep_watch.h"
#include "sim/snapshot.h"
#include "sim/status.h"
#include "sim/tick_loop.h"
#include "sim/tick_timing.h"
#include "sim/world_event.h"
#include "tumble/physics/world.h"
#include "tumble/v1/scene.pb.h"
#include "tumble/v1/state.pb.h"

namespace tumble::sim {

struct SimConfig {
  double tick_rate_hz = 240;             // kMinTickRateHz to kMaxTickRateHz (request_check.h)
  std::uint32_t max_catch_up_ticks = 8;  // late ticks run back to back before the rest are skipped
  std::uint32_t max_bodies = 100000;     // SpawnBody beyond it is RESOURCE_EXHAUSTED
  std::uint32_t max_joints = 100000;     // AddJoint beyond it is RESOURCE_EXHAUSTED
  // The most bytes of BodyInfo one BodyList page holds (at least one body
  // always goes in): a reply a client can take in one read of its limit.
  std::size_t list_page_bytes = std::size_t{1} << 20;
  // Threads that solve the world's contact islands, the sim thread included
  // (physics::World::set_thread_count); the helpers start with the sim thread.
  int physics_threads = 1;
};

// Receives each published snapshot on the sim thread; must not block.
using SnapshotListener = std::function<void(std::shared_ptr<const Snapshot>)>;

// Adds a consumer's own figures to a GetStats reply, on the sim thread;
// must not block (reads counters).
using StatsHook = std::function<void(tumble::v1::Stats*)>;

// One consumer's publish interest and sleep-event wish (see
// set_publish_interest): 0 is there from the start, more come from
// add_publish_source().
using PublishSource = std::uint32_t;
inline constexpr PublishSource kMaxPublishSources = 64;

class Simulation {
 public:
  // Builds the world of `scene`, which it keeps for Reset; fails with a
  // message naming the body or joint and field when the scene does not
  // describe a valid world or holds more than max_bodies bodies or
  // max_joints joints.
  static Status create(const tumble::v1::Scene& scene, const SimConfig& config, std::unique_ptr<Simulation>* out);
  // Resumes a saved world exactly (world_state.h): bodies, joints, loads, tick, sim
  // time, tick rate (config.tick_rate_hz is ignored) and paused; Reset goes
  // back to the scene saved with it.
  static Status create_from_state(const tumble::v1::WorldState& state, const SimConfig& config,
                                  std::unique_ptr<Simulation>* out);
  ~Simulation();

  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  // Added before start(); each is called with every published snapshot, in
  // the order they were added.
  void add_snapshot_listener(SnapshotListener listener);

  // Added before start(); each is called with the events of each tick that
  // has any. Spawns, removals and resets are always reported; sleep changes
  // only while a source wants them (set_sleep_events_wanted).
  void add_event_listener(WorldEventListener listener);

  // Added before start(); each fills in its part of every GetStats reply.
  void add_stats_hook(StatsHook hook);

  // Set before start(): every request that can change the world is
  // recorded with the tick it is executed at, and the end of the run when
  // the simulation stops. Not owned; must outlive the simulation.
  void set_journal(JournalWriter* journal);

  // Set before start(): every `interval` of wall time (while the world
  // changes) the sim thread captures the world and hands it to `sink` with
  // the time the capture took; `sink` must not block (e.g. StateSaver::offer).
  void set_checkpoints(std::chrono::steady_clock::duration interval, RunRecord::CheckpointSink sink);

  // The whole world as it is now. On the sim thread, or while not started.
  void capture(tumble::v1::WorldState* state) const;

  // Starts the sim thread.
  void start();
  // Stops and joins the sim thread, and ends the journal. Idempotent.
  void stop();

  // Queues a checked request; it is applied at the start of the next tick
  // and its reply handed to command.reply. A SpawnBody's spec is converted
  // here, on the calling thread; if it does not describe a body the reply
  // (INVALID_ARGUMENT) is given at once and nothing is queued.
  void submit(Command command);

  // The id of the body `ref` names now, or kInvalidBodyId.
  physics::BodyId resolve(const tumble::v1::BodyRef& ref) const;

  // Makes the next pass of the loop publish a snapshot of every body,
  // whatever the interest is, paused or not.
  void request_snapshot();

  // A publish source of its own for another consumer; at most
  // kMaxPublishSources in all (0 included), beyond which it returns 0.
  PublishSource add_publish_source();

  // What the active subscriptions of `source` read: a snapshot is published
  // after every tick that one of the periods of any source divides, holding
  // the bodies of the interests due at that tick (every body when one of
  // them asks for all). Interests of at most early_bodies bodies go early
  // (sim/publish_plan.h); the publisher draws that line, and the sim uses
  // the largest line a source gives. Replaces the source's previous
  // interest; every source empty: nothing is published but what
  // request_snapshot() and edits while paused ask for.
  void set_publish_interest(std::vector<PublishInterest> interest, std::size_t early_bodies, PublishSource source = 0);

  // Whether to watch for bodies falling asleep and waking (a scan of the
  // bodies after every step): while any source wants those events.
  void set_sleep_events_wanted(bool wanted, PublishSource source = 0);

  // One pass of the loop without the clock: applies queued commands, then,
  // unless paused, steps once and publishes if due; paused, it runs one tick
  // of a Step under way, or publishes an edit or a requested snapshot of the
  // current tick. One tick a call, whatever the wall time, so a test or a
  // replay executes each command at the same tick on any machine.
  void run_tick();

  double tick_rate_hz() const { return tick_rate_hz_.load(std::memory_order_relaxed); }
  std::uint64_t tick() const { return tick_.load(std::memory_order_relaxed); }
  double sim_time() const { return sim_time_.load(std::memory_order_relaxed); }
  std::uint32_t body_count() const { return body_count_.load(std::memory_order_relaxed); }
  bool paused() const { return paused_flag_.load(std::memory_order_relaxed); }
  // Ticks skipped because the sim fell too far behind its clock.
  std::uint64_t overruns() const { return loop_.overruns(); }

  // The world and its loads, for tests that run the sim with run_tick();
  // not while started.
  const physics::World& world() const { return world_; }
  const BodyLoads& loads() const { return loads_; }

 private:
  using Clock = std::chrono::steady_clock;
  using ServerMessage = tumble::v1::ServerMessage;
  using ClientMessage = tumble::v1::ClientMessage;

  Simulation(const tumble::v1::Scene& scene, const SimConfig& config);

  // Fills an empty world and directories with the bodies and joints of scene_.
  Status build_world(physics::World* world, BodyDirectory* directory, JointDirectory* joints) const;
  // capture() but the scene.
  void capture_without_scene(tumble::v1::WorldState* state) const;

  // One pass of the clock loop on the sim thread: a Step under way runs as
  // many ticks as one tick period of wall time allows.
  void run_pass(double late_ms);
  // One pass (run_tick()), with a Step under way running its ticks back to
  // back for up to step_budget of wall time, and at least one.
  void pass(Clock::duration step_budget);
  // One step: loads, World::step, the tick, sleep changes, a Step's
  // countdown, events and the snapshot if due.
  void advance();
  // Publishes a snapshot of `bodies` (sorted), or of every body when null
  // or when they are most of the world, with every joint's state when a
  // stream wants it; more_follows: a larger snapshot of this tick comes
  // next.
  void publish(const std::vector<physics::BodyId>* bodies, bool out_of_band, bool more_follows = false);
  // Copies every joint's state of `world` into the snapshot, in ascending
  // id order (for a published snapshot and a Step's frame alike).
  static void copy_joints(const physics::World& world, Snapshot& snapshot);
  // Gives a snapshot to every listener.
  void hand_over(std::shared_ptr<const Snapshot> snapshot);
  // Takes up the latest interest and a requested snapshot, and plans the
  // snapshots of this tick in plan_.
  PublishPlan::Due plan_publish();
  // Takes up the sources' interests in plan_ and joints_wanted_ if they
  // changed.
  void take_interest();

  void flush_events();
  void set_directory(BodyDirectory directory);
  void refresh_body_count();
  double time_of(std::uint64_t tick) const;

  // The command handlers (sim/command_handlers.cpp). apply() executes one
  // command on the sim thread and hands its reply to command.reply.
  void apply(Command& command);
  void note_spawned(physics::BodyId id, const std::string& name, std::uint64_t tick);
  // Takes a body out of the world, its loads and the directory, with a
  // body_removed event of `tick`, after a joint_removed event for each of
  // its joints.
  void remove_from_world(physics::BodyId id, std::uint64_t tick);
  // A joint event of `tick` for the joint `id` of the joint directory.
  void note_joint(WorldEventKind kind, physics::JointId id, std::uint64_t tick);
  // After a step: the joints it broke (physics::World::broken_joints), with
  // a joint_broken and a joint_removed event each, out of the directory.
  void remove_broken_joints();
  // After a step: removes each body the step left diverged
  // (physics::World::diverged_bodies), with a body_diverged event, a log
  // line and a count, so no non-finite value stays in the world or reaches
  // a snapshot or a state file.
  void remove_diverged();
  // The tick whose state first shows an edit applied now: the next step's,
  // or the current one while paused.
  std::uint64_t edit_tick() const { return paused_ ? next_tick_ : next_tick_ + 1; }
  std::uint32_t duration_ticks(bool has_seconds, double seconds, bool has_ticks, std::uint32_t ticks) const;
  ServerMessage apply_force(const ClientMessage& message);
  ServerMessage apply_torque(const ClientMessage& message);
  ServerMessage apply_impulse(const ClientMessage& message);
  ServerMessage list_bodies(const ClientMessage& message) const;
  ServerMessage spawn_body(const Command& command);
  ServerMessage remove_body(const ClientMessage& message);
  ServerMessage set_body_state(const ClientMessage& message);
  ServerMessage add_joint(const ClientMessage& message);
  ServerMessage remove_joint(const ClientMessage& message);
  ServerMessage set_joint_motor(const ClientMessage& message);
  ServerMessage list_joints(const ClientMessage& message) const;
  ServerMessage clear_forces(const ClientMessage& message);
  ServerMessage pause(const ClientMessage& message);
  ServerMessage resume(const ClientMessage& message);
  // Empty when the Step is accepted: its Ack comes when its ticks are done
  // or end_step() cuts it short.
  std::optional<ServerMessage> step(Command& command);
  // Answers the Step under way, if any, with the tick reached, the ticks
  // left (steps_left_), `end` and, when it asked, the frame of that tick,
  // and forgets it and its loads.
  void end_step(tumble::v1::StepEnd end);
  // The FULL PoseFrame of step_frame_bodies_ (empty: every body) as they
  // are now, with every joint's state when `joints`.
  void fill_step_frame(tumble::v1::PoseFields fields, bool joints, tumble::v1::PoseFrame* frame) const;
  ServerMessage reset(const ClientMessage& message);
  ServerMessage set_tick_rate(const ClientMessage& message);
  ServerMessage stats(const ClientMessage& message) const;

  const SimConfig config_;
  // The world Reset goes back to. Never changed, so a checkpoint on the
  // writer's thread may read it in place rather than a copy.
  const std::shared_ptr<const tumble::v1::Scene> scene_;

  // Sim thread state.
  physics::World world_;
  BodyLoads loads_;
  BodyDirectory directory_;  // written under directory_mutex_, read freely on the sim thread
  JointDirectory joints_;    // the sim thread's only
  std::vector<Command> draining_;
  PublishPlan plan_;                   // holds the sim thread's copy of published_interest_
  std::uint64_t next_tick_ = 0;        // sim-thread copy of tick_
  double dt_;                          // s, 1 / tick rate
  std::uint64_t rate_since_tick_ = 0;  // the tick at which dt_ took effect
  double rate_since_time_ = 0;         // s, sim time at that tick
  bool paused_ = false;
  std::uint32_t steps_left_ = 0;                    // ticks of the Step under way; never above 0 while running
  Command step_command_;                            // the Step under way (empty when none), answered by end_step()
  BodyLoads step_loads_;                            // the Step under way's own forces and torques, dropped when it ends
  std::vector<physics::BodyId> step_frame_bodies_;  // Step.frame_bodies, resolved; empty: every body
  bool edited_ = false;                             // the world was edited since the last snapshot
  bool joints_wanted_ = false;                      // a stream wants the joints' states (PublishInterest::joints)
  std::uint64_t bodies_diverged_ = 0;               // removed by remove_diverged() since the start
  SleepWatch sleep_;                                // watching while sleep_events_wanted_
  WorldEvents events_;                              // of the tick being made
  TickTiming timing_;
  RunRecord record_;  // the journal and the checkpoints
  std::vector<SnapshotListener> listeners_;
  std::vector<WorldEventListener> event_listeners_;
  std::vector<StatsHook> stats_hooks_;

  // Shared with other threads.
  CommandQueue commands_;
  std::mutex interest_mutex_;
  // A source's interest as it last stated it.
  struct SourceInterest {
    std::vector<PublishInterest> interest;
    std::size_t early_bodies = 0;
  };
  std::vector<SourceInterest> sources_{1};  // by PublishSource; guarded by interest_mutex_
  bool interest_changed_ = false;           // guarded by interest_mutex_
  std::atomic<bool> snapshot_requested_{false};
  std::atomic<std::uint64_t> sleep_events_sources_{0};  // bit s: source s wants sleep events
  std::atomic<double> tick_rate_hz_;
  std::atomic<std::uint64_t> tick_{0};
  std::atomic<double> sim_time_{0};
  std::atomic<std::uint32_t> body_count_{0};
  std::atomic<bool> paused_flag_{false};
  mutable std::mutex directory_mutex_;  // guards directory_ against readers on other threads

  TickLoop loop_;  // the sim thread; last, so that it stops before the state it runs on goes
};

}  // namespace tumble::sim
