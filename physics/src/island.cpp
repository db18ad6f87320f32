// World: islands and sleeping.
//
// An island is a set of dynamic bodies connected by contacts with manifold
// points and by joints; static and kinematic bodies do not connect islands
// (a floor under two separate piles keeps them separate). Each step every
// awake dynamic body counts the time it has stayed still: near the pose
// where the count started (a pose that moves on once it is 2 time_to_sleep
// old), and not speeding up (SleepProgress). Within an island, a sleep
// group is a set of bodies joined by joints and by contacts that touch or
// can touch within the step; a group whose bodies have all been still for
// time_to_sleep, are all slower than the sleep speed, and that touches
// something, falls asleep as a whole: its bodies stop being integrated,
// their contacts are neither updated nor solved, and to an awake body
// merely near one of them (its speculative contact) a sleeping body is of
// infinite mass (Catto, "Box2D" b2Island; Baraff's notes leave sleeping
// out). In a group whose other bodies are settling (slow, but not yet still
// for long enough), the bodies that are ready and rest on something that
// does not move sleep already; the settling ones lean on them as on the
// ground. Anything that disturbs a sleeping body, or comes to touch it,
// wakes its whole group and the sleeping bodies touching it, and so does a
// body that stirs (stirring()) in a group that touches it; a touch leaves
// their counts running. The islands of a step are built once, by the
// contact solver (contact_islands.h), and read here.
#include <algorithm>
#include <span>

#include "union_find.h"
#include "world_impl.h"

namespace tumble::physics {

namespace {

// A body speeding up steadily is leaving rest, however slow it still is:
// one tipping over an edge it was balanced on gains speed as
// exp(sqrt(m g r / I) t) from almost nothing (an inverted pendulum), and
// stays below the sleep speed for most of a second. Its speed has then
// risen for kRisingSteps steps in a row, by kRiseFactor or more, to at
// least kRiseFloor of the sleep speed; a settled pile's jitter does not
// rise for that long.
constexpr std::uint32_t kRisingSteps = 10;
constexpr double kRiseFactor = 1.5;
constexpr double kRiseFloor = 0.1;

// A contact's points within this gap (m) touch, for sleeping and waking:
// a resting contact sits at or below zero, and bodies at rest side by side
// a few millimetres apart are not one heap (Box2D's linear slop).
constexpr double kTouchSlop = 0.005;

// What a sleep group holds, at its root in sleep_flags_.
constexpr std::uint8_t kGroupNotReady = 1;  // a body not yet ready to sleep
constexpr std::uint8_t kGroupTouches = 2;   // a contact that touches, or a joint
constexpr std::uint8_t kGroupCarried = 4;   // a kinematic body in motion
constexpr std::uint8_t kGroupStirs = 8;     // a body not ready that stirs (stirring())
constexpr std::uint8_t kGroupRests = 16;    // a touch or joint to what does not move: static, asleep, the world

// sleep_parent_ of a body outside the settled part of its group.
constexpr std::uint32_t kNotSettled = 0xffffffff;

// wake_beside_stirring()'s verdict on a body its flood reached, in
// stir_marks_ (0: not reached).
constexpr std::uint8_t kReachedQuiet = 1;
constexpr std::uint8_t kReachedStirs = 2;

}  // namespace

bool World::Impl::accelerating(const SleepProgress& sleep) const {
  return sleep.rising_steps >= kRisingSteps && sleep.last_speed >= kRiseFloor * settings_.sleep_speed &&
         sleep.last_speed >= kRiseFactor * sleep.rise_start_speed;
}

bool World::Impl::ready_to_sleep(const BodyRecord& record) const {
  return record.sleep.time >= settings_.time_to_sleep && record.sleep.last_speed < settings_.sleep_speed;
}

void World::Impl::update_sleep(double dt) {
  if (!settings_.sleep_enabled) return;
  const double time_to_sleep = settings_.time_to_sleep;
  // Still means within this reach of where the count started over the
  // whole of time_to_sleep: the distance a body at half the sleep speed
  // covers in it. A pile's jitter moves its bodies back and forth by far
  // less, and a single fast step does not restart the count (a body that
  // creeps, or has moved, does).
  const double max_movement = 0.5 * settings_.sleep_speed * time_to_sleep;
  bool any_ready = false;
  for (std::size_t i = 0; i < records_.size(); ++i) {
    if (!awake_[i]) continue;
    BodyRecord& record = records_[i];
    if (record.motion_type != MotionType::dynamic_body) continue;
    SleepProgress& sleep = record.sleep;
    const SolverVelocity& v = velocities_[i];
    const double speed = std::max(v.linear.norm(), v.angular.norm() * record.bounding_radius);
    if (speed > sleep.last_speed) {
      if (sleep.rising_steps++ == 0) sleep.rise_start_speed = sleep.last_speed;
    } else {
      sleep.rising_steps = 0;
    }
    sleep.last_speed = speed;
    const BodyState& state = states_[i];
    // The turn since the count started, as the chord 2 |vec(q q_rest^-1)|
    // (at most the angle), carried out to the bounding radius.
    const double turned = 2.0 * (state.orientation * sleep.rest_orientation.conjugate()).vec().norm();
    const double moved = std::max((state.position - sleep.rest_position).norm(), turned * record.bounding_radius);
    if (moved > max_movement || accelerating(sleep)) {
      sleep.time = 0;
      sleep.rest_position = state.position;
      sleep.rest_orientation = state.orientation;
      continue;
    }
    sleep.time += dt;
    // A body its group holds awake keeps counting. Its window moves on once
    // it has been still for two of them, so that a slow creep over seconds
    // (under the sleep speed, as every body of a pile has) is not mistaken
    // for having moved: it stays ready while what holds it settles.
    if (sleep.time >= 2.0 * time_to_sleep) {
      sleep.time = time_to_sleep;
      sleep.rest_position = state.position;
      sleep.rest_orientation = state.orientation;
    }
    any_ready = any_ready || ready_to_sleep(record);
  }
  if (!any_ready) return;

  // The islands the solver built from this step's contacts with points
  // (contact_islands.h), split into sleep groups: bodies joined by joints
  // and by contacts that touch or may touch this step (may_touch). A
  // contact whose points are all farther apart than that is a speculative
  // one between bodies at rest near each other: the two sides may sleep
  // apart, and a side asleep is of infinite mass to the other until they
  // touch (finish_contact_update). A group sleeps when every body in it has
  // been slow long enough, it touches something, and no kinematic body in
  // motion carries it.
  if (sleep_parent_.size() < records_.size()) {
    sleep_parent_.resize(records_.size());
    sleep_flags_.resize(records_.size());
  }
  const ContactIslands& islands = solver_.islands();
  const std::span<const std::uint32_t> bodies = islands.bodies();
  const std::span<const ContactConstraint> constraints = islands.constraints();
  const std::span<const JointConstraint> joints = islands.joints();
  auto in_group = [&](std::uint32_t body) {
    return body != kNoJointBody && records_[body].motion_type == MotionType::dynamic_body && awake_[body];
  };
  auto moving_kinematic = [&](std::uint32_t body) {
    return body != kNoJointBody && records_[body].motion_type == MotionType::kinematic_body && awake_[body];
  };
  auto sleep_root = [&](std::uint32_t body) { return find_root(sleep_parent_, body); };
  // Marks the group of each side of a constraint that is in one.
  auto mark = [&](std::uint32_t a, std::uint32_t b, std::uint8_t flags) {
    if (in_group(a)) sleep_flags_[sleep_root(a)] |= flags;
    if (in_group(b)) sleep_flags_[sleep_root(b)] |= flags;
  };
  for (const ContactIsland& island : islands.islands()) {
    const std::span<const std::uint32_t> members = bodies.subspan(island.first_body, island.body_count);
    const std::span<const ContactConstraint> contacts =
        constraints.subspan(island.first_constraint, island.constraint_count);
    const std::span<const JointConstraint> island_joints = joints.subspan(island.first_joint, island.joint_count);
    if (std::none_of(members.begin(), members.end(),
                     [&](std::uint32_t body) { return ready_to_sleep(records_[body]); })) {
      continue;
    }
    for (std::uint32_t body : members) {
      sleep_parent_[body] = body;
      sleep_flags_[body] = 0;
    }
    for (const ContactConstraint& c : contacts) {
      if (c.may_touch && in_group(c.body_a) && in_group(c.body_b)) unite(sleep_parent_, c.body_a, c.body_b);
    }
    for (const JointConstraint& j : island_joints) {
      if (in_group(j.body_a) && in_group(j.body_b)) unite(sleep_parent_, j.body_a, j.body_b);
    }
    for (std::uint32_t body : members) {
      if (ready_to_sleep(records_[body])) continue;
      sleep_flags_[sleep_root(body)] |= kGroupNotReady;
      if (stirring(body)) sleep_flags_[sleep_root(body)] |= kGroupStirs;
    }
    for (const ContactConstraint& c : contacts) {
      mark(c.body_a, c.body_b,
           static_cast<std::uint8_t>((c.may_touch ? kGroupTouches : 0) |
                                     (moving_kinematic(c.body_a) || moving_kinematic(c.body_b) ? kGroupCarried : 0)));
    }
    for (const JointConstraint& j : island_joints) {
      mark(j.body_a, j.body_b,
           static_cast<std::uint8_t>(kGroupTouches |
                                     (moving_kinematic(j.body_a) || moving_kinematic(j.body_b) ? kGroupCarried : 0)));
    }
    // A group all ready sleeps whole. In a group whose bodies not ready are
    // all settling (none stirs), the ready ones that rest on something that
    // does not move sleep on their own: each part of them joined by
    // contacts that may touch and by joints. A settling body then leans on
    // them as on the ground until it is ready too, or stirs and wakes them
    // (wake_beside_stirring): a landing heap sleeps cube by cube while its
    // last cubes settle, instead of all at once after the last.
    settled_.clear();
    for (std::uint32_t body : members) {
      const std::uint8_t flags = sleep_flags_[sleep_root(body)];
      if (flags == kGroupTouches) {
        put_to_sleep(body);
      } else if (!(flags & (kGroupStirs | kGroupCarried)) && ready_to_sleep(records_[body])) {
        settled_.push_back(body);
      }
    }
    if (settled_.empty()) continue;
    for (std::uint32_t body : members) sleep_parent_[body] = kNotSettled;
    for (std::uint32_t body : settled_) {
      sleep_parent_[body] = body;
      sleep_flags_[body] = 0;
    }
    auto settled = [&](std::uint32_t body) { return in_group(body) && sleep_parent_[body] != kNotSettled; };
    for (const ContactConstraint& c : contacts) {
      if (c.may_touch && settled(c.body_a) && settled(c.body_b)) unite(sleep_parent_, c.body_a, c.body_b);
    }
    for (const JointConstraint& j : island_joints) {
      if (settled(j.body_a) && settled(j.body_b)) unite(sleep_parent_, j.body_a, j.body_b);
    }
    // What each part rests on: a contact that may touch a static body, a
    // kinematic one at rest or a sleeping one, or a joint to such a body or
    // to the world. A joint to a body not ready holds the part awake.
    auto rest = [&](std::uint32_t body, std::uint32_t other, bool joint) {
      if (!settled(body)) return;
      if (other == kNoJointBody || !in_group(other)) {
        sleep_flags_[sleep_root(body)] |= kGroupRests;
      } else if (joint && !settled(other)) {
        sleep_flags_[sleep_root(body)] |= kGroupNotReady;
      }
    };
    for (const ContactConstraint& c : contacts) {
      if (!c.may_touch) continue;
      rest(c.body_a, c.body_b, false);
      rest(c.body_b, c.body_a, false);
    }
    for (const JointConstraint& j : island_joints) {
      rest(j.body_a, j.body_b, true);
      rest(j.body_b, j.body_a, true);
    }
    for (std::uint32_t body : settled_) {
      if (sleep_flags_[sleep_root(body)] == kGroupRests) put_to_sleep(body);
    }
  }
}

template <typename Visit>
void World::Impl::for_each_neighbour(std::uint32_t body, Visit&& visit) const {
  for (ContactKey key = records_[body].contact_head; key != kNullContactKey;) {
    const ContactLink& link = links_[key >> 1];
    const std::uint32_t side = key & 1;
    key = link.next[side];
    if (link.may_touch) visit(side == 0 ? link.body_b : link.body_a);
  }
  const BodyId id = dense_to_id_[body];
  if (id >= body_joints_.size()) return;
  for (JointId joint_id : body_joints_[id]) {
    const JointDesc& desc = joints_[joint_id_to_dense_[joint_id]].desc;
    const BodyId other_id = desc.body_a == id ? desc.body_b : desc.body_a;
    if (other_id != kWorldBodyId) visit(id_to_dense_[other_id]);
  }
}

bool World::Impl::stirring(std::uint32_t body) const {
  const BodyRecord& record = records_[body];
  if (record.motion_type == MotionType::kinematic_body) return awake_[body] != 0;
  const SleepProgress& sleep = record.sleep;
  return sleep.time == 0 || sleep.last_speed >= settings_.sleep_speed || accelerating(sleep);
}

void World::Impl::wake_beside_stirring() {
  if (beside_sleepers_.empty()) return;
  if (stir_marks_.size() < records_.size()) stir_marks_.resize(records_.size(), 0);
  // Floods the awake bodies joined to `start` by contacts that may touch
  // and by joints, and marks them all with whether one of them stirs (or
  // touches a kinematic body in motion, which stirs but joins nothing).
  auto flood = [&](std::uint32_t start) {
    const std::size_t first = stir_reached_.size();
    stir_reached_.push_back(start);
    stir_marks_[start] = kReachedQuiet;
    bool stirs = false;
    auto reach = [&](std::uint32_t other) {
      if (!awake_[other]) return;
      if (!is_dynamic(other)) {
        stirs = stirs || stirring(other);
      } else if (stir_marks_[other] == 0) {
        stir_marks_[other] = kReachedQuiet;
        stir_reached_.push_back(other);
      }
    };
    for (std::size_t k = first; k < stir_reached_.size(); ++k) {
      const std::uint32_t i = stir_reached_[k];
      stirs = stirs || stirring(i);
      for_each_neighbour(i, reach);
    }
    if (!stirs) return;
    for (std::size_t k = first; k < stir_reached_.size(); ++k) stir_marks_[stir_reached_[k]] = kReachedStirs;
  };
  stir_reached_.clear();
  for (std::uint32_t slot : beside_sleepers_) {
    const ContactLink& link = links_[slot];
    // An earlier slot's wake may have reached either side.
    std::uint32_t sleeper = link.body_a, neighbour = link.body_b;
    if (!asleep(sleeper)) std::swap(sleeper, neighbour);
    if (!asleep(sleeper) || !awake_[neighbour] || !is_dynamic(neighbour)) continue;
    if (stir_marks_[neighbour] == 0) flood(neighbour);
    if (stir_marks_[neighbour] == kReachedStirs) wake_island(sleeper, WakeCause::touched);
  }
  for (std::uint32_t body : stir_reached_) stir_marks_[body] = 0;
}

bool World::Impl::may_touch(std::uint32_t slot) const {
  const ContactLink& link = links_[slot];
  const Manifold& m = contacts_[slot].manifold;
  const double reach = kTouchSlop + records_[link.body_a].reach + records_[link.body_b].reach;
  for (int k = 0; k < m.point_count; ++k) {
    if (m.points[k].separation <= reach) return true;
  }
  return false;
}

void World::Impl::put_to_sleep(std::uint32_t body) {
  awake_[body] = 0;
  records_[body].reach = 0;
  // It keeps its time, and is still from here on: a touch that wakes it
  // measures its movement from the pose it slept in (wake_island).
  SleepProgress& sleep = records_[body].sleep;
  sleep.rest_position = states_[body].position;
  sleep.rest_orientation = states_[body].orientation;
  sleep.last_speed = 0;
  sleep.rising_steps = 0;
  states_[body].linear_momentum.setZero();
  states_[body].angular_momentum.setZero();
  // Zero velocities, and of infinite mass to the solver while asleep: an
  // awake body near it (a contact that does not touch, see update_sleep)
  // stops against it.
  refresh_solver_data(body);
}

void World::Impl::wake_island(std::uint32_t body, WakeCause cause) {
  if (!is_dynamic(body)) return;
  if (awake_[body]) {
    // Its count starts over, so that it stirs (stirring()): whatever
    // sleeps against it wakes before the step moves it.
    if (cause == WakeCause::disturbed) {
      records_[body].sleep = SleepProgress{0, states_[body].position, states_[body].orientation};
    }
    return;
  }
  // Flood over touching contacts and joints to the sleeping dynamic bodies.
  island_stack_.clear();
  island_stack_.push_back(body);
  awake_[body] = 1;
  if (collecting_woken_) woken_.push_back(body);
  while (!island_stack_.empty()) {
    const std::uint32_t i = island_stack_.back();
    island_stack_.pop_back();
    BodyRecord& record = records_[i];
    // A kept count measures from the pose the body slept in (put_to_sleep):
    // a body the touch then moves, or speeds up, starts over (update_sleep).
    if (cause == WakeCause::disturbed) record.sleep = SleepProgress{0, states_[i].position, states_[i].orientation};
    record.reach = 0;
    external_[i] = SolverVelocity{};
    refresh_solver_data(i);
    for_each_neighbour(i, [&](std::uint32_t other) {
      if (!asleep(other)) return;
      awake_[other] = 1;
      island_stack_.push_back(other);
      if (collecting_woken_) woken_.push_back(other);
    });
  }
}

}  // namespace tumble::physics
