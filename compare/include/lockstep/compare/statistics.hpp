// Statistics of a pile at one frame: what must still agree between engines
// once a chaotic scene's trajectories have parted (Judge::statistics).
#pragma once
#include <map>
#include <string>
#include <vector>

#include "lockstep/compare/engine.hpp"
#include "lockstep/compare/tolerances.hpp"
#include "lockstep/scene.hpp"

namespace lockstep::compare {

struct PileStatistics {
  int bodies = 0;                        // dynamic bodies counted
  std::vector<double> heights;           // p_y of each body, ascending (m)
  std::map<long, int> height_histogram;  // bin floor(p_y / height_bin) -> count
  std::map<std::string, int> faces;      // face-up label (face_up) -> count
  int asleep = 0;
  int median_sleep_frame = -1;           // over the bodies asleep (lower median); -1 if none
  double mean_height = 0;                // mean p_y (m)
};

// Over the scene's dynamic bodies.
PileStatistics pile_statistics(const Scene& scene, const std::vector<BodySnapshot>& bodies, const CompareTolerances& t);

// Earth mover's (Wasserstein-1) distance between two height distributions
// of the same size: mean |a[k] - b[k]| over the sorted values (m); the
// distributions' sizes must match (std::invalid_argument otherwise).
double height_distance(const std::vector<double>& sorted_a, const std::vector<double>& sorted_b);

// The largest |count_a - count_b| over all labels in either map.
int max_count_difference(const std::map<std::string, int>& a, const std::map<std::string, int>& b, std::string* label);

}  // namespace lockstep::compare
