// Small builders for the collision and solver tests: bodies of the common
// shapes and a ground plane. Header-only.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "rotation.h"
#include "tumble/physics/mass_properties.h"
#include "tumble/physics/world.h"

namespace tumble::physics::testing {

// The server's default tick rate.
inline constexpr double kTick = 1.0 / 240.0;
inline constexpr double kGravity = 9.81;

inline BodyDesc box_body(const Vec3& position, double half_extent = 0.5, double mass = 1.0) {
  BodyDesc desc;
  desc.shape = box_shape(Vec3::Constant(half_extent));
  desc.mass_properties = box_mass_properties(mass, desc.shape.half_extents);
  desc.position = position;
  return desc;
}

inline BodyDesc sphere_body(const Vec3& position, double radius = 0.5, double mass = 1.0) {
  BodyDesc desc;
  desc.shape = sphere_shape(radius);
  desc.mass_properties = sphere_mass_properties(mass, radius);
  desc.position = position;
  return desc;
}

// The default settings with sleeping off: every body is stepped every step.
inline WorldSettings settings_without_sleep() {
  WorldSettings settings;
  settings.sleep_enabled = false;
  return settings;
}

// The plane y = 0, solid below.
inline BodyDesc ground_plane() {
  BodyDesc desc;
  desc.shape = plane_shape(Vec3::UnitY(), 0.0);
  return desc;
}

// FNV-1a over the raw bytes of every body's position and orientation.
inline std::uint64_t state_hash(const World& world) {
  std::uint64_t hash = 14695981039346656037ull;
  auto mix = [&](const double* values, int count) {
    unsigned char bytes[sizeof(double)];
    for (int i = 0; i < count; ++i) {
      std::memcpy(bytes, &values[i], sizeof(double));
      for (unsigned char b : bytes) hash = (hash ^ b) * 1099511628211ull;
    }
  };
  for (std::size_t i = 0; i < world.body_count(); ++i) {
    const BodyId id = world.body_id_at(i);
    const Vec3& x = world.position(id);
    const Quat& q = world.orientation(id);
    const double values[7] = {x.x(), x.y(), x.z(), q.w(), q.x(), q.y(), q.z()};
    mix(values, 7);
  }
  return hash;
}

// The pile of the determinism tests: 100 bodies (boxes, and spheres every
// seventh) dropped in a loose block of 5 x 5 x 4 with varied orientations.
// Returns their ids in the order added.
inline std::vector<BodyId> add_loose_pile(World& world) {
  std::vector<BodyId> ids;
  for (int i = 0; i < 100; ++i) {
    const int x = i % 5, z = (i / 5) % 5, y = i / 25;
    const Vec3 position(1.2 * x + 0.1 * (y % 2), 1.0 + 1.3 * y, 1.2 * z);
    BodyDesc desc = i % 7 == 3 ? sphere_body(position, 0.45) : box_body(position, 0.5);
    desc.orientation = quat_from_rotation_vector(Vec3(0.3 * std::sin(i), 0.7 * std::cos(3.0 * i), 0.2 * i));
    ids.push_back(world.add_body(desc));
  }
  return ids;
}

// What happens to that pile on the way, before step `step`: a push off
// centre at step 600, a removal at step 900.
inline void disturb_loose_pile(World& world, const std::vector<BodyId>& ids, int step) {
  if (step == 600)
    world.apply_impulse_at_point(ids[42], Vec3(2.0, 1.0, 0.0), world.position(ids[42]) + Vec3::UnitY() * 0.5);
  if (step == 900) world.remove_body(ids[17]);
}

// How many steps the determinism tests run that pile: 10 s at full speed,
// past the push and the removal. A sanitizer build runs the same code five
// to twenty times slower and finds its races and bad accesses in the first
// seconds as well, so there it stops at 4 s, still past both.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
inline constexpr int kLoosePileSteps = 4 * 240;
#else
inline constexpr int kLoosePileSteps = 10 * 240;
#endif

}  // namespace tumble::physics::testing
