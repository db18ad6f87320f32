// ODE (Debian's libode-dev, double precision): dWorldQuickStep with 10
// iterations, a hash space, and one contact joint per contact point (up to 4
// per pair, like Bullet's and tumble's manifolds) with Coulomb friction 0.5
// (dContactApprox1: a friction pyramid whose limit is mu times the normal
// force, which makes mu a friction coefficient as in the other engines).
//
// Everything else is ODE's default: global ERP 0.2 and CFM 1e-10 (every
// contact joint uses them), no contact surface layer, no limit on the
// correcting velocity, successive over-relaxation 1.3, and auto-disable
// (sleeping, switched on here unless EngineOptions turn sleeping off) of
// bodies slower than 0.01 m/s and 0.01 rad/s for 10 steps.
//
// Joints: a ball joint is dJointCreateBall, without its cone (ODE's ball
// joint has no cone limit); a hinge is dJointCreateHinge with dParamLoStop
// and dParamHiStop. Both use the global ERP and CFM. Bodies a joint
// connects are not collided.
#include <ode/ode.h>

#include <cstddef>
#include <vector>

#include "engine.h"

namespace tumble::bench {
namespace {

// dInitODE2 once per process, dCloseODE at exit.
class OdeLibrary {
 public:
  OdeLibrary() { dInitODE2(0); }
  ~OdeLibrary() { dCloseODE(); }
  OdeLibrary(const OdeLibrary&) = delete;
  OdeLibrary& operator=(const OdeLibrary&) = delete;
};

void ensure_ode_initialised() { static const OdeLibrary library; }

constexpr int kMaxContactsPerPair = 4;

class OdeEngine final : public Engine {
 public:
  OdeEngine(const Scene& scene, const EngineOptions& options) {
    ensure_ode_initialised();
    // QuickStep shuffles the constraint order with ODE's global generator;
    // reseed it so every world of a scene runs the same way.
    dRandSetSeed(1);
    world_ = dWorldCreate();
    dWorldSetGravity(world_, 0, -kGravity, 0);
    dWorldSetQuickStepNumIterations(world_, kSolverIterations);
    dWorldSetAutoDisableFlag(world_, options.sleeping ? 1 : 0);
    space_ = dHashSpaceCreate(nullptr);
    contacts_ = dJointGroupCreate(0);

    dCreatePlane(space_, 0, 1, 0, 0);  // y = 0, solid below; owned by the space
    for (const StaticBox& wall : scene.walls) {
      // A geom without a body is static.
      const dGeomID box =
          dCreateBox(space_, 2 * wall.half_extents.x(), 2 * wall.half_extents.y(), 2 * wall.half_extents.z());
      dGeomSetPosition(box, wall.position.x(), wall.position.y(), wall.position.z());
    }

    bodies_.reserve(scene.bodies.size());
    for (const DynamicBody& body : scene.bodies) {
      const dBodyID id = dBodyCreate(world_);
      dMass mass;
      dMassSetZero(&mass);
      dMassSetParameters(&mass, body.mass, 0, 0, 0, body.inertia.x(), body.inertia.y(), body.inertia.z(), 0, 0, 0);
      dBodySetMass(id, &mass);
      dBodySetPosition(id, body.position.x(), body.position.y(), body.position.z());
      const dQuaternion orientation = {body.orientation.w(), body.orientation.x(), body.orientation.y(),
                                       body.orientation.z()};  // ODE: [w, x, y, z]
      dBodySetQuaternion(id, orientation);
      const dGeomID geom =
          body.shape == BodyShape::box
              ? dCreateBox(space_, 2 * body.half_extents.x(), 2 * body.half_extents.y(), 2 * body.half_extents.z())
              : dCreateSphere(space_, body.radius);
      dGeomSetBody(geom, id);
      bodies_.push_back(id);
    }

    for (const SceneJoint& joint : scene.joints) {
      // ODE's hinge angle is that of its first body relative to its second:
      // body_b goes first, so the angle is body_b's relative to body_a as
      // the scene has it. A null second body is the world.
      const dBodyID child = bodies_[static_cast<std::size_t>(joint.body_b)];
      const dBodyID parent = joint.body_a == kWorld ? nullptr : bodies_[static_cast<std::size_t>(joint.body_a)];
      const Vec3& p = joint.anchor;
      if (joint.type == JointType::hinge) {
        const dJointID hinge = dJointCreateHinge(world_, nullptr);
        dJointAttach(hinge, child, parent);
        dJointSetHingeAnchor(hinge, p.x(), p.y(), p.z());
        dJointSetHingeAxis(hinge, joint.axis.x(), joint.axis.y(), joint.axis.z());
        dJointSetHingeParam(hinge, dParamLoStop, joint.lower);
        dJointSetHingeParam(hinge, dParamHiStop, joint.upper);
      } else {
        const dJointID ball = dJointCreateBall(world_, nullptr);
        dJointAttach(ball, child, parent);
        dJointSetBallAnchor(ball, p.x(), p.y(), p.z());
      }
    }
  }

  // The space destroys its geoms; the world its bodies and joints.
  ~OdeEngine() override {
    dJointGroupDestroy(contacts_);
    dSpaceDestroy(space_);
    dWorldDestroy(world_);
  }

  OdeEngine(const OdeEngine&) = delete;
  OdeEngine& operator=(const OdeEngine&) = delete;

  void step() override {
    dSpaceCollide(space_, this, &OdeEngine::near_callback);
    dWorldQuickStep(world_, kTimeStep);
    dJointGroupEmpty(contacts_);
  }

  void read_poses(std::vector<Pose>& poses) const override {
    poses.resize(bodies_.size());
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
      const dReal* x = dBodyGetPosition(bodies_[i]);
      const dReal* q = dBodyGetQuaternion(bodies_[i]);  // w, x, y, z
      poses[i].position = Vec3(x[0], x[1], x[2]);
      poses[i].orientation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
    }
  }

  std::size_t awake_count() const override {
    std::size_t count = 0;
    for (const dBodyID body : bodies_) count += dBodyIsEnabled(body) ? 1u : 0u;
    return count;
  }

 private:
  // Called by dSpaceCollide for each pair of geoms whose boxes overlap: adds
  // a contact joint per contact point for this step.
  static void near_callback(void* data, dGeomID a, dGeomID b) {
    auto* self = static_cast<OdeEngine*>(data);
    const dBodyID body_a = dGeomGetBody(a);
    const dBodyID body_b = dGeomGetBody(b);
    // Nothing can move: both sides disabled (asleep) or static.
    const bool a_moves = body_a != nullptr && dBodyIsEnabled(body_a);
    const bool b_moves = body_b != nullptr && dBodyIsEnabled(body_b);
    if (!a_moves && !b_moves) return;
    // Joined by a joint (this step's contact joints aside).
    if (body_a != nullptr && body_b != nullptr && dAreConnectedExcluding(body_a, body_b, dJointTypeContact)) return;

    dContact contact[kMaxContactsPerPair] = {};
    const int count = dCollide(a, b, kMaxContactsPerPair, &contact[0].geom, sizeof(dContact));
    for (int i = 0; i < count; ++i) {
      contact[i].surface.mode = dContactApprox1;
      contact[i].surface.mu = kFriction;
      const dJointID joint = dJointCreateContact(self->world_, self->contacts_, &contact[i]);
      dJointAttach(joint, body_a, body_b);
    }
  }

  dWorldID world_ = nullptr;
  dSpaceID space_ = nullptr;
  dJointGroupID contacts_ = nullptr;  // this step's contact joints
  std::vector<dBodyID> bodies_;       // scene.bodies, in order
};

}  // namespace

std::unique_ptr<Engine> make_ode_engine(const Scene& scene, const EngineOptions& options) {
  return std::make_unique<OdeEngine>(scene, options);
}

}  // namespace tumble::bench
