// Bullet (btDiscreteDynamicsWorld) behind lockstep's EngineRun interface, so
// that the peer tests and peer_bench drive it exactly like lockstep's engines:
// the same Scene (boxes, ground, gravity, damping, dt, materials), one
// stepSimulation(dt, 0) per frame (one fixed step, no interpolation), body
// snapshots in double. Built only when Bullet is found (tests/peer/CMakeLists.txt).
#pragma once
#include <memory>
#include <string>

#include "lockstep/compare/engine.hpp"

namespace lockstep::peer {

struct BulletOptions {
  int solver_iterations = 10;  // Bullet's default (btContactSolverInfo::m_numIterations)
  double margin = 0.001;       // box collision margin (m); Bullet keeps the outer half extents
  double floor_half_extent = 100.0;  // (m) the ground: the top face of a static box 2 m thick
};

class BulletRun final : public EngineRun {
 public:
  explicit BulletRun(const Scene& scene, const BulletOptions& options = {});
  ~BulletRun() override;
  BulletRun(const BulletRun&) = delete;
  BulletRun& operator=(const BulletRun&) = delete;

  std::string name() const override { return "bullet"; }
  std::string description() const override;
  void step() override;
  int frame() const override;
  int body_count() const override;
  BodySnapshot body(int i) const override;
  std::uint64_t state_hash() const override;  // FNV-1a 64 over the IEEE bits of p, q, v, w
  double energy() const override;             // (J) kinetic + rotational + gravitational
  StageCounters counters() const override { return {}; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// "Bullet 3.24 (double)" or "(float)": the library and precision linked.
std::string bullet_version();

}  // namespace lockstep::peer
