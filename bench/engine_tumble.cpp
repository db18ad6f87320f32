// tumble's own engine, with its default WorldSettings (sleeping on unless
// EngineOptions say otherwise). Joints are tumble's own (joint.h), with
// their defaults: the bodies they connect do not collide.
#include <cstddef>
#include <vector>

#include "engine.h"
#include "tumble/physics/mass_properties.h"
#include "tumble/physics/world.h"

namespace tumble::bench {
namespace {

namespace tp = tumble::physics;

class TumbleEngine final : public Engine {
 public:
  TumbleEngine(const Scene& scene, const EngineOptions& options) {
    tp::WorldSettings settings;
    settings.sleep_enabled = options.sleeping;
    world_.set_settings(settings);
    world_.set_thread_count(options.tumble_threads);
    world_.set_gravity(tp::Vec3(0.0, -kGravity, 0.0));

    tp::BodyDesc ground;
    ground.shape = tp::plane_shape(tp::Vec3::UnitY(), 0.0);
    ground.friction = kFriction;
    world_.add_body(ground);

    for (const StaticBox& wall : scene.walls) {
      tp::BodyDesc desc;
      desc.shape = tp::box_shape(wall.half_extents);
      desc.motion_type = tp::MotionType::static_body;
      desc.position = wall.position;
      desc.friction = kFriction;
      world_.add_body(desc);
    }

    ids_.reserve(scene.bodies.size());
    for (const DynamicBody& body : scene.bodies) {
      tp::BodyDesc desc;
      desc.shape = body.shape == BodyShape::box ? tp::box_shape(body.half_extents) : tp::sphere_shape(body.radius);
      desc.mass_properties.mass = body.mass;
      desc.mass_properties.inertia = body.inertia.asDiagonal();
      desc.position = body.position;
      desc.orientation = body.orientation;
      desc.friction = kFriction;  // combined as sqrt(f_a f_b) = 0.5
      ids_.push_back(world_.add_body(desc));
    }

    for (const SceneJoint& joint : scene.joints) {
      tp::JointDesc desc;
      desc.type = joint.type == JointType::ball ? tp::JointType::ball : tp::JointType::hinge;
      desc.body_a = joint.body_a == kWorld ? tp::kWorldBodyId : ids_[static_cast<std::size_t>(joint.body_a)];
      desc.body_b = ids_[static_cast<std::size_t>(joint.body_b)];
      // Both frames at the anchor with their x axes along the joint's axis.
      world_.set_joint_frames(desc, joint.anchor, joint.anchor, joint.axis);
      desc.cone_limit = joint.cone;
      if (joint.type == JointType::hinge) {
        desc.limits_enabled = true;
        desc.lower = joint.lower;
        desc.upper = joint.upper;
      }
      world_.add_joint(desc);
    }
  }

  void step() override { world_.step(kTimeStep); }

  void read_poses(std::vector<Pose>& poses) const override {
    poses.resize(ids_.size());
    for (std::size_t i = 0; i < ids_.size(); ++i) poses[i] = {world_.position(ids_[i]), world_.orientation(ids_[i])};
  }

  std::size_t awake_count() const override { return world_.awake_body_count(); }

 private:
  tp::World world_;
  std::vector<tp::BodyId> ids_;  // of scene.bodies, in order
};

}  // namespace

std::unique_ptr<Engine> make_tumble_engine(const Scene& scene, const EngineOptions& options) {
  return std::make_unique<TumbleEngine>(scene, options);
}

}  // namespace tumble::bench
