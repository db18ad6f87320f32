#include "sim/simulation.h"

#include <algorithm>
#include <cmath>

#include "sim/body_spec.h"
#include "sim/log.h"
#include "sim/request_check.h"
#include "sim/world_state.h"

namespace tumble::sim {
namespace {

using tumble::v1::ClientMessage;
using tumble::v1::ServerMessage;

physics::Vec3 to_vec3(const tumble::v1::Vec3& v) { return {v.x(), v.y(), v.z()}; }

void set_vec3(const physics::Vec3& v, tumble::v1::Vec3* out) {
  out->set_x(v.x());
  out->set_y(v.y());
  out->set_z(v.z());
}

ServerMessage ack(const ClientMessage& message, std::uint64_t applied_tick) {
  ServerMessage reply;
  reply.mutable_ack()->set_request_id(message.request_id());
  reply.mutable_ack()->set_applied_tick(applied_tick);
  return reply;
}

ServerMessage error(const ClientMessage& message, tumble::v1::ErrorCode code, std::string text) {
  ServerMessage reply;
  auto* e = reply.mutable_error();
  e->set_request_id(message.request_id());
  e->set_code(code);
  e->set_message(std::move(text));
  return reply;
}

ServerMessage unknown_body(const ClientMessage& message, const tumble::v1::BodyRef& ref) {
  return error(message, tumble::v1::UNKNOWN_BODY, "no " + BodyDirectory::describe(ref) + " in the world");
}

// The body-frame offset from the centre of mass of a point given in
// `frame`: p_body = R^T (r - x) for a world point.
physics::Vec3 body_point(const physics::World& world, physics::BodyId body, bool has_point,
                         const tumble::v1::Vec3& point, tumble::v1::Frame frame) {
  if (!has_point) return physics::Vec3::Zero();
  if (frame == tumble::v1::FRAME_BODY) return to_vec3(point);
  return world.orientation(body).conjugate() * (to_vec3(point) - world.position(body));
}

bool is_dynamic(const physics::World& world, physics::BodyId id) {
  return world.motion_type(id) == physics::MotionType::dynamic_body;
}

double milliseconds(std::chrono::steady_clock::duration d) {
  return std::chrono::duration<double, std::milli>(d).count();
}

}  // namespace

Status Simulation::create(const tumble::v1::Scene& scene, const SimConfig& config,
                          std::unique_ptr<Simulation>* out) {
  if (!std::isfinite(config.tick_rate_hz) || config.tick_rate_hz < kMinTickRateHz ||
      config.tick_rate_hz > kMaxTickRateHz) {
    return Status::error("tick rate must be from 1 to 10000 Hz");
  }
  if (static_cast<std::uint64_t>(scene.bodies_size()) > config.max_bodies) {
    return Status::error("the scene has " + std::to_string(scene.bodies_size()) + " bodies, more than the " +
                         std::to_string(config.max_bodies) + " allowed");
  }
  std::unique_ptr<Simulation> sim(new Simulation(scene, config));
  BodyDirectory directory;
  if (Status status = sim->build_world(&sim->world_, &directory); !status.ok()) return status;
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
  SimConfig resumed = config;
  resumed.tick_rate_hz = state.tick_rate_hz();
  std::unique_ptr<Simulation> sim(new Simulation(state.scene(), resumed));
  BodyDirectory directory;
  if (Status status = restore_world(state, &sim->world_, &directory, &sim->loads_); !status.ok()) return status;
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
  state->Clear();
  capture_world(world_, directory_, loads_, state);
  state->set_tick(next_tick_);
  state->set_sim_time(time_of(next_tick_));
  state->set_tick_rate_hz(tick_rate_hz());
  state->set_paused(paused_);
  *state->mutable_scene() = scene_;
}

void Simulation::set_journal(JournalWriter* journal) { record_.set_journal(journal); }

void Simulation::set_checkpoints(std::chrono::steady_clock::duration interval,
                                 std::function<void(std::shared_ptr<const tumble::v1::WorldState>)> sink) {
  record_.set_checkpoints(interval, std::move(sink), [this](tumble::v1::WorldState* state) { capture(state); });
}

Simulation::Simulation(const tumble::v1::Scene& scene, const SimConfig& config)
    : config_(config),
      scene_(scene),
      dt_(1.0 / config.tick_rate_hz),
      tick_rate_hz_(config.tick_rate_hz),
      loop_(config.max_catch_up_ticks) {}

Simulation::~Simulation() { stop(); }

Status Simulation::build_world(physics::World* world, BodyDirectory* directory) const {
  world->set_gravity(to_vec3(scene_.gravity()));
  for (int i = 0; i < scene_.bodies_size(); ++i) {
    const tumble::v1::BodySpec& spec = scene_.bodies(i);
    const std::string where = "bodies[" + std::to_string(i) + "]";
    physics::BodyDesc desc;
    if (Status status = body_desc_from_spec(spec, where, &desc); !status.ok()) return status;
    if (!spec.name().empty() && directory->id_of(spec.name()) != physics::kInvalidBodyId) {
      return Status::error(where + ".name: '" + spec.name() + "' is used by another body");
    }
    const physics::BodyId id = world->add_body(desc);
    directory->add(id, BodyEntry{spec.name(), spec.shape(), world->mass(id)});
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

void Simulation::set_snapshot_listener(SnapshotListener listener) { listener_ = std::move(listener); }

void Simulation::set_event_listener(WorldEventListener listener) { event_listener_ = std::move(listener); }

void Simulation::start() {
  loop_.start(
      // The physics helpers start here so they inherit the sim thread's
      // scheduling (SCHED_FIFO under --realtime-priority): the step waits for
      // an island a helper has begun, and a helper behind ordinary processes
      // would stall it.
      [this] { world_.set_thread_count(config_.physics_threads); },
      [this](double late_ms) { run_pass(late_ms); }, [this] { return tick_rate_hz(); });
}

void Simulation::stop() {
  loop_.stop();
  record_.finish(next_tick_);
}

void Simulation::submit(Command command) {
  if (command.message.kind_case() == ClientMessage::kSpawnBody) {
    auto desc = std::make_shared<physics::BodyDesc>();
    if (Status status = body_desc_from_spec(command.message.spawn_body().body(), "body", desc.get()); !status.ok()) {
      if (command.reply) command.reply(error(command.message, tumble::v1::INVALID_ARGUMENT, status.message()));
      return;
    }
    command.body_desc = std::move(desc);
  }
  commands_.push(std::move(command));
}

void Simulation::request_snapshot() { snapshot_requested_.store(true, std::memory_order_relaxed); }

void Simulation::set_publish_interest(std::vector<PublishInterest> interest, std::size_t early_bodies) {
  std::lock_guard lock(interest_mutex_);
  published_interest_ = std::move(interest);
  published_early_bodies_ = early_bodies;
  interest_changed_ = true;
}

void Simulation::set_sleep_events_wanted(bool wanted) { sleep_events_wanted_.store(wanted, std::memory_order_relaxed); }

void Simulation::run_pass(double late_ms) {
  timing_.record_start_late(late_ms);
  run_tick();
  record_.checkpoint_if_due();
}

void Simulation::run_tick() {
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
    // A Step: its ticks back to back, for at most one tick period of wall time per pass.
    const Clock::time_point budget_end =
        started + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(dt_));
    do {
      advance();
      const double cpu_now = TickTiming::thread_cpu_ms();
      const Clock::time_point now = Clock::now();
      timing_.record_step(milliseconds(now - started), cpu_now - cpu_started);
      started = Clock::now();
      cpu_started = TickTiming::thread_cpu_ms();
    } while (paused_ && steps_left_ > 0 && started < budget_end && !replaying_);
  } else {
    // No step: show edits at once, and serve a new subscriber's first frame.
    if (edited_ && sleep_.watching()) sleep_.scan(world_, directory_, next_tick_, &events_);
    flush_events();
    const bool requested = snapshot_requested_.exchange(false, std::memory_order_relaxed);
    if (edited_ || requested) publish(nullptr, edited_);
    edited_ = false;
  }
  timing_.record_clock(Clock::now(), time_of(next_tick_));
}

void Simulation::advance() {
  record_.note_change();
  loads_.apply(world_);
  world_.step(dt_);
  ++next_tick_;
  tick_.store(next_tick_, std::memory_order_relaxed);
  sim_time_.store(time_of(next_tick_), std::memory_order_relaxed);

  if (!sleep_events_wanted_.load(std::memory_order_relaxed)) {
    sleep_.stop();
  } else if (!sleep_.watching()) {
    sleep_.start(world_);  // only changes from now on are events
  } else {
    sleep_.scan(world_, directory_, next_tick_, &events_);
  }

  if (steps_left_ > 0 && --steps_left_ == 0) {
    if (step_command_.reply) step_command_.reply(ack(step_command_.message, next_tick_));
    step_command_ = Command{};
  }
  flush_events();
  const PublishPlan::Due due = plan_publish();
  if (due == PublishPlan::Due::nothing) {
    edited_ = false;
    return;
  }
  // With a large snapshot due, the small streams' bodies (early_) go
  // first, in a snapshot of their own, or the copy of the large one would
  // hold their frames back (about a millisecond for 10,000 bodies on this
  // kind of machine, on every tick of a 60 Hz stream of all of them).
  if (!plan_.early().empty()) publish(&plan_.early(), false, true);
  publish(due == PublishPlan::Due::every_body ? nullptr : &plan_.collect_wanted(), false);
  edited_ = false;
}

void Simulation::flush_events() {
  if (events_.empty()) return;
  if (event_listener_) event_listener_(std::make_shared<const WorldEvents>(std::move(events_)));
  events_.clear();
}

PublishPlan::Due Simulation::plan_publish() {
  {
    std::lock_guard lock(interest_mutex_);
    if (interest_changed_) {
      plan_.set_interests(std::move(published_interest_), published_early_bodies_);
      interest_changed_ = false;
    }
  }
  const bool requested = snapshot_requested_.exchange(false, std::memory_order_relaxed);
  return plan_.plan(next_tick_, world_.body_count(), requested);
}

void Simulation::publish(const std::vector<physics::BodyId>* bodies, bool out_of_band, bool more_follows) {
  if (!listener_) return;
  auto snapshot = std::make_shared<Snapshot>();
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
    listener_(std::move(snapshot));
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
  listener_(std::move(snapshot));
}

void Simulation::apply(Command& command) {
  const ClientMessage& message = command.message;
  std::optional<ServerMessage> reply;
  switch (message.kind_case()) {
    case ClientMessage::kApplyForce: reply = apply_force(message); break;
    case ClientMessage::kApplyTorque: reply = apply_torque(message); break;
    case ClientMessage::kApplyImpulse: reply = apply_impulse(message); break;
    case ClientMessage::kListBodies: reply = list_bodies(message); break;
    case ClientMessage::kSpawnBody: reply = spawn_body(command); break;
    case ClientMessage::kRemoveBody: reply = remove_body(message); break;
    case ClientMessage::kSetBodyState: reply = set_body_state(message); break;
    case ClientMessage::kClearForces: reply = clear_forces(message); break;
    case ClientMessage::kPause: reply = pause(message); break;
    case ClientMessage::kResume: reply = resume(message); break;
    case ClientMessage::kStep: reply = step(command); break;
    case ClientMessage::kReset: reply = reset(message); break;
    case ClientMessage::kSetTickRate: reply = set_tick_rate(message); break;
    case ClientMessage::kGetStats: reply = stats(message); break;
    default:
      reply = error(message, tumble::v1::UNKNOWN_MESSAGE, "the simulation does not handle this request");
      break;
  }
  if (reply && command.reply) command.reply(std::move(*reply));
}

std::uint32_t Simulation::duration_ticks(bool has_seconds, double seconds, bool has_ticks,
                                         std::uint32_t ticks) const {
  // The longest timed load: one tick more would read as persistent.
  constexpr std::uint32_t kLongest = BodyLoad::kPersistent - 1;
  if (has_ticks) return std::min(ticks, kLongest);
  if (!has_seconds) return 1;
  // check_request bounds seconds to (0, 1e6] and the rate to 1e4 Hz: up to
  // 1e10 ticks, more than 32 bits hold, so the count is capped before the
  // conversion (reached only above about 4295 Hz).
  return static_cast<std::uint32_t>(std::clamp(std::round(seconds * tick_rate_hz()), 1.0, double{kLongest}));
}

ServerMessage Simulation::apply_force(const ClientMessage& message) {
  const auto& m = message.apply_force();
  const physics::BodyId body = directory_.resolve(m.body());
  if (body == physics::kInvalidBodyId) return unknown_body(message, m.body());
  const std::uint32_t ticks = m.persistent() ? BodyLoad::kPersistent
                                             : duration_ticks(m.has_seconds(), m.seconds(), m.has_ticks(), m.ticks());
  loads_.add_force(body, to_vec3(m.force()), body_point(world_, body, m.has_point(), m.point(), m.point_frame()),
                   ticks);
  return ack(message, next_tick_ + 1);
}

ServerMessage Simulation::apply_torque(const ClientMessage& message) {
  const auto& m = message.apply_torque();
  const physics::BodyId body = directory_.resolve(m.body());
  if (body == physics::kInvalidBodyId) return unknown_body(message, m.body());
  const std::uint32_t ticks = m.persistent() ? BodyLoad::kPersistent
                                             : duration_ticks(m.has_seconds(), m.seconds(), m.has_ticks(), m.ticks());
  loads_.add_torque(body, to_vec3(m.torque()), ticks);
  return ack(message, next_tick_ + 1);
}

ServerMessage Simulation::apply_impulse(const ClientMessage& message) {
  const auto& m = message.apply_impulse();
  const physics::BodyId body = directory_.resolve(m.body());
  if (body == physics::kInvalidBodyId) return unknown_body(message, m.body());
  // World point r = x + R p_body (or as given), then P += J, L += (r - x) x J.
  const physics::Vec3 local = body_point(world_, body, m.has_point(), m.point(), m.point_frame());
  const physics::Vec3 point = world_.position(body) + world_.orientation(body) * local;
  world_.apply_impulse_at_point(body, to_vec3(m.impulse()), point);
  edited_ = true;
  return ack(message, edit_tick());
}

ServerMessage Simulation::list_bodies(const ClientMessage& message) const {
  ServerMessage reply;
  auto* list = reply.mutable_body_list();
  list->set_request_id(message.request_id());
  list->set_tick(next_tick_);
  for (std::size_t i = 0; i < world_.body_count(); ++i) {
    const physics::BodyId id = world_.body_id_at(i);
    auto* info = list->add_bodies();
    info->set_id(id);
    if (const BodyEntry* entry = directory_.find(id)) {
      info->set_name(entry->name);
      *info->mutable_shape() = entry->shape;
    }
    info->set_mass(world_.mass(id));
    set_vec3(world_.position(id), info->mutable_position());
    const physics::Quat& q = world_.orientation(id);
    auto* o = info->mutable_orientation();
    o->set_w(q.w());
    o->set_x(q.x());
    o->set_y(q.y());
    o->set_z(q.z());
    set_vec3(world_.linear_velocity(id), info->mutable_linear_velocity());
    set_vec3(world_.angular_velocity(id), info->mutable_angular_velocity());
    info->set_motion(wire_motion(world_.motion_type(id)));
    info->set_asleep(is_dynamic(world_, id) && !world_.is_awake(id));
  }
  return reply;
}

void Simulation::note_spawned(physics::BodyId id, const std::string& name, std::uint64_t tick) {
  events_.push_back({tick, WorldEventKind::body_spawned, id, name});
  sleep_.add(world_, id);
}

ServerMessage Simulation::spawn_body(const Command& command) {
  const ClientMessage& message = command.message;
  const tumble::v1::BodySpec& spec = message.spawn_body().body();
  if (world_.body_count() >= config_.max_bodies) {
    return error(message, tumble::v1::RESOURCE_EXHAUSTED,
                 "the world already holds " + std::to_string(world_.body_count()) + " bodies, the most allowed");
  }
  if (world_.next_body_id() >= kMaxBodyIds) {
    return error(message, tumble::v1::RESOURCE_EXHAUSTED,
                 "the world has handed out all of the " + std::to_string(kMaxBodyIds) + " body ids it may");
  }
  if (!spec.name().empty() && directory_.id_of(spec.name()) != physics::kInvalidBodyId) {
    return error(message, tumble::v1::INVALID_ARGUMENT, "body.name: '" + spec.name() + "' is used by another body");
  }
  physics::BodyDesc converted;
  const physics::BodyDesc* desc = command.body_desc.get();
  if (desc == nullptr) {
    // Queued without submit() (a replay): convert here.
    if (Status status = body_desc_from_spec(spec, "body", &converted); !status.ok()) {
      return error(message, tumble::v1::INVALID_ARGUMENT, status.message());
    }
    desc = &converted;
  }
  const physics::BodyId id = world_.add_body(*desc);
  {
    std::lock_guard lock(directory_mutex_);
    directory_.add(id, BodyEntry{spec.name(), spec.shape(), world_.mass(id)});
  }
  refresh_body_count();
  const std::uint64_t tick = edit_tick();
  note_spawned(id, spec.name(), tick);
  edited_ = true;
  ServerMessage reply = ack(message, tick);
  reply.mutable_ack()->set_body_id(id);
  return reply;
}

ServerMessage Simulation::remove_body(const ClientMessage& message) {
  const auto& ref = message.remove_body().body();
  const physics::BodyId id = directory_.resolve(ref);
  if (id == physics::kInvalidBodyId) return unknown_body(message, ref);
  const std::string name = directory_.name_of(id);
  world_.remove_body(id);
  loads_.remove_body(id);
  {
    std::lock_guard lock(directory_mutex_);
    directory_.remove(id);
  }
  refresh_body_count();
  const std::uint64_t tick = edit_tick();
  events_.push_back({tick, WorldEventKind::body_removed, id, name});
  edited_ = true;
  return ack(message, tick);
}

ServerMessage Simulation::set_body_state(const ClientMessage& message) {
  const auto& m = message.set_body_state();
  const physics::BodyId id = directory_.resolve(m.body());
  if (id == physics::kInvalidBodyId) return unknown_body(message, m.body());
  const physics::Vec3 position = m.has_position() ? to_vec3(m.position()) : world_.position(id);
  physics::Quat orientation = world_.orientation(id);
  if (m.has_orientation()) {
    const auto& q = m.orientation();
    orientation = physics::Quat(q.w(), q.x(), q.y(), q.z()).normalized();
  }
  // Velocities not given keep their world-frame values, also when the orientation changes.
  const physics::Vec3 v = m.has_linear_velocity() ? to_vec3(m.linear_velocity()) : world_.linear_velocity(id);
  const physics::Vec3 w = m.has_angular_velocity() ? to_vec3(m.angular_velocity()) : world_.angular_velocity(id);
  world_.set_state(id, position, orientation, v, w);
  edited_ = true;
  return ack(message, edit_tick());
}

ServerMessage Simulation::clear_forces(const ClientMessage& message) {
  const auto& m = message.clear_forces();
  if (m.has_body()) {
    const physics::BodyId id = directory_.resolve(m.body());
    if (id == physics::kInvalidBodyId) return unknown_body(message, m.body());
    loads_.remove_body(id);
  } else {
    loads_.clear();
  }
  // The next step is the first without them.
  return ack(message, next_tick_ + 1);
}

ServerMessage Simulation::pause(const ClientMessage& message) {
  if (!paused_) sim_log().info("paused at tick {}", next_tick_);
  paused_ = true;
  paused_flag_.store(true, std::memory_order_relaxed);
  return ack(message, next_tick_);
}

ServerMessage Simulation::resume(const ClientMessage& message) {
  if (paused_) sim_log().info("resumed at tick {}", next_tick_);
  paused_ = false;
  paused_flag_.store(false, std::memory_order_relaxed);
  return ack(message, next_tick_ + 1);
}

std::optional<ServerMessage> Simulation::step(Command& command) {
  const ClientMessage& message = command.message;
  if (!paused_) {
    return error(message, tumble::v1::FAILED_PRECONDITION, "the simulation is running; Pause it before stepping");
  }
  if (steps_left_ > 0) {
    return error(message, tumble::v1::FAILED_PRECONDITION,
                 "a Step is under way with " + std::to_string(steps_left_) + " ticks left");
  }
  steps_left_ = message.step().ticks();
  step_command_ = std::move(command);
  return std::nullopt;
}

ServerMessage Simulation::reset(const ClientMessage& message) {
  physics::World fresh;
  fresh.set_settings(world_.settings());
  fresh.set_thread_count(world_.thread_count());
  BodyDirectory directory;
  // The scene built once in create(), so it builds again.
  if (Status status = build_world(&fresh, &directory); !status.ok()) {
    return error(message, tumble::v1::INTERNAL, "the scene no longer builds: " + status.message());
  }
  // The scene's bodies get their first ids again; ids handed out since are never reused.
  fresh.set_next_body_id(world_.next_body_id());
  const std::uint64_t tick = edit_tick();
  events_.push_back({tick, WorldEventKind::world_reset, physics::kInvalidBodyId, {}});
  // Ids below the scene's body count are the scene's bodies in both worlds
  // (ids are handed out in order and never reused).
  for (std::size_t i = 0; i < world_.body_count(); ++i) {
    const physics::BodyId id = world_.body_id_at(i);
    if (!fresh.contains(id)) events_.push_back({tick, WorldEventKind::body_removed, id, directory_.name_of(id)});
  }
  std::vector<physics::BodyId> restored;
  for (std::size_t i = 0; i < fresh.body_count(); ++i) {
    const physics::BodyId id = fresh.body_id_at(i);
    if (!world_.contains(id)) restored.push_back(id);
  }
  world_ = std::move(fresh);
  set_directory(std::move(directory));
  loads_.clear();
  refresh_body_count();
  if (sleep_.watching()) sleep_.start(world_);  // the fresh world's states, without events
  for (physics::BodyId id : restored) note_spawned(id, directory_.name_of(id), tick);
  edited_ = true;
  sim_log().info("reset to the scene at tick {}", next_tick_);
  return ack(message, tick);
}

ServerMessage Simulation::set_tick_rate(const ClientMessage& message) {
  const double rate = message.set_tick_rate().rate_hz();
  // Sim time so far stays; ticks from here on last 1 / rate.
  rate_since_time_ = time_of(next_tick_);
  rate_since_tick_ = next_tick_;
  dt_ = 1.0 / rate;
  tick_rate_hz_.store(rate, std::memory_order_relaxed);
  return ack(message, next_tick_ + 1);
}

ServerMessage Simulation::stats(const ClientMessage& message) const {
  ServerMessage reply;
  auto& stats = *reply.mutable_stats();
  stats.set_request_id(message.request_id());
  stats.set_tick(next_tick_);
  stats.set_sim_time(time_of(next_tick_));
  stats.set_paused(paused_);
  stats.set_tick_rate_hz(tick_rate_hz());
  stats.set_real_time_factor(paused_ ? 0.0 : timing_.real_time_factor());
  stats.set_tick_ms_p50(timing_.step_ms_quantile(0.5));
  stats.set_tick_ms_p99(timing_.step_ms_quantile(0.99));
  stats.set_tick_cpu_ms_p50(timing_.step_cpu_ms_quantile(0.5));
  stats.set_tick_cpu_ms_p99(timing_.step_cpu_ms_quantile(0.99));
  stats.set_tick_start_late_ms_p50(timing_.start_late_ms_quantile(0.5));
  stats.set_tick_start_late_ms_p99(timing_.start_late_ms_quantile(0.99));
  stats.set_overruns(overruns());
  stats.set_bodies(static_cast<std::uint32_t>(world_.body_count()));
  stats.set_bodies_awake(static_cast<std::uint32_t>(world_.awake_body_count()));
  stats.set_bodies_asleep(static_cast<std::uint32_t>(world_.sleeping_body_count()));
  return reply;
}

}  // namespace tumble::sim
