#include "sim/world_state.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "sim/body_limits.h"
#include "sim/body_spec.h"
#include "sim/log.h"
#include "sim/log_text.h"
#include "sim/string_limits.h"

namespace tumble::sim {
namespace {

void set_vec3(const physics::Vec3& v, tumble::v1::Vec3* out) {
  out->set_x(v.x());
  out->set_y(v.y());
  out->set_z(v.z());
}

physics::Vec3 to_vec3(const tumble::v1::Vec3& v) { return {v.x(), v.y(), v.z()}; }

bool finite(const tumble::v1::Vec3& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

// The spec of `saved` as this server accepts it: the saved one, or, when its
// name breaks a limit of string_limits.h (a file written before there were
// any), a copy in `renamed` without the name, with a warning in the log. The
// body itself is kept: refusing the file would lose the whole world.
const tumble::v1::BodySpec& allowed_name(const tumble::v1::SavedBody& saved, const std::string& where,
                                         tumble::v1::BodySpec* renamed) {
  const Status refused = check_body_name(saved.spec().name(), where + ".spec.name");
  if (refused.ok()) return saved.spec();
  sim_log().warn("{}; body {} is loaded without a name", log_text(refused.message(), kLogMessageBytes), saved.id());
  *renamed = saved.spec();
  renamed->clear_name();
  return *renamed;
}

bool within_magnitude(const physics::Vec3& v) {
  return std::abs(v.x()) <= kMaxMagnitude && std::abs(v.y()) <= kMaxMagnitude && std::abs(v.z()) <= kMaxMagnitude;
}

// Whether restore_world would take the body's state back: the pose and
// velocities its spec checks (body_spec.h), and finite momenta and sleep
// time. Mass and shape were checked when the body was made and never change.
bool restorable(const physics::World& world, physics::BodyId id) {
  const physics::Quat& q = world.orientation(id);
  return within_magnitude(world.position(id)) && within_magnitude(world.linear_velocity(id)) &&
         within_magnitude(world.angular_velocity(id)) && q.coeffs().allFinite() && std::abs(q.norm() - 1.0) <= 1e-3 &&
         world.linear_momentum(id).allFinite() && world.angular_momentum(id).allFinite() &&
         std::isfinite(world.sleep_time(id));
}

}  // namespace

void body_spec_now(const physics::World& world, const BodyDirectory& directory, physics::BodyId id,
                   tumble::v1::BodySpec* out) {
  tumble::v1::BodySpec& spec = *out;
  if (const BodyEntry* entry = directory.find(id)) {
    spec.set_name(entry->name);
    *spec.mutable_shape() = entry->shape;
    spec.set_mass(entry->mass);
  }
  spec.set_motion(wire_motion(world.motion_type(id)));
  spec.set_friction(world.friction(id));
  spec.set_restitution(world.restitution(id));
  set_vec3(world.position(id), spec.mutable_position());
  const physics::Quat& q = world.orientation(id);
  auto* orientation = spec.mutable_orientation();
  orientation->set_w(q.w());
  orientation->set_x(q.x());
  orientation->set_y(q.y());
  orientation->set_z(q.z());
  set_vec3(world.linear_velocity(id), spec.mutable_linear_velocity());
  set_vec3(world.angular_velocity(id), spec.mutable_angular_velocity());
}

std::size_t capture_world(const physics::World& world, const BodyDirectory& directory, const BodyLoads& loads,
                          tumble::v1::WorldState* state) {
  state->set_format_version(kWorldStateFormat);
  set_vec3(world.gravity(), state->mutable_gravity());
  state->set_next_body_id(world.next_body_id());
  state->clear_bodies();
  state->mutable_bodies()->Reserve(static_cast<int>(world.body_count()));
  std::vector<physics::BodyId> left_out;
  for (std::size_t i = 0; i < world.body_count(); ++i) {
    const physics::BodyId id = world.body_id_at(i);
    if (!restorable(world, id)) {
      left_out.push_back(id);
      continue;
    }
    tumble::v1::SavedBody* saved = state->add_bodies();
    saved->set_id(id);
    body_spec_now(world, directory, id, saved->mutable_spec());
    set_vec3(world.linear_momentum(id), saved->mutable_linear_momentum());
    set_vec3(world.angular_momentum(id), saved->mutable_angular_momentum());
    saved->set_asleep(world.motion_type(id) == physics::MotionType::dynamic_body && !world.is_awake(id));
    saved->set_sleep_time(world.sleep_time(id));
  }
  state->clear_loads();
  for (const BodyLoad& load : loads.loads()) {
    if (std::find(left_out.begin(), left_out.end(), load.body) != left_out.end()) continue;
    tumble::v1::SavedLoad* saved = state->add_loads();
    saved->set_body(load.body);
    set_vec3(load.force, saved->mutable_force());
    set_vec3(load.local_point, saved->mutable_local_point());
    set_vec3(load.torque, saved->mutable_torque());
    saved->set_ticks_left(load.ticks_left);
  }
  return left_out.size();
}

Status restore_world(const tumble::v1::WorldState& state, physics::World* world, BodyDirectory* directory,
                     BodyLoads* loads) {
  if (state.format_version() != kWorldStateFormat) {
    return Status::error("format_version: expected " + std::to_string(kWorldStateFormat) + ", got " +
                         std::to_string(state.format_version()));
  }
  if (!state.has_gravity() || !finite(state.gravity())) {
    return Status::error("gravity: missing or not finite");
  }
  world->set_gravity(to_vec3(state.gravity()));
  if (state.next_body_id() > kMaxBodyIds) {
    return Status::error("next_body_id: " + std::to_string(state.next_body_id()) + " is more than the " +
                         std::to_string(kMaxBodyIds) + " ids a world may hand out");
  }

  tumble::v1::BodySpec renamed;  // the spec of a body whose saved name is refused, without it
  for (int i = 0; i < state.bodies_size(); ++i) {
    const tumble::v1::SavedBody& saved = state.bodies(i);
    const std::string where = "bodies[" + std::to_string(i) + "]";
    if (saved.id() >= state.next_body_id()) {
      return Status::error(where + ".id: " + std::to_string(saved.id()) + " is not below next_body_id");
    }
    if (world->contains(saved.id())) {
      return Status::error(where + ".id: " + std::to_string(saved.id()) + " is used by another body");
    }
    const tumble::v1::BodySpec& spec =
        saved.spec().name().empty() ? saved.spec() : allowed_name(saved, where, &renamed);
    if (!spec.name().empty() && directory->id_of(spec.name()) != physics::kInvalidBodyId) {
      return Status::error(where + ".spec.name: '" + log_text(spec.name()) + "' is used by another body");
    }
    // The saved pose must be exact: no normalisation beyond what the spec
    // check does, and then the saved quaternion itself is put back.
    physics::BodyDesc desc;
    if (Status status = body_desc_from_spec(spec, where + ".spec", &desc); !status.ok()) return status;
    if (!finite(saved.linear_momentum()) || !finite(saved.angular_momentum()) || !std::isfinite(saved.sleep_time())) {
      return Status::error(where + ": momenta and sleep_time must be finite");
    }
    world->add_body_with_id(desc, saved.id());
    if (spec.shape().kind_case() != tumble::v1::Shape::kPlane) {
      // A spec without an orientation means the identity (desc has it), not
      // the zero quaternion protobuf's defaults would give.
      const auto& q = spec.orientation();
      const physics::Quat orientation =
          spec.has_orientation() ? physics::Quat(q.w(), q.x(), q.y(), q.z()) : desc.orientation;
      world->restore_state(saved.id(), desc.position, orientation, to_vec3(saved.linear_momentum()),
                           to_vec3(saved.angular_momentum()), !saved.asleep(), saved.sleep_time());
      // The momenta are checked through the velocities they give (v = p / m,
      // w = I^-1 L), held to the same ranges as a spawned body's: a file
      // that loads must save again to a file that loads.
      if (!restorable(*world, saved.id())) {
        const physics::Vec3 v = world->linear_velocity(saved.id());
        const physics::Vec3 w = world->angular_velocity(saved.id());
        return Status::error(where + ": its momenta give a velocity of [" + std::to_string(v.x()) + ", " +
                             std::to_string(v.y()) + ", " + std::to_string(v.z()) + "] m/s and [" +
                             std::to_string(w.x()) + ", " + std::to_string(w.y()) + ", " + std::to_string(w.z()) +
                             "] rad/s, outside -1e9 .. 1e9 in some component");
      }
    }
    directory->add(saved.id(), BodyEntry{spec.name(), spec.shape(), world->mass(saved.id())});
  }
  world->set_next_body_id(state.next_body_id());

  for (int i = 0; i < state.loads_size(); ++i) {
    const tumble::v1::SavedLoad& saved = state.loads(i);
    const std::string where = "loads[" + std::to_string(i) + "]";
    if (!world->contains(saved.body())) {
      return Status::error(where + ".body: no body " + std::to_string(saved.body()));
    }
    if (!finite(saved.force()) || !finite(saved.local_point()) || !finite(saved.torque())) {
      return Status::error(where + ": force, local_point and torque must be finite");
    }
    if (saved.ticks_left() == 0) return Status::error(where + ".ticks_left: must be at least 1");
    loads->add(BodyLoad{saved.body(), to_vec3(saved.force()), to_vec3(saved.local_point()), to_vec3(saved.torque()),
                        saved.ticks_left()});
  }
  return {};
}

tumble::v1::Scene restorable_scene(const tumble::v1::Scene& scene) {
  tumble::v1::Scene allowed = scene;
  for (int i = 0; i < allowed.bodies_size(); ++i) {
    tumble::v1::BodySpec& body = *allowed.mutable_bodies(i);
    const Status refused = check_body_name(body.name(), "scene.bodies[" + std::to_string(i) + "].name");
    if (refused.ok()) continue;
    sim_log().warn("{}; Reset will bring the body back without a name", log_text(refused.message(), kLogMessageBytes));
    body.clear_name();
  }
  return allowed;
}

}  // namespace tumble::sim
