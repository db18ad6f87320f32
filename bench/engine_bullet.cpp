// Bullet (Debian's libbullet-dev, single precision): btDiscreteDynamicsWorld
// with btDbvtBroadphase, btSequentialImpulseConstraintSolver (10
// iterations, Bullet's default) and btDefaultCollisionConfiguration, one
// step of kTimeStep per stepSimulation. Everything else is Bullet's default:
// warm starting, split impulse, ERP 0.2, and deactivation (sleeping) of
// bodies slower than 0.8 m/s and 1 rad/s for 2 s (unless EngineOptions turn
// sleeping off).
#include <btBulletDynamicsCommon.h>

#include <cmath>
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
      const Eigen::Quaterniond& q = body.orientation;
      info.m_startWorldTransform.setRotation(btQuaternion(static_cast<btScalar>(q.x()), static_cast<btScalar>(q.y()),
                                                          static_cast<btScalar>(q.z()), static_cast<btScalar>(q.w())));
      info.m_friction = kBodyFriction;
      dynamic_.push_back(std::make_unique<btRigidBody>(info));
      if (!options.sleeping) dynamic_.back()->setActivationState(DISABLE_DEACTIVATION);
      world_.addRigidBody(dynamic_.back().get());
    }
  }

  // The world's destructor reaches into the bodies still in it; take them
  // out while they exist.
  ~BulletEngine() override {
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
  btDiscreteDynamicsWorld world_{&dispatcher_, &broadphase_, &solver_, &configuration_};
};

}  // namespace

std::unique_ptr<Engine> make_bullet_engine(const Scene& scene, const EngineOptions& options) {
  return std::make_unique<BulletEngine>(scene, options);
}

}  // namespace tumble::bench
