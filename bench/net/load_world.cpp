#include "load_world.h"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <thread>

#include "tumble/v1/scene.pb.h"

namespace tumble::bench {
namespace {

using tumble::v1::BodySpec;

void set_vec3(tumble::v1::Vec3* out, double x, double y, double z) {
  out->set_x(x);
  out->set_y(y);
  out->set_z(z);
}

BodySpec field_body(const WorldOptions& options, unsigned i) {
  const auto side = static_cast<unsigned>(std::ceil(std::sqrt(static_cast<double>(options.bodies))));
  const unsigned spin_every = options.moving > 0 ? static_cast<unsigned>(std::lround(1 / options.moving)) : 0;
  const double centre = 0.5 * (side - 1) / 2;
  BodySpec spec;
  spec.mutable_shape()->mutable_sphere()->set_radius(0.2);
  spec.set_mass(1);
  set_vec3(spec.mutable_position(), 0.5 * (i % side) - centre, 0.2, 0.5 * (i / side) - centre);
  if (spin_every > 0 && i % spin_every == 0) {
    spec.mutable_angular_velocity()->set_y(1);
    // Kinematic: spun by the world's owner, not simulated; it does not touch the ground or anything else.
    if (options.kinematic_movers) spec.set_motion(tumble::v1::MOTION_KINEMATIC);
  }
  return spec;
}

// A unit quaternion tilted about an axis and angle that vary with i
// (a fixed sequence, so that every run drops the same world).
void set_tilt(tumble::v1::Quat* out, unsigned i) {
  const double angle = 0.3 + 0.7 * static_cast<double>((i * 37) % 100) / 100;  // rad
  const double axis[3] = {std::cos(i * 2.39996), 0.5, std::sin(i * 2.39996)};  // golden angle around y
  const double norm = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
  const double s = std::sin(angle / 2) / norm;
  out->set_w(std::cos(angle / 2));
  out->set_x(axis[0] * s);
  out->set_y(axis[1] * s);
  out->set_z(axis[2] * s);
}

BodySpec cube_body(const WorldOptions& options, unsigned i) {
  BodySpec spec;
  spec.set_mass(1);
  auto* half = spec.mutable_shape()->mutable_box()->mutable_half_extents();
  if (i + 1 == options.bodies) {  // the big one, last, level, onto the middle
    set_vec3(half, 0.5, 0.5, 0.5);
    spec.set_mass(10);
    set_vec3(spec.mutable_position(), 0, 2.3, 0);
    return spec;
  }
  const unsigned small = std::max(1u, options.bodies - 1);
  const auto side = static_cast<unsigned>(std::ceil(std::sqrt(static_cast<double>(small))));
  const unsigned column = i % side;
  const unsigned row = i / side;
  const double centre = 0.4 * (side - 1) / 2;
  // Neighbours along a row or a column are 0.55 m apart in height, more
  // than two tilted cubes need (their half diagonals are 0.26 m).
  const double height = 0.4 + 0.55 * ((column + row) % 3);
  set_vec3(half, 0.15, 0.15, 0.15);
  set_vec3(spec.mutable_position(), 0.4 * column - centre, height, 0.4 * row - centre);
  set_tilt(spec.mutable_orientation(), i);
  return spec;
}

BodySpec ground() {
  BodySpec spec;
  spec.set_name("net_load_ground");
  set_vec3(spec.mutable_shape()->mutable_plane()->mutable_normal(), 0, 1, 0);
  spec.set_motion(tumble::v1::MOTION_STATIC);
  return spec;
}

BodySpec probe() {
  BodySpec spec;
  spec.set_name("net_load_probe");
  spec.mutable_shape()->mutable_sphere()->set_radius(0.2);
  spec.set_motion(tumble::v1::MOTION_KINEMATIC);
  set_vec3(spec.mutable_position(), -100, 5, 0);
  return spec;
}

std::uint32_t spawn(client::Connection& connection, const BodySpec& spec) {
  for (;;) {
    auto ack = connection.spawn_body(spec, std::chrono::seconds(10));
    if (ack) return ack->body_id();
    if (ack.failure().code != tumble::v1::RATE_LIMITED) exit_with("spawn", ack.failure());
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

}  // namespace

LoadWorld spawn_world(const LoadTarget& target, const WorldOptions& options, unsigned parallel) {
  LoadWorld world;
  {
    client::Connection connection = connect_or_exit(target, "net_load-spawner");
    spawn(connection, ground());
    world.probe = spawn(connection, probe());
  }
  std::mutex ids_mutex;
  std::vector<std::thread> spawners;
  parallel = std::max(1u, std::min(parallel, options.bodies));
  for (unsigned k = 0; k < parallel; ++k) {
    spawners.emplace_back([&, k] {
      client::Connection connection = connect_or_exit(target, "net_load-spawner-" + std::to_string(k));
      for (unsigned i = k; i < options.bodies; i += parallel) {
        const BodySpec spec = options.layout == WorldLayout::cubes ? cube_body(options, i) : field_body(options, i);
        const std::uint32_t id = spawn(connection, spec);
        std::lock_guard lock(ids_mutex);
        world.bodies.push_back(id);
      }
    });
  }
  for (std::thread& spawner : spawners) spawner.join();
  std::sort(world.bodies.begin(), world.bodies.end());
  world.resting = options.bodies;
  if (options.layout == WorldLayout::field && options.moving > 0) {
    const auto spin_every = static_cast<unsigned>(std::lround(1 / options.moving));
    world.resting -= (options.bodies + spin_every - 1) / spin_every;  // i = 0, spin_every, 2 spin_every, ...
  }
  return world;
}

const char* layout_name(WorldLayout layout) { return layout == WorldLayout::cubes ? "cubes" : "field"; }

}  // namespace tumble::bench
