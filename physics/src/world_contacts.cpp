// World: contact bookkeeping, the broadphase update and the narrowphase
// pass.
//
// Pairs come from the broadphase trees (static_tree_ for static bodies,
// movable_tree_ for dynamic and kinematic ones) and from the planes, which
// stay outside the trees and are tested against every awake body's box. A
// contact lives while the fat boxes overlap (for planes: while the body's
// box, grown by the fat margin, reaches the plane), so a pair is found once
// and then only updated.
#include <algorithm>
#include <cmath>

#include "collide.h"
#include "run_tasks.h"
#include "world_impl.h"

namespace tumble::physics {
namespace {

// Manifold reuse: while B's pose relative to A stays within this distance
// (m) and angle of the pose at the last full test, the manifold is
// re-evaluated from its anchors.
constexpr double kReuseDistance = 1e-3;
// cos of half of 1 degree: |q1 . q2| = cos(theta / 2) for the angle theta
// between two orientations.
constexpr double kReuseCosHalfAngle = 0.99996192306417131;

// Pairs a narrowphase task updates: enough to outweigh claiming a task
// (tens of nanoseconds) many times over, few enough that a thousand
// touching pairs make tasks for every thread.
constexpr std::size_t kPairsPerTask = 64;

// A Contact is hundreds of bytes and the pairs' contacts are far apart in
// memory: each is asked of the cache this many pairs before it is updated.
constexpr std::size_t kPrefetchAhead = 4;

// Asks the cache for the lines of c that update_manifold() reads first: the
// cache key at its end, and the manifold at its start.
void prefetch_contact(const Contact& c) {
  __builtin_prefetch(&c.cached_position);
  __builtin_prefetch(&c.cached_max_separation);
  __builtin_prefetch(&c.manifold);
}

// What update_contact() asks of finish_contact_update(), as bits.
constexpr std::uint8_t kContactDestroy = 1;           // the fat boxes no longer overlap
constexpr std::uint8_t kContactCollided = 2;          // the manifold was updated (computed or reused)
constexpr std::uint8_t kContactComputed = 4;          // ... computed afresh from the shapes
constexpr std::uint8_t kContactTouching = 8;          // the manifold has points
constexpr std::uint8_t kContactStartedTouching = 16;  // may_touch now and not at the last update

bool is_polyhedron(ShapeType type) { return type == ShapeType::box || type == ShapeType::convex_hull; }

// Height of the lowest corner of box above the plane n.p = offset.
double lowest_height(const Aabb& box, const Vec3& n, double offset) {
  const Vec3 center = 0.5 * (box.min + box.max);
  const Vec3 half = 0.5 * (box.max - box.min);
  return n.dot(center) - n.cwiseAbs().dot(half) - offset;
}

}  // namespace

bool World::Impl::can_collide(std::size_t a, std::size_t b) const {
  if (a == b) return false;
  if (shapes_[a].type == ShapeType::none || shapes_[b].type == ShapeType::none) return false;
  return (is_dynamic(a) || is_dynamic(b)) && !jointed(a, b);
}

std::uint32_t World::Impl::find_contact(std::uint32_t a, std::uint32_t b) const {
  static_assert(PairSet::kNotFound == kNoIndex);
  return pairs_.find(a, b);
}

void World::Impl::create_contact(std::uint32_t a, std::uint32_t b) {
  if (collide_order(shapes_[a].type) > collide_order(shapes_[b].type)) std::swap(a, b);  // body_a first
  std::uint32_t slot;
  if (free_contacts_.empty()) {
    slot = static_cast<std::uint32_t>(contacts_.size());
    contacts_.emplace_back();
    links_.emplace_back();
  } else {
    slot = free_contacts_.back();
    free_contacts_.pop_back();
    contacts_[slot] = Contact{};
    links_[slot] = ContactLink{};
  }
  ContactLink& link = links_[slot];
  link.alive = true;
  link.body_a = a;
  link.body_b = b;
  link.with_plane = shapes_[b].type == ShapeType::plane;
  pairs_.insert(a, b, slot);
  const std::uint32_t bodies[2] = {a, b};
  for (std::uint32_t side = 0; side < 2; ++side) {
    BodyRecord& record = records_[bodies[side]];
    const ContactKey key = (slot << 1) | side;
    link.prev[side] = kNullContactKey;
    link.next[side] = record.contact_head;
    if (record.contact_head != kNullContactKey) links_[record.contact_head >> 1].prev[record.contact_head & 1] = key;
    record.contact_head = key;
  }
}

void World::Impl::destroy_contact(std::uint32_t slot) {
  ContactLink& link = links_[slot];
  const std::uint32_t bodies[2] = {link.body_a, link.body_b};
  for (std::uint32_t side = 0; side < 2; ++side) {
    BodyRecord& record = records_[bodies[side]];
    const ContactKey prev = link.prev[side];
    const ContactKey next = link.next[side];
    if (prev != kNullContactKey) {
      links_[prev >> 1].next[prev & 1] = next;
    } else {
      record.contact_head = next;
    }
    if (next != kNullContactKey) links_[next >> 1].prev[next & 1] = prev;
  }
  pairs_.erase(link.body_a, link.body_b);
  link.alive = false;
  link.touching = false;
  link.may_touch = false;
  free_contacts_.push_back(slot);
}

void World::Impl::destroy_contacts_of(std::uint32_t body, bool wake_others) {
  while (records_[body].contact_head != kNullContactKey) {
    const ContactKey key = records_[body].contact_head;
    const ContactLink& link = links_[key >> 1];
    const std::uint32_t other = (key & 1) == 0 ? link.body_b : link.body_a;
    if (wake_others && link.touching) wake_island(other);
    destroy_contact(key >> 1);
  }
}

void World::Impl::relabel_body(std::uint32_t from, std::uint32_t to) {
  for (ContactKey key = records_[from].contact_head; key != kNullContactKey;) {
    ContactLink& link = links_[key >> 1];
    const std::uint32_t side = key & 1;
    const std::uint32_t other = side == 0 ? link.body_b : link.body_a;
    pairs_.erase(from, other);
    pairs_.insert(to, other, key >> 1);
    (side == 0 ? link.body_a : link.body_b) = to;
    key = link.next[side];
  }
  const BodyRecord& record = records_[from];
  if (record.proxy != DynamicTree::kNull) {
    (record.motion_type == MotionType::static_body ? static_tree_ : movable_tree_).set_user(record.proxy, to);
  }
  std::replace(planes_.begin(), planes_.end(), from, to);
}

void World::Impl::wake_overlapping(const Aabb& box) {
  movable_tree_.query(box, [&](std::uint32_t other) { wake_island(other); });
}

void World::Impl::update_broadphase(double dt) {
  moved_.clear();
  const double half_margin = 0.5 * settings_.contact_margin;
  for (std::uint32_t i = 0; i < records_.size(); ++i) {
    if (!awake_[i]) continue;
    BodyRecord& record = records_[i];
    if (record.proxy == DynamicTree::kNull) continue;
    // The box the body can reach this step, with half the contact margin on
    // each side so two boxes meet when the bodies come within the margin.
    const Aabb tight = shape_aabb(i).expanded(half_margin + record.reach);
    set_box(i, tight);
    if (movable_tree_.fat_aabb(record.proxy).contains(tight)) continue;
    // The fat box also leads the body by two steps of its motion, so a body
    // in steady flight is not reinserted every step.
    Aabb fat = tight.expanded(settings_.aabb_margin);
    const Vec3 lead = (2.0 * dt) * velocities_[i].linear;
    fat.min += lead.cwiseMin(0.0);
    fat.max += lead.cwiseMax(0.0);
    movable_tree_.move_proxy(record.proxy, fat);
    fat_passes_[i] = contact_pass_ + 1;
    record.moved = true;
    moved_.push_back(i);
  }
  stats_.moved_proxies = moved_.size();

  for (std::uint32_t i : moved_) {
    const Aabb& fat = movable_tree_.fat_aabb(records_[i].proxy);
    auto visit = [&](std::uint32_t j) {
      if (records_[j].moved && j < i) return;  // already found from j's query
      if (!can_collide(i, j) || has_contact(i, j)) return;
      create_contact(i, j);
    };
    movable_tree_.query(fat, visit);
    if (is_dynamic(i)) static_tree_.query(fat, visit);
  }
  for (std::uint32_t i : moved_) records_[i].moved = false;

  // Planes against every awake dynamic body with a shape.
  for (std::uint32_t p : planes_) {
    Vec3 normal;
    double offset;
    world_plane(shapes_[p], transforms_[p], &normal, &offset);
    for (std::uint32_t i = 0; i < records_.size(); ++i) {
      if (!awake_[i]) continue;
      const BodyRecord& record = records_[i];
      if (record.proxy == DynamicTree::kNull || !is_dynamic(i)) continue;
      if (lowest_height(aabbs_[i], normal, offset) > 0 || has_contact(i, p)) continue;
      create_contact(i, p);
    }
  }
}

void World::Impl::update_contacts() {
  active_.clear();
  woken_.clear();
  ++contact_pass_;
  // The pairs to look at: one pass over the compact links in slot order; a
  // pair whose bodies both sleep costs a look at two flags and nothing more
  // (its Contact is not read). A pair still apart whose step boxes have not
  // changed is settled here as update_contact() would settle it, so the
  // tasks below get only pairs with work (a kinematic body spinning among
  // sleeping ones leaves thousands of such pairs a step).
  updating_.clear();
  for (std::uint32_t slot = 0; slot < links_.size(); ++slot) {
    ContactLink& link = links_[slot];
    if (!link.alive) continue;
    if (!awake_[link.body_a] && !awake_[link.body_b]) continue;
    if (still_apart(link)) {
      link.updated_pass = contact_pass_;
      continue;
    }
    updating_.push_back(slot);
  }
  updates_.resize(updating_.size());
  // Their narrowphase, in tasks of consecutive pairs on the task system's
  // threads; each writes only its own pairs, so the outcome does not depend
  // on the thread count or the task system.
  const std::size_t tasks = (updating_.size() + kPairsPerTask - 1) / kPairsPerTask;
  auto update_pairs = [this](std::size_t task) {
    const std::size_t end = std::min(updating_.size(), (task + 1) * kPairsPerTask);
    for (std::size_t k = task * kPairsPerTask; k < end; ++k) {
      if (k + kPrefetchAhead < end) prefetch_contact(contacts_[updating_[k + kPrefetchAhead]]);
      updates_[k] = update_contact(updating_[k]);
    }
  };
  TaskSystem* task_system = this->tasks();
  if (task_system != nullptr && task_system->thread_count() > 1 && tasks > 1) {
    run_tasks(*task_system, tasks, update_pairs);
  } else {
    for (std::size_t task = 0; task < tasks; ++task) update_pairs(task);
  }
  // Then, in slot order, what the pairs ask of the world.
  collecting_woken_ = true;
  beside_sleepers_.clear();
  for (std::size_t k = 0; k < updating_.size(); ++k) finish_contact_update(updating_[k], updates_[k]);
  wake_beside_stirring();
  // Bodies woken by a touch above have contacts that were not looked at
  // (both bodies slept): those join this step too. The list grows while it
  // is walked.
  for (std::size_t k = 0; k < woken_.size(); ++k) {
    for (ContactKey key = records_[woken_[k]].contact_head; key != kNullContactKey;) {
      const std::uint32_t slot = key >> 1;
      key = links_[slot].next[key & 1];  // read before the contact can be destroyed
      if (links_[slot].updated_pass != contact_pass_) finish_contact_update(slot, update_contact(slot));
    }
  }
  collecting_woken_ = false;
}

std::uint8_t World::Impl::update_contact(std::uint32_t slot) {
  const double half_margin = 0.5 * settings_.contact_margin;
  ContactLink& link = links_[slot];
  const std::uint32_t a = link.body_a, b = link.body_b;
  // A pair reached through a body woken this step may still be apart.
  const bool apart = still_apart(link);
  const std::uint64_t last_update = link.updated_pass;
  link.updated_pass = contact_pass_;
  if (apart) return 0;

  // Persistence: the pair lives while the fat boxes overlap.
  bool overlap;
  bool can_touch = true;
  if (link.with_plane) {
    Vec3 normal;
    double offset;
    world_plane(shapes_[b], transforms_[b], &normal, &offset);
    overlap = lowest_height(aabbs_[a], normal, offset) <= settings_.aabb_margin;
  } else {
    // They overlapped at the last update (the pair would be gone otherwise);
    // while neither fat box has moved since, they still do, and the tree's
    // nodes, far apart in memory, need not be read.
    overlap = (fat_passes_[a] <= last_update && fat_passes_[b] <= last_update) || fat_box(a).overlaps(fat_box(b));
    // aabbs_[i] holds body i's shape grown by its reach this step (a
    // body not stepped has reach 0 and its box from when it last moved).
    // Apart by more than half the margin each, the shapes are farther
    // apart than the manifold's reach (margin + both reaches): no points.
    can_touch = aabbs_[a].expanded(half_margin).overlaps(aabbs_[b].expanded(half_margin));
  }
  link.apart = !can_touch;
  if (!overlap) {
    link.touching = false;  // no flood of wake_island() crosses a pair on its way out
    link.may_touch = false;
    return kContactDestroy;
  }
  if (!can_touch) {
    if (link.touching) {
      Contact& c = contacts_[slot];
      c.manifold.point_count = 0;
      c.cached_max_separation = -1;  // the anchors describe points that are gone
      link.touching = false;
      link.may_touch = false;
    }
    return 0;
  }

  Contact& c = contacts_[slot];
  std::uint8_t update = kContactCollided;
  if (update_manifold(c, slot)) update |= kContactComputed;
  const bool touched_before = link.may_touch;
  link.touching = c.manifold.point_count > 0;
  link.speculative = std::all_of(c.manifold.points, c.manifold.points + c.manifold.point_count,
                                 [](const ManifoldPoint& p) { return p.separation > 0; });
  link.may_touch = link.touching && may_touch(slot);
  if (link.touching) update |= kContactTouching;
  if (link.may_touch && !touched_before) update |= kContactStartedTouching;
  return update;
}

void World::Impl::finish_contact_update(std::uint32_t slot, std::uint8_t update) {
  if (update & kContactDestroy) {
    destroy_contact(slot);
    return;
  }
  if (update & kContactCollided) ++stats_.narrowphase_pairs;
  if (update & kContactComputed) ++stats_.manifolds_computed;
  if (!(update & kContactTouching)) return;
  // Coming to touch a sleeping body wakes its group; one merely near stays
  // asleep, of infinite mass to the solver (island.cpp). So does one that
  // stays in touch with a settling body, until something it is in touch
  // with stirs (wake_beside_stirring).
  const ContactLink& link = links_[slot];
  if (link.may_touch && (asleep(link.body_a) || asleep(link.body_b))) {
    if (update & kContactStartedTouching) {
      wake_island(link.body_a, WakeCause::touched);
      wake_island(link.body_b, WakeCause::touched);
    } else {
      beside_sleepers_.push_back(slot);
    }
  }
  active_.push_back(slot);
}

bool World::Impl::update_manifold(Contact& c, std::uint32_t index) {
  const std::uint32_t a = links_[index].body_a, b = links_[index].body_b;
  const Transform& ta = transforms_[a];
  const Transform& tb = transforms_[b];
  // Points up to the margin plus the distance the two can close this step.
  const double max_separation = settings_.contact_margin + records_[a].reach + records_[b].reach;
  const ShapeType type_a = shapes_[a].type, type_b = shapes_[b].type;
  // Pairs with a polyhedron, the ground plane's included: a box settling on
  // the ground keeps its corners where they were.
  const bool cacheable = is_polyhedron(type_a) || is_polyhedron(type_b);

  Vec3 relative_position = Vec3::Zero();
  Quat relative_rotation = Quat::Identity();
  if (cacheable) {
    relative_position = ta.rotation.transpose() * (tb.position - ta.position);
    relative_rotation = states_[a].orientation.conjugate() * states_[b].orientation;
    if (c.cached_max_separation >= max_separation &&
        (relative_position - c.cached_position).squaredNorm() < kReuseDistance * kReuseDistance &&
        std::abs(relative_rotation.dot(c.cached_rotation)) > kReuseCosHalfAngle) {
      Manifold& m = c.manifold;
      m.normal = ta.rotation * c.local_normal;
      for (int k = 0; k < m.point_count; ++k) {
        ManifoldPoint& p = m.points[k];
        p.point_a = ta.apply(c.local_a[k]);
        p.point_b = tb.apply(c.local_b[k]);
        p.separation = (p.point_b - p.point_a).dot(m.normal);
      }
      return false;
    }
  }

  Manifold fresh;
  collide(shapes_[a], ta, shapes_[b], tb, max_separation, fresh);

  // Warm starting: a point keeps the impulses of the old point with its id.
  double normal_impulse[kMaxManifoldPoints];
  Vec3 tangent_impulse[kMaxManifoldPoints];
  for (int k = 0; k < fresh.point_count; ++k) {
    normal_impulse[k] = 0;
    tangent_impulse[k] = Vec3::Zero();
    for (int j = 0; j < c.manifold.point_count; ++j) {
      if (c.manifold.points[j].id == fresh.points[k].id) {
        normal_impulse[k] = c.normal_impulse[j];
        tangent_impulse[k] = c.tangent_impulse[j];
        break;
      }
    }
  }
  // The spin row's impulse lives only while the manifold stays one point.
  if (fresh.point_count != 1 || c.manifold.point_count != 1) c.spin_impulse = 0;
  c.manifold = fresh;
  c.local_normal = ta.rotation.transpose() * fresh.normal;
  for (int k = 0; k < fresh.point_count; ++k) {
    c.normal_impulse[k] = normal_impulse[k];
    c.tangent_impulse[k] = tangent_impulse[k];
    c.local_a[k] = ta.apply_inverse(fresh.points[k].point_a);
    c.local_b[k] = tb.apply_inverse(fresh.points[k].point_b);
  }
  if (cacheable) {
    c.cached_position = relative_position;
    c.cached_rotation = relative_rotation;
    c.cached_max_separation = max_separation;
  }
  return true;
}

}  // namespace tumble::physics
