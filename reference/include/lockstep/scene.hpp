// A scene: everything a run needs, independent of the number type. Values are
// doubles; a value the JSON gives as raw Q16.16 ({"raw": R}) is stored as the
// exact double R / 2^16, so every engine (and Q16 bit for bit) sees it exactly.
// The JSON format is documented in docs/SCENES.md; validation in scene_json.hpp.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace lockstep {

struct Vec3d { double x = 0, y = 0, z = 0; };
struct Quatd { double w = 1, x = 0, y = 0, z = 0; };

// Surface material (Jolt style: unit and range on every field).
struct Material {
  double restitution = 0.2;  // e (1), [0, 1]; eq 50 takes the min of the two
  double friction = 0.5;     // mu (1), [0, 4]; eq 58 takes the geometric mean
};

struct BodyDesc {
  Vec3d half_extents{0.5, 0.5, 0.5};  // h (m), each in [2^-8, 1024] (Q16.16)
  double mass = 1.0;                  // m (kg), (0, 10000]; ignored when is_static
  Vec3d position;                     // p (m), |p_i| < 32768 (Q16.16)
  Quatd orientation;                  // q (1), any non-zero quaternion; normalised (eq 10) on load
  Vec3d velocity;                     // v (m/s)
  Vec3d angular_velocity;             // omega (rad/s), world frame
  Material material;
  bool is_static = false;             // never moves; infinite mass
  bool asleep = false;                // starts asleep (5.1 wakes it)
};

struct GroundDesc {
  bool present = true;
  double height = 0.0;  // plane y = height (m)
  Material material;
};

// Static SDF volume (source 2.3): samples on a regular grid over [min, max].
struct SdfDesc {
  std::string name;
  Vec3d min, max;                // bounds (m), max > min on every axis
  int nx = 2, ny = 2, nz = 2;    // resolution, each >= 2
  std::vector<double> values;    // d (m), index i + nx * (j + ny * k), positive outside the solid
  Material material;
};

// The effects a scene calls for (only these stages run; spec 7.2).
struct Effects {
  bool gravity = true;       // eq 5
  bool damping = true;       // eqs 6, 13
  bool ground = true;        // eqs 44-46 refined by 84, 97 against the ground plane
  bool contacts = true;      // body-body: broadphase 6.1 (82-83) and eqs 38-43, 85, 97
  bool friction = true;      // eqs 56-62, 88, 95
  bool restitution = true;   // eqs 50, 53 with e > 0 and (76)
  bool settling = true;      // eqs 64-74 and 4.4-4.6
  bool sleep = true;         // 4.7, 5.1
  bool sdf = true;           // eqs 32-37, 93, 97 (needs SDF volumes)
};

// Appendix A: every constant, overridable per scene. Q16.16 raw values are in
// docs/SPEC.md Appendix A.
struct Constants {
  double dt = 1.0 / 60.0;               // (s) 7.1; Q16.16 raw 1092
  Vec3d gravity{0.0, -9.81, 0.0};       // g (m/s^2) eq 5
  double linear_damping = 0.005;        // lambda_v (1/s) eq 6
  double angular_damping = 0.02;        // lambda_w (1/s) eq 13
  double cell_size = 4.0;               // (m) eq 25
  double slop = 0.001;                  // (m) eq 63
  double baumgarte = 1.0;               // percent (1) eq 63
  int solver_iterations = 8;            // sequential-impulse passes (7.2), alternating direction
  double contact_tolerance = 0.01;      // (m) points this close to touching are (speculative) contacts (84, 97)
  double converged_speed = 0.0;         // (m/s, rad/s) eq 113: a solver visit whose sides move less is converged; 0 (default): every pass in full
  double kp = 30.0;                     // (rad/s) eq 69
  double kd = 10.0;                     // (1/s) eq 71
  double speed_factor_min = 0.5;        // eq 69
  double speed_factor_max = 2.0;        // eq 69
  double support_normal_min = 0.7;      // n.up above this is a support contact (settling)
  double align_fine = 0.998;            // eq 72
  double align_good = 0.99;             // eq 73
  double align_fair = 0.95;             // eq 74
  double damp_fine = 0.4;               // eq 72
  double damp_good = 0.7;               // eq 73
  double damp_fair = 0.85;              // eq 74
  double rest_speed = 0.2;              // (m/s) 4.4, eq 75
  double restitution_min_speed = 0.5;   // (m/s) 4.5, eq 76
  double settle_speed = 0.3;            // (m/s) 4.6, eq 77
  double settle_damping = 0.1;          // (1) 4.6, eq 77
  double sleep_linear = 0.05;           // (m/s) 4.7, eq 78
  double sleep_angular = 0.05;          // (rad/s) 4.7, eq 78
  double sleep_alignment = 0.99;        // 4.7, eq 78
  int drowsy_frames = 10;               // 4.7, eq 79
  double drowsy_damping = 0.5;          // 4.7, eq 79
  int sleep_frames = 30;                // 4.7, eq 80
  double wake_speed = 0.25;             // (m/s) 5.1, eq 81; above g*dt = 0.1635 so a resting neighbour does not wake a sleeper
  double wake_penetration = 0.02;       // (m) 5.1, eq 81
  double wake_support_distance = 0.005; // (m) 5.1, eq 108: a sleeper wakes when a support point it rests on moves this far
};

// How a body pair touches (docs/SPEC.md 2.2, 2.4).
enum class PairModel {
  kOrientedBox,  // eqs 100-106: separating axes on the oriented boxes, a manifold of up to 4 points (default)
  kAabb,         // eqs 38-43, 85: the source's single point at the centre of the two AABBs' overlap
};

struct Scene {
  std::string name = "scene";
  int frames = 600;
  PairModel pair_contacts = PairModel::kOrientedBox;  // JSON "pair_contacts": "oriented_box" or "aabb"
  Effects effects;
  Constants constants;
  GroundDesc ground;
  std::vector<BodyDesc> bodies;
  std::vector<SdfDesc> sdfs;
};

}  // namespace lockstep
