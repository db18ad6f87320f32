// hello_physics: a 1 m box dropped from 4 m onto the ground; prints the
// height of its centre once per simulated second.
#include <cstdio>

#include "tumble/physics/world.h"

int main() {
  namespace tp = tumble::physics;
  tp::World world;  // gravity (0, -9.81, 0): +Y is up
  tp::BodyDesc ground;
  ground.shape = tp::plane_shape(tp::Vec3::UnitY(), 0.0);  // the plane y = 0, solid below
  world.add_body(ground);
  tp::BodyDesc box;
  box.shape = tp::box_shape(tp::Vec3(0.5, 0.5, 0.5));                          // half extents (m)
  box.mass_properties = tp::box_mass_properties(2.0, box.shape.half_extents);  // 2 kg
  box.position = tp::Vec3(0.0, 4.0, 0.0);
  const tp::BodyId id = world.add_body(box);
  for (int step = 1; step <= 5 * 60; ++step) {
    world.step(1.0 / 60.0);
    if (step % 60 == 0) std::printf("t = %d s  y = %.4f m\n", step / 60, world.position(id).y());
  }
}
