#include "sim/simulation.h"

#include <algorithm>
#include <cmath>

#include "sim/body_spec.h"
#include "sim/joint_spec.h"
#include "sim/log.h"
#include "sim/log_text.h"
#include "sim/reply.h"
#include "sim/request_check.h"
#include "sim/world_state.h"

namespace tumble::sim {
Status Simulation::create(const tumble::v1::Scene& scene, const SimConfig& config, std::unique_ptr<Simulation>* out) {
  if (!std::isfinite(config.tick_rate_hz) || config.tick_rate_hz < kMinTickRateHz ||
      config.tick_rate_hz > kMaxTickRateHz) {
    return Status::error("tick rate must be from 1 to 10000 Hz");
  }
  if (static_cast<std::uint64_t>(scene.bodies_size()) > config.max_bodies) {
    return Status::error("the scene has " + std::to_string(scene.bodies_size()) + " bodies, more than the " +
                         std::to_string(config.max_bodies) + " allowed");
  }
  if (static_cast<std::uint64_t>(scene.joints_size()) > config.max_joints) {
    return Status::error("the scene has " + std::to_string(scene.joints_size()) + " joints, more than the " +
                         std::to_string(config.max_joints) + " allowed");
  }
  std::unique_ptr<Simulation> sim(new Simulation(scene, config));
  BodyDirectory directory;
  if (Status status = sim->build_world(&sim->world_, &directory, &sim->joints_); !status.ok()) return status;
  sim->set_directory(std::move(directory));
  sim->refresh_body_count();
  *out = std::move(sim);
  return {};
}

Status Simulation::create_from_state(const tumble::v1::WorldState& state, const SimConfig& config,
                                     std::unique_ptr<Simulation>* out) {
  if (!std::isfinite(state.tick_rate_hz()) || state.tick_rate_hz() < kMinTickRateHz ||
      state.tick_rate_hz() > kMaxTickRateHz) {
    return Status::error("tick_rate_hz: must be from 1 to 10000 Hz");
  }
  if (!std::isfinite(state.sim_time()) || state.sim_time() < 0) {
    return Status::error("sim_time: must be a finite number >= 0");
  }
  if (static_cast<std::uint64_t>(state.bodies_size()) > config.max_bodies) {
    return Status::error("the saved world has " + std::to_string(state.bodies_size()) + " bodies, more than the " +
                         std::to_string(config.max_bodies) + " allowed");
  }
  if (static_cast<std::uint64_t>(state.joints_size()) > config.max_joints) {
    return Status::error("the saved world has " + std::to_string(state.joints_size()) + " joints, more than the " +
                         std::to_string(config.max_joints) + " allowed");
  }
  SimConfig resumed = config;
  resumed.tick_rate_hz = state.tick_rate_hz();
  std::unique_ptr<Simulation> sim(new Simulation(restorable_scene(state.scene()), resumed));
  BodyDirectory directory;
  if (Status status = restore_world(state, &sim->world_, &directory, &sim->joints_, &sim->loads_); !status.ok()) {
    return status;
  }
  sim->set_directory(std::move(directory));
  sim->refresh_body_count();
  // The clock goes on from the saved tick; sim time is counted from there.
  sim->next_tick_ = state.tick();
  sim->rate_since_tick_ = state.tick();
  sim->rate_since_time_ = state.sim_time();
  sim->tick_.store(state.tick(), std::memory_order_relaxed);
  sim->sim_time_.store(state.sim_time(), std::memory_order_relaxed);
  sim->paused_ = state.paused();
  sim->paused_flag_.store(state.paused(), std::memory_order_relaxed);
  *out = std::move(sim);
  return {};
}

void Simulation::capture(tumble::v1::WorldState* state) const {
  capture_without_scene(state);
  *state->mutable_scene() = *scene_;
}

void Simulation::capture_without_scene(tumble::v1::WorldState* state) const {
  state->Clear();
  if (const std::size_t left_out = capture_world(world_, directory_, joints_, loads_, state); left_out > 0) {
    sim_log().error("left {} bodies out of the saved world at tick {}: their states are not finite or out of range",
                    left_out, next_tick_);
  }
  state->set_tick(next_tick_);
  state->set_sim_time(time_of(next_tick_));
  state->set_tick_rate_hz(tick_rate_hz());
  state->set_paused(paused_);
}

void Simulation::set_journal(JournalWriter* journal) { record_.set_journal(journal); }

void Simulation::set_checkpoints(std::chrono::steady_clock::duration interval, RunRecord::CheckpointSink sink) {
  // The state is on an arena (RunRecord): it points at the scene rather
  // than copying it (a third of a checkpoint's bytes and more than half its
  // capture), and keeps the scene alive as long as it lives.
  record_.set_checkpoints(interval, std::move(sink), [this](tumble::v1::WorldState* state) {
    capture_without_scene(state);
    state->unsafe_arena_set_allocated_scene(const_cast<tumble::v1::Scene*>(scene_.get()));
    return std::shared_ptr<const void>(scene_);
  });
}

Simulation::Simulation(const tumble::v1::Scene& scene, const SimConfig& config)
    : config_(config),
      scene_(std::make_shared<const tumble::v1::Scene>(scene)),
      dt_(1.0 / config.tick_rate_hz),
      tick_rate_hz_(config.tick_rate_hz),
      loop_(config.max_catch_up_ticks) {}

Simulation::~Simulation() { stop(); }

Status Simulation::build_world(physics::World* world, BodyDirectory* directory, JointDirectory* joints) const {
  const tumble::v1::Vec3& g = scene_->gravity();
  world->set_gravity(physics::Vec3(g.x(), g.y(), g.z()));
  for (int i = 0; i < scene_->bodies_size(); ++i) {
    const tumble::v1::BodySpec& spec = scene_->bodies(i);
    const std::string where = "bodies[" + std::to_string(i) + "]";
    physics::BodyDesc desc;
    if (Status status = body_desc_from_spec(spec, where, &desc); !status.ok()) return status;
    if (!spec.name().empty() && directory->id_of(spec.name()) != physics::kInvalidBodyId) {
      return Status::error(where + ".name: '" + log_text(spec.name()) + "' is used by another body");
    }
    const physics::BodyId id = world->add_body(desc);
    directory->add(id, BodyEntry{spec.name(), spec.shape(), world->mass(id)});
  }
  // Joints after every body, so that one may join bodies listed after it;
  // their points and axes are read at the bodies' scene poses.
  for (int i = 0; i < scene_->joints_size(); ++i) {
    const tumble::v1::JointSpec& spec = scene_->joints(i);
    const std::string where = "joints[" + std::to_string(i) + "]";
    // A named joint is named at the end of its message too, as a person looks for it.
    const std::string named = spec.name().empty() ? "" : " (joint '" + log_text(spec.name()) + "')";
    physics::JointDesc desc;
    if (Status status = joint_desc_from_spec(spec, where, *world, *directory, &desc); !status.ok()) {
      return Status::error(status.message() + named);
    }
    if (!spec.name().empty() && joints->id_of(spec.name()) != physics::kInvalidJointId) {
      return Status::error(where + ".name: '" + log_text(spec.name()) + "' is used by another joint");
    }
    const physics::JointId id = world->add_joint(desc);
    joints->add(id, JointEntry{spec.name(), desc.body_a, desc.body_b});
  }
  return {};
}

physics::BodyId Simulation::resolve(const tumble::v1::BodyRef& ref) const {
  std::lock_guard lock(directory_mutex_);
  return directory_.resolve(ref);
}

void Simulation::set_directory(BodyDirectory directory) {
  std::lock_guard lock(directory_mutex_);
  directory_ = std::move(directory);
}

void Simulation::refresh_body_count() {
  body_count_.store(static_cast<std::uint32_t>(world_.body_count()), std::memory_order_relaxed);
}

double Simulation::time_of(std::uint64_t tick) const {
  return rate_since_time_ + static_cast<double>(tick - rate_since_tick_) * dt_;
}

void Simulation::add_snapshot_listener(SnapshotListener listener) { listeners_.push_back(std::move(listener)); }

void Simulation::add_event_listener(WorldEventListener listener) { event_listeners_.push_back(std::move(listener)); }

void Simulation::add_stats_hook(StatsHook hook) { stats_hooks_.push_back(std::move(hook)); }

void Simulation::start() {
  loop_.start(
      // The physics helpers start here so they inherit the sim thread's
      // scheduling (SCHED_FIFO under --realtime-priority): the step waits for
      // an island a helper has begun, and a helper behind ordinary processes
      // would stall it.
      [this] { world_.set_thread_count(config_.physics_threads); }, [this](double late_ms) { run_pass(late_ms); },
      [this] { return tick_rate_hz(); });
}

void Simulation::stop() {
  loop_.stop();
  record_.finish(next_tick_);
}

void Simulation::submit(Command command) {
  if (command.message.kind_case() == ClientMessage::kSpawnBody) {
    auto desc = std::make_shared<physics::BodyDesc>();
    if (Status status = body_desc_from_spec(command.message.spawn_body().body(), "body", desc.get()); !status.ok()) {
      if (command.reply) command.reply(error_reply(command.message, tumble::v1::INVALID_ARGUMENT, status.message()));
      return;
    }
    command.body_desc = std::move(desc);
  }
  commands_.push(std::move(command));
  // Paused, the loop's passes only apply commands: one at once rather than
  // at the next tick's deadline. Running, the command waits for the tick
  // (a pass there steps the world).
  if (paused_flag_.load(std::memory_order_relaxed)) loop_.wake();
}

void Simulation::request_snapshot() {
  snapshot_requested_.store(true, std::memory_order_relaxed);
  if (paused_flag_.load(std::memory_order_relaxed)) loop_.wake();
}

PublishSource Simulation::add_publish_source() {
  std::lock_guard lock(interest_mutex_);
  if (sources_.size() >= kMaxPublishSources) return 0;
  sources_.emplace_back();
  return static_cast<PublishSource>(sources_.size() - 1);
}

void Simulation::set_publish_interest(std::vector<PublishInterest> interest, std::size_t early_bodies,
                                      PublishSource source) {
  std::lock_guard lock(interest_mutex_);
  if (source >= sources_.size()) return;
  sources_[source] = {std::move(interest), early_bodies};
  interest_changed_ = true;
}

void Simulation::set_sleep_events_wanted(bool wanted, PublishSource source) {
  if (source >= kMaxPublishSources) return;
  const std::uint64_t bit = std::uint64_t{1} << source;
  if (wanted) {
    sleep_events_sources_.fetch_or(bit, std::memory_order_relaxed);
  } else {
    sleep_events_sources_.fetch_and(~bit, std::memory_order_relaxed);
  }
}

void Simulation::run_pass(double late_ms) {
  timing_.record_start_late(late_ms);
  pass(std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(dt_)));
  record_.checkpoint_if_due();
}

void Simulation::run_tick() { pass(Clock::duration::zero()); }

void Simulation::pass(Clock::duration step_budget) {
  // CPU time read inside the wall-clock span, so a tick's is never above its wall time.
  Clock::time_point started = Clock::now();
  double cpu_started = TickTiming::thread_cpu_ms();
  commands_.drain(draining_);
  for (Command& command : draining_) {
    record_.record(next_tick_, command.message);
    apply(command);
  }
  if (!draining_.empty()) record_.note_change();
  draining_.clear();
  record_.flush();

  if (!paused_) {
    advance();
    const double cpu_now = TickTiming::thread_cpu_ms();
    const Clock::time_point now = Clock::now();
    timing_.record_step(milliseconds(now - started), cpu_now - cpu_started);
  } else if (steps_left_ > 0) {
    // A Step: its ticks back to back, for at most step_budget of wall time (at least one tick).
    const Clock::time_point budget_end = started + step_budget;
    do {
      advance();
      const double cpu_now = TickTiming::thread_cpu_ms();
      const Clock::time_point now = Clock::now();
      timing_.record_step(milliseconds(now - started), cpu_now - cpu_started);
      started = Clock::now();
      cpu_started = TickTiming::thread_cpu_ms();
    } while (paused_ && steps_left_ > 0 && started < budget_end);
  } else {
    // No step: show edits at once, and serve a new subscriber's first frame.
    if (edited_ && sleep_.watching()) sleep_.scan(world_, directory_, next_tick_, &events_);
    flush_events();
    const bool requested = snapshot_requested_.exchange(false, std::memory_order_relaxed);
    if (edited_ || requested) {
      take_interest();  // no plan here: whether the joints are wanted
      publish(nullptr, edited_);
    }
    edited_ = false;
  }
  timing_.record_clock(Clock::now(), time_of(next_tick_));
}

void Simulation::advance() {
  record_.note_change();
  loads_.apply(world_);
  step_loads_.apply(world_);  // empty unless a Step brought its own
  world_.step(dt_);
  ++next_tick_;
  tick_.store(next_tick_, std::memory_order_relaxed);
  sim_time_.store(time_of(next_tick_), std::memory_order_relaxed);
  if (!world_.broken_joints().empty()) remove_broken_joints();
  if (!world_.diverged_bodies().empty()) remove_diverged();

  if (sleep_events_sources_.load(std::memory_order_relaxed) == 0) {
    sleep_.stop();
  } else if (!sleep_.watching()) {
    sleep_.start(world_);  // only changes from now on are events
  } else {
    sleep_.scan(world_, directory_, next_tick_, &events_);
  }

  if (steps_left_ > 0 && --steps_left_ == 0) end_step(tumble::v1::STEP_END_COMPLETED);
  flush_events();
  const PublishPlan::Due due = plan_publish();
  if (due == PublishPlan::Due::nothing) {
    edited_ = false;
    return;
  }
  // With a large snapshot due, the small streams' bodies (plan_.early()) go
  // first, in a snapshot of their own, or the copy of the large one would
  // hold their frames back by as long as the large copy takes, on every tick
  // a stream of the whole world is due.
  if (!plan_.early().empty()) publish(&plan_.early(), false, true);
  publish(due == PublishPlan::Due::every_body ? nullptr : &plan_.collect_wanted(), false);
  edited_ = false;
}

void Simulation::flush_events() {
  if (events_.empty()) return;
  if (!event_listeners_.empty()) {
    const auto batch = std::make_shared<const WorldEvents>(std::move(events_));
    for (const WorldEventListener& listener : event_listeners_) listener(batch);
  }
  events_.clear();
}

void Simulation::take_interest() {
  std::lock_guard lock(interest_mutex_);
  if (!interest_changed_) return;
  // The union of the sources: the plan publishes for each interest alike.
  std::vector<PublishInterest> merged;
  std::size_t early_bodies = 0;
  joints_wanted_ = false;
  for (const SourceInterest& source : sources_) {
    merged.insert(merged.end(), source.interest.begin(), source.interest.end());
    if (!source.interest.empty()) early_bodies = std::max(early_bodies, source.early_bodies);
    for (const PublishInterest& interest : source.interest) joints_wanted_ = joints_wanted_ || interest.joints;
  }
  plan_.set_interests(std::move(merged), early_bodies);
  interest_changed_ = false;
}

PublishPlan::Due Simulation::plan_publish() {
  take_interest();
  const bool requested = snapshot_requested_.exchange(false, std::memory_order_relaxed);
  return plan_.plan(next_tick_, world_.body_count(), requested);
}

void Simulation::publish(const std::vector<physics::BodyId>* bodies, bool out_of_band, bool more_follows) {
  if (listeners_.empty()) return;
  auto snapshot = std::make_shared<Snapshot>();
  // Every snapshot carries the joints while a stream wants them (they are
  // few beside the bodies): a stream of joints is then served from any.
  if (joints_wanted_) copy_joints(world_, *snapshot);
  snapshot->tick = next_tick_;
  snapshot->sim_time = time_of(next_tick_);
  snapshot->out_of_band = out_of_band;
  snapshot->more_follows = more_follows;
  const bool every_body = bodies == nullptr || plan_.copies_every_body(bodies->size(), world_.body_count());
  snapshot->all_bodies = every_body;
  std::size_t n = world_.body_count();
  if (!every_body) {
    snapshot->wanted = *bodies;
    n = static_cast<std::size_t>(
        std::count_if(bodies->begin(), bodies->end(), [this](physics::BodyId id) { return world_.contains(id); }));
  }
  snapshot->ids.resize(n);
  snapshot->positions.resize(3 * n);
  snapshot->orientations.resize(4 * n);
  snapshot->linear_velocities.resize(3 * n);
  snapshot->angular_velocities.resize(3 * n);
  if (every_body) {
    world_.copy_poses(snapshot->ids.data(), snapshot->positions.data(), snapshot->orientations.data(),
                      snapshot->linear_velocities.data(), snapshot->angular_velocities.data());
    hand_over(std::move(snapshot));
    return;
  }
  std::size_t next_wanted = 0;
  for (std::size_t i = 0; i < n; ++i) {
    while (!world_.contains((*bodies)[next_wanted])) ++next_wanted;  // removed since the streams asked
    const physics::BodyId id = (*bodies)[next_wanted++];
    snapshot->ids[i] = id;
    const physics::Vec3& x = world_.position(id);
    const physics::Quat& q = world_.orientation(id);
    const physics::Vec3 v = world_.linear_velocity(id);
    const physics::Vec3 w = world_.angular_velocity(id);
    std::copy(x.data(), x.data() + 3, snapshot->positions.begin() + static_cast<std::ptrdiff_t>(3 * i));
    std::copy(v.data(), v.data() + 3, snapshot->linear_velocities.begin() + static_cast<std::ptrdiff_t>(3 * i));
    std::copy(w.data(), w.data() + 3, snapshot->angular_velocities.begin() + static_cast<std::ptrdiff_t>(3 * i));
    double* o = snapshot->orientations.data() + 4 * i;
    o[0] = q.w();
    o[1] = q.x();
    o[2] = q.y();
    o[3] = q.z();
  }
  hand_over(std::move(snapshot));
}

void Simulation::copy_joints(const physics::World& world, Snapshot& snapshot) {
  snapshot.has_joints = true;
  const std::size_t n = world.joint_count();
  snapshot.joint_ids.resize(n);
  for (std::size_t i = 0; i < n; ++i) snapshot.joint_ids[i] = world.joint_id_at(i);
  std::sort(snapshot.joint_ids.begin(), snapshot.joint_ids.end());
  snapshot.joint_positions.resize(n);
  snapshot.joint_speeds.resize(n);
  snapshot.joint_motor_impulses.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const physics::JointState state = world.joint_state(snapshot.joint_ids[i]);
    snapshot.joint_positions[i] = state.position;
    snapshot.joint_speeds[i] = state.speed;
    snapshot.joint_motor_impulses[i] = state.motor_impulse;
  }
}

void Simulation::hand_over(std::shared_ptr<const Snapshot> snapshot) {
  for (const SnapshotListener& listener : listeners_) listener(snapshot);
}

}  // namespace tumble::sim
