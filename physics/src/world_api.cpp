// World's public methods: each forwards to World::Impl (world_impl.h),
// which holds the state, so world.h shows none of it.
#include <memory>

#include "tumble/physics/world.h"
#include "world_impl.h"

namespace tumble::physics {

World::World() : impl_(std::make_unique<Impl>()) {}
World::~World() = default;
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;

void World::set_gravity(const Vec3& g) { impl_->set_gravity(g); }
const Vec3& World::gravity() const { return impl_->gravity(); }
void World::set_settings(const WorldSettings& settings) { impl_->set_settings(settings); }
const WorldSettings& World::settings() const { return impl_->settings(); }
void World::set_thread_count(int threads) { impl_->set_thread_count(threads); }
void World::set_task_system(TaskSystem* tasks) { impl_->set_task_system(tasks); }
int World::thread_count() const { return impl_->thread_count(); }
BodyId World::add_body(const BodyDesc& desc) { return impl_->add_body(desc); }
BodyId World::add_body_with_id(const BodyDesc& desc, BodyId id) { return impl_->add_body_with_id(desc, id); }
BodyId World::next_body_id() const { return impl_->next_body_id(); }
void World::set_next_body_id(BodyId next) { impl_->set_next_body_id(next); }
void World::restore_state(BodyId id, const Vec3& position, const Quat& orientation, const Vec3& linear_momentum,
                          const Vec3& angular_momentum, bool awake, const SleepProgress& sleep) {
  impl_->restore_state(id, position, orientation, linear_momentum, angular_momentum, awake, sleep);
}
SleepProgress World::sleep_progress(BodyId id) const { return impl_->sleep_progress(id); }
bool World::remove_body(BodyId id) { return impl_->remove_body(id); }
bool World::contains(BodyId id) const { return impl_->contains(id); }
std::size_t World::body_count() const { return impl_->body_count(); }
BodyId World::body_id_at(std::size_t index) const { return impl_->body_id_at(index); }
const Vec3& World::position(BodyId id) const { return impl_->position(id); }
const Quat& World::orientation(BodyId id) const { return impl_->orientation(id); }
Vec3 World::linear_velocity(BodyId id) const { return impl_->linear_velocity(id); }
Vec3 World::angular_velocity(BodyId id) const { return impl_->angular_velocity(id); }
void World::copy_poses(BodyId* ids, double* positions, double* orientations, double* linear_velocities,
                       double* angular_velocities) const {
  impl_->copy_poses(ids, positions, orientations, linear_velocities, angular_velocities);
}
const Vec3& World::linear_momentum(BodyId id) const { return impl_->linear_momentum(id); }
const Vec3& World::angular_momentum(BodyId id) const { return impl_->angular_momentum(id); }
double World::mass(BodyId id) const { return impl_->mass(id); }
Mat3 World::inertia_world(BodyId id) const { return impl_->inertia_world(id); }
const Mat3& World::inertia_body(BodyId id) const { return impl_->inertia_body(id); }
const Shape& World::shape(BodyId id) const { return impl_->shape(id); }
double World::kinetic_energy(BodyId id) const { return impl_->kinetic_energy(id); }
MotionType World::motion_type(BodyId id) const { return impl_->motion_type(id); }
double World::friction(BodyId id) const { return impl_->friction(id); }
double World::restitution(BodyId id) const { return impl_->restitution(id); }
void World::set_friction(BodyId id, double friction) { impl_->set_friction(id, friction); }
void World::set_restitution(BodyId id, double restitution) { impl_->set_restitution(id, restitution); }
void World::set_state(BodyId id, const Vec3& position, const Quat& orientation, const Vec3& linear_velocity,
                      const Vec3& angular_velocity) {
  impl_->set_state(id, position, orientation, linear_velocity, angular_velocity);
}
void World::add_force(BodyId id, const Vec3& force) { impl_->add_force(id, force); }
void World::add_force_at_point(BodyId id, const Vec3& force, const Vec3& world_point) {
  impl_->add_force_at_point(id, force, world_point);
}
void World::add_torque(BodyId id, const Vec3& torque) { impl_->add_torque(id, torque); }
const Vec3& World::accumulated_force(BodyId id) const { return impl_->accumulated_force(id); }
const Vec3& World::accumulated_torque(BodyId id) const { return impl_->accumulated_torque(id); }
void World::apply_impulse(BodyId id, const Vec3& impulse) { impl_->apply_impulse(id, impulse); }
void World::apply_impulse_at_point(BodyId id, const Vec3& impulse, const Vec3& world_point) {
  impl_->apply_impulse_at_point(id, impulse, world_point);
}
void World::wake(BodyId id) { impl_->wake(id); }
bool World::is_awake(BodyId id) const { return impl_->is_awake(id); }
std::size_t World::awake_body_count() const { return impl_->awake_body_count(); }
std::size_t World::sleeping_body_count() const { return impl_->sleeping_body_count(); }
std::size_t World::contact_count() const { return impl_->contact_count(); }
std::size_t World::contact_point_count() const { return impl_->contact_point_count(); }
double World::max_penetration() const { return impl_->max_penetration(); }
const StepStats& World::last_step_stats() const { return impl_->last_step_stats(); }
std::span<const BodyId> World::diverged_bodies() const { return impl_->diverged_bodies(); }
void World::step(double dt) { impl_->step(dt); }

JointId World::add_joint(const JointDesc& desc) { return impl_->add_joint(desc); }
JointId World::add_joint_with_id(const JointDesc& desc, JointId id) { return impl_->add_joint_with_id(desc, id); }
JointId World::next_joint_id() const { return impl_->next_joint_id(); }
void World::set_next_joint_id(JointId next) { impl_->set_next_joint_id(next); }
const char* World::joint_desc_error(const JointDesc& desc) const { return impl_->joint_desc_error(desc); }
void World::set_joint_frames(JointDesc& desc, const Vec3& anchor_a, const Vec3& anchor_b, const Vec3& axis) const {
  impl_->set_joint_frames(desc, anchor_a, anchor_b, axis);
}
bool World::remove_joint(JointId id) { return impl_->remove_joint(id); }
bool World::contains_joint(JointId id) const { return impl_->contains_joint(id); }
std::size_t World::joint_count() const { return impl_->joint_count(); }
JointId World::joint_id_at(std::size_t index) const { return impl_->joint_id_at(index); }
const JointDesc& World::joint_desc(JointId id) const { return impl_->joint_desc(id); }
void World::set_joint_motor(JointId id, const JointMotor& motor) { impl_->set_joint_motor(id, motor); }
JointState World::joint_state(JointId id) const { return impl_->joint_state(id); }
const JointImpulses& World::joint_impulses(JointId id) const { return impl_->joint_impulses(id); }
void World::restore_joint_impulses(JointId id, const JointImpulses& impulses) {
  impl_->restore_joint_impulses(id, impulses);
}
std::span<const JointId> World::body_joints(BodyId id) const { return impl_->body_joints(id); }
std::span<const JointId> World::broken_joints() const { return impl_->broken_joints(); }

}  // namespace tumble::physics
