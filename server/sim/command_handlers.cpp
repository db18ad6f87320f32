// The requests the sim thread executes: Simulation::apply() and one
// handler a request kind. Each edits the world, its loads and directories,
// or the clock, and answers with the tick at which the change first shows.
#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <google/protobuf/io/coded_stream.h>

#include "sim/body_spec.h"
#include "sim/joint_spec.h"
#include "sim/log.h"
#include "sim/log_text.h"
#include "sim/proto_math.h"
#include "sim/reply.h"
#include "sim/simulation.h"
#include "sim/world_state.h"

namespace tumble::sim {
namespace {

using tumble::v1::ClientMessage;
using tumble::v1::ServerMessage;

ServerMessage unknown_body(const ClientMessage& message, const tumble::v1::BodyRef& ref) {
  return error_reply(message, tumble::v1::UNKNOWN_BODY, "no " + BodyDirectory::describe(ref) + " in the world");
}

ServerMessage unknown_joint(const ClientMessage& message, const tumble::v1::JointRef& ref) {
  return error_reply(message, tumble::v1::UNKNOWN_JOINT, "no " + JointDirectory::describe(ref) + " in the world");
}

// The encoded size of one repeated entry of `size` bytes in a list page:
// tag, length and message.
std::size_t page_entry_bytes(std::size_t size) {
  return 1 + google::protobuf::io::CodedOutputStream::VarintSize64(size) + size;
}

// The body-frame offset from the centre of mass of a point given in
// `frame`: p_body = R^T (r - x) for a world point.
physics::Vec3 body_point(const physics::World& world, physics::BodyId body, bool has_point,
                         const tumble::v1::Vec3& point, tumble::v1::Frame frame) {
  if (!has_point) return physics::Vec3::Zero();
  if (frame == tumble::v1::FRAME_BODY) return to_vec3(point);
  return world.orientation(body).conjugate() * (to_vec3(point) - world.position(body));
}

// The request that cut a Step short with `end`, for the log.
const char* clock_request_name(tumble::v1::StepEnd end) {
  switch (end) {
    case tumble::v1::STEP_END_PAUSE:
      return "Pause";
    case tumble::v1::STEP_END_RESUME:
      return "Resume";
    case tumble::v1::STEP_END_RESET:
      return "Reset";
    default:
      return "request";
  }
}

}  // namespace

void Simulation::apply(Command& command) {
  const ClientMessage& message = command.message;
  std::optional<ServerMessage> reply;
  switch (message.kind_case()) {
    case ClientMessage::kApplyForce:
      reply = apply_force(message);
      break;
    case ClientMessage::kApplyTorque:
      reply = apply_torque(message);
      break;
    case ClientMessage::kApplyImpulse:
      reply = apply_impulse(message);
      break;
    case ClientMessage::kListBodies:
      reply = list_bodies(message);
      break;
    case ClientMessage::kSpawnBody:
      reply = spawn_body(command);
      break;
    case ClientMessage::kRemoveBody:
      reply = remove_body(message);
      break;
    case ClientMessage::kSetBodyState:
      reply = set_body_state(message);
      break;
    case ClientMessage::kAddJoint:
      reply = add_joint(message);
      break;
    case ClientMessage::kRemoveJoint:
      reply = remove_joint(message);
      break;
    case ClientMessage::kSetJointMotor:
      reply = set_joint_motor(message);
      break;
    case ClientMessage::kListJoints:
      reply = list_joints(message);
      break;
    case ClientMessage::kClearForces:
      reply = clear_forces(message);
      break;
    case ClientMessage::kPause:
      reply = pause(message);
      break;
    case ClientMessage::kResume:
      reply = resume(message);
      break;
    case ClientMessage::kStep:
      reply = step(command);
      break;
    case ClientMessage::kReset:
      reply = reset(message);
      break;
    case ClientMessage::kSetTickRate:
      reply = set_tick_rate(message);
      break;
    case ClientMessage::kGetStats:
      reply = stats(message);
      break;
    default:
      reply = error_reply(message, tumble::v1::UNKNOWN_MESSAGE, "the simulation does not handle this request");
      break;
  }
  if (reply && command.reply) command.reply(std::move(*reply));
}

std::uint32_t Simulation::duration_ticks(bool has_seconds, double seconds, bool has_ticks, std::uint32_t ticks) const {
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
  const std::uint32_t ticks =
      m.persistent() ? BodyLoad::kPersistent : duration_ticks(m.has_seconds(), m.seconds(), m.has_ticks(), m.ticks());
  loads_.add_force(body, to_vec3(m.force()), body_point(world_, body, m.has_point(), m.point(), m.point_frame()),
                   ticks);
  return ack_reply(message, next_tick_ + 1);
}

ServerMessage Simulation::apply_torque(const ClientMessage& message) {
  const auto& m = message.apply_torque();
  const physics::BodyId body = directory_.resolve(m.body());
  if (body == physics::kInvalidBodyId) return unknown_body(message, m.body());
  const std::uint32_t ticks =
      m.persistent() ? BodyLoad::kPersistent : duration_ticks(m.has_seconds(), m.seconds(), m.has_ticks(), m.ticks());
  loads_.add_torque(body, to_vec3(m.torque()), ticks);
  return ack_reply(message, next_tick_ + 1);
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
  return ack_reply(message, edit_tick());
}

ServerMessage Simulation::list_bodies(const ClientMessage& message) const {
  const auto& request = message.list_bodies();
  ServerMessage reply;
  auto* list = reply.mutable_body_list();
  list->set_request_id(message.request_id());
  list->set_tick(next_tick_);
  list->set_total_bodies(static_cast<std::uint32_t>(world_.body_count()));
  const std::uint32_t most =
      request.max_bodies() == 0 ? std::numeric_limits<std::uint32_t>::max() : request.max_bodies();
  std::size_t page_bytes = 0;
  const auto& entries = directory_.entries();
  for (auto it = entries.lower_bound(request.start_id()); it != entries.end(); ++it) {
    const physics::BodyId id = it->first;
    if (!world_.contains(id)) continue;
    if (static_cast<std::uint32_t>(list->bodies_size()) == most) {
      list->set_next_start_id(id);
      break;
    }
    tumble::v1::BodyInfo info;
    info.set_id(id);
    info.set_name(it->second.name);
    *info.mutable_shape() = it->second.shape;
    info.set_mass(world_.mass(id));
    set_vec3(world_.position(id), info.mutable_position());
    set_quat(world_.orientation(id), info.mutable_orientation());
    set_vec3(world_.linear_velocity(id), info.mutable_linear_velocity());
    set_vec3(world_.angular_velocity(id), info.mutable_angular_velocity());
    info.set_motion(wire_motion(world_.motion_type(id)));
    info.set_asleep(sleeps(world_, id) && !world_.is_awake(id));
    // The body as the page encodes it.
    const std::size_t encoded = page_entry_bytes(info.ByteSizeLong());
    if (list->bodies_size() > 0 && page_bytes + encoded > config_.list_page_bytes) {
      list->set_next_start_id(id);
      break;
    }
    page_bytes += encoded;
    *list->add_bodies() = std::move(info);
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
    return error_reply(message, tumble::v1::RESOURCE_EXHAUSTED,
                       "the world already holds " + std::to_string(world_.body_count()) + " bodies, the most allowed");
  }
  if (world_.next_body_id() >= kMaxBodyIds) {
    return error_reply(message, tumble::v1::RESOURCE_EXHAUSTED,
                       "the world has handed out all of the " + std::to_string(kMaxBodyIds) + " body ids it may");
  }
  if (!spec.name().empty() && directory_.id_of(spec.name()) != physics::kInvalidBodyId) {
    return error_reply(message, tumble::v1::INVALID_ARGUMENT,
                       "body.name: '" + log_text(spec.name()) + "' is used by another body");
  }
  physics::BodyDesc converted;
  const physics::BodyDesc* desc = command.body_desc.get();
  if (desc == nullptr) {
    // Queued without submit() (a replay): convert here.
    if (Status status = body_desc_from_spec(spec, "body", &converted); !status.ok()) {
      return error_reply(message, tumble::v1::INVALID_ARGUMENT, status.message());
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
  ServerMessage reply = ack_reply(message, tick);
  reply.mutable_ack()->set_body_id(id);
  return reply;
}

void Simulation::note_joint(WorldEventKind kind, physics::JointId id, std::uint64_t tick) {
  const JointEntry* entry = joints_.find(id);
  if (entry == nullptr) return;
  events_.push_back({tick, kind, entry->body_b, entry->name, id, entry->body_a});
}

void Simulation::remove_from_world(physics::BodyId id, std::uint64_t tick) {
  const std::string name = directory_.name_of(id);
  // The world removes the body's joints with it; a copy, as the list goes with them.
  const std::vector<physics::JointId> joints(world_.body_joints(id).begin(), world_.body_joints(id).end());
  for (const physics::JointId joint : joints) {
    note_joint(WorldEventKind::joint_removed, joint, tick);
    joints_.remove(joint);
  }
  world_.remove_body(id);
  loads_.remove_body(id);
  step_loads_.remove_body(id);
  {
    std::lock_guard lock(directory_mutex_);
    directory_.remove(id);
  }
  refresh_body_count();
  events_.push_back({tick, WorldEventKind::body_removed, id, name});
}

void Simulation::remove_diverged() {
  // At most this many log lines a step; a step that loses more says how many.
  constexpr std::size_t kLoggedPerStep = 8;
  // A copy: the world's list is valid only until it changes.
  const std::vector<physics::BodyId> diverged(world_.diverged_bodies().begin(), world_.diverged_bodies().end());
  for (std::size_t i = 0; i < diverged.size(); ++i) {
    const physics::BodyId id = diverged[i];
    if (i < kLoggedPerStep) {
      // The name is a client's text: escaped and bounded (log_text.h).
      const physics::Vec3& x = world_.position(id);
      const physics::Vec3 v = world_.linear_velocity(id);
      sim_log().warn(
          "removed body {} '{}' at tick {}: its state diverged (position [{}, {}, {}] m, velocity [{}, {}, {}] "
          "m/s)",
          id, log_text(directory_.name_of(id)), next_tick_, x.x(), x.y(), x.z(), v.x(), v.y(), v.z());
    }
    events_.push_back({next_tick_, WorldEventKind::body_diverged, id, directory_.name_of(id)});
    remove_from_world(id, next_tick_);
  }
  if (diverged.size() > kLoggedPerStep) {
    sim_log().warn("removed {} bodies in all at tick {}: their states diverged", diverged.size(), next_tick_);
  }
  bodies_diverged_ += diverged.size();
}

void Simulation::remove_broken_joints() {
  // A copy: the world's list is valid only until it changes.
  const std::vector<physics::JointId> broken(world_.broken_joints().begin(), world_.broken_joints().end());
  for (const physics::JointId id : broken) {
    if (const JointEntry* entry = joints_.find(id)) {
      sim_log().info("joint {} '{}' broke at tick {}", id, log_text(entry->name), next_tick_);
    }
    note_joint(WorldEventKind::joint_broken, id, next_tick_);
    note_joint(WorldEventKind::joint_removed, id, next_tick_);
    joints_.remove(id);
  }
}

ServerMessage Simulation::remove_body(const ClientMessage& message) {
  const auto& ref = message.remove_body().body();
  const physics::BodyId id = directory_.resolve(ref);
  if (id == physics::kInvalidBodyId) return unknown_body(message, ref);
  const std::uint64_t tick = edit_tick();
  remove_from_world(id, tick);
  edited_ = true;
  return ack_reply(message, tick);
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
  return ack_reply(message, edit_tick());
}

ServerMessage Simulation::add_joint(const ClientMessage& message) {
  const tumble::v1::JointSpec& spec = message.add_joint().joint();
  if (world_.joint_count() >= config_.max_joints) {
    return error_reply(message, tumble::v1::RESOURCE_EXHAUSTED,
                       "the world already holds " + std::to_string(world_.joint_count()) + " joints, the most allowed");
  }
  if (world_.next_joint_id() >= kMaxJointIds) {
    return error_reply(message, tumble::v1::RESOURCE_EXHAUSTED,
                       "the world has handed out all of the " + std::to_string(kMaxJointIds) + " joint ids it may");
  }
  if (!spec.name().empty() && joints_.id_of(spec.name()) != physics::kInvalidJointId) {
    return error_reply(message, tumble::v1::INVALID_ARGUMENT,
                       "joint.name: '" + log_text(spec.name()) + "' is used by another joint");
  }
  // An unknown body is UNKNOWN_BODY, as for every other request that names one.
  for (const auto& [ref, field] :
       {std::pair{&spec.body_a(), "joint.body_a"}, std::pair{&spec.body_b(), "joint.body_b"}}) {
    if (resolve_joint_body(*ref, world_, directory_) == physics::kInvalidBodyId) {
      return error_reply(message, tumble::v1::UNKNOWN_BODY,
                         std::string(field) + ": no body '" + log_text(*ref) + "' in the world");
    }
  }
  physics::JointDesc desc;
  if (Status status = joint_desc_from_spec(spec, "joint", world_, directory_, &desc); !status.ok()) {
    return error_reply(message, tumble::v1::INVALID_ARGUMENT, status.message());
  }
  const physics::JointId id = world_.add_joint(desc);
  joints_.add(id, JointEntry{spec.name(), desc.body_a, desc.body_b});
  const std::uint64_t tick = edit_tick();
  note_joint(WorldEventKind::joint_added, id, tick);
  edited_ = true;
  ServerMessage reply = ack_reply(message, tick);
  reply.mutable_ack()->set_joint_id(id);
  return reply;
}

ServerMessage Simulation::remove_joint(const ClientMessage& message) {
  const tumble::v1::JointRef& ref = message.remove_joint().joint();
  const physics::JointId id = joints_.resolve(ref);
  if (id == physics::kInvalidJointId) return unknown_joint(message, ref);
  const std::uint64_t tick = edit_tick();
  note_joint(WorldEventKind::joint_removed, id, tick);
  joints_.remove(id);
  world_.remove_joint(id);
  edited_ = true;
  return ack_reply(message, tick);
}

ServerMessage Simulation::set_joint_motor(const ClientMessage& message) {
  const auto& m = message.set_joint_motor();
  const physics::JointId id = joints_.resolve(m.joint());
  if (id == physics::kInvalidJointId) return unknown_joint(message, m.joint());
  const physics::JointType type = world_.joint_desc(id).type;
  if (type != physics::JointType::hinge && type != physics::JointType::slider) {
    return error_reply(message, tumble::v1::INVALID_ARGUMENT,
                       JointDirectory::describe(m.joint()) + " is a " + joint_type_name(wire_joint_type(type)) +
                           " joint, which has no motor; only a hinge or a slider has one");
  }
  physics::JointMotor motor;  // off
  if (m.has_motor()) {
    if (Status status = check_joint_motor(m.motor(), wire_joint_type(type), "motor"); !status.ok()) {
      return error_reply(message, tumble::v1::INVALID_ARGUMENT, status.message());
    }
    motor = physics_motor(m.motor());
  }
  world_.set_joint_motor(id, motor);
  edited_ = true;
  return ack_reply(message, edit_tick());
}

ServerMessage Simulation::list_joints(const ClientMessage& message) const {
  const auto& request = message.list_joints();
  ServerMessage reply;
  auto* list = reply.mutable_joint_list();
  list->set_request_id(message.request_id());
  list->set_tick(next_tick_);
  list->set_total_joints(static_cast<std::uint32_t>(world_.joint_count()));
  const std::uint32_t most =
      request.max_joints() == 0 ? std::numeric_limits<std::uint32_t>::max() : request.max_joints();
  // A body's name as a listing shows it; the world's is "world".
  const auto body_name = [this](physics::BodyId id) {
    return id == physics::kWorldBodyId ? std::string(kWorldBodyName) : directory_.name_of(id);
  };
  // A point or direction of a joint's frame on `body` in the world frame now.
  const auto world_point = [this](physics::BodyId body, const physics::Vec3& local) -> physics::Vec3 {
    if (body == physics::kWorldBodyId) return local;
    return world_.position(body) + world_.orientation(body) * local;
  };
  std::size_t page_bytes = 0;
  const auto& entries = joints_.entries();
  for (auto it = entries.lower_bound(request.start_id()); it != entries.end(); ++it) {
    const physics::JointId id = it->first;
    if (!world_.contains_joint(id)) continue;
    if (static_cast<std::uint32_t>(list->joints_size()) == most) {
      list->set_next_start_id(id);
      break;
    }
    const physics::JointDesc& desc = world_.joint_desc(id);
    tumble::v1::JointInfo info;
    info.set_id(id);
    info.set_name(it->second.name);
    info.set_type(wire_joint_type(desc.type));
    info.set_body_a(desc.body_a);
    info.set_body_a_name(body_name(desc.body_a));
    info.set_body_b(desc.body_b);
    info.set_body_b_name(body_name(desc.body_b));
    set_vec3(world_point(desc.body_a, desc.local_anchor_a), info.mutable_anchor_a());
    set_vec3(world_point(desc.body_b, desc.local_anchor_b), info.mutable_anchor_b());
    const physics::Quat basis_a = desc.body_a == physics::kWorldBodyId
                                      ? desc.local_basis_a
                                      : world_.orientation(desc.body_a) * desc.local_basis_a;
    set_vec3(basis_a * physics::Vec3::UnitX(), info.mutable_axis());
    if (desc.limits_enabled) {
      info.mutable_limits()->set_lower(desc.lower);
      info.mutable_limits()->set_upper(desc.upper);
    }
    if (std::isfinite(desc.cone_limit)) info.set_cone_limit(desc.cone_limit);
    info.set_length(desc.length);
    info.set_min_length(desc.min_length);
    info.set_max_length(desc.max_length);
    if (desc.spring_hertz > 0) {
      info.mutable_spring()->set_hertz(desc.spring_hertz);
      info.mutable_spring()->set_damping_ratio(desc.spring_damping_ratio);
    }
    if (desc.motor.mode != physics::JointMotor::Mode::off) wire_motor(desc.motor, desc.type, info.mutable_motor());
    if (std::isfinite(desc.break_force)) info.set_break_force(desc.break_force);
    if (std::isfinite(desc.break_torque)) info.set_break_torque(desc.break_torque);
    info.set_collide_connected(desc.collide_connected);
    info.set_friction(desc.friction);
    fill_joint_state(world_, id, info.mutable_state());
    const std::size_t encoded = page_entry_bytes(info.ByteSizeLong());
    if (list->joints_size() > 0 && page_bytes + encoded > config_.list_page_bytes) {
      list->set_next_start_id(id);
      break;
    }
    page_bytes += encoded;
    *list->add_joints() = std::move(info);
  }
  return reply;
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
  return ack_reply(message, next_tick_ + 1);
}

ServerMessage Simulation::pause(const ClientMessage& message) {
  end_step(tumble::v1::STEP_END_PAUSE);
  if (!paused_) sim_log().info("paused at tick {}", next_tick_);
  paused_ = true;
  paused_flag_.store(true, std::memory_order_relaxed);
  return ack_reply(message, next_tick_);
}

ServerMessage Simulation::resume(const ClientMessage& message) {
  end_step(tumble::v1::STEP_END_RESUME);
  if (paused_) sim_log().info("resumed at tick {}", next_tick_);
  paused_ = false;
  paused_flag_.store(false, std::memory_order_relaxed);
  return ack_reply(message, next_tick_ + 1);
}

std::optional<ServerMessage> Simulation::step(Command& command) {
  const ClientMessage& message = command.message;
  if (!paused_) {
    return error_reply(message, tumble::v1::FAILED_PRECONDITION, "the simulation is running; Pause it before stepping");
  }
  if (steps_left_ > 0) {
    return error_reply(message, tumble::v1::FAILED_PRECONDITION,
                       "a Step is under way with " + std::to_string(steps_left_) + " ticks left");
  }
  const tumble::v1::Step& m = message.step();
  // Every body named is resolved before anything is applied: an unknown one refuses the whole Step.
  std::vector<physics::BodyId> force_bodies(static_cast<std::size_t>(m.forces_size()));
  for (int i = 0; i < m.forces_size(); ++i) {
    force_bodies[static_cast<std::size_t>(i)] = directory_.resolve(m.forces(i).body());
    if (force_bodies[static_cast<std::size_t>(i)] == physics::kInvalidBodyId) {
      return unknown_body(message, m.forces(i).body());
    }
  }
  std::vector<physics::BodyId> torque_bodies(static_cast<std::size_t>(m.torques_size()));
  for (int i = 0; i < m.torques_size(); ++i) {
    torque_bodies[static_cast<std::size_t>(i)] = directory_.resolve(m.torques(i).body());
    if (torque_bodies[static_cast<std::size_t>(i)] == physics::kInvalidBodyId) {
      return unknown_body(message, m.torques(i).body());
    }
  }
  step_frame_bodies_.clear();
  for (const tumble::v1::BodyRef& ref : m.frame_bodies()) {
    const physics::BodyId id = directory_.resolve(ref);
    if (id == physics::kInvalidBodyId) return unknown_body(message, ref);
    step_frame_bodies_.push_back(id);
  }
  std::sort(step_frame_bodies_.begin(), step_frame_bodies_.end());
  step_frame_bodies_.erase(std::unique(step_frame_bodies_.begin(), step_frame_bodies_.end()), step_frame_bodies_.end());
  // The Step's loads last as long as it does: end_step() drops them, whatever ended it.
  for (int i = 0; i < m.forces_size(); ++i) {
    const auto& f = m.forces(i);
    const physics::BodyId body = force_bodies[static_cast<std::size_t>(i)];
    step_loads_.add_force(body, to_vec3(f.force()), body_point(world_, body, f.has_point(), f.point(), f.point_frame()),
                          BodyLoad::kPersistent);
  }
  for (int i = 0; i < m.torques_size(); ++i) {
    step_loads_.add_torque(torque_bodies[static_cast<std::size_t>(i)], to_vec3(m.torques(i).torque()),
                           BodyLoad::kPersistent);
  }
  steps_left_ = m.ticks();
  step_command_ = std::move(command);
  return std::nullopt;
}

void Simulation::fill_step_frame(tumble::v1::PoseFields fields, bool joints, tumble::v1::PoseFrame* frame) const {
  frame->set_tick(next_tick_);
  frame->set_sim_time(time_of(next_tick_));
  frame->set_encoding(tumble::v1::POSE_ENCODING_FULL);
  std::vector<physics::BodyId> every_body;
  const std::vector<physics::BodyId>* bodies = &step_frame_bodies_;
  if (step_frame_bodies_.empty()) {
    every_body.reserve(world_.body_count());
    for (std::size_t i = 0; i < world_.body_count(); ++i) every_body.push_back(world_.body_id_at(i));
    std::sort(every_body.begin(), every_body.end());
    bodies = &every_body;
  }
  const bool velocities = fields == tumble::v1::POSE_FIELDS_POSE_AND_VELOCITY;
  const int n = static_cast<int>(bodies->size());
  frame->mutable_ids()->Reserve(n);
  frame->mutable_positions()->Reserve(3 * n);
  frame->mutable_orientations()->Reserve(4 * n);
  if (velocities) {
    frame->mutable_linear_velocities()->Reserve(3 * n);
    frame->mutable_angular_velocities()->Reserve(3 * n);
  }
  const auto add3 = [](const physics::Vec3& v, google::protobuf::RepeatedField<float>* out) {
    out->Add(static_cast<float>(v.x()));
    out->Add(static_cast<float>(v.y()));
    out->Add(static_cast<float>(v.z()));
  };
  for (const physics::BodyId id : *bodies) {
    if (!world_.contains(id)) continue;  // removed during the Step (it diverged)
    frame->add_ids(id);
    add3(world_.position(id), frame->mutable_positions());
    const physics::Quat& q = world_.orientation(id);
    for (const double c : {q.w(), q.x(), q.y(), q.z()}) frame->add_orientations(static_cast<float>(c));
    if (velocities) {
      add3(world_.linear_velocity(id), frame->mutable_linear_velocities());
      add3(world_.angular_velocity(id), frame->mutable_angular_velocities());
    }
  }
  if (!joints) return;
  Snapshot states;
  copy_joints(world_, states);
  for (std::size_t i = 0; i < states.joint_ids.size(); ++i) {
    frame->add_joint_ids(states.joint_ids[i]);
    frame->add_joint_positions(static_cast<float>(states.joint_positions[i]));
    frame->add_joint_speeds(static_cast<float>(states.joint_speeds[i]));
    frame->add_joint_motor_impulses(static_cast<float>(states.joint_motor_impulses[i]));
  }
}

void Simulation::end_step(tumble::v1::StepEnd end) {
  if (!step_command_.message.has_step()) return;  // no Step under way
  if (end != tumble::v1::STEP_END_COMPLETED) {
    sim_log().info("a Step of {} ticks was cut short by a {} at tick {}, {} ticks before its end",
                   step_command_.message.step().ticks(), clock_request_name(end), next_tick_, steps_left_);
  }
  ServerMessage reply = ack_reply(step_command_.message, next_tick_);
  reply.mutable_ack()->set_step_ticks_left(steps_left_);
  reply.mutable_ack()->set_step_ended_by(end);
  const tumble::v1::Step& step = step_command_.message.step();
  if (step.reply_frame()) {
    fill_step_frame(step.frame_fields(), step.frame_joints(), reply.mutable_ack()->mutable_frame());
  }
  steps_left_ = 0;
  step_loads_.clear();
  step_frame_bodies_.clear();
  const Command ended = std::exchange(step_command_, Command{});
  if (ended.reply) ended.reply(std::move(reply));
}

ServerMessage Simulation::reset(const ClientMessage& message) {
  physics::World fresh;
  fresh.set_settings(world_.settings());
  fresh.set_thread_count(world_.thread_count());
  BodyDirectory directory;
  JointDirectory joints;
  // The scene built once in create(), so it builds again.
  if (Status status = build_world(&fresh, &directory, &joints); !status.ok()) {
    return error_reply(message, tumble::v1::INTERNAL, "the scene no longer builds: " + status.message());
  }
  // The scene's bodies and joints get their first ids again; ids handed out since are never reused.
  fresh.set_next_body_id(world_.next_body_id());
  fresh.set_next_joint_id(world_.next_joint_id());
  // A Step ends with the world it stepped, at the tick it reached.
  end_step(tumble::v1::STEP_END_RESET);
  const std::uint64_t tick = edit_tick();
  events_.push_back({tick, WorldEventKind::world_reset, physics::kInvalidBodyId, {}});
  // Ids below the scene's body (joint) count are the scene's bodies
  // (joints) in both worlds (ids are handed out in order and never reused).
  // Joints go before the bodies they join, and come back after them.
  for (std::size_t i = 0; i < world_.joint_count(); ++i) {
    const physics::JointId id = world_.joint_id_at(i);
    if (!fresh.contains_joint(id)) note_joint(WorldEventKind::joint_removed, id, tick);
  }
  std::vector<physics::JointId> restored_joints;
  for (std::size_t i = 0; i < fresh.joint_count(); ++i) {
    const physics::JointId id = fresh.joint_id_at(i);
    if (!world_.contains_joint(id)) restored_joints.push_back(id);
  }
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
  joints_ = std::move(joints);
  loads_.clear();
  refresh_body_count();
  if (sleep_.watching()) sleep_.start(world_);  // the fresh world's states, without events
  for (physics::BodyId id : restored) note_spawned(id, directory_.name_of(id), tick);
  for (physics::JointId id : restored_joints) note_joint(WorldEventKind::joint_added, id, tick);
  edited_ = true;
  sim_log().info("reset to the scene at tick {}", next_tick_);
  return ack_reply(message, tick);
}

ServerMessage Simulation::set_tick_rate(const ClientMessage& message) {
  const double rate = message.set_tick_rate().rate_hz();
  // Sim time so far stays; ticks from here on last 1 / rate.
  rate_since_time_ = time_of(next_tick_);
  rate_since_tick_ = next_tick_;
  dt_ = 1.0 / rate;
  tick_rate_hz_.store(rate, std::memory_order_relaxed);
  return ack_reply(message, next_tick_ + 1);
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
  stats.set_bodies_diverged(bodies_diverged_);
  for (const StatsHook& hook : stats_hooks_) hook(&stats);
  return reply;
}

}  // namespace tumble::sim
