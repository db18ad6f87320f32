// Bullet (Debian's libbullet-dev, single precision): btDiscreteDynamicsWorld
// with btDbvtBroadphase, btSequentialImpulseConstraintSolver (10
// iterations, Bullet's default) and btDefaultCollisionConfiguration, one
// step of kTimeStep per stepSimulation. Everything else is Bullet's default:
// warm starting, split impulse, ERP 0.2, and deactivation (sleeping) of
// bodies slower than 0.8 m/s and 1 rad/s for 2 s (unless EngineOptions turn
// sleeping off).
//
// Joints: a ball joint is a btPoint2PointConstraint, or with a cone a
// btConeTwistConstraint (the cone's two swing spans equal, the twist left
// free); a hinge is a btHingeConstraint with setLimit. Each with Bullet's
// defaults, and added with disableCollisionsBetweenLinkedBodies.
#include <btBulletDynamicsCommon.h>

#include <cmath>
#include <cstddef>
#include <memory>
#include <vector>

#include "engine.h"

namespace tumble::bench {
namespace {

btVector3 to_bt(const Vec3& v) {
  return btVector3(static_cast<btScalar>(v.x()), static_cast<btScalar>(v.y()), static_cast<btScalar>(v.z()));
}

// Bullet combines the friction of a contact's two bodies as the product
// f_a f_b; giving every body sqrt(0.5) makes every contact's friction 0.5,
// like tumble (sqrt(f_a f_b)) and ODE (set per contact).
const btScalar kBodyFriction = static_cast<btScalar>(std::sqrt(kFriction));

btQuaternion to_bt(const Eigen::Quaterniond& q) {
  return btQuaternion(static_cast<btScalar>(q.x()), static_cast<btScalar>(q.y()), static_cast<btScalar>(q.z()),
                      static_cast<btScalar>(q.w()));
}

// A joint's frame on one of its bodies (kWorld: on the world), in that
// body's frame at its starting pose: origin at the anchor, and the basis
// that turns frame_axis into the joint's axis (the hinge's z, the cone's x).
btTransform joint_frame(const Scene& scene, int body, const SceneJoint& joint, const Vec3& frame_axis) {
  const Eigen::Quaterniond basis = Eigen::Quaterniond::FromTwoVectors(frame_axis, joint.axis);
  if (body == kWorld) return btTransform(to_bt(basis), to_bt(joint.anchor));
  const DynamicBody& on = scene.bodies[static_cast<std::size_t>(body)];
  return btTransform(to_bt(on.orientation.conjugate() * basis), to_bt(body_point(on, joint.anchor)));
}

class BulletEngine final : public Engine {
 public:
  BulletEngine(const Scene& scene, const EngineOptions& options) {
    world_.setGravity(btVector3(0, static_cast<btScalar>(-kGravity), 0));
    world_.getSolverInfo().m_numIterations = kSolverIterations;

    add_static(std::make_unique<btStaticPlaneShape>(btVector3(0, 1, 0), btScalar(0)), Vec3::Zero());
    for (const StaticBox& wall : scene.walls) {
      add_static(std::make_unique<btBoxShape>(to_bt(wall.half_extents)), wall.position);
    }

    dynamic_.reserve(scene.bodies.size());
    for (const DynamicBody& body : scene.bodies) {
      btCollisionShape* shape = shared_shape(body);
      btRigidBody::btRigidBodyConstructionInfo info(static_cast<btScalar>(body.mass), nullptr, shape,
                                                    to_bt(body.inertia));
      info.m_startWorldTransform.setOrigin(to_bt(body.position));
      info.m_startWorldTransform.setRotation(to_bt(body.orientation));
      info.m_friction = kBodyFriction;
      dynamic_.push_back(std::make_unique<btRigidBody>(info));
      if (!options.sleeping) dynamic_.back()->setActivationState(DISABLE_DEACTIVATION);
      world_.addRigidBody(dynamic_.back().get());
    }

    for (const SceneJoint& joint : scene.joints) add_joint(scene, joint);
  }

  // The world's destructor reaches into the bodies and constraints still in
  // it; take them out while they exist.
  ~BulletEngine() override {
    for (auto& joint : joints_) world_.removeConstraint(joint.get());
    for (auto& body : dynamic_) world_.removeRigidBody(body.get());
    for (auto& body : static_) world_.removeRigidBody(body.get());
  }

  BulletEngine(const BulletEngine&) = delete;
  BulletEngine& operator=(const BulletEngine&) = delete;

  // maxSubSteps 0: exactly one internal step of kTimeStep, no interpolation.
  void step() override { world_.stepSimulation(static_cast<btScalar>(kTimeStep), 0); }

  void read_poses(std::vector<Pose>& poses) const override {
    poses.resize(dynamic_.size());
    for (std::size_t i = 0; i < dynamic_.size(); ++i) {
      const btTransform& t = dynamic_[i]->getWorldTransform();
      const btVector3& x = t.getOrigin();
      const btQuaternion q = t.getRotation();
      poses[i].position = Vec3(x.x(), x.y(), x.z());
      poses[i].orientation = Eigen::Quaterniond(q.w(), q.x(), q.y(), q.z());
    }
  }

  std::size_t awake_count() const override {
    std::size_t count = 0;
    for (const auto& body : dynamic_) count += body->isActive() ? 1u : 0u;
    return count;
  }

 private:
  // One collision shape per distinct size, shared by the bodies of that size
  // as Bullet intends.
  btCollisionShape* shared_shape(const DynamicBody& body) {
    for (const SharedShape& known : shapes_) {
      if (known.shape == body.shape && known.half_extents == body.half_extents && known.radius == body.radius) {
        return known.collision.get();
      }
    }
    std::unique_ptr<btCollisionShape> collision;
    if (body.shape == BodyShape::box) {
      collision = std::make_unique<btBoxShape>(to_bt(body.half_extents));
    } else {
      collision = std::make_unique<btSphereShape>(static_cast<btScalar>(body.radius));
    }
    shapes_.push_back({body.shape, body.half_extents, body.radius, std::move(collision)});
    return shapes_.back().collision.get();
  }

  // Bullet's hinge angle is that of its rbA relative to its rbB: body_b
  // goes first, so the angle is body_b's relative to body_a as the scene
  // has it. The world is Bullet's fixed body.
  void add_joint(const Scene& scene, const SceneJoint& joint) {
    btRigidBody& child = *dynamic_[static_cast<std::size_t>(joint.body_b)];
    btRigidBody& parent =
        joint.body_a == kWorld ? btTypedConstraint::getFixedBody() : *dynamic_[static_cast<std::size_t>(joint.body_a)];
    std::unique_ptr<btTypedConstraint> constraint;
    if (joint.type == JointType::hinge) {
      auto hinge =
          std::make_unique<btHingeConstraint>(child, parent, joint_frame(scene, joint.body_b, joint, Vec3::UnitZ()),
                                              joint_frame(scene, joint.body_a, joint, Vec3::UnitZ()));
      hinge->setLimit(static_cast<btScalar>(joint.lower), static_cast<btScalar>(joint.upper));
      constraint = std::move(hinge);
    } else if (std::isfinite(joint.cone)) {
      auto cone =
          std::make_unique<btConeTwistConstraint>(child, parent, joint_frame(scene, joint.body_b, joint, Vec3::UnitX()),
                                                  joint_frame(scene, joint.body_a, joint, Vec3::UnitX()));
      // A twist span of pi never binds: the twist is free, as in tumble's
      // ball joint.
      cone->setLimit(static_cast<btScalar>(joint.cone), static_cast<btScalar>(joint.cone), SIMD_PI);
      constraint = std::move(cone);
    } else {
      constraint = std::make_unique<btPoint2PointConstraint>(
          child, parent, joint_frame(scene, joint.body_b, joint, Vec3::UnitX()).getOrigin(),
          joint_frame(scene, joint.body_a, joint, Vec3::UnitX()).getOrigin());
    }
    world_.addConstraint(constraint.get(), /*disableCollisionsBetweenLinkedBodies=*/true);
    joints_.push_back(std::move(constraint));
  }

  void add_static(std::unique_ptr<btCollisionShape> shape, const Vec3& position) {
    btRigidBody::btRigidBodyConstructionInfo info(0, nullptr, shape.get());
    info.m_startWorldTransform.setOrigin(to_bt(position));
    info.m_friction = kBodyFriction;
    static_.push_back(std::make_unique<btRigidBody>(info));
    world_.addRigidBody(static_.back().get());
    static_shapes_.push_back(std::move(shape));
  }

  // A shape of the dynamic bodies and the size it was made for.
  struct SharedShape {
    BodyShape shape;
    Vec3 half_extents;
    double radius;
    std::unique_ptr<btCollisionShape> collision;
  };

  // Declared before the world so they outlive it.
  btDefaultCollisionConfiguration configuration_;
  btCollisionDispatcher dispatcher_{&configuration_};
  btDbvtBroadphase broadphase_;
  btSequentialImpulseConstraintSolver solver_;
  std::vector<SharedShape> shapes_;
  std::vector<std::unique_ptr<btCollisionShape>> static_shapes_;
  std::vector<std::unique_ptr<btRigidBody>> dynamic_;  // scene.bodies, in order
  std::vector<std::unique_ptr<btRigidBody>> static_;   // ground and walls
  std::vector<std::unique_ptr<btTypedConstraint>> joints_;
  btDiscreteDynamicsWorld world_{&dispatcher_, &broadphase_, &solver_, &configuration_};
};

}  // namespace

std::unique_ptr<Engine> make_bullet_engine(const Scene& scene, const EngineOptions& options) {
  return std::make_unique<BulletEngine>(scene, options);
}

}  // namespace tumble::bench
