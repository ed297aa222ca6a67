#include "bullet_run.hpp"

#include <btBulletDynamicsCommon.h>

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace lockstep::peer {
namespace {

// lockstep's material rules (eq 50: the smaller restitution; eq 58: the
// geometric mean of the frictions), so that a pair of materials means the same
// in both engines (Bullet's defaults multiply both).
btScalar combined_friction(const btCollisionObject* a, const btCollisionObject* b) {
  return std::sqrt(a->getFriction() * b->getFriction());
}
btScalar combined_restitution(const btCollisionObject* a, const btCollisionObject* b) {
  return std::min(a->getRestitution(), b->getRestitution());
}

}  // namespace

struct BulletRun::Impl {
  Scene scene;
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher{&config};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &config};
  std::unique_ptr<btBoxShape> floor;
  std::unique_ptr<btRigidBody> ground;
  std::vector<std::unique_ptr<btBoxShape>> shapes;
  std::vector<std::unique_ptr<btRigidBody>> bodies;
  std::vector<double> mass;
  std::vector<int> sleep_frame;
  int frame = 0;

  explicit Impl(const Scene& s, const BulletOptions& o) : scene(s) {
    if (!s.sdfs.empty()) throw std::invalid_argument("bullet: scene '" + s.name + "' has SDF volumes; BulletRun runs boxes and a ground plane only");
    gCalculateCombinedFrictionCallback = &combined_friction;
    gCalculateCombinedRestitutionCallback = &combined_restitution;
    const Constants& c = s.constants;
    const Effects& fx = s.effects;
    world.setGravity(fx.gravity ? btVector3(c.gravity.x, c.gravity.y, c.gravity.z) : btVector3(0, 0, 0));
    world.getSolverInfo().m_numIterations = o.solver_iterations;
    if (s.ground.present && fx.ground) {
      // The ground plane as the top face of a large static box, as Bullet's
      // own demos make a floor: box-box contacts get btBoxBoxDetector's full
      // manifold, where btStaticPlaneShape gets one point a frame (and then
      // stands 63 of peer_stacking_test's 100 columns instead of 86).
      floor = std::make_unique<btBoxShape>(btVector3(o.floor_half_extent, 1.0, o.floor_half_extent));
      floor->setMargin(o.margin);
      btRigidBody::btRigidBodyConstructionInfo info(0.0, nullptr, floor.get());
      info.m_startWorldTransform.setOrigin(btVector3(0, s.ground.height - 1.0, 0));
      ground = std::make_unique<btRigidBody>(info);
      ground->setFriction(fx.friction ? s.ground.material.friction : 0.0);
      ground->setRestitution(fx.restitution ? s.ground.material.restitution : 0.0);
      world.addRigidBody(ground.get());
    }
    for (const BodyDesc& b : s.bodies) {
      auto shape = std::make_unique<btBoxShape>(btVector3(b.half_extents.x, b.half_extents.y, b.half_extents.z));
      shape->setMargin(o.margin);
      const double m = b.is_static ? 0.0 : b.mass;
      btVector3 inertia(0, 0, 0);
      if (m > 0) shape->calculateLocalInertia(m, inertia);
      const Quatd& q = b.orientation;
      const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
      btTransform t(btQuaternion(q.x / n, q.y / n, q.z / n, q.w / n), btVector3(b.position.x, b.position.y, b.position.z));
      btRigidBody::btRigidBodyConstructionInfo info(m, nullptr, shape.get(), inertia);
      info.m_startWorldTransform = t;
      info.m_friction = fx.friction ? b.material.friction : 0.0;
      info.m_restitution = fx.restitution ? b.material.restitution : 0.0;
      if (fx.damping) {
        info.m_linearDamping = c.linear_damping;
        info.m_angularDamping = c.angular_damping;
      }
      auto body = std::make_unique<btRigidBody>(info);
      body->setLinearVelocity(btVector3(b.velocity.x, b.velocity.y, b.velocity.z));
      body->setAngularVelocity(btVector3(b.angular_velocity.x, b.angular_velocity.y, b.angular_velocity.z));
      if (!fx.sleep) body->setActivationState(DISABLE_DEACTIVATION);
      world.addRigidBody(body.get());
      shapes.push_back(std::move(shape));
      bodies.push_back(std::move(body));
      mass.push_back(m);
      sleep_frame.push_back(-1);
    }
  }

  ~Impl() {
    for (auto& b : bodies) world.removeRigidBody(b.get());
    if (ground) world.removeRigidBody(ground.get());
  }
};

BulletRun::BulletRun(const Scene& scene, const BulletOptions& options) : impl_(std::make_unique<Impl>(scene, options)) {}
BulletRun::~BulletRun() = default;

std::string BulletRun::description() const {
  return bullet_version() + ": btDiscreteDynamicsWorld, sequential impulses, " +
         std::to_string(impl_->world.getSolverInfo().m_numIterations) + " iterations";
}

void BulletRun::step() {
  impl_->world.stepSimulation(impl_->scene.constants.dt, 0);  // 0 sub-steps: exactly one step of dt
  ++impl_->frame;
  for (std::size_t i = 0; i < impl_->bodies.size(); ++i) {
    const bool asleep = impl_->bodies[i]->getActivationState() == ISLAND_SLEEPING;
    if (!asleep) impl_->sleep_frame[i] = -1;
    else if (impl_->sleep_frame[i] < 0) impl_->sleep_frame[i] = impl_->frame;
  }
}

int BulletRun::frame() const { return impl_->frame; }
int BulletRun::body_count() const { return static_cast<int>(impl_->bodies.size()); }

BodySnapshot BulletRun::body(int i) const {
  const btRigidBody& b = *impl_->bodies[static_cast<std::size_t>(i)];
  const btTransform& t = b.getWorldTransform();
  const btVector3& p = t.getOrigin();
  const btQuaternion q = t.getRotation();
  const btVector3& v = b.getLinearVelocity();
  const btVector3& w = b.getAngularVelocity();
  const int sf = impl_->sleep_frame[static_cast<std::size_t>(i)];
  return {{p.x(), p.y(), p.z()}, {q.w(), q.x(), q.y(), q.z()}, {v.x(), v.y(), v.z()}, {w.x(), w.y(), w.z()}, sf >= 0, sf};
}

std::uint64_t BulletRun::state_hash() const {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  auto mix = [&h](double x) {
    std::uint64_t u;
    std::memcpy(&u, &x, sizeof u);
    for (int k = 0; k < 8; ++k) {
      h ^= (u >> (8 * k)) & 0xffu;
      h *= 0x100000001b3ULL;
    }
  };
  for (int i = 0; i < body_count(); ++i) {
    const BodySnapshot s = body(i);
    for (double x : s.p) mix(x);
    for (double x : s.q) mix(x);
    for (double x : s.v) mix(x);
    for (double x : s.w) mix(x);
  }
  return h;
}

double BulletRun::energy() const {
  const Vec3d& g = impl_->scene.constants.gravity;
  double e = 0.0;
  for (std::size_t i = 0; i < impl_->bodies.size(); ++i) {
    if (impl_->mass[i] <= 0) continue;
    const btRigidBody& b = *impl_->bodies[i];
    const btVector3& v = b.getLinearVelocity();
    const btVector3& w = b.getAngularVelocity();
    const btVector3& p = b.getWorldTransform().getOrigin();
    const btVector3 wb = b.getWorldTransform().getBasis().transpose() * w;  // body-frame omega
    const btVector3& inv_i = b.getInvInertiaDiagLocal();
    double rot = 0.0;
    for (int a = 0; a < 3; ++a)
      if (inv_i[a] > 0) rot += wb[a] * wb[a] / inv_i[a];
    e += 0.5 * impl_->mass[i] * v.length2() + 0.5 * rot - impl_->mass[i] * (g.x * p.x() + g.y * p.y() + g.z * p.z());
  }
  return e;
}

std::string bullet_version() {
  return "Bullet " + std::to_string(btGetVersion() / 100) + "." + std::to_string(btGetVersion() % 100) +
         (btIsDoublePrecision() ? " (double)" : " (float)");
}

}  // namespace lockstep::peer
