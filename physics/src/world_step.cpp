// World::step: the pipeline described in world.h.
#include <cmath>
#include <cstring>
#include <limits>

#include "integrator.h"
#include "rotation.h"
#include "world_impl.h"

namespace tumble::physics {
namespace {

// At most this many substeps by default, however long the step (a world
// stepped once a second would otherwise take 240).
constexpr int kMaxDefaultSubsteps = 64;

// Substeps of a step of dt seconds when WorldSettings::substeps is 0 (see
// there); the tolerance keeps 1/60 s at 4, not 5, under rounding.
int substeps_for(double dt) {
  const double needed = std::ceil(dt * kSubstepRate - 1e-9);
  if (needed < kMinSubsteps) return kMinSubsteps;
  return needed > kMaxDefaultSubsteps ? kMaxDefaultSubsteps : static_cast<int>(needed);
}

// True when some component of v is beyond limit in magnitude or not
// finite: the comparison is false for NaN, and infinity exceeds any finite limit.
template <typename Vector>
bool beyond(const Vector& v, double limit) {
  for (Eigen::Index k = 0; k < v.size(); ++k) {
    if (!(std::abs(v[k]) <= limit)) return true;
  }
  return false;
}

}  // namespace

void World::Impl::step(double dt) {
  stats_ = StepStats{};
  diverged_.clear();
  broken_.clear();
  if (!(dt > 0)) {
    for (BodyState& state : states_) {
      state.force.setZero();
      state.torque.setZero();
    }
    return;
  }
  // A world whose dynamic bodies all sleep and whose kinematic bodies stand
  // still has nothing to step: every pass below visits only awake bodies and
  // the pairs and joints they are in, and a force, a command or a new body
  // wakes what it touches before the next step. The scan of the flags is
  // then the whole step. (An empty world's flags have no data to scan:
  // memchr must not be given a null pointer even for no bytes.)
  if (awake_.empty() || std::memchr(awake_.data(), 1, awake_.size()) == nullptr) {
    stats_.pairs = live_pair_count();
    return;
  }
  integrate_velocities(dt);
  update_broadphase(dt);
  update_contacts();
  stats_.pairs = live_pair_count();
  solve_contacts(dt);
  integrate_positions(dt);
  update_sleep(dt);
  // Last: the sleep pass reads the step's islands, which index the joints.
  break_joints();
}

void World::Impl::integrate_velocities(double dt) {
  for (std::size_t i = 0; i < states_.size(); ++i) {
    // Nothing to do for a body at rest: forces only reach dynamic bodies,
    // and adding one wakes the body, so a sleeping, static or still
    // kinematic body has none to clear (its state is not even read).
    if (!awake_[i]) continue;
    BodyRecord& record = records_[i];
    BodyState& state = states_[i];
    if (record.motion_type == MotionType::dynamic_body) {
      // v = P / M and w = I^-1 L with I^-1 = R I_body^-1 R^T at the pose
      // of the start of the step (Baraff, "Angular Momentum").
      const Mat3& r = transforms_[i].rotation;
      inverse_inertia_[i] = body_to_world_tensor(r, masses_[i].inverse_inertia_body);
      const double inverse_mass = masses_[i].inverse_mass;
      external_[i] = {((state.force + masses_[i].mass * gravity_) * dt) * inverse_mass,
                      inverse_inertia_[i] * (state.torque * dt)};
      integrate_momentum(state, masses_[i], gravity_, dt);
      velocities_[i] = {state.linear_momentum * inverse_mass, inverse_inertia_[i] * state.angular_momentum};
    }
    // How far any point of the body can move this step: |v| + |w| r.
    record.reach = (velocities_[i].linear.norm() + velocities_[i].angular.norm() * record.bounding_radius) * dt;
    state.force.setZero();
    state.torque.setZero();
  }
}

void World::Impl::set_thread_count(int threads) {
  if (threads > 1 && !team_) team_ = std::make_unique<WorkerTeam>();
  if (team_) team_->set_thread_count(threads);
}

void World::Impl::solve_contacts(double dt) {
  ContactSolverSettings solver_settings;
  solver_settings.substeps = settings_.substeps > 0 ? settings_.substeps : substeps_for(dt);
  solver_settings.iterations = settings_.velocity_iterations;
  solver_settings.relax_iterations = settings_.relax_iterations;
  // An eighth of the substep rate by default (world.h).
  solver_settings.contact_hertz =
      settings_.contact_hertz > 0 ? settings_.contact_hertz : 0.125 * solver_settings.substeps / dt;
  solver_settings.damping_ratio = settings_.contact_damping_ratio;
  solver_settings.max_push_speed = settings_.max_push_speed;
  solver_settings.restitution_threshold = settings_.restitution_threshold;
  solver_settings.spin_friction = settings_.spin_friction;
  solver_settings.joint_hertz = settings_.joint_hertz;
  solver_settings.joint_damping_ratio = settings_.joint_damping_ratio;
  solver_settings.joint_position_correction = settings_.joint_position_correction;
  const ContactSolverBodies bodies{inverse_masses_, inverse_inertia_, transforms_,
                                   frictions_,      restitutions_,    external_};
  collect_joint_edges();
  solver_.prepare(contacts_, links_, active_, joints_, joint_edges_, bodies, velocities_, dt, solver_settings);
  stats_.solved_contacts = solver_.constraint_count();
  stats_.solved_joints = solver_.joint_count();
  stats_.solved_points = solver_.point_count();
  stats_.islands = solver_.island_count();
  stats_.plan_kept = solver_.plan_kept();
  if (solver_.constraint_count() == 0 && solver_.joint_count() == 0) return;

  solver_.solve(velocities_, tasks());

  // Back to Baraff's state: P = M v and L = I w with I = R I_body R^T.
  for (std::uint32_t i : solver_.touched_bodies()) {
    if (!is_dynamic(i)) continue;
    const Mat3& r = transforms_[i].rotation;
    states_[i].linear_momentum = masses_[i].mass * velocities_[i].linear;
    states_[i].angular_momentum = apply_body_to_world_tensor(r, masses_[i].inertia_body, velocities_[i].angular);
  }
}

void World::Impl::integrate_positions(double dt) {
  // The solver's correction first: it moves the pose towards the motion of
  // the substeps and never touches the momenta.
  if (solver_.constraint_count() > 0 || solver_.joint_count() > 0) {
    for (std::uint32_t i : solver_.touched_bodies()) {
      if (!is_dynamic(i) || !awake_[i]) continue;
      const SolverVelocity pseudo = solver_.pseudo_velocity(i, velocities_[i]);
      BodyState& state = states_[i];
      state.position += pseudo.linear * dt;
      state.orientation = (quat_from_rotation_vector(pseudo.angular * dt) * state.orientation).normalized();
    }
  }
  // The divergence guard's bound; an infinite setting still catches what is not finite.
  const double limit =
      std::isfinite(settings_.max_state_magnitude) ? settings_.max_state_magnitude : std::numeric_limits<double>::max();
  for (std::size_t i = 0; i < states_.size(); ++i) {
    if (!awake_[i]) continue;
    const BodyRecord& record = records_[i];
    BodyState& state = states_[i];
    if (record.motion_type == MotionType::dynamic_body) {
      integrate_pose(state, masses_[i], dt);
    } else {
      // Kinematic: constant velocities.
      state.position += record.kinematic_linear_velocity * dt;
      state.orientation =
          (quat_from_rotation_vector(record.kinematic_angular_velocity * dt) * state.orientation).normalized();
    }
    transforms_[i] = Transform{state.position, state.orientation.toRotationMatrix()};
    ++stats_.integrated_bodies;
    // Checked here, while the state is in cache: only a body that moved can have diverged.
    if (diverged(i, limit)) diverged_.push_back(dense_to_id_[i]);
  }
}

bool World::Impl::diverged(std::size_t i, double limit) const {
  // The velocities are the step's (v = P / M, w = I^-1 L, or the solver's);
  // the momenta they came from need only be finite.
  constexpr double kFinite = std::numeric_limits<double>::max();
  const BodyState& state = states_[i];
  return beyond(state.position, limit) || beyond(state.orientation.coeffs(), kFinite) ||
         beyond(velocities_[i].linear, limit) || beyond(velocities_[i].angular, limit) ||
         beyond(state.linear_momentum, kFinite) || beyond(state.angular_momentum, kFinite);
}

}  // namespace tumble::physics
