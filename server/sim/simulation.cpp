#include "sim/simulation.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "sim/body_spec.h"
#include "sim/log.h"

namespace tumble::sim {
namespace {

using tumble::v1::ClientMessage;
using tumble::v1::ServerMessage;
using Clock = std::chrono::steady_clock;

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

}  // namespace

Status Simulation::create(const tumble::v1::Scene& scene, const SimConfig& config,
                          std::unique_ptr<Simulation>* out) {
  if (!std::isfinite(config.tick_rate_hz) || config.tick_rate_hz <= 0 || config.tick_rate_hz > 10000) {
    return Status::error("tick rate must be in (0, 10000] Hz");
  }
  std::unique_ptr<Simulation> sim(new Simulation(config));
  sim->world_.set_gravity(to_vec3(scene.gravity()));
  auto directory = std::make_shared<BodyDirectory>();
  for (int i = 0; i < scene.bodies_size(); ++i) {
    const tumble::v1::BodySpec& spec = scene.bodies(i);
    const std::string where = "bodies[" + std::to_string(i) + "]";
    physics::BodyDesc desc;
    if (Status status = body_desc_from_spec(spec, where, &desc); !status.ok()) return status;
    if (!spec.name().empty() && directory->id_of(spec.name()) != physics::kInvalidBodyId) {
      return Status::error(where + ".name: '" + spec.name() + "' is used by another body");
    }
    const physics::BodyId id = sim->world_.add_body(desc);
    directory->add(id, BodyEntry{spec.name(), spec.shape(), desc.mass_properties.mass});
  }
  sim->directory_ = directory;
  sim->shared_directory_ = std::move(directory);
  sim->body_count_ = static_cast<std::uint32_t>(sim->world_.body_count());
  *out = std::move(sim);
  return {};
}

Simulation::Simulation(const SimConfig& config) : config_(config), dt_(1.0 / config.tick_rate_hz) {}

Simulation::~Simulation() { stop(); }

std::shared_ptr<const BodyDirectory> Simulation::directory() const {
  std::lock_guard lock(directory_mutex_);
  return shared_directory_;
}

void Simulation::set_snapshot_listener(SnapshotListener listener) { listener_ = std::move(listener); }

void Simulation::start() {
  if (thread_.joinable()) return;
  {
    std::lock_guard lock(run_mutex_);
    stopping_ = false;
  }
  thread_ = std::thread([this] { run_loop(); });
}

void Simulation::stop() {
  {
    std::lock_guard lock(run_mutex_);
    stopping_ = true;
  }
  run_wakeup_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void Simulation::submit(Command command) { commands_.push(std::move(command)); }

void Simulation::request_snapshot() { snapshot_requested_.store(true, std::memory_order_relaxed); }

void Simulation::set_publish_periods(std::vector<std::uint32_t> periods) {
  std::lock_guard lock(periods_mutex_);
  publish_periods_ = std::move(periods);
  periods_changed_ = true;
}

void Simulation::run_loop() {
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(dt_));
  Clock::time_point start = Clock::now();
  std::uint64_t ticks_since_start = 0;
  sim_log().info("stepping at {} Hz", config_.tick_rate_hz);

  std::unique_lock lock(run_mutex_);
  while (!stopping_) {
    lock.unlock();
    run_tick();
    ++ticks_since_start;
    // Absolute deadlines: tick n ends at start + n * period, no accumulation of sleep error.
    const Clock::time_point deadline = start + ticks_since_start * period;
    const Clock::time_point now = Clock::now();
    lock.lock();
    if (now < deadline) {
      run_wakeup_.wait_until(lock, deadline, [this] { return stopping_; });
    } else if (now - deadline > config_.max_catch_up_ticks * period) {
      // Too far behind to catch up: skip the missed ticks and start counting again from now.
      const auto missed = static_cast<std::uint64_t>((now - deadline) / period);
      overruns_.fetch_add(missed, std::memory_order_relaxed);
      sim_log().warn("fell {} ticks behind the clock; skipped them", missed);
      start = now;
      ticks_since_start = 0;
    }
  }
}

void Simulation::run_tick() {
  commands_.drain(draining_);
  for (Command& command : draining_) apply(command);
  draining_.clear();

  loads_.apply(world_);
  world_.step(dt_);
  ++next_tick_;
  tick_.store(next_tick_, std::memory_order_relaxed);
  sim_time_.store(static_cast<double>(next_tick_) * dt_, std::memory_order_relaxed);

  if (publish_due()) publish();
}

bool Simulation::publish_due() {
  {
    std::lock_guard lock(periods_mutex_);
    if (periods_changed_) {
      periods_ = publish_periods_;
      periods_changed_ = false;
    }
  }
  if (snapshot_requested_.exchange(false, std::memory_order_relaxed)) return true;
  return std::any_of(periods_.begin(), periods_.end(),
                     [this](std::uint32_t p) { return p > 0 && next_tick_ % p == 0; });
}

void Simulation::publish() {
  if (!listener_) return;
  auto snapshot = std::make_shared<Snapshot>();
  snapshot->tick = next_tick_;
  snapshot->sim_time = static_cast<double>(next_tick_) * dt_;
  snapshot->directory = directory_;
  const std::size_t n = world_.body_count();
  snapshot->ids.resize(n);
  snapshot->positions.resize(3 * n);
  snapshot->orientations.resize(4 * n);
  snapshot->linear_velocities.resize(3 * n);
  snapshot->angular_velocities.resize(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const physics::BodyId id = world_.body_id_at(i);
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
  ServerMessage reply;
  switch (message.kind_case()) {
    case ClientMessage::kApplyForce: reply = apply_force(message); break;
    case ClientMessage::kApplyTorque: reply = apply_torque(message); break;
    case ClientMessage::kApplyImpulse: reply = apply_impulse(message); break;
    case ClientMessage::kListBodies: reply = list_bodies(message); break;
    default:
      reply = error(message, tumble::v1::UNKNOWN_MESSAGE, "the simulation does not handle this request");
      break;
  }
  if (command.reply) command.reply(std::move(reply));
}

std::uint32_t Simulation::duration_ticks(bool has_seconds, double seconds, bool has_ticks,
                                         std::uint32_t ticks) const {
  if (has_ticks) return ticks;
  if (!has_seconds) return 1;
  // check_request bounds seconds to (0, 1e6], so this fits in 32 bits for any tick rate we accept.
  return static_cast<std::uint32_t>(std::max(1.0, std::round(seconds * config_.tick_rate_hz)));
}

ServerMessage Simulation::apply_force(const ClientMessage& message) {
  const auto& m = message.apply_force();
  const physics::BodyId body = directory_->resolve(m.body());
  if (body == physics::kInvalidBodyId) return unknown_body(message, m.body());
  loads_.add_force(body, to_vec3(m.force()), body_point(world_, body, m.has_point(), m.point(), m.point_frame()),
                   duration_ticks(m.has_seconds(), m.seconds(), m.has_ticks(), m.ticks()));
  return ack(message, next_tick_ + 1);
}

ServerMessage Simulation::apply_torque(const ClientMessage& message) {
  const auto& m = message.apply_torque();
  const physics::BodyId body = directory_->resolve(m.body());
  if (body == physics::kInvalidBodyId) return unknown_body(message, m.body());
  loads_.add_torque(body, to_vec3(m.torque()), duration_ticks(m.has_seconds(), m.seconds(), m.has_ticks(), m.ticks()));
  return ack(message, next_tick_ + 1);
}

ServerMessage Simulation::apply_impulse(const ClientMessage& message) {
  const auto& m = message.apply_impulse();
  const physics::BodyId body = directory_->resolve(m.body());
  if (body == physics::kInvalidBodyId) return unknown_body(message, m.body());
  // World point r = x + R p_body (or as given), then P += J, L += (r - x) x J.
  const physics::Vec3 local = body_point(world_, body, m.has_point(), m.point(), m.point_frame());
  const physics::Vec3 point = world_.position(body) + world_.orientation(body) * local;
  world_.apply_impulse_at_point(body, to_vec3(m.impulse()), point);
  return ack(message, next_tick_ + 1);
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
    if (const BodyEntry* entry = directory_->find(id)) {
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
  }
  return reply;
}

}  // namespace tumble::sim
