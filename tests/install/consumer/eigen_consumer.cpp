// lockstep/eigen.hpp from an installed lockstep, with the consumer's own
// Eigen: a cube posed from an Eigen::Isometry3d (2 m up, turned 45 degrees
// about y), World<Q16>; prints the raycast down onto it (body, distance),
// the bodies containing its centre and its pose's height.
#include <cstdio>

#include "lockstep/eigen.hpp"
#include "lockstep/fixed/q16_vec.hpp"

int main() {
  lockstep::Scene scene;
  lockstep::BodyDesc cube;
  lockstep::eigen::set_pose(cube, Eigen::Translation3d(0, 2, 0) * Eigen::AngleAxisd(0.25 * 3.141592653589793, Eigen::Vector3d::UnitY()));
  scene.bodies.push_back(cube);
  const lockstep::World<lockstep::Q16> world(scene);
  const lockstep::eigen::RayHit hit =
      lockstep::eigen::raycast(world, Eigen::Vector3d(0, 10, 0), Eigen::Vector3d(0, -1, 0), 100.0);
  const std::vector<int> inside = lockstep::eigen::point_query(world, Eigen::Vector3d(0, 2, 0));
  const Eigen::Isometry3d pose = lockstep::eigen::poses(world)[0];
  std::printf("%d %.4f %zu %.4f\n", hit.body, hit.distance, inside.size(), pose.translation().y());
  return 0;
}
