// ContactSolver's passes (contact_solver.h): the step's settings and
// springs, and what one group's task runs: its slots and rows, the substeps
// (warm start, soft passes, the move, relax passes), restitution, and the
// impulses stored for the next step.
#include "contact_solver.h"

#include <algorithm>
#include <cstring>

#include "rotation.h"

namespace tumble::physics {
namespace {

// The stiffest joint spring, as a fraction of the substep rate. At a
// quarter (the contacts' cap) chains that fold onto themselves gained
// energy until their joints opened by metres (physics_compare's chain: 20
// chains of 40 links holding 100 times a link's mass, at 60 Hz and 4
// substeps); at 3/16 they stay within centimetres.
constexpr double kMaxJointHertzPerSubstepRate = 0.1875;

// No slot yet: an unset entry of slot_of_body_.
constexpr std::uint32_t kNoSlot = 0xffffffff;

// What a pass over the contacts does to one wide constraint. A side
// whose every lane reads the slot of zeros (WideConstraint::moves_a,
// moves_b: a body of infinite mass at rest, as the ground under a pile) has
// no velocity, no motion and no response: kSideA or kSideB false leaves its
// terms out, and the results are those of the full rows.

// The terms of a solve pass the same for every wide constraint.
struct PassTerms {
  Float4 inverse_h;  // 1/h of the substep
  Float4 max_push;   // -max_push_speed
  bool soft;         // a soft pass, or a relax pass
};

// d.(x_b - x_a) without the terms of a fixed side.
template <bool kSideA, bool kSideB>
[[gnu::always_inline]] inline Float4 along(const Vec3x4& d, const Vec3x4& xa, const Vec3x4& xb) {
  if constexpr (kSideA && kSideB) {
    return dot4(d, xb - xa);
  } else if constexpr (kSideB) {
    return dot4(d, xb);
  } else {
    return splat4(0.0f) - dot4(d, xa);
  }
}

// d.(x_b - x_a) + j_b.y_b - j_a.y_a, the relative velocity along a row
// (x linear, y angular velocities) or its relative motion (x displacement,
// y rotation), without the terms of a fixed side.
template <bool kSideA, bool kSideB>
[[gnu::always_inline]] inline Float4 along_row(const Vec3x4& d, const Vec3x4& jacobian_a, const Vec3x4& jacobian_b,
                                               const Vec3x4& xa, const Vec3x4& ya, const Vec3x4& xb, const Vec3x4& yb) {
  Float4 v = along<kSideA, kSideB>(d, xa, xb);
  if constexpr (kSideB) v = v + dot4(jacobian_b, yb);
  if constexpr (kSideA) v = v - dot4(jacobian_a, ya);
  return v;
}

// Applies an impulse: -P (linear) and -angular_a on side a, +P and
// +angular_b on side b.
template <bool kSideA, bool kSideB>
[[gnu::always_inline]] inline void apply_impulse(WideVelocity& a, WideVelocity& b, const WideConstraint& w,
                                                 const Vec3x4& impulse, const Vec3x4& angular_a,
                                                 const Vec3x4& angular_b) {
  if constexpr (kSideA) {
    a.linear = a.linear - w.inverse_mass_a * impulse;
    a.angular = a.angular - angular_a;
  }
  if constexpr (kSideB) {
    b.linear = b.linear + w.inverse_mass_b * impulse;
    b.angular = b.angular + angular_b;
  }
}

// Applies an impulse d along the normal row: (1/M d) n and d I^-1 (r x n).
template <bool kSideA, bool kSideB>
[[gnu::always_inline]] inline void apply_normal_impulse(WideVelocity& a, WideVelocity& b, const WideConstraint& w,
                                                        Float4 d, const WideRow& row) {
  if constexpr (kSideA) {
    a.linear = a.linear - (w.inverse_mass_a * d) * w.normal;
    a.angular = a.angular - d * row.response_a;
  }
  if constexpr (kSideB) {
    b.linear = b.linear + (w.inverse_mass_b * d) * w.normal;
    b.angular = b.angular + d * row.response_b;
  }
}

template <bool kSideA, bool kSideB>
[[gnu::always_inline]] inline void gather_sides(const SolverBody* slots, const WideConstraint& w, WideVelocity& a,
                                                WideVelocity& b) {
  if constexpr (kSideA) a = gather_velocity(slots, w.slot_a);
  if constexpr (kSideB) b = gather_velocity(slots, w.slot_b);
}

template <bool kSideA, bool kSideB>
[[gnu::always_inline]] inline void scatter_sides(SolverBody* slots, const WideConstraint& w, const WideVelocity& a,
                                                 const WideVelocity& b) {
  if constexpr (kSideA) scatter_velocity(slots, w.slot_a, w.inverse_mass_a, a);
  if constexpr (kSideB) scatter_velocity(slots, w.slot_b, w.inverse_mass_b, b);
}

// The lanes whose point takes no impulse: normal and friction all zero.
inline Mask4 holds_no_impulse(const WidePoint& p) {
  const Float4 zero = splat4(0.0f);
  return (p.normal.impulse == zero) & (p.tangent1.impulse == zero) & (p.tangent2.impulse == zero);
}

// The accumulated impulses of the last step, applied again.
template <bool kSideA, bool kSideB>
[[gnu::always_inline]] inline void warm_start_wide(const WideConstraint& w, const WidePoint* points,
                                                   SolverBody* slots) {
  // Mostly the lanes of contacts whose points are all apart: nothing to
  // apply, and the bodies need not be read.
  bool idle = !w.spins || all4(w.spin_impulse == splat4(0.0f));
  for (std::uint32_t k = 0; k < w.point_count && idle; ++k) idle = all4(holds_no_impulse(points[k]));
  if (idle) return;
  WideVelocity a{}, b{};
  gather_sides<kSideA, kSideB>(slots, w, a, b);
  for (std::uint32_t k = 0; k < w.point_count; ++k) {
    const WidePoint& p = points[k];
    if (all4(holds_no_impulse(p))) continue;
    const Vec3x4 impulse =
        p.normal.impulse * w.normal + p.tangent1.impulse * w.tangent1 + p.tangent2.impulse * w.tangent2;
    apply_impulse<kSideA, kSideB>(a, b, w, impulse,
                                  p.normal.impulse * p.normal.response_a + p.tangent1.impulse * p.tangent1.response_a +
                                      p.tangent2.impulse * p.tangent2.response_a,
                                  p.normal.impulse * p.normal.response_b + p.tangent1.impulse * p.tangent1.response_b +
                                      p.tangent2.impulse * p.tangent2.response_b);
  }
  if (w.spins) {
    if constexpr (kSideA) a.angular = a.angular - w.spin_impulse * w.spin_response_a;
    if constexpr (kSideB) b.angular = b.angular + w.spin_impulse * w.spin_response_b;
  }
  scatter_sides<kSideA, kSideB>(slots, w, a, b);
}

// One pass of the normal rows, the friction rows and the spin row.
template <bool kSideA, bool kSideB>
[[gnu::always_inline]] inline void solve_wide(WideConstraint& w, WidePoint* points, SolverBody* slots,
                                              const PassTerms& terms) {
  const Float4 zero = splat4(0.0f), one = splat4(1.0f);
  WideVelocity a{}, b{};
  gather_sides<kSideA, kSideB>(slots, w, a, b);
  WideMotion ma{}, mb{};
  if constexpr (kSideA) ma = gather_motion(slots, w.slot_a);
  if constexpr (kSideB) mb = gather_motion(slots, w.slot_b);
  const Float4 moved = along<kSideA, kSideB>(w.normal, ma.displacement, mb.displacement);

  for (std::uint32_t k = 0; k < w.point_count; ++k) {
    WidePoint& p = points[k];
    // Separation now: the start value plus the relative motion of the two
    // contact points along the normal.
    Float4 s;
    if constexpr (kSideA && kSideB) {
      s = p.separation + moved + dot4(p.normal.jacobian_b, mb.rotation) - dot4(p.normal.jacobian_a, ma.rotation);
    } else if constexpr (kSideB) {
      s = p.separation + moved + dot4(p.normal.jacobian_b, mb.rotation);
    } else {
      s = p.separation + moved - dot4(p.normal.jacobian_a, ma.rotation);
    }
    const Float4 vn = along_row<kSideA, kSideB>(w.normal, p.normal.jacobian_a, p.normal.jacobian_b, a.linear, a.angular,
                                                b.linear, b.angular);
    // The target (contact_solver.h): a speculative point (s > 0) may close
    // its gap within the substep; an overlap is pushed out through the
    // soft spring, or not at all in a relax pass.
    const Mask4 speculative = s > zero;
    Float4 bias = s * terms.inverse_h, mass_scale = one, impulse_scale = zero;
    if (terms.soft) {
      bias = select4(speculative, bias, max4(w.bias_rate * s, terms.max_push));
      mass_scale = select4(speculative, one, w.mass_scale);
      impulse_scale = select4(speculative, zero, w.impulse_scale);
    } else {
      bias = select4(speculative, bias, zero);
    }
    const Float4 accumulated =
        max4(p.normal.impulse - p.normal.mass * mass_scale * (vn + bias) - impulse_scale * p.normal.impulse, zero);
    const Float4 d = accumulated - p.normal.impulse;
    p.normal.impulse = accumulated;
    p.max_normal_impulse = max4(p.max_normal_impulse, accumulated);
    apply_normal_impulse<kSideA, kSideB>(a, b, w, d, p.normal);
  }

  for (std::uint32_t k = 0; k < w.point_count; ++k) {
    WidePoint& p = points[k];
    // No lane pushes at this point and none holds a friction impulse: the
    // disc is a point at zero, so the rows would leave every impulse zero.
    if (all4(holds_no_impulse(p))) continue;
    const Float4 vt1 = along_row<kSideA, kSideB>(w.tangent1, p.tangent1.jacobian_a, p.tangent1.jacobian_b, a.linear,
                                                 a.angular, b.linear, b.angular);
    const Float4 vt2 = along_row<kSideA, kSideB>(w.tangent2, p.tangent2.jacobian_a, p.tangent2.jacobian_b, a.linear,
                                                 a.angular, b.linear, b.angular);
    Float4 new1 = p.tangent1.impulse - p.tangent1.mass * vt1;
    Float4 new2 = p.tangent2.impulse - p.tangent2.mass * vt2;
    // Coulomb's cone: the two tangent impulses together within the disc of
    // radius friction * normal impulse.
    const Float4 limit = w.friction * p.normal.impulse;
    const Float4 length2 = new1 * new1 + new2 * new2;
    const Mask4 outside = length2 > limit * limit;
    // Mostly every lane sticks (a resting pile): then nothing is scaled,
    // and the division and square root are skipped.
    if (any4(outside)) {
      const Float4 scale = select4(outside, limit / sqrt4(max4(length2, splat4(1e-30f))), one);
      new1 *= scale;
      new2 *= scale;
    }
    const Float4 d1 = new1 - p.tangent1.impulse, d2 = new2 - p.tangent2.impulse;
    p.tangent1.impulse = new1;
    p.tangent2.impulse = new2;
    apply_impulse<kSideA, kSideB>(a, b, w, d1 * w.tangent1 + d2 * w.tangent2,
                                  d1 * p.tangent1.response_a + d2 * p.tangent2.response_a,
                                  d1 * p.tangent1.response_b + d2 * p.tangent2.response_b);
  }

  if (w.spins) {
    // The spin row of the one-point lanes (zero mass in the others),
    // within friction * spin_friction * the point's normal impulse.
    const Float4 spin = along<kSideA, kSideB>(w.normal, a.angular, b.angular);
    const Float4 limit = w.spin_limit * points[0].normal.impulse;
    const Float4 accumulated = min4(max4(w.spin_impulse - w.spin_mass * spin, zero - limit), limit);
    const Float4 d = accumulated - w.spin_impulse;
    w.spin_impulse = accumulated;
    if constexpr (kSideA) a.angular = a.angular - d * w.spin_response_a;
    if constexpr (kSideB) b.angular = b.angular + d * w.spin_response_b;
  }
  scatter_sides<kSideA, kSideB>(slots, w, a, b);
}

// Restitution on the points that approached faster than the threshold and
// took an impulse: target v_n = -e v_n(before).
template <bool kSideA, bool kSideB>
[[gnu::always_inline]] inline void restitution_wide(WideConstraint& w, WidePoint* points, SolverBody* slots,
                                                    Mask4 bouncy, Float4 threshold) {
  const Float4 zero = splat4(0.0f);
  WideVelocity a{}, b{};
  gather_sides<kSideA, kSideB>(slots, w, a, b);
  for (std::uint32_t k = 0; k < w.point_count; ++k) {
    WidePoint& p = points[k];
    const Mask4 bounces = bouncy & (p.relative_velocity <= threshold) & (p.max_normal_impulse > zero);
    const Float4 vn = along_row<kSideA, kSideB>(w.normal, p.normal.jacobian_a, p.normal.jacobian_b, a.linear, a.angular,
                                                b.linear, b.angular);
    const Float4 accumulated =
        max4(p.normal.impulse - p.normal.mass * (vn + w.restitution * p.relative_velocity), zero);
    const Float4 d = select4(bounces, accumulated - p.normal.impulse, zero);
    p.normal.impulse = p.normal.impulse + d;
    apply_normal_impulse<kSideA, kSideB>(a, b, w, d, p.normal);
  }
  scatter_sides<kSideA, kSideB>(slots, w, a, b);
}

// Calls f.template operator()<kSideA, kSideB>() with the sides that w
// moves: a side fixed in every lane is left out.
template <typename F>
[[gnu::always_inline]] inline void with_sides(const WideConstraint& w, F&& f) {
  if (!w.moves_a) {
    f.template operator()<false, true>();
  } else if (!w.moves_b) {
    f.template operator()<true, false>();
  } else {
    f.template operator()<true, true>();
  }
}

}  // namespace

void ContactSolver::prepare(std::span<Contact> contacts, std::span<const ContactLink> links,
                            std::span<const std::uint32_t> active, std::span<Joint> joints,
                            std::span<const JointConstraint> joint_edges, const ContactSolverBodies& bodies,
                            std::span<const SolverVelocity> velocities, double dt,
                            const ContactSolverSettings& settings) {
  const std::size_t body_count = bodies.inverse_mass.size();
  if (motion_.size() < body_count) {
    motion_.resize(body_count);
    slot_of_body_.resize(body_count, kNoSlot);
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

  // The spring of the push (make_softness). Stiffer than a quarter of the
  // substep rate would ring, so f is capped there; contacts against static
  // or kinematic bodies get twice the frequency. Joints get their own,
  // twice the contacts' by default as Box2D v3's, under a lower cap.
  const double hertz = std::min(settings_.contact_hertz, 0.25 / h_);
  soft_ = make_softness(hertz, settings_.damping_ratio, h_);
  static_soft_ = make_softness(2.0 * hertz, settings_.damping_ratio, h_);
  const double joint_hertz = settings_.joint_hertz > 0 ? settings_.joint_hertz : 2.0 * hertz;
  joint_settings_.joint_soft =
      make_softness(std::min(joint_hertz, kMaxJointHertzPerSubstepRate / h_), settings_.joint_damping_ratio, h_);
  joint_settings_.h = h_;
  joint_settings_.inverse_h = inverse_h_;
  joints_ = joints;

  // The islands and the plan (solve()) read of the constraints only their
  // bodies, point counts and flags, and of the bodies only their kind_of():
  // dynamic, a kinematic one in motion (its own slot) or fixed.
  auto kind = [&](std::uint32_t body) -> std::uint64_t {
    return body == kNoJointBody ? 0 : static_cast<std::uint64_t>(kind_of(body, velocities));
  };
  plan_key_.clear();
  for (const std::uint32_t index : active) {
    const ContactLink& link = links[index];
    const std::uint64_t point_count = static_cast<std::uint64_t>(contacts[index].manifold.point_count);
    plan_key_.push_back((std::uint64_t{index} << 32) | link.body_a);
    plan_key_.push_back((std::uint64_t{link.body_b} << 32) | point_count | std::uint64_t{link.may_touch} << 8 |
                        std::uint64_t{link.speculative} << 9 | kind(link.body_a) << 10 | kind(link.body_b) << 12);
  }
  for (const JointConstraint& j : joint_edges) {
    plan_key_.push_back((std::uint64_t{j.joint} << 32) | j.body_a);
    plan_key_.push_back((std::uint64_t{j.body_b} << 32) | 1u << 14 | kind(j.body_a) << 10 | kind(j.body_b) << 12);
  }
  plan_kept_ = planned_ && plan_key_ == planned_key_;
  if (plan_kept_) return;
  planned_ = false;
  std::swap(plan_key_, planned_key_);
  islands_.build(contacts, links, active, joint_edges, bodies.inverse_mass);
}

ContactSolver::BodyKind ContactSolver::kind_of(std::uint32_t body, std::span<const SolverVelocity> velocities) const {
  if (bodies_.inverse_mass[body] != 0) return BodyKind::dynamic;
  const SolverVelocity& v = velocities[body];
  return v.linear.isZero(0) && v.angular.isZero(0) ? BodyKind::fixed : BodyKind::moving;
}

void ContactSolver::reserve(std::size_t constraints) {
  islands_.reserve(constraints);
  graph_.reserve(constraints);
  groups_.reserve(constraints);
  group_order_.reserve(constraints);
  // Each wide constraint holds at least one constraint, each slot is a
  // body of one (or a group's slot of zeros).
  wide_.reserve(constraints);
  wide_points_.reserve(kMaxManifoldPoints * constraints);
  plan_key_.reserve(2 * constraints);
  planned_key_.reserve(2 * constraints);
  solver_bodies_.reserve(2 * constraints);
  solver_external_.reserve(2 * constraints);
  slot_turns_.reserve(2 * constraints);
  slot_body_.reserve(2 * constraints);
  packing_.reserve(constraints);
}

void ContactSolver::warm_start(const Group& group) {
  SolverBody* slots = solver_bodies_.data() + group.first_slot;
  for (std::uint32_t i = 0; i < group.wide_count; ++i) {
    const WideConstraint& w = wide_[group.first_wide + i];
    const WidePoint* points = wide_points_.data() + w.first_point;
    with_sides(
        w, [&]<bool kSideA, bool kSideB>()
               __attribute__((always_inline)) { warm_start_wide<kSideA, kSideB>(w, points, slots); });
  }
}

void ContactSolver::solve_pass(const Group& group, bool soft) {
  SolverBody* slots = solver_bodies_.data() + group.first_slot;
  const PassTerms terms{splat4(static_cast<float>(inverse_h_)), splat4(static_cast<float>(-settings_.max_push_speed)),
                        soft};
  for (std::uint32_t i = 0; i < group.wide_count; ++i) {
    WideConstraint& w = wide_[group.first_wide + i];
    WidePoint* points = wide_points_.data() + w.first_point;
    with_sides(
        w, [&]<bool kSideA, bool kSideB>()
               __attribute__((always_inline)) { solve_wide<kSideA, kSideB>(w, points, slots, terms); });
  }
}

void ContactSolver::solve_joints(const Group& group, bool soft) {
  SolverBody* slots = solver_bodies_.data() + group.first_slot;
  const std::span<const JointConstraint> joint_constraints = islands_.joints();
  for (std::uint32_t k = 0; k < group.joint_count; ++k) {
    const std::uint32_t index = group.first_joint + k;
    solve_joint(joint_rows_[index], joints_[joint_constraints[index].joint], slots, joint_settings_, soft);
  }
}

void ContactSolver::apply_restitution(const Group& group) {
  SolverBody* slots = solver_bodies_.data() + group.first_slot;
  const Float4 threshold = splat4(static_cast<float>(-settings_.restitution_threshold));
  for (std::uint32_t i = 0; i < group.wide_count; ++i) {
    WideConstraint& w = wide_[group.first_wide + i];
    const Mask4 bouncy = w.restitution > splat4(0.0f);
    if (!any4(bouncy)) continue;
    WidePoint* points = wide_points_.data() + w.first_point;
    with_sides(
        w, [&]<bool kSideA, bool kSideB>() __attribute__((always_inline)) {
          restitution_wide<kSideA, kSideB>(w, points, slots, bouncy, threshold);
        });
  }
}

void ContactSolver::store_impulses(const Group& group) const {
  const std::span<const ContactConstraint> constraints = islands_.constraints();
  for (std::uint32_t i = 0; i < group.wide_count; ++i) {
    const WideConstraint& w = wide_[group.first_wide + i];
    const WidePoint* points = wide_points_.data() + w.first_point;
    for (int lane = 0; lane < kLanes; ++lane) {
      if (w.constraint[lane] == kNoConstraint) continue;
      const ContactConstraint& c = constraints[w.constraint[lane]];
      Contact& contact = contacts_[c.contact];
      const Vec3 tangent1 = lane_of(w.tangent1, lane), tangent2 = lane_of(w.tangent2, lane);
      contact.spin_impulse = w.spin_impulse[lane];
      for (std::uint32_t k = 0; k < c.point_count; ++k) {
        const WidePoint& p = points[k];
        contact.normal_impulse[k] = p.normal.impulse[lane];
        contact.tangent_impulse[k] =
            double{p.tangent1.impulse[lane]} * tangent1 + double{p.tangent2.impulse[lane]} * tangent2;
      }
    }
  }
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
      store_vec3(slot.linear, v.linear - change.linear);
      store_vec3(slot.angular, v.angular - change.angular);
      store_vec3(external[s].linear, change.linear);
      store_vec3(external[s].angular, change.angular);
    } else {
      store_vec3(slot.linear, v.linear);
      store_vec3(slot.angular, v.angular);
      external[s] = SolverBody{};
    }
    store_vec3(slot.displacement, Vec3::Zero());
    store_vec3(slot.rotation, Vec3::Zero());
  }

  // The rows: what each lane reads, lane by lane, then the rows of the four
  // lanes at once. A lane without a constraint, or without a point k,
  // keeps the zeros written here.
  const std::span<const ContactConstraint> constraints = islands_.constraints();
  const WideRowInputs inputs{bodies_, velocities, soft_, static_soft_, settings_.spin_friction};
  for (std::uint32_t i = 0; i < group.wide_count; ++i) {
    WideConstraint& w = wide_[group.first_wide + i];
    std::memset(static_cast<void*>(wide_points_.data() + w.first_point), 0, w.point_count * sizeof(WidePoint));
    w.normal = w.tangent1 = w.tangent2 = Vec3x4{};
    w.inverse_mass_a = w.inverse_mass_b = w.friction = w.restitution = Float4{};
    w.bias_rate = w.mass_scale = w.impulse_scale = Float4{};
    w.spin_response_a = w.spin_response_b = Vec3x4{};
    w.spin_mass = w.spin_impulse = w.spin_limit = Float4{};
    w.spins = false;
    WidePoint* points = wide_points_.data() + w.first_point;
    WideArms arms{};
    for (int lane = 0; lane < kLanes; ++lane) {
      if (w.constraint[lane] == kNoConstraint) continue;
      const ContactConstraint& c = constraints[w.constraint[lane]];
      build_lane(inputs, c, contacts_[c.contact], lane, w, points, arms);
    }
    build_rows(w, points, arms);
  }

  // The joints' rows, on the same slots.
  const std::span<JointRow> rows(joint_rows_.data() + group.first_joint, group.joint_count);
  Quat* turns = slot_turns_.data() + group.first_slot;
  if (!rows.empty()) std::fill(turns, turns + group.slot_count, Quat::Identity());
  const std::span<const JointConstraint> joint_constraints = islands_.joints();
  for (std::uint32_t k = 0; k < group.joint_count; ++k) {
    const std::uint32_t index = group.first_joint + k;
    const JointConstraint& j = joint_constraints[index];
    prepare_joint_row(joints_[j.joint], j.body_a, j.body_b, joint_slots_[index].a, joint_slots_[index].b, bodies_,
                      joint_settings_, rows[k]);
    measure_joint(rows[k], slots, turns);
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
    // Joints before contacts in each stage, as Box2D v3 orders them.
    for (JointRow& row : rows) warm_start_joint(row, slots);
    warm_start(group);
    for (int i = 0; i < settings_.iterations; ++i) {
      solve_joints(group, true);
      solve_pass(group, true);
    }
    for (std::uint32_t s = 1; s < group.slot_count; ++s) {
      for (int i = 0; i < 3; ++i) {
        slots[s].displacement[i] += h * slots[s].linear[i];
        slots[s].rotation[i] += h * slots[s].angular[i];
      }
    }
    if (!rows.empty()) {
      for (std::uint32_t s = 1; s < group.slot_count; ++s) {
        turns[s] = quat_from_rotation_vector(load_vec3(slots[s].rotation));
      }
    }
    for (JointRow& row : rows) measure_joint(row, slots, turns);
    for (int i = 0; i < settings_.relax_iterations; ++i) {
      solve_joints(group, false);
      solve_pass(group, false);
    }
    for (JointRow& row : rows) end_joint_substep(row);
  }
  if (settings_.joint_position_correction > 0) {
    for (JointRow& row : rows) correct_joint_position(row, slots, turns, settings_.joint_position_correction);
  }
  apply_restitution(group);
  store_impulses(group);
  for (std::uint32_t k = 0; k < group.joint_count; ++k) {
    store_joint(rows[k], joint_settings_, joints_[joint_constraints[group.first_joint + k].joint]);
  }

  // Back to double precision: the solve's change of each dynamic body's
  // velocity (the float difference, exact in double) on top of its velocity
  // before the external change, and the motion.
  for (std::uint32_t s = 1; s < group.slot_count; ++s) {
    const std::uint32_t body = slot_body[s];
    if (bodies_.inverse_mass[body] == 0) continue;
    SolverVelocity& v = velocities[body];
    const SolverVelocity& change = bodies_.external_change[body];
    float start_linear[4], start_angular[4];
    store_vec3(start_linear, v.linear - change.linear);
    store_vec3(start_angular, v.angular - change.angular);
    v.linear = v.linear - change.linear + (load_vec3(slots[s].linear) - load_vec3(start_linear));
    v.angular = v.angular - change.angular + (load_vec3(slots[s].angular) - load_vec3(start_angular));
    motion_[body] = Motion{load_vec3(slots[s].displacement), load_vec3(slots[s].rotation)};
  }
}

SolverVelocity ContactSolver::pseudo_velocity(std::uint32_t body, const SolverVelocity& final_velocity) const {
  const Motion& m = motion_[body];
  const double inv_dt = 1.0 / dt_;
  return {m.displacement * inv_dt - final_velocity.linear, m.rotation * inv_dt - final_velocity.angular};
}

}  // namespace tumble::physics
