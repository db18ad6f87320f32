// Small builders for the collision and solver tests: bodies of the common
// shapes and a ground plane. Header-only.
#pragma once

#include <cstdint>
#include <cstring>

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

}  // namespace tumble::physics::testing
