#include "physics/world.h"

#include <Eigen/Cholesky>
#include <cassert>

#include "physics/integrator.h"
#include "physics/rotation.h"

namespace tumble::physics {

World::World() : gravity_(0.0, -9.81, 0.0) {}

void World::set_gravity(const Vec3& g) { gravity_ = g; }

const Vec3& World::gravity() const { return gravity_; }

BodyId World::add_body(const BodyDesc& desc) {
  const MassProperties& props = desc.mass_properties;
  assert(props.mass > 0);
  assert(props.inertia.isApprox(props.inertia.transpose()));
  assert(props.inertia.llt().info() == Eigen::Success);  // positive definite
  assert(id_to_dense_.size() < kInvalidBodyId);

  const BodyId id = static_cast<BodyId>(id_to_dense_.size());
  id_to_dense_.push_back(static_cast<std::uint32_t>(states_.size()));
  dense_to_id_.push_back(id);

  BodyMass mass;
  mass.mass = props.mass;
  mass.inverse_mass = 1.0 / props.mass;
  mass.inertia_body = props.inertia;
  mass.inverse_inertia_body = props.inertia.inverse();
  masses_.push_back(mass);

  BodyState state;
  state.position = desc.position;
  state.orientation = desc.orientation.normalized();
  state.linear_momentum = props.mass * desc.linear_velocity;
  state.angular_momentum = body_to_world_tensor(state.orientation, props.inertia) * desc.angular_velocity;
  states_.push_back(state);

  shapes_.push_back(desc.shape);
  return id;
}

bool World::remove_body(BodyId id) {
  if (!contains(id)) return false;
  const std::size_t index = id_to_dense_[id];
  const std::size_t last = states_.size() - 1;
  if (index != last) {
    // Swap-remove: the last body moves into the freed slot.
    states_[index] = states_[last];
    masses_[index] = masses_[last];
    shapes_[index] = shapes_[last];
    dense_to_id_[index] = dense_to_id_[last];
    id_to_dense_[dense_to_id_[index]] = static_cast<std::uint32_t>(index);
  }
  states_.pop_back();
  masses_.pop_back();
  shapes_.pop_back();
  dense_to_id_.pop_back();
  id_to_dense_[id] = kNoIndex;
  return true;
}

bool World::contains(BodyId id) const { return id < id_to_dense_.size() && id_to_dense_[id] != kNoIndex; }

std::size_t World::body_count() const { return states_.size(); }

BodyId World::body_id_at(std::size_t index) const {
  assert(index < dense_to_id_.size());
  return dense_to_id_[index];
}

std::size_t World::dense_index(BodyId id) const {
  assert(contains(id));
  return id_to_dense_[id];
}

const Vec3& World::position(BodyId id) const { return states_[dense_index(id)].position; }

const Quat& World::orientation(BodyId id) const { return states_[dense_index(id)].orientation; }

Vec3 World::linear_velocity(BodyId id) const {
  const std::size_t i = dense_index(id);
  return states_[i].linear_momentum * masses_[i].inverse_mass;
}

Vec3 World::angular_velocity(BodyId id) const {
  const std::size_t i = dense_index(id);
  // w = R I_body^-1 R^T L (Baraff, "Angular Momentum").
  return body_to_world_tensor(states_[i].orientation, masses_[i].inverse_inertia_body) * states_[i].angular_momentum;
}

const Vec3& World::linear_momentum(BodyId id) const { return states_[dense_index(id)].linear_momentum; }

const Vec3& World::angular_momentum(BodyId id) const { return states_[dense_index(id)].angular_momentum; }

double World::mass(BodyId id) const { return masses_[dense_index(id)].mass; }

Mat3 World::inertia_world(BodyId id) const {
  const std::size_t i = dense_index(id);
  return body_to_world_tensor(states_[i].orientation, masses_[i].inertia_body);
}

const Mat3& World::inertia_body(BodyId id) const { return masses_[dense_index(id)].inertia_body; }

const Shape& World::shape(BodyId id) const { return shapes_[dense_index(id)]; }

double World::kinetic_energy(BodyId id) const {
  // 1/2 (P.v + L.w) = 1/2 M v.v + 1/2 w^T I w.
  return 0.5 * (linear_momentum(id).dot(linear_velocity(id)) + angular_momentum(id).dot(angular_velocity(id)));
}

void World::set_state(BodyId id, const Vec3& position, const Quat& orientation, const Vec3& linear_velocity,
                      const Vec3& angular_velocity) {
  const std::size_t i = dense_index(id);
  BodyState& state = states_[i];
  state.position = position;
  state.orientation = orientation.normalized();
  state.linear_momentum = masses_[i].mass * linear_velocity;
  state.angular_momentum = body_to_world_tensor(state.orientation, masses_[i].inertia_body) * angular_velocity;
}

void World::add_force(BodyId id, const Vec3& force) { states_[dense_index(id)].force += force; }

void World::add_force_at_point(BodyId id, const Vec3& force, const Vec3& world_point) {
  BodyState& state = states_[dense_index(id)];
  state.force += force;
  // tau = (r - x) x F (Baraff, "Force and Torque").
  state.torque += (world_point - state.position).cross(force);
}

void World::add_torque(BodyId id, const Vec3& torque) { states_[dense_index(id)].torque += torque; }

const Vec3& World::accumulated_force(BodyId id) const { return states_[dense_index(id)].force; }

const Vec3& World::accumulated_torque(BodyId id) const { return states_[dense_index(id)].torque; }

void World::apply_impulse(BodyId id, const Vec3& impulse) { states_[dense_index(id)].linear_momentum += impulse; }

void World::apply_impulse_at_point(BodyId id, const Vec3& impulse, const Vec3& world_point) {
  BodyState& state = states_[dense_index(id)];
  state.linear_momentum += impulse;
  // The angular impulse about the centre of mass, (r - x) x J.
  state.angular_momentum += (world_point - state.position).cross(impulse);
}

void World::step(double dt) {
  for (std::size_t i = 0; i < states_.size(); ++i) {
    BodyState& state = states_[i];
    integrate_body(state, masses_[i], gravity_, dt);
    state.force.setZero();
    state.torque.setZero();
  }
}

}  // namespace tumble::physics
