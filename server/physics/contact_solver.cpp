#include "physics/contact_solver.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "physics/rotation.h"

namespace tumble::physics {
namespace {

// No body, no island: an unset entry of the union-find scratch.
constexpr std::uint32_t kNone = 0xffffffff;

// Constraints whose rows one task builds.
constexpr std::size_t kRowBlock = 64;

// An orthonormal basis (t1, t2) of the plane normal to unit n, continuous
// except at n.z = 0 crossings (Duff et al., "Building an Orthonormal Basis,
// Revisited", JCGT 2017).
void tangent_basis(const Vec3& n, Vec3* t1, Vec3* t2) {
  const double sign = std::copysign(1.0, n.z());
  const double a = -1.0 / (sign + n.z());
  const double b = n.x() * n.y() * a;
  *t1 = Vec3(1.0 + sign * n.x() * n.x() * a, sign * b, -sign * n.x());
  *t2 = Vec3(b, sign + n.y() * n.y() * a, -n.y());
}

}  // namespace

std::uint32_t ContactSolver::island_root(std::uint32_t body) {
  // Union-find with path halving.
  while (parent_[body] != body) {
    parent_[body] = parent_[parent_[body]];
    body = parent_[body];
  }
  return body;
}

void ContactSolver::touch(std::uint32_t body) {
  if (bodies_.inverse_mass[body] == 0 || is_touched_[body]) return;
  is_touched_[body] = 1;
  motion_[body] = Motion{};
  touched_.push_back(body);
}

void ContactSolver::prepare(std::span<Contact> contacts, std::span<const ContactLink> links,
                            std::span<const std::uint32_t> active, const ContactSolverBodies& bodies, double dt,
                            const ContactSolverSettings& settings) {
  for (std::uint32_t body : touched_) is_touched_[body] = 0;
  touched_.clear();
  constraint_count_ = 0;
  point_count_ = 0;
  islands_.clear();
  pending_.clear();
  const std::size_t body_count = bodies.inverse_mass.size();
  if (motion_.size() < body_count) {
    motion_.resize(body_count);
    is_touched_.resize(body_count, 0);
    parent_.resize(body_count, kNone);
    island_of_root_.resize(body_count, kNone);
  }
  contacts_ = contacts;
  bodies_ = bodies;
  settings_ = settings;
  settings_.substeps = std::max(settings_.substeps, 1);
  settings_.iterations = std::max(settings_.iterations, 1);
  settings_.relax_iterations = std::max(settings_.relax_iterations, 0);
  dt_ = dt;
  h_ = dt / settings_.substeps;
  inverse_h_ = 1.0 / h_;

  // The spring of the push (b2MakeSoft): with omega = 2 pi f and zeta the
  // damping ratio, a1 = 2 zeta + h omega, a2 = h omega a1, a3 = 1 / (1 + a2);
  // bias rate omega / a1, mass scale a2 a3, impulse scale a3. Stiffer than a
  // quarter of the substep rate would ring, so f is capped there; contacts
  // against static or kinematic bodies get twice the frequency.
  auto make_soft = [&](double hertz) {
    Softness s;
    if (hertz <= 0) return s;
    const double omega = 2.0 * std::numbers::pi * hertz;
    const double a1 = 2.0 * settings_.damping_ratio + h_ * omega;
    const double a2 = h_ * omega * a1;
    const double a3 = 1.0 / (1.0 + a2);
    s.bias_rate = omega / a1;
    s.mass_scale = a2 * a3;
    s.impulse_scale = a3;
    return s;
  };
  const double hertz = std::min(settings_.contact_hertz, 0.25 / h_);
  soft_ = make_soft(hertz);
  static_soft_ = make_soft(2.0 * hertz);

  // The contacts with points, and the islands their dynamic bodies form.
  auto dynamic = [&](std::uint32_t body) { return bodies.inverse_mass[body] != 0; };
  for (std::uint32_t index : active) {
    if (contacts[index].manifold.point_count == 0) continue;
    pending_.push_back(index);
    const std::uint32_t a = links[index].body_a, b = links[index].body_b;
    if (dynamic(a) && parent_[a] == kNone) parent_[a] = a;
    if (dynamic(b) && parent_[b] == kNone) parent_[b] = b;
    if (dynamic(a) && dynamic(b)) {
      const std::uint32_t root_a = island_root(a), root_b = island_root(b);
      // The smaller index becomes the root, so the forest's shape depends
      // only on the order of the contacts.
      if (root_a < root_b) parent_[root_b] = root_a;
      if (root_b < root_a) parent_[root_a] = root_b;
    }
  }
  if (pending_.empty()) return;

  // Islands numbered in the order their first contact comes in active; a
  // contact between two bodies of infinite mass (which moves nothing) is an
  // island of its own.
  island_of_pending_.resize(pending_.size());
  for (std::size_t k = 0; k < pending_.size(); ++k) {
    const std::uint32_t index = pending_[k];
    const std::uint32_t a = links[index].body_a, b = links[index].body_b;
    std::uint32_t island = kNone;
    if (dynamic(a) || dynamic(b)) {
      const std::uint32_t root = island_root(dynamic(a) ? a : b);
      if (island_of_root_[root] == kNone) {
        island_of_root_[root] = static_cast<std::uint32_t>(islands_.size());
        islands_.emplace_back();
      }
      island = island_of_root_[root];
    } else {
      island = static_cast<std::uint32_t>(islands_.size());
      islands_.emplace_back();
    }
    island_of_pending_[k] = island;
    ++islands_[island].constraint_count;
    islands_[island].point_count += static_cast<std::uint32_t>(contacts[index].manifold.point_count);
  }
  std::uint32_t first = 0, first_point = 0;
  for (Island& island : islands_) {
    island.first_constraint = first;
    first += island.constraint_count;
    first_point += island.point_count;
    island.constraint_count = 0;  // counts again as the constraints are placed
  }
  // Grown, never shrunk: the slots of a step are all written below and in
  // build_rows(), so they need no clearing.
  constraint_count_ = pending_.size();
  point_count_ = first_point;
  if (constraints_.size() < constraint_count_) constraints_.resize(constraint_count_);
  if (points_.size() < point_count_) points_.resize(point_count_);

  // Constraints island by island, each island's in active order.
  slot_of_pending_.resize(pending_.size());
  for (std::size_t k = 0; k < pending_.size(); ++k) {
    Island& island = islands_[island_of_pending_[k]];
    slot_of_pending_[k] = island.first_constraint + island.constraint_count++;
    Constraint& c = constraints_[slot_of_pending_[k]];
    c.contact = pending_[k];
    c.body_a = links[c.contact].body_a;
    c.body_b = links[c.contact].body_b;
    c.point_count = static_cast<std::uint32_t>(contacts[c.contact].manifold.point_count);
  }
  first_point = 0;
  for (Island& island : islands_) {
    island.first_body = static_cast<std::uint32_t>(touched_.size());
    for (std::uint32_t k = 0; k < island.constraint_count; ++k) {
      Constraint& c = constraints_[island.first_constraint + k];
      c.first_point = first_point;
      first_point += c.point_count;
      touch(c.body_a);
      touch(c.body_b);
    }
    island.body_count = static_cast<std::uint32_t>(touched_.size()) - island.first_body;
  }

  // The forest is cleared for the next step through the bodies it holds.
  for (std::uint32_t body : touched_) {
    island_of_root_[body] = kNone;
    parent_[body] = kNone;
  }

}

void ContactSolver::build_rows(Constraint& c, std::span<const SolverVelocity> velocities) {
  const Contact& contact = contacts_[c.contact];
  const Manifold& m = contact.manifold;
  const ContactSolverBodies& bodies = bodies_;
  c.inverse_mass_a = bodies.inverse_mass[c.body_a];
  c.inverse_mass_b = bodies.inverse_mass[c.body_b];
  c.against_infinite_mass = c.inverse_mass_a == 0 || c.inverse_mass_b == 0;
  // Mixing rules: friction is the geometric mean, so a frictionless body
  // slides on anything; restitution the maximum, so a bouncy body bounces
  // on anything (as Box2D).
  c.friction = std::sqrt(bodies.friction[c.body_a] * bodies.friction[c.body_b]);
  c.restitution = std::max(bodies.restitution[c.body_a], bodies.restitution[c.body_b]);
  c.normal = m.normal;
  const SolverVelocity& va = velocities[c.body_a];
  const SolverVelocity& vb = velocities[c.body_b];
  const Vec3& xa = bodies.transforms[c.body_a].position;
  const Vec3& xb = bodies.transforms[c.body_b].position;
  // Friction directions: the first along the sliding velocity at the
  // manifold's centre when there is one, so a sliding body's friction stays
  // opposite to its motion; otherwise a fixed basis.
  {
    Vec3 center = Vec3::Zero();
    for (int k = 0; k < m.point_count; ++k) center += m.points[k].point_a + m.points[k].point_b;
    center /= 2.0 * m.point_count;
    Vec3 slip = vb.linear + vb.angular.cross(center - xb) - va.linear - va.angular.cross(center - xa);
    slip -= slip.dot(c.normal) * c.normal;
    const double slip_speed = slip.norm();
    if (slip_speed > 1e-3) {
      c.tangent1 = slip / slip_speed;
      c.tangent2 = c.normal.cross(c.tangent1);
    } else {
      tangent_basis(c.normal, &c.tangent1, &c.tangent2);
    }
  }

  // A fixed body (contact_solver.h, Constraint::moving_side) adds nothing
  // to a row: only the other side's terms are built.
  auto fixed = [](double inverse_mass, const SolverVelocity& v) {
    return inverse_mass == 0 && v.linear.isZero(0) && v.angular.isZero(0);
  };
  c.moving_side = fixed(c.inverse_mass_a, va) ? 1 : fixed(c.inverse_mass_b, vb) ? 0 : kBothSides;
  const bool moves_a = c.moving_side != 1, moves_b = c.moving_side != 0;
  const Mat3& inertia_a = bodies.inverse_inertia[c.body_a];
  const Mat3& inertia_b = bodies.inverse_inertia[c.body_b];
  // I^-1 j: an isotropic inverse inertia s 1 (a cube's, a sphere's) makes
  // it s j, three products instead of nine, the same numbers.
  const bool isotropic_a = is_isotropic(inertia_a), isotropic_b = is_isotropic(inertia_b);
  auto response = [](const Mat3& inertia, bool isotropic, const Vec3& jacobian) {
    return isotropic ? Vec3(inertia(0, 0) * jacobian) : Vec3(inertia * jacobian);
  };
  const double inverse_mass_sum = c.inverse_mass_a + c.inverse_mass_b;
  for (int k = 0; k < m.point_count; ++k) {
    const ManifoldPoint& mp = m.points[k];
    const Vec3 point = 0.5 * (mp.point_a + mp.point_b);
    const Vec3 ra = point - xa;
    const Vec3 rb = point - xb;
    Point& p = points_[c.first_point + static_cast<std::uint32_t>(k)];
    auto make_row = [&](Row& row, const Vec3& d, double impulse) {
      double k_row = inverse_mass_sum;
      if (moves_a) {
        row.jacobian[0] = ra.cross(d);
        row.response[0] = response(inertia_a, isotropic_a, row.jacobian[0]);
        k_row += row.jacobian[0].dot(row.response[0]);
      }
      if (moves_b) {
        row.jacobian[1] = rb.cross(d);
        row.response[1] = response(inertia_b, isotropic_b, row.jacobian[1]);
        k_row += row.jacobian[1].dot(row.response[1]);
      }
      row.mass = k_row > 0 ? 1.0 / k_row : 0.0;
      row.impulse = impulse;
    };
    const Vec3& friction_impulse = contact.tangent_impulse[k];
    make_row(p.normal, c.normal, contact.normal_impulse[k]);
    make_row(p.tangent1, c.tangent1, friction_impulse.dot(c.tangent1));
    make_row(p.tangent2, c.tangent2, friction_impulse.dot(c.tangent2));
    p.separation = mp.separation;
    if (c.moving_side == kBothSides) {
      p.relative_velocity = c.normal.dot(vb.linear - va.linear) + p.normal.jacobian[1].dot(vb.angular) -
                            p.normal.jacobian[0].dot(va.angular);
    } else {
      const MovingBody moving = moving_body(c);
      const SolverVelocity& v = velocities[moving.body];
      p.relative_velocity =
          moving.sign * c.normal.dot(v.linear) + moving.sign * p.normal.jacobian[moving.side].dot(v.angular);
    }
    p.max_normal_impulse = 0;
  }
}

void ContactSolver::reserve(std::size_t constraints) {
  constraints_.reserve(constraints);
  points_.reserve(kMaxManifoldPoints * constraints);
  pending_.reserve(constraints);
  island_of_pending_.reserve(constraints);
  slot_of_pending_.reserve(constraints);
  islands_.reserve(constraints);
  island_order_.reserve(constraints);
}

ContactSolver::MovingBody ContactSolver::moving_body(const Constraint& c) {
  if (c.moving_side == 1) return {1, c.body_b, c.inverse_mass_b, 1.0};
  return {0, c.body_a, c.inverse_mass_a, -1.0};
}

ContactSolver::Motion ContactSolver::motion_of(std::uint32_t body, double inverse_mass, const SolverVelocity& velocity,
                                               double elapsed) const {
  if (inverse_mass != 0) return motion_[body];
  return Motion{elapsed * velocity.linear, elapsed * velocity.angular};
}

void ContactSolver::warm_start(const IslandView& island, std::span<SolverVelocity> velocities) const {
  for (const Constraint& c : island.constraints) {
    if (c.moving_side != kBothSides) {
      // The moving body alone; the fixed one takes nothing.
      const MovingBody moving = moving_body(c);
      if (moving.inverse_mass == 0) continue;
      SolverVelocity v = velocities[moving.body];
      for (std::uint32_t k = 0; k < c.point_count; ++k) {
        const Point& p = points_[c.first_point + k];
        const Vec3 impulse =
            p.normal.impulse * c.normal + p.tangent1.impulse * c.tangent1 + p.tangent2.impulse * c.tangent2;
        v.linear += (moving.sign * moving.inverse_mass) * impulse;
        v.angular += moving.sign * (p.normal.impulse * p.normal.response[moving.side] +
                                   p.tangent1.impulse * p.tangent1.response[moving.side] +
                                   p.tangent2.impulse * p.tangent2.response[moving.side]);
      }
      velocities[moving.body] = v;
      continue;
    }
    SolverVelocity a = velocities[c.body_a];
    SolverVelocity b = velocities[c.body_b];
    for (std::uint32_t k = 0; k < c.point_count; ++k) {
      const Point& p = points_[c.first_point + k];
      const Vec3 impulse =
          p.normal.impulse * c.normal + p.tangent1.impulse * c.tangent1 + p.tangent2.impulse * c.tangent2;
      a.linear -= c.inverse_mass_a * impulse;
      a.angular -= p.normal.impulse * p.normal.response[0] + p.tangent1.impulse * p.tangent1.response[0] +
                   p.tangent2.impulse * p.tangent2.response[0];
      b.linear += c.inverse_mass_b * impulse;
      b.angular += p.normal.impulse * p.normal.response[1] + p.tangent1.impulse * p.tangent1.response[1] +
                   p.tangent2.impulse * p.tangent2.response[1];
    }
    // A body of infinite mass is shared by islands and never written.
    if (c.inverse_mass_a != 0) velocities[c.body_a] = a;
    if (c.inverse_mass_b != 0) velocities[c.body_b] = b;
  }
}

ContactSolver::NormalTarget ContactSolver::normal_target(const Constraint& c, double separation, bool soft) const {
  NormalTarget target;
  if (separation > 0) {
    target.bias = separation * inverse_h_;  // speculative: may close the gap within the substep
  } else if (soft) {
    const Softness& softness = c.against_infinite_mass ? static_soft_ : soft_;
    target.bias = std::max(softness.bias_rate * separation, -settings_.max_push_speed);
    target.mass_scale = softness.mass_scale;
    target.impulse_scale = softness.impulse_scale;
  }
  return target;
}

double ContactSolver::accumulate_normal(Point& p, double vn, const NormalTarget& target) {
  const double accumulated =
      std::max(p.normal.impulse - p.normal.mass * target.mass_scale * (vn + target.bias) -
                   target.impulse_scale * p.normal.impulse,
               0.0);
  const double d = accumulated - p.normal.impulse;
  p.normal.impulse = accumulated;
  p.max_normal_impulse = std::max(p.max_normal_impulse, accumulated);
  return d;
}

void ContactSolver::accumulate_friction(Point& p, double friction, double vt1, double vt2, double* d1, double* d2) {
  double new1 = p.tangent1.impulse - p.tangent1.mass * vt1;
  double new2 = p.tangent2.impulse - p.tangent2.mass * vt2;
  const double limit = friction * p.normal.impulse;
  const double length2 = new1 * new1 + new2 * new2;
  if (length2 > limit * limit) {
    const double scale = limit / std::sqrt(length2);
    new1 *= scale;
    new2 *= scale;
  }
  *d1 = new1 - p.tangent1.impulse;
  *d2 = new2 - p.tangent2.impulse;
  p.tangent1.impulse = new1;
  p.tangent2.impulse = new2;
}

void ContactSolver::solve_pass(const IslandView& island, std::span<SolverVelocity> velocities, bool soft) {
  for (const Constraint& c : island.constraints) {
    if (c.moving_side != kBothSides) {
      one_sided_pass(c, island, velocities, soft);
      continue;
    }
    // Work on local copies; bodies of inverse mass 0 are not written back.
    Vec3 va = velocities[c.body_a].linear, wa = velocities[c.body_a].angular;
    Vec3 vb = velocities[c.body_b].linear, wb = velocities[c.body_b].angular;
    const Motion ma = motion_of(c.body_a, c.inverse_mass_a, velocities[c.body_a], island.elapsed);
    const Motion mb = motion_of(c.body_b, c.inverse_mass_b, velocities[c.body_b], island.elapsed);
    const double moved = c.normal.dot(mb.displacement - ma.displacement);
    Point* points = points_.data() + c.first_point;

    for (std::uint32_t k = 0; k < c.point_count; ++k) {
      Point& p = points[k];
      // Separation now: the start value plus the relative motion of the two
      // contact points along the normal.
      const double s =
          p.separation + moved + p.normal.jacobian[1].dot(mb.rotation) - p.normal.jacobian[0].dot(ma.rotation);
      const double vn = c.normal.dot(vb - va) + p.normal.jacobian[1].dot(wb) - p.normal.jacobian[0].dot(wa);
      const double d = accumulate_normal(p, vn, normal_target(c, s, soft));
      va -= (c.inverse_mass_a * d) * c.normal;
      wa -= d * p.normal.response[0];
      vb += (c.inverse_mass_b * d) * c.normal;
      wb += d * p.normal.response[1];
    }

    for (std::uint32_t k = 0; k < c.point_count; ++k) {
      Point& p = points[k];
      const Vec3 dv = vb - va;
      const double vt1 = c.tangent1.dot(dv) + p.tangent1.jacobian[1].dot(wb) - p.tangent1.jacobian[0].dot(wa);
      const double vt2 = c.tangent2.dot(dv) + p.tangent2.jacobian[1].dot(wb) - p.tangent2.jacobian[0].dot(wa);
      double d1, d2;
      accumulate_friction(p, c.friction, vt1, vt2, &d1, &d2);
      const Vec3 impulse = d1 * c.tangent1 + d2 * c.tangent2;
      va -= c.inverse_mass_a * impulse;
      wa -= d1 * p.tangent1.response[0] + d2 * p.tangent2.response[0];
      vb += c.inverse_mass_b * impulse;
      wb += d1 * p.tangent1.response[1] + d2 * p.tangent2.response[1];
    }

    if (c.inverse_mass_a != 0) velocities[c.body_a] = {va, wa};
    if (c.inverse_mass_b != 0) velocities[c.body_b] = {vb, wb};
  }
}

// The pass of solve_pass() for a constraint with one fixed body: the same
// rows with the fixed body's terms, all zero, left out. Body b takes the
// impulse and a its opposite, so the moving body's share carries sign.
void ContactSolver::one_sided_pass(const Constraint& c, const IslandView& island,
                                   std::span<SolverVelocity> velocities, bool soft) {
  const auto [side, body, inverse_mass, sign] = moving_body(c);
  Vec3 v = velocities[body].linear, w = velocities[body].angular;
  const Motion motion = motion_of(body, inverse_mass, velocities[body], island.elapsed);
  const double moved = sign * c.normal.dot(motion.displacement);
  Point* points = points_.data() + c.first_point;

  for (std::uint32_t k = 0; k < c.point_count; ++k) {
    Point& p = points[k];
    const double s = p.separation + moved + sign * p.normal.jacobian[side].dot(motion.rotation);
    const double vn = sign * c.normal.dot(v) + sign * p.normal.jacobian[side].dot(w);
    const double d = accumulate_normal(p, vn, normal_target(c, s, soft));
    v += (sign * (inverse_mass * d)) * c.normal;
    w += (sign * d) * p.normal.response[side];
  }

  for (std::uint32_t k = 0; k < c.point_count; ++k) {
    Point& p = points[k];
    const double vt1 = sign * c.tangent1.dot(v) + sign * p.tangent1.jacobian[side].dot(w);
    const double vt2 = sign * c.tangent2.dot(v) + sign * p.tangent2.jacobian[side].dot(w);
    double d1, d2;
    accumulate_friction(p, c.friction, vt1, vt2, &d1, &d2);
    const Vec3 impulse = d1 * c.tangent1 + d2 * c.tangent2;
    v += (sign * inverse_mass) * impulse;
    w += sign * (d1 * p.tangent1.response[side] + d2 * p.tangent2.response[side]);
  }

  if (inverse_mass != 0) velocities[body] = {v, w};
}

void ContactSolver::integrate_motion(const IslandView& island, std::span<const SolverVelocity> velocities) {
  for (std::uint32_t body : island.bodies) {
    Motion& m = motion_[body];
    m.displacement += h_ * velocities[body].linear;
    m.rotation += h_ * velocities[body].angular;
  }
}

void ContactSolver::solve(std::span<SolverVelocity> velocities, WorkerTeam* team) {
  // Rows first, in the contacts' order (the order they lie in memory, which
  // a pass island by island would read scattered), in blocks; then the
  // islands. Both write disjoint slots.
  const std::size_t blocks = (pending_.size() + kRowBlock - 1) / kRowBlock;
  auto rows = [&](std::size_t block) {
    const std::size_t end = std::min(pending_.size(), (block + 1) * kRowBlock);
    for (std::size_t k = block * kRowBlock; k < end; ++k) build_rows(constraints_[slot_of_pending_[k]], velocities);
  };
  if (team == nullptr || team->thread_count() == 1) {
    for (std::size_t block = 0; block < blocks; ++block) rows(block);
    for (const Island& island : islands_) solve_island(island, velocities);
    return;
  }
  team->for_each(blocks, rows);
  // Largest islands first, so the last task to start is a small one. (The
  // order changes which thread takes an island, not its result.)
  island_order_.resize(islands_.size());
  for (std::uint32_t i = 0; i < island_order_.size(); ++i) island_order_[i] = i;
  std::sort(island_order_.begin(), island_order_.end(), [&](std::uint32_t x, std::uint32_t y) {
    return islands_[x].point_count != islands_[y].point_count ? islands_[x].point_count > islands_[y].point_count
                                                              : x < y;
  });
  auto island = [&](std::size_t k) { solve_island(islands_[island_order_[k]], velocities); };
  team->for_each(island_order_.size(), island);
}

void ContactSolver::solve_island(const Island& island, std::span<SolverVelocity> velocities) {
  IslandView view{{constraints_.data() + island.first_constraint, island.constraint_count},
                  {touched_.data() + island.first_body, island.body_count},
                  0.0};

  // The caller added the whole step's external change; the substeps add it
  // a share at a time instead.
  const double share = 1.0 / settings_.substeps;
  for (std::uint32_t body : view.bodies) {
    velocities[body].linear -= bodies_.external_change[body].linear;
    velocities[body].angular -= bodies_.external_change[body].angular;
  }
  for (int substep = 0; substep < settings_.substeps; ++substep) {
    for (std::uint32_t body : view.bodies) {
      velocities[body].linear += share * bodies_.external_change[body].linear;
      velocities[body].angular += share * bodies_.external_change[body].angular;
    }
    warm_start(view, velocities);
    for (int i = 0; i < settings_.iterations; ++i) solve_pass(view, velocities, true);
    integrate_motion(view, velocities);
    view.elapsed += h_;
    for (int i = 0; i < settings_.relax_iterations; ++i) solve_pass(view, velocities, false);
  }
  apply_restitution(view, velocities);
  store_impulses(view);
}

void ContactSolver::apply_restitution(const IslandView& island, std::span<SolverVelocity> velocities) {
  for (const Constraint& c : island.constraints) {
    if (c.restitution == 0) continue;
    // Both bodies' velocities, the side terms of a fixed one left out
    // (it has none: see one_sided_pass()).
    const bool moves_a = c.moving_side != 1, moves_b = c.moving_side != 0;
    SolverVelocity a = velocities[c.body_a];
    SolverVelocity b = velocities[c.body_b];
    for (std::uint32_t k = 0; k < c.point_count; ++k) {
      Point& p = points_[c.first_point + k];
      if (p.relative_velocity > -settings_.restitution_threshold || p.max_normal_impulse == 0) continue;
      double vn = c.normal.dot(b.linear - a.linear);
      if (moves_b) vn += p.normal.jacobian[1].dot(b.angular);
      if (moves_a) vn -= p.normal.jacobian[0].dot(a.angular);
      // Target v_n = -e v_n(before).
      const double accumulated =
          std::max(p.normal.impulse - p.normal.mass * (vn + c.restitution * p.relative_velocity), 0.0);
      const double d = accumulated - p.normal.impulse;
      p.normal.impulse = accumulated;
      if (moves_a) {
        a.linear -= (c.inverse_mass_a * d) * c.normal;
        a.angular -= d * p.normal.response[0];
      }
      if (moves_b) {
        b.linear += (c.inverse_mass_b * d) * c.normal;
        b.angular += d * p.normal.response[1];
      }
    }
    if (c.inverse_mass_a != 0) velocities[c.body_a] = a;
    if (c.inverse_mass_b != 0) velocities[c.body_b] = b;
  }
}

void ContactSolver::store_impulses(const IslandView& island) const {
  for (const Constraint& c : island.constraints) {
    Contact& contact = contacts_[c.contact];
    for (std::uint32_t k = 0; k < c.point_count; ++k) {
      const Point& p = points_[c.first_point + k];
      contact.normal_impulse[k] = p.normal.impulse;
      contact.tangent_impulse[k] = p.tangent1.impulse * c.tangent1 + p.tangent2.impulse * c.tangent2;
    }
  }
}

SolverVelocity ContactSolver::pseudo_velocity(std::uint32_t body, const SolverVelocity& final_velocity) const {
  const Motion& m = motion_[body];
  const double inv_dt = 1.0 / dt_;
  return {m.displacement * inv_dt - final_velocity.linear, m.rotation * inv_dt - final_velocity.angular};
}

}  // namespace tumble::physics
