#include "contact_solver.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <cstring>
#include <cstdlib>

#include "rotation.h"
#include "run_tasks.h"

namespace tumble::physics {
namespace {

// No body, no island: an unset entry of the union-find scratch.
constexpr std::uint32_t kNone = 0xffffffff;

// A group (contact_solver.h) gathers islands until it holds this many
// points: enough to fill the lanes of each colour, few enough that the
// landing of a thousand boxes makes several tasks for a team.
constexpr std::uint32_t kGroupPoints = 1024;

// Colours of the graph colouring; a constraint that finds none free is
// solved alone.
constexpr std::uint32_t kColours = 16;

// Lanes of a wide constraint (Float4).
constexpr int kLanes = 4;

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
    slot_of_body_.resize(body_count, kNone);
    slot_stamp_.resize(body_count, 0);
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
  // Grown, never shrunk: the slots of a step are all written below.
  constraint_count_ = pending_.size();
  point_count_ = first_point;
  if (constraints_.size() < constraint_count_) constraints_.resize(constraint_count_);

  // Constraints island by island, each island's in active order.
  for (std::size_t k = 0; k < pending_.size(); ++k) {
    Island& island = islands_[island_of_pending_[k]];
    Constraint& c = constraints_[island.first_constraint + island.constraint_count++];
    c.contact = pending_[k];
    c.body_a = links[c.contact].body_a;
    c.body_b = links[c.contact].body_b;
    c.point_count = static_cast<std::uint32_t>(contacts[c.contact].manifold.point_count);
  }
  for (Island& island : islands_) {
    island.first_body = static_cast<std::uint32_t>(touched_.size());
    for (std::uint32_t k = 0; k < island.constraint_count; ++k) {
      const Constraint& c = constraints_[island.first_constraint + k];
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

namespace {

void set_lane(Vec3x4& v, int lane, const Vec3& x) {
  v.x[lane] = static_cast<float>(x.x());
  v.y[lane] = static_cast<float>(x.y());
  v.z[lane] = static_cast<float>(x.z());
}

Vec3 lane_of(const Vec3x4& v, int lane) { return Vec3(v.x[lane], v.y[lane], v.z[lane]); }

Vec3 to_vec3(const float (&x)[4]) { return Vec3(x[0], x[1], x[2]); }

void store(float (&to)[4], const Vec3& x) {
  to[0] = static_cast<float>(x.x());
  to[1] = static_cast<float>(x.y());
  to[2] = static_cast<float>(x.z());
  to[3] = 0.0f;
}

}  // namespace

void ContactSolver::reserve(std::size_t constraints) {
  constraints_.reserve(constraints);
  pending_.reserve(constraints);
  island_of_pending_.reserve(constraints);
  islands_.reserve(constraints);
  groups_.reserve(constraints);
  group_order_.reserve(constraints);
  // Each wide constraint holds at least one constraint, each slot is a
  // body of one (or a group's slot of zeros).
  wide_.reserve(constraints);
  wide_points_.reserve(kMaxManifoldPoints * constraints);
  solver_bodies_.reserve(2 * constraints);
  solver_external_.reserve(2 * constraints);
  slot_body_.reserve(2 * constraints);
  colour_members_.reserve(constraints);
  colour_of_.reserve(constraints);
}

void ContactSolver::plan_group(Group& group, std::span<const SolverVelocity> velocities) {
  // Slots: the slot of zeros, the group's dynamic bodies, then each
  // kinematic body in motion that a constraint reads. A static body, or a
  // kinematic one standing still, reads the slot of zeros.
  group.first_slot = static_cast<std::uint32_t>(slot_count_);
  auto add_slot = [&](std::uint32_t body) {
    if (slot_body_.size() <= slot_count_) slot_body_.resize(slot_count_ + 1);
    slot_body_[slot_count_++] = body;
  };
  add_slot(kNoBody);
  for (std::uint32_t k = 0; k < group.body_count; ++k) {
    const std::uint32_t body = touched_[group.first_body + k];
    slot_of_body_[body] = k + 1;
    add_slot(body);
  }
  // A kinematic body's slot is valid in this group only: stamped with the
  // plan that made it.
  ++plan_stamp_;
  auto slot_of = [&](std::uint32_t body) -> std::uint32_t {
    if (bodies_.inverse_mass[body] != 0) return slot_of_body_[body];
    const SolverVelocity& v = velocities[body];
    if (v.linear.isZero(0) && v.angular.isZero(0)) return 0;
    if (slot_stamp_[body] != plan_stamp_) {
      slot_stamp_[body] = plan_stamp_;
      slot_of_body_[body] = static_cast<std::uint32_t>(slot_count_) - group.first_slot;
      add_slot(body);
    }
    return slot_of_body_[body];
  };

  // Colours, first fit in the constraints' order: a colour holds a
  // dynamic body at most once (bit slot of colour_bits_ row c).
  const std::size_t words = (group.body_count + 1 + 63) / 64;
  colour_bits_.assign(kColours * words, 0);
  if (colour_of_.size() < group.constraint_count) colour_of_.resize(group.constraint_count);
  std::uint32_t members[kColours + 1] = {};
  for (std::uint32_t k = 0; k < group.constraint_count; ++k) {
    const Constraint& c = constraints_[group.first_constraint + k];
    const bool moves_a = bodies_.inverse_mass[c.body_a] != 0, moves_b = bodies_.inverse_mass[c.body_b] != 0;
    const std::uint32_t slot_a = moves_a ? slot_of_body_[c.body_a] : 0;
    const std::uint32_t slot_b = moves_b ? slot_of_body_[c.body_b] : 0;
    const std::uint64_t bit_a = std::uint64_t{1} << (slot_a % 64), bit_b = std::uint64_t{1} << (slot_b % 64);
    std::uint32_t colour = 0;
    for (; colour < kColours; ++colour) {
      std::uint64_t* row = colour_bits_.data() + colour * words;
      if (moves_a && (row[slot_a / 64] & bit_a) != 0) continue;
      if (moves_b && (row[slot_b / 64] & bit_b) != 0) continue;
      if (moves_a) row[slot_a / 64] |= bit_a;
      if (moves_b) row[slot_b / 64] |= bit_b;
      break;
    }
    colour_of_[k] = colour;  // kColours: none free
    ++members[colour];
  }
  // The constraints colour by colour (a counting sort, stable).
  std::uint32_t start[kColours + 1];
  for (std::uint32_t colour = 0, offset = 0; colour <= kColours; ++colour) {
    start[colour] = offset;
    offset += members[colour];
  }
  if (colour_members_.size() < group.constraint_count) colour_members_.resize(group.constraint_count);
  {
    std::uint32_t next[kColours + 1];
    std::copy(start, start + kColours + 1, next);
    for (std::uint32_t k = 0; k < group.constraint_count; ++k) colour_members_[next[colour_of_[k]]++] = k;
  }

  // Wide constraints: each colour four at a time, then the uncoloured one
  // at a time.
  group.first_wide = static_cast<std::uint32_t>(wide_count_);
  for (std::uint32_t colour = 0; colour <= kColours; ++colour) {
    const std::uint32_t width = colour < kColours ? static_cast<std::uint32_t>(kLanes) : 1;
    for (std::uint32_t k = start[colour]; k < start[colour] + members[colour]; k += width) {
      if (wide_.size() <= wide_count_) wide_.resize(wide_count_ + 1);
      WideConstraint& w = wide_[wide_count_++];
      w.point_count = 0;
      for (int lane = 0; lane < kLanes; ++lane) {
        const std::uint32_t at = k + static_cast<std::uint32_t>(lane);
        const bool used = static_cast<std::uint32_t>(lane) < width && at < start[colour] + members[colour];
        if (!used) {
          w.constraint[lane] = kNoConstraint;
          w.slot_a[lane] = w.slot_b[lane] = 0;
          continue;
        }
        const std::uint32_t index = group.first_constraint + colour_members_[at];
        const Constraint& c = constraints_[index];
        w.constraint[lane] = index;
        w.slot_a[lane] = slot_of(c.body_a);
        w.slot_b[lane] = slot_of(c.body_b);
        w.point_count = std::max(w.point_count, c.point_count);
      }
      w.first_point = static_cast<std::uint32_t>(wide_point_count_);
      wide_point_count_ += w.point_count;
    }
  }
  group.wide_count = static_cast<std::uint32_t>(wide_count_) - group.first_wide;
  group.slot_count = static_cast<std::uint32_t>(slot_count_) - group.first_slot;
}

void ContactSolver::build_lane(WideConstraint& w, int lane, std::span<const SolverVelocity> velocities) {
  const Constraint& c = constraints_[w.constraint[lane]];
  const Contact& contact = contacts_[c.contact];
  const Manifold& m = contact.manifold;
  const ContactSolverBodies& bodies = bodies_;
  const double inverse_mass_a = bodies.inverse_mass[c.body_a];
  const double inverse_mass_b = bodies.inverse_mass[c.body_b];
  w.inverse_mass_a[lane] = static_cast<float>(inverse_mass_a);
  w.inverse_mass_b[lane] = static_cast<float>(inverse_mass_b);
  // Mixing rules: friction is the geometric mean, so a frictionless body
  // slides on anything; restitution the maximum, so a bouncy body bounces
  // on anything (as Box2D).
  w.friction[lane] = static_cast<float>(std::sqrt(bodies.friction[c.body_a] * bodies.friction[c.body_b]));
  w.restitution[lane] = static_cast<float>(std::max(bodies.restitution[c.body_a], bodies.restitution[c.body_b]));
  // A body of infinite mass gets the stiffer push.
  const Softness& softness = inverse_mass_a == 0 || inverse_mass_b == 0 ? static_soft_ : soft_;
  w.bias_rate[lane] = static_cast<float>(softness.bias_rate);
  w.mass_scale[lane] = static_cast<float>(softness.mass_scale);
  w.impulse_scale[lane] = static_cast<float>(softness.impulse_scale);

  const Vec3& normal = m.normal;
  const SolverVelocity& va = velocities[c.body_a];
  const SolverVelocity& vb = velocities[c.body_b];
  const Vec3& xa = bodies.transforms[c.body_a].position;
  const Vec3& xb = bodies.transforms[c.body_b].position;
  // Friction directions: the first along the sliding velocity at the
  // manifold's centre when there is one, so a sliding body's friction stays
  // opposite to its motion; otherwise a fixed basis.
  Vec3 tangent1, tangent2;
  {
    Vec3 center = Vec3::Zero();
    for (int k = 0; k < m.point_count; ++k) center += m.points[k].point_a + m.points[k].point_b;
    center /= 2.0 * m.point_count;
    Vec3 slip = vb.linear + vb.angular.cross(center - xb) - va.linear - va.angular.cross(center - xa);
    slip -= slip.dot(normal) * normal;
    const double slip_speed = slip.norm();
    if (slip_speed > 1e-3) {
      tangent1 = slip / slip_speed;
      tangent2 = normal.cross(tangent1);
    } else {
      tangent_basis(normal, &tangent1, &tangent2);
    }
  }
  set_lane(w.normal, lane, normal);
  set_lane(w.tangent1, lane, tangent1);
  set_lane(w.tangent2, lane, tangent2);

  // Rows. A static body, or a kinematic one, has a zero inverse inertia, so
  // its response and its share of the effective mass are zero.
  const Mat3& inertia_a = bodies.inverse_inertia[c.body_a];
  const Mat3& inertia_b = bodies.inverse_inertia[c.body_b];
  // I^-1 j: an isotropic inverse inertia s 1 (a cube's, a sphere's) makes
  // it s j, three products instead of nine, the same numbers.
  const bool reads_a = w.slot_a[lane] != 0, reads_b = w.slot_b[lane] != 0;
  const bool isotropic_a = reads_a && is_isotropic(inertia_a), isotropic_b = reads_b && is_isotropic(inertia_b);
  auto response = [](const Mat3& inertia, bool isotropic, const Vec3& jacobian) {
    return isotropic ? Vec3(inertia(0, 0) * jacobian) : Vec3(inertia * jacobian);
  };
  const double inverse_mass_sum = inverse_mass_a + inverse_mass_b;
  for (int k = 0; k < m.point_count; ++k) {
    const ManifoldPoint& mp = m.points[k];
    const Vec3 point = 0.5 * (mp.point_a + mp.point_b);
    const Vec3 ra = point - xa;
    const Vec3 rb = point - xb;
    WidePoint& p = wide_points_[w.first_point + static_cast<std::uint32_t>(k)];
    // A fixed side (the slot of zeros: no velocity, no motion, no inverse
    // inertia) keeps the zeros its terms were given.
    auto make_row = [&](WideRow& row, const Vec3& d, double impulse) {
      double k_row = inverse_mass_sum, angular_part = 0;
      if (reads_a) {
        const Vec3 jacobian = ra.cross(d), r = response(inertia_a, isotropic_a, jacobian);
        k_row += jacobian.dot(r);
        angular_part -= jacobian.dot(va.angular);
        set_lane(row.jacobian_a, lane, jacobian);
        set_lane(row.response_a, lane, r);
      }
      if (reads_b) {
        const Vec3 jacobian = rb.cross(d), r = response(inertia_b, isotropic_b, jacobian);
        k_row += jacobian.dot(r);
        angular_part += jacobian.dot(vb.angular);
        set_lane(row.jacobian_b, lane, jacobian);
        set_lane(row.response_b, lane, r);
      }
      row.mass[lane] = static_cast<float>(k_row > 0 ? 1.0 / k_row : 0.0);
      row.impulse[lane] = static_cast<float>(impulse);
      return angular_part;
    };
    const Vec3& friction_impulse = contact.tangent_impulse[k];
    const double angular_part = make_row(p.normal, normal, contact.normal_impulse[k]);
    make_row(p.tangent1, tangent1, friction_impulse.dot(tangent1));
    make_row(p.tangent2, tangent2, friction_impulse.dot(tangent2));
    p.separation[lane] = static_cast<float>(mp.separation);
    p.relative_velocity[lane] = static_cast<float>(normal.dot(vb.linear - va.linear) + angular_part);
  }
}

namespace {

// The first three floats of four rows, one row a lane, as three Float4 (a
// 4 x 4 transpose; the fourth float of each row is padding).
Vec3x4 transpose_rows(const float* r0, const float* r1, const float* r2, const float* r3) {
  Float4 a, b, c, d;
  std::memcpy(&a, r0, sizeof a);
  std::memcpy(&b, r1, sizeof b);
  std::memcpy(&c, r2, sizeof c);
  std::memcpy(&d, r3, sizeof d);
  const Float4 xy01 = __builtin_shufflevector(a, b, 0, 4, 1, 5);  // x0 x1 y0 y1
  const Float4 xy23 = __builtin_shufflevector(c, d, 0, 4, 1, 5);
  const Float4 zw01 = __builtin_shufflevector(a, b, 2, 6, 3, 7);  // z0 z1 w0 w1
  const Float4 zw23 = __builtin_shufflevector(c, d, 2, 6, 3, 7);
  return Vec3x4{__builtin_shufflevector(xy01, xy23, 0, 1, 4, 5), __builtin_shufflevector(xy01, xy23, 2, 3, 6, 7),
                __builtin_shufflevector(zw01, zw23, 0, 1, 4, 5)};
}

}  // namespace

Vec3x4 ContactSolver::gather(const SolverBody* slots, const std::uint32_t (&index)[4], Field field) {
  return transpose_rows(slots[index[0]].*field, slots[index[1]].*field, slots[index[2]].*field,
                        slots[index[3]].*field);
}

ContactSolver::WideVelocity ContactSolver::gather_velocity(const SolverBody* slots, const std::uint32_t (&index)[4]) {
  return WideVelocity{gather(slots, index, &SolverBody::linear), gather(slots, index, &SolverBody::angular)};
}

ContactSolver::WideMotion ContactSolver::gather_motion(const SolverBody* slots, const std::uint32_t (&index)[4]) {
  return WideMotion{gather(slots, index, &SolverBody::displacement), gather(slots, index, &SolverBody::rotation)};
}

void ContactSolver::scatter_velocity(SolverBody* slots, const std::uint32_t (&index)[4], const Float4& inverse_mass,
                                     const WideVelocity& v) {
  // Lane l's (x, y, z, 0) of both vectors: the transpose back.
  const Float4 zero = splat4(0.0f);
  const Float4 xy01 = __builtin_shufflevector(v.linear.x, v.linear.y, 0, 4, 1, 5);  // x0 y0 x1 y1
  const Float4 xy23 = __builtin_shufflevector(v.linear.x, v.linear.y, 2, 6, 3, 7);
  const Float4 z01 = __builtin_shufflevector(v.linear.z, zero, 0, 4, 1, 5);  // z0 0 z1 0
  const Float4 z23 = __builtin_shufflevector(v.linear.z, zero, 2, 6, 3, 7);
  const Float4 linear[4] = {__builtin_shufflevector(xy01, z01, 0, 1, 4, 5), __builtin_shufflevector(xy01, z01, 2, 3, 6, 7),
                            __builtin_shufflevector(xy23, z23, 0, 1, 4, 5), __builtin_shufflevector(xy23, z23, 2, 3, 6, 7)};
  const Float4 axy01 = __builtin_shufflevector(v.angular.x, v.angular.y, 0, 4, 1, 5);
  const Float4 axy23 = __builtin_shufflevector(v.angular.x, v.angular.y, 2, 6, 3, 7);
  const Float4 az01 = __builtin_shufflevector(v.angular.z, zero, 0, 4, 1, 5);
  const Float4 az23 = __builtin_shufflevector(v.angular.z, zero, 2, 6, 3, 7);
  const Float4 angular[4] = {
      __builtin_shufflevector(axy01, az01, 0, 1, 4, 5), __builtin_shufflevector(axy01, az01, 2, 3, 6, 7),
      __builtin_shufflevector(axy23, az23, 0, 1, 4, 5), __builtin_shufflevector(axy23, az23, 2, 3, 6, 7)};
  // Only bodies a constraint moves are written: a lane's body of infinite
  // mass may be another lane's too, or the slot of zeros.
  for (int lane = 0; lane < kLanes; ++lane) {
    if (inverse_mass[lane] == 0) continue;
    SolverBody& b = slots[index[lane]];
    std::memcpy(b.linear, &linear[lane], sizeof b.linear);
    std::memcpy(b.angular, &angular[lane], sizeof b.angular);
  }
}

void ContactSolver::warm_start(const Group& group) {
  SolverBody* slots = solver_bodies_.data() + group.first_slot;
  for (std::uint32_t i = 0; i < group.wide_count; ++i) {
    const WideConstraint& w = wide_[group.first_wide + i];
    WideVelocity a = gather_velocity(slots, w.slot_a);
    WideVelocity b = gather_velocity(slots, w.slot_b);
    const WidePoint* points = wide_points_.data() + w.first_point;
    for (std::uint32_t k = 0; k < w.point_count; ++k) {
      const WidePoint& p = points[k];
      const Vec3x4 impulse =
          p.normal.impulse * w.normal + p.tangent1.impulse * w.tangent1 + p.tangent2.impulse * w.tangent2;
      a.linear = a.linear - w.inverse_mass_a * impulse;
      a.angular = a.angular - (p.normal.impulse * p.normal.response_a + p.tangent1.impulse * p.tangent1.response_a +
                               p.tangent2.impulse * p.tangent2.response_a);
      b.linear = b.linear + w.inverse_mass_b * impulse;
      b.angular = b.angular + (p.normal.impulse * p.normal.response_b + p.tangent1.impulse * p.tangent1.response_b +
                               p.tangent2.impulse * p.tangent2.response_b);
    }
    scatter_velocity(slots, w.slot_a, w.inverse_mass_a, a);
    scatter_velocity(slots, w.slot_b, w.inverse_mass_b, b);
  }
}

void ContactSolver::solve_pass(const Group& group, bool soft) {
  SolverBody* slots = solver_bodies_.data() + group.first_slot;
  const Float4 inverse_h = splat4(static_cast<float>(inverse_h_));
  const Float4 max_push = splat4(static_cast<float>(-settings_.max_push_speed));
  const Float4 zero = splat4(0.0f), one = splat4(1.0f);
  for (std::uint32_t i = 0; i < group.wide_count; ++i) {
    WideConstraint& w = wide_[group.first_wide + i];
    WideVelocity a = gather_velocity(slots, w.slot_a);
    WideVelocity b = gather_velocity(slots, w.slot_b);
    const WideMotion ma = gather_motion(slots, w.slot_a);
    const WideMotion mb = gather_motion(slots, w.slot_b);
    const Float4 moved = dot4(w.normal, mb.displacement - ma.displacement);
    WidePoint* points = wide_points_.data() + w.first_point;

    for (std::uint32_t k = 0; k < w.point_count; ++k) {
      WidePoint& p = points[k];
      // Separation now: the start value plus the relative motion of the two
      // contact points along the normal.
      const Float4 s = p.separation + moved + dot4(p.normal.jacobian_b, mb.rotation) -
                       dot4(p.normal.jacobian_a, ma.rotation);
      const Float4 vn = dot4(w.normal, b.linear - a.linear) + dot4(p.normal.jacobian_b, b.angular) -
                        dot4(p.normal.jacobian_a, a.angular);
      // The target (contact_solver.h): a speculative point (s > 0) may close
      // its gap within the substep; an overlap is pushed out through the
      // soft spring, or not at all in a relax pass.
      const Mask4 speculative = s > zero;
      Float4 bias = s * inverse_h, mass_scale = one, impulse_scale = zero;
      if (soft) {
        bias = select4(speculative, bias, max4(w.bias_rate * s, max_push));
        mass_scale = select4(speculative, one, w.mass_scale);
        impulse_scale = select4(speculative, zero, w.impulse_scale);
      } else {
        bias = select4(speculative, bias, zero);
      }
      const Float4 accumulated = max4(
          p.normal.impulse - p.normal.mass * mass_scale * (vn + bias) - impulse_scale * p.normal.impulse, zero);
      const Float4 d = accumulated - p.normal.impulse;
      p.normal.impulse = accumulated;
      p.max_normal_impulse = max4(p.max_normal_impulse, accumulated);
      a.linear = a.linear - (w.inverse_mass_a * d) * w.normal;
      a.angular = a.angular - d * p.normal.response_a;
      b.linear = b.linear + (w.inverse_mass_b * d) * w.normal;
      b.angular = b.angular + d * p.normal.response_b;
    }

    for (std::uint32_t k = 0; k < w.point_count; ++k) {
      WidePoint& p = points[k];
      const Vec3x4 dv = b.linear - a.linear;
      const Float4 vt1 =
          dot4(w.tangent1, dv) + dot4(p.tangent1.jacobian_b, b.angular) - dot4(p.tangent1.jacobian_a, a.angular);
      const Float4 vt2 =
          dot4(w.tangent2, dv) + dot4(p.tangent2.jacobian_b, b.angular) - dot4(p.tangent2.jacobian_a, a.angular);
      Float4 new1 = p.tangent1.impulse - p.tangent1.mass * vt1;
      Float4 new2 = p.tangent2.impulse - p.tangent2.mass * vt2;
      // Coulomb's cone: the two tangent impulses together within the disc of
      // radius friction * normal impulse.
      const Float4 limit = w.friction * p.normal.impulse;
      const Float4 length2 = new1 * new1 + new2 * new2;
      const Mask4 outside = length2 > limit * limit;
      const Float4 scale = select4(outside, limit / sqrt4(max4(length2, splat4(1e-30f))), one);
      new1 *= scale;
      new2 *= scale;
      const Float4 d1 = new1 - p.tangent1.impulse, d2 = new2 - p.tangent2.impulse;
      p.tangent1.impulse = new1;
      p.tangent2.impulse = new2;
      const Vec3x4 impulse = d1 * w.tangent1 + d2 * w.tangent2;
      a.linear = a.linear - w.inverse_mass_a * impulse;
      a.angular = a.angular - (d1 * p.tangent1.response_a + d2 * p.tangent2.response_a);
      b.linear = b.linear + w.inverse_mass_b * impulse;
      b.angular = b.angular + (d1 * p.tangent1.response_b + d2 * p.tangent2.response_b);
    }

    scatter_velocity(slots, w.slot_a, w.inverse_mass_a, a);
    scatter_velocity(slots, w.slot_b, w.inverse_mass_b, b);
  }
}

void ContactSolver::apply_restitution(const Group& group) {
  SolverBody* slots = solver_bodies_.data() + group.first_slot;
  const Float4 threshold = splat4(static_cast<float>(-settings_.restitution_threshold));
  const Float4 zero = splat4(0.0f);
  for (std::uint32_t i = 0; i < group.wide_count; ++i) {
    WideConstraint& w = wide_[group.first_wide + i];
    const Mask4 bouncy = w.restitution > zero;
    if ((bouncy[0] | bouncy[1] | bouncy[2] | bouncy[3]) == 0) continue;
    WideVelocity a = gather_velocity(slots, w.slot_a);
    WideVelocity b = gather_velocity(slots, w.slot_b);
    WidePoint* points = wide_points_.data() + w.first_point;
    for (std::uint32_t k = 0; k < w.point_count; ++k) {
      WidePoint& p = points[k];
      // Points that approached faster than the threshold and took an
      // impulse; target v_n = -e v_n(before).
      const Mask4 bounces = bouncy & (p.relative_velocity <= threshold) & (p.max_normal_impulse > zero);
      const Float4 vn = dot4(w.normal, b.linear - a.linear) + dot4(p.normal.jacobian_b, b.angular) -
                        dot4(p.normal.jacobian_a, a.angular);
      const Float4 accumulated =
          max4(p.normal.impulse - p.normal.mass * (vn + w.restitution * p.relative_velocity), zero);
      const Float4 d = select4(bounces, accumulated - p.normal.impulse, zero);
      p.normal.impulse = p.normal.impulse + d;
      a.linear = a.linear - (w.inverse_mass_a * d) * w.normal;
      a.angular = a.angular - d * p.normal.response_a;
      b.linear = b.linear + (w.inverse_mass_b * d) * w.normal;
      b.angular = b.angular + d * p.normal.response_b;
    }
    scatter_velocity(slots, w.slot_a, w.inverse_mass_a, a);
    scatter_velocity(slots, w.slot_b, w.inverse_mass_b, b);
  }
}

void ContactSolver::store_impulses(const Group& group) const {
  for (std::uint32_t i = 0; i < group.wide_count; ++i) {
    const WideConstraint& w = wide_[group.first_wide + i];
    const WidePoint* points = wide_points_.data() + w.first_point;
    for (int lane = 0; lane < kLanes; ++lane) {
      if (w.constraint[lane] == kNoConstraint) continue;
      const Constraint& c = constraints_[w.constraint[lane]];
      Contact& contact = contacts_[c.contact];
      const Vec3 tangent1 = lane_of(w.tangent1, lane), tangent2 = lane_of(w.tangent2, lane);
      for (std::uint32_t k = 0; k < c.point_count; ++k) {
        const WidePoint& p = points[k];
        contact.normal_impulse[k] = p.normal.impulse[lane];
        contact.tangent_impulse[k] = double{p.tangent1.impulse[lane]} * tangent1 + double{p.tangent2.impulse[lane]} * tangent2;
      }
    }
  }
}

void ContactSolver::solve(std::span<SolverVelocity> velocities, TaskSystem* team) {
  // Groups of consecutive islands (their constraints and bodies are
  // contiguous), then their slots and wide constraints, on this thread.
  groups_.clear();
  slot_count_ = 0;
  wide_count_ = 0;
  wide_point_count_ = 0;
  for (const Island& island : islands_) {
    if (groups_.empty() || groups_.back().point_count >= kGroupPoints) {
      Group group;
      group.first_constraint = island.first_constraint;
      group.first_body = island.first_body;
      groups_.push_back(group);
    }
    Group& group = groups_.back();
    group.constraint_count += island.constraint_count;
    group.body_count += island.body_count;
    group.point_count += island.point_count;
  }
  for (Group& group : groups_) plan_group(group, velocities);
  if (solver_bodies_.size() < slot_count_) {
    solver_bodies_.resize(slot_count_);
    solver_external_.resize(slot_count_);
  }
  if (wide_points_.size() < wide_point_count_) wide_points_.resize(wide_point_count_);

  if (team == nullptr || team->thread_count() == 1) {
    for (const Group& group : groups_) solve_group(group, velocities);
    return;
  }
  // Largest groups first, so the last task to start is a small one. (The
  // order changes which thread takes a group, not its result.)
  group_order_.resize(groups_.size());
  for (std::uint32_t i = 0; i < group_order_.size(); ++i) group_order_[i] = i;
  std::sort(group_order_.begin(), group_order_.end(), [&](std::uint32_t x, std::uint32_t y) {
    return groups_[x].point_count != groups_[y].point_count ? groups_[x].point_count > groups_[y].point_count : x < y;
  });
  auto task = [&](std::size_t k) { solve_group(groups_[group_order_[k]], velocities); };
  run_tasks(*team, group_order_.size(), task);
}

void ContactSolver::solve_group(const Group& group, std::span<SolverVelocity> velocities) {
  SolverBody* slots = solver_bodies_.data() + group.first_slot;
  SolverBody* external = solver_external_.data() + group.first_slot;
  const std::uint32_t* slot_body = slot_body_.data() + group.first_slot;

  // The slots. The caller added the whole step's external change to a
  // dynamic body's velocity; the substeps add it a share at a time instead.
  slots[0] = SolverBody{};
  external[0] = SolverBody{};
  for (std::uint32_t s = 1; s < group.slot_count; ++s) {
    const std::uint32_t body = slot_body[s];
    const SolverVelocity& v = velocities[body];
    SolverBody& slot = slots[s];
    if (bodies_.inverse_mass[body] != 0) {
      const SolverVelocity& change = bodies_.external_change[body];
      store(slot.linear, v.linear - change.linear);
      store(slot.angular, v.angular - change.angular);
      store(external[s].linear, change.linear);
      store(external[s].angular, change.angular);
    } else {
      store(slot.linear, v.linear);
      store(slot.angular, v.angular);
      external[s] = SolverBody{};
    }
    store(slot.displacement, Vec3::Zero());
    store(slot.rotation, Vec3::Zero());
  }

  // The rows, lane by lane; a lane without a constraint, or without a
  // point k, keeps the zeros written here.
  for (std::uint32_t i = 0; i < group.wide_count; ++i) {
    WideConstraint& w = wide_[group.first_wide + i];
    std::memset(static_cast<void*>(wide_points_.data() + w.first_point), 0, w.point_count * sizeof(WidePoint));
    w.normal = w.tangent1 = w.tangent2 = Vec3x4{};
    w.inverse_mass_a = w.inverse_mass_b = w.friction = w.restitution = Float4{};
    w.bias_rate = w.mass_scale = w.impulse_scale = Float4{};
    for (int lane = 0; lane < kLanes; ++lane) {
      if (w.constraint[lane] != kNoConstraint) build_lane(w, lane, velocities);
    }
  }

  const float share = 1.0f / static_cast<float>(settings_.substeps);
  const float h = static_cast<float>(h_);
  for (int substep = 0; substep < settings_.substeps; ++substep) {
    for (std::uint32_t s = 1; s < group.slot_count; ++s) {
      for (int i = 0; i < 3; ++i) {
        slots[s].linear[i] += share * external[s].linear[i];
        slots[s].angular[i] += share * external[s].angular[i];
      }
    }
    warm_start(group);
    for (int i = 0; i < settings_.iterations; ++i) solve_pass(group, true);
    for (std::uint32_t s = 1; s < group.slot_count; ++s) {
      for (int i = 0; i < 3; ++i) {
        slots[s].displacement[i] += h * slots[s].linear[i];
        slots[s].rotation[i] += h * slots[s].angular[i];
      }
    }
    for (int i = 0; i < settings_.relax_iterations; ++i) solve_pass(group, false);
  }
  apply_restitution(group);
  store_impulses(group);

  // Back to double precision: the solve's change of each dynamic body's
  // velocity (the float difference, exact in double) on top of its velocity
  // before the external change, and the motion.
  for (std::uint32_t s = 1; s < group.slot_count; ++s) {
    const std::uint32_t body = slot_body[s];
    if (bodies_.inverse_mass[body] == 0) continue;
    SolverVelocity& v = velocities[body];
    const SolverVelocity& change = bodies_.external_change[body];
    float start_linear[4], start_angular[4];
    store(start_linear, v.linear - change.linear);
    store(start_angular, v.angular - change.angular);
    v.linear = v.linear - change.linear + (to_vec3(slots[s].linear) - to_vec3(start_linear));
    v.angular = v.angular - change.angular + (to_vec3(slots[s].angular) - to_vec3(start_angular));
    motion_[body] = Motion{to_vec3(slots[s].displacement), to_vec3(slots[s].rotation)};
  }
}

SolverVelocity ContactSolver::pseudo_velocity(std::uint32_t body, const SolverVelocity& final_velocity) const {
  const Motion& m = motion_[body];
  const double inv_dt = 1.0 / dt_;
  return {m.displacement * inv_dt - final_velocity.linear, m.rotation * inv_dt - final_velocity.angular};
}

}  // namespace tumble::physics
