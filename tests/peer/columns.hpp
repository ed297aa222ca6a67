// The harder family of perturbed columns (issue 12) and the rules a column
// must keep to stand, judged on body snapshots so that lockstep's engines and
// Bullet are judged by the same code.
//
// A column: 2-10 cubes of one size in 0.25-1 m, masses 0.5-2 kg, each tilted
// by up to 2 degrees about a random axis, shifted by up to 10 % of the size in
// x and in z, and dropped by up to 0.3 m onto the one below (the first onto
// the ground): its lowest corner starts that far above the highest corner of
// the cube below, so no two cubes start touching and the starting energy
// bounds every later one. Friction 0.5, restitution 0.2 everywhere.
//
// It stands when, at the last frame, every cube is within 2 cm of its ideal
// stacked height (size/2 + k size for the k-th lowest) and within half the
// size of the column's mean axis, every cube is asleep, and at no frame did a
// sleeping cube hang over a gap of more than 1 cm (nothing, ground or cube,
// within 1 cm below it).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "lockstep/compare/engine.hpp"
#include "lockstep/scene.hpp"

namespace lockstep::peer {

inline constexpr double kHeightTolerance = 0.02;  // m, from the ideal stacked height
inline constexpr double kSleepGap = 0.01;         // m, the most a sleeper may hang above its support

struct Column {
  int index = 0;
  double size = 1.0;  // edge length (m), the same for every cube of the column
  Scene scene;        // frames = 600
};

// The seed of peer_stacking_test's columns ("peers").
inline constexpr std::uint64_t kPeerColumnSeed = 0x7065657273ULL;

// `count` columns from `seed` (SplitMix64; the same columns on every run).
std::vector<Column> harder_columns(int count, std::uint64_t seed);

struct ColumnResult {
  bool stands = false;
  std::string why;                 // the first rule broken, "" when it stands
  double worst_sleeping_gap = 0;   // m, over all frames
  int gap_frame = -1;              // first frame a sleeper hung over more than kSleepGap (-1: never)
  double energy_start = 0;         // J, kinetic + rotational + gravitational at frame 0
  double energy_gain = 0;          // J, max over frames 1..N of E - energy_start (negative: only lost)
  int gain_frame = -1;             // the frame of that maximum
  double rebound = 0;              // J, max over frames of E - (the least E of the frames before): energy regained
  int rebound_frame = -1;          // the frame of that maximum
  int all_asleep_frame = -1;       // first frame at which every cube was asleep (-1: never)
};

// Steps `engine` (built on c.scene) c.scene.frames times and judges it.
ColumnResult run_column(EngineRun& engine, const Column& c);

// Kinetic + rotational + gravitational energy (J) of the engine's bodies,
// from their snapshots and the scene's masses (the same formula for every engine).
double snapshot_energy(const EngineRun& engine, const Scene& scene);

// The largest gap (m) below a sleeping cube this frame: for each sleeper, the
// least of its lowest corner's height above the ground and its separation from
// every cube whose centre is lower (0 when none sleeps).
double worst_sleeping_gap(const EngineRun& engine, const Scene& scene);

}  // namespace lockstep::peer
