#include "lockstep/compare/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

#include "lockstep/compare/resting.hpp"

namespace lockstep::compare {

PileStatistics pile_statistics(const Scene& scene, const std::vector<BodySnapshot>& bodies, const CompareTolerances& t) {
  PileStatistics s;
  std::vector<int> sleep_frames;
  double sum = 0;
  for (std::size_t i = 0; i < bodies.size() && i < scene.bodies.size(); ++i) {
    if (scene.bodies[i].is_static) continue;
    const BodySnapshot& b = bodies[i];
    ++s.bodies;
    sum += b.p[1];
    s.heights.push_back(b.p[1]);
    ++s.height_histogram[static_cast<long>(std::floor(b.p[1] / t.height_bin))];
    ++s.faces[face_up(b.q, t.flat_alignment).label];
    if (b.asleep) {
      ++s.asleep;
      sleep_frames.push_back(b.sleep_frame);
    }
  }
  if (s.bodies > 0) s.mean_height = sum / s.bodies;
  std::sort(s.heights.begin(), s.heights.end());
  if (!sleep_frames.empty()) {
    std::sort(sleep_frames.begin(), sleep_frames.end());
    s.median_sleep_frame = sleep_frames[(sleep_frames.size() - 1) / 2];
  }
  return s;
}

double height_distance(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) throw std::invalid_argument("height_distance: the distributions differ in size");
  if (a.empty()) return 0;
  double sum = 0;
  for (std::size_t k = 0; k < a.size(); ++k) sum += std::fabs(a[k] - b[k]);
  return sum / static_cast<double>(a.size());
}

int max_count_difference(const std::map<std::string, int>& a, const std::map<std::string, int>& b, std::string* label) {
  int worst = 0;
  auto visit = [&](const std::string& key) {
    const auto ia = a.find(key), ib = b.find(key);
    const int d = std::abs((ia == a.end() ? 0 : ia->second) - (ib == b.end() ? 0 : ib->second));
    if (d > worst) {
      worst = d;
      if (label) *label = key;
    }
  };
  for (const auto& kv : a) visit(kv.first);
  for (const auto& kv : b) visit(kv.first);
  return worst;
}

}  // namespace lockstep::compare
