// Contact: the persistent record of a pair of bodies whose fat AABBs overlap
// (or a body near a plane). It lives from the step the broadphase finds the
// pair until the boxes part, holds the pair's manifold, and carries the
// solver's accumulated impulses from step to step for warm starting (Catto,
// "Iterative Dynamics with Temporal Coherence", GDC 2005).
//
// Contacts sit in one array with a free list (World::contacts_); each is
// linked into the contact lists of both its bodies through its ContactLink,
// kept apart in a parallel array (World::links_): a step scans the links of
// every contact in slot order, and a link is 40 bytes where a Contact is
// over 700, so the scan stays in cache and touches a Contact only for a pair
// whose boxes can touch. Plain data.
#pragma once

#include <cstdint>

#include "manifold.h"
#include "tumble/physics/math.h"

namespace tumble::physics {

// A contact as seen from one of its bodies: (contact index << 1) | side,
// side 0 for body_a and 1 for body_b. Keys chain the per-body lists.
using ContactKey = std::uint32_t;
inline constexpr ContactKey kNullContactKey = 0xffffffff;

// The part of a contact that the passes over all contacts read: the pair,
// its place in both bodies' lists, and whether it touches.
struct ContactLink {
  std::uint32_t body_a = 0;  // dense body indices; the shape of a is not later than b's in collide()'s order
  std::uint32_t body_b = 0;
  ContactKey next[2] = {kNullContactKey, kNullContactKey};  // [side]: the next contact of that body
  ContactKey prev[2] = {kNullContactKey, kNullContactKey};
  std::uint64_t updated_pass = 0;  // World's contact pass that last updated it
  bool alive = false;
  bool touching = false;  // the manifold has points
  // It has a point that touches or that the bodies can reach within the
  // step (World::Impl::may_touch): what joins a sleep group (island.cpp).
  bool may_touch = false;
  // The bodies' step boxes were apart at the last update (no points
  // possible); while neither box changes the pair needs no look.
  bool apart = false;
  bool with_plane = false;  // body_b is a plane: the pair lives while a's box reaches it
  // Every point of the manifold is apart (separation > 0): the pair takes
  // no impulse unless its bodies close the gap within the step.
  bool speculative = false;
};

// The rest of a contact; its pair is in the ContactLink at the same index.
struct Contact {
  Manifold manifold;  // current points, world frame
  // Per point, persistent: anchors in the bodies' frames (to re-evaluate a
  // reused manifold) and the accumulated impulses of the last solve.
  Vec3 local_a[kMaxManifoldPoints];
  Vec3 local_b[kMaxManifoldPoints];
  double normal_impulse[kMaxManifoldPoints] = {};
  Vec3 tangent_impulse[kMaxManifoldPoints];  // friction impulse, world frame (N s)
  double spin_impulse = 0;                   // about the normal, a one-point manifold's (N m s)
  Vec3 local_normal = Vec3::UnitY();         // manifold normal in A's frame

  // The relative pose at the last full collision test; while the bodies'
  // relative pose stays close to it the manifold is re-evaluated from the
  // anchors instead of recomputed (Jolt's body pair cache).
  Vec3 cached_position = Vec3::Zero();      // B's centre in A's frame
  Quat cached_rotation = Quat::Identity();  // q_a^-1 q_b
  double cached_max_separation = -1;        // < 0: no cache
};

}  // namespace tumble::physics
