// A body's resting state, read from its pose (in double): which face is up,
// how well it is aligned, and what it rests on. The harness compares these
// between engines at the final frame.
#pragma once
#include <string>
#include <vector>

#include "lockstep/compare/engine.hpp"
#include "lockstep/scene.hpp"

namespace lockstep::compare {

// The body axis pointing most nearly up (eq 65 with its sign): "+x", "-x",
// "+y", "-y", "+z", "-z"; "none" when the alignment (eq 66) is at most
// flat_alignment (the body stands on an edge or a corner).
struct FaceUp {
  std::string label;
  double alignment = 0;  // eq 66 (1)
};
FaceUp face_up(const double q[4], double flat_alignment);

// The angle between two orientations (rad), in [0, pi]: 2 atan2(|vec(r)|, |w(r)|)
// with r = conj(a) * b, both normalised first (Q16 quaternions are unit only to
// within their rounding).
double orientation_angle(const double a[4], const double b[4]);

// One thing a body can rest on: the ground, another body or an SDF volume.
struct Support {
  enum Kind { ground, sdf, body } kind = ground;
  int index = -1;  // body index or SDF index
  std::string label() const;  // "ground", "sdf 0", "body 3"
  auto operator<=>(const Support&) const = default;
};

// Everything a body rests on, in the order ground, SDFs, bodies (by index):
// "ground", "body 5 + body 6" (a pyramid's upper cube), "none".
std::string supports_label(const std::vector<Support>& supports);

struct RestingState {
  double p[3];
  FaceUp face;
  std::vector<Support> supports;  // sorted; empty: rests on nothing
  bool asleep = false;
  double lowest = 0;  // y of the body's lowest point (m)
};

// The resting states of all bodies of a scene from one engine's snapshots.
// A body rests on every surface within support_gap of its lowest point: the
// ground plane; an SDF volume whose distance (eq 33) at one of the body's
// corners is within the gap; a lower body whose AABB (eq 31) top is within the
// gap and whose footprint (x-z extent) overlaps the body's.
std::vector<RestingState> resting_states(const Scene& scene, const std::vector<BodySnapshot>& bodies, double support_gap,
                                         double flat_alignment);

}  // namespace lockstep::compare
