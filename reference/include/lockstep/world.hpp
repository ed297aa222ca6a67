// World<T>: the Level 1 engine, one frame at a time, generic over the number
// type T (float, double, Mp, Q16). The order of operations is docs/SPEC.md 7.2;
// each stage lives in its own file under reference/src/.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "lockstep/body_ids.hpp"
#include "lockstep/input.hpp"
#include "lockstep/math/vec.hpp"
#include "lockstep/physics/box_box.hpp"
#include "lockstep/physics/params.hpp"
#include "lockstep/physics/settle.hpp"
#include "lockstep/physics/sleep.hpp"
#include "lockstep/physics/sdf.hpp"
#include "lockstep/physics/solve_order.hpp"
#include "lockstep/physics/solver.hpp"
#include "lockstep/scene.hpp"
#include "lockstep/snapshot.hpp"

namespace lockstep {

namespace snap {
class Reader;
}  // namespace snap
class ThreadPool;

// A run that cannot go on: a Q16.16 overflow or other numeric fault (fixed),
// or a non-finite value (float engines). Names body, frame and quantity.
struct RunError : std::runtime_error {
  RunError(int frame_, int body_, std::string quantity_, const std::string& what);
  int frame;         // the frame being computed (1 = the first step)
  int body;          // body index, or -1 when not tied to one body
  std::string quantity;
};

// The stages of a frame (docs/SPEC.md 7.2), in their order; World<T>::step
// with an observer calls it after each.
enum class FrameStage : std::uint8_t {
  forces,                // 0: eq 121, the forces of run-time inputs
  integrate_velocities,  // 1: eqs 1, 5, 6, 13
  support_wake,          // 2a: eq 108
  broad_phase,           // 2: eqs 31, 82, 83, 107
  narrow_phase,          // 3-4: contacts, the wake (81)
  solve,                 // 5: the solver
  settle,                // 6: settling
  correct_positions,     // 7: eqs 63, 89, 110, 111
  integrate_positions,   // 8: eqs 2, 7-10
  sleep,                 // 9: eqs 78-80, 109
};
inline constexpr int kFrameStageCount = 10;
// "0 forces", "1 integrate_velocities", "2a support_wake", ...: SPEC 7.2's
// number and the stage's name.
inline const char* frame_stage_name(FrameStage s) {
  switch (s) {
    case FrameStage::forces: return "0 forces";
    case FrameStage::integrate_velocities: return "1 integrate_velocities";
    case FrameStage::support_wake: return "2a support_wake";
    case FrameStage::broad_phase: return "2 broad_phase";
    case FrameStage::narrow_phase: return "3-4 narrow_phase";
    case FrameStage::solve: return "5 solve";
    case FrameStage::settle: return "6 settle";
    case FrameStage::correct_positions: return "7 correct_positions";
    case FrameStage::integrate_positions: return "8 integrate_positions";
    case FrameStage::sleep: return "9 sleep";
  }
  return "?";
}

template <class T>
struct Body {
  Vec3<T> p, v, w;              // position (m), velocity (m/s), angular velocity (rad/s, world)
  Quat<T> q{Num<T>::from_int(1), T{}, T{}, T{}};  // orientation (unit)
  Vec3<T> half;                 // half extents (m)
  T inv_mass{};                 // 1/m (1/kg); 0 for static
  Vec3<T> inv_inertia;          // body-frame diagonal of I^-1 (eqs 14-18)
  T restitution{}, friction{};
  bool is_static = false;
  bool asleep = false;
  int sleep_counter = 0;        // eq 78
  int sleep_frame = -1;         // frame at which it last fell asleep (-1: never)
  // Derived each frame from q (not state):
  Mat3<T> R;                    // rotation matrix of q
  Vec3<T> aabb_half;            // eq 31
  bool awake() const { return !is_static && !asleep; }
};

// Work done per stage (docs/SPEC.md "Per-stage counters"); a stage that the
// scene does not call for leaves its counter at 0.
struct StageCounters {
  std::uint64_t integrate_velocity = 0;  // bodies given gravity (eqs 1, 5)
  std::uint64_t damping = 0;             // bodies damped (eqs 6, 13)
  std::uint64_t integrate_position = 0;  // bodies moved (eqs 2, 7-10)
  std::uint64_t broadphase_bodies = 0;   // bodies inserted into the grid (82)
  std::uint64_t pairs_tested = 0;        // pairs given eqs 38-39 (83)
  std::uint64_t ground_contacts = 0;     // eq 84 against the plane
  std::uint64_t sdf_contacts = 0;        // eqs 32-37, 93
  std::uint64_t body_contacts = 0;       // eqs 38-43, 85
  std::uint64_t solver_contacts = 0;     // contact visits in the solver
  std::uint64_t normal_impulses = 0;     // eqs 53, 86-87
  std::uint64_t restitution_bounces = 0; // contacts prepared with e_eff > 0 (eqs 76, 97)
  std::uint64_t friction_steps = 0;      // eqs 56-62, 88
  std::uint64_t corrections = 0;         // eq 63 / 89
  std::uint64_t settling_bodies = 0;     // eqs 64-75, 77
  std::uint64_t sleep_updates = 0;       // eqs 78-80
  std::uint64_t wakes = 0;               // eq 81
};

// A contact (docs/SPEC.md 7.2 step 3). Body b < 0 is the ground (-1) or SDF
// volume k (-2 - k). n points from b towards a.
template <class T>
struct Contact {
  int a = 0, b = -1;
  Vec3<T> n, point;
  T penetration{};
  bool corrects = true;  // carries the body's position correction (eq 89)
  T correct_depth{};     // eq 110: the depth (m) a box-box pair is corrected by: the mean of its points' depths
  int feature = 0;       // which point of the pair: ground corner k, SDF sample s, 0 for body pairs (eq 96)
  // Solver state (eqs 94-96), set when the solve starts.
  Vec3<T> r1, r2;        // lever arms c - p (eq 48, m)
  ContactState<T> state; // impulses, approach speed, e, mu, k_n (physics/solver.hpp)
  ContactRows<T> row;    // eqs 114, 128-129: the normal and tangent rows and effective masses, for every pass
};

// A contact as the narrow phase finds it (the fields of Contact that stages
// 3-4 set): the frame's list is filled from these on the world's threads,
// each Contact written once (copying whole contacts, 288 bytes in Q16, from
// the threads' lists was 0.1 ms of a 1,000-cube frame).
template <class T>
struct ContactPoint {
  int a = 0, b = -1;
  Vec3<T> n, point;
  T penetration{};
  bool corrects = true;
  T correct_depth{};
  int feature = 0;
  // c becomes this point's contact, its solver state unset (in place: a
  // Contact formed and then copied wrote its 288 bytes twice).
  void assign_to(Contact<T>& c) const {
    c.a = a;
    c.b = b;
    c.n = n;
    c.point = point;
    c.penetration = penetration;
    c.corrects = corrects;
    c.correct_depth = correct_depth;
    c.feature = feature;
    c.r1 = c.r2 = Vec3<T>{};
    c.state = ContactState<T>{};
    c.row = ContactRows<T>{};
  }
};

// Result of a raycast (Appendix B).
template <class T>
struct RayHit {
  bool hit = false;
  int body = -2;   // -1: the ground
  T distance{};
  Vec3<T> point, normal;
};

template <class T>
class World {
 public:
  // Builds the world from a scene (validated by the loader). Throws RunError
  // (frame 0) when a body's derived quantities (inertia, ...) overflow T.
  explicit World(const Scene& scene);
  // Copying a world saves its whole state; assigning restores it (the SDF
  // views are re-pointed at the copy's own samples; the frame's scratch is
  // not state and is not copied; the copy steps on as many threads).
  World(const World& other) = default;
  World& operator=(const World& other) = default;
  // Moving keeps the SDF views valid (the samples' buffers move with them).
  World(World&&) noexcept = default;
  World& operator=(World&&) noexcept = default;

  // Advances one frame (docs/SPEC.md 7.2). Throws RunError on a numeric fault.
  void step();
  // step() with a look inside the frame: after_stage(stage, *this) is called
  // after each stage of docs/SPEC.md 7.2 in order, a stage the scene's
  // effects leave out included (the world is then as the stage before left
  // it). With an observer that changes nothing the frame's bits are step()'s.
  // For tools that bisect a frame (`lockstep replay`) and tests that perturb
  // one through the public inputs (what the observer changes, the rest of the
  // frame sees).
  using StageObserver = std::function<void(FrameStage, World&)>;
  void step(const StageObserver& after_stage);
  int frame() const { return frame_; }
  // Threads (docs/SPEC.md 7.7 "Threads"): step() runs its parallel parts
  // (the solver's per-body visits and colours, eqs 125-127) on `threads`
  // threads, the caller's included; 1 (the default) runs everything on the
  // caller's. Every frame's bits are the same for every count. Throws
  // std::invalid_argument naming the value when threads < 1 or > 256.
  void set_threads(int threads);
  int threads() const { return workers_.threads; }
  const Scene& scene() const { return scene_; }
  const Params<T>& params() const { return P_; }
  const Effects& effects() const { return scene_.effects; }
  const std::vector<Body<T>>& bodies() const { return bodies_; }
  const Body<T>& body(int i) const { return bodies_[static_cast<std::size_t>(i)]; }
  const std::vector<Contact<T>>& contacts() const { return contacts_; }
  const StageCounters& counters() const { return counters_; }
  int awake_count() const;
  bool all_asleep() const;

  // eq 92: FNV-1a 64 over each body's state (raw int32 for Q16; the IEEE bits
  // of the value as a double for the other types).
  std::uint64_t state_hash() const;
  // Total kinetic + gravitational potential energy (J), evaluated in double.
  double energy() const;

  // 5.1: wakes body i (a user's touch); no effect on static bodies.
  void wake(int i);
  // Replaces body i's velocities (and wakes it): what a game's input does.
  void set_velocity(int i, const Vec3<T>& v, const Vec3<T>& w);

  // Run-time inputs (docs/SPEC.md "Run-time inputs", eqs 118-123): what a
  // game does between two frames. Values are doubles converted to T as
  // World(scene) converts a scene's. A body is named by its BodyId (stable
  // across creations and removals); its index (bodies(), body(i), contacts)
  // changes when a body before it is destroyed. Every call throws
  // std::invalid_argument, naming the field, the value and a fix, for a stale
  // or unknown id, a body description the scene loader would refuse or this
  // number type cannot represent, or a value out of range; the world is then
  // unchanged. An input on a static body that cannot move it (impulse,
  // force, velocity, wake) has no effect.
  //
  // Applies `input` now (create: returns the new body's id; otherwise
  // input.id). input.frame must be frame() + 1: an input of frame f is
  // applied before the step that computes frame f.
  BodyId apply(const Input& input);
  // eq 118: appends a body (index bodies().size()) built as World(scene)
  // builds a scene's body; its id takes the lowest free slot.
  BodyId create_body(const BodyDesc& desc);
  // eq 119: removes the body; the bodies after it move down one index (their
  // order kept); the sleepers resting on it wake.
  void destroy_body(BodyId id);
  // eq 120: impulse J (N s) at the world point `point` (m): v += J/m,
  // omega += I^-1 ((point - p) x J); wakes the body.
  void apply_impulse(BodyId id, const Vec3d& J, const Vec3d& point);
  // eq 121: force F (N) at the centre of mass and torque (N m) for the next
  // step (summed over the calls before it); wakes the body.
  void add_force(BodyId id, const Vec3d& F, const Vec3d& torque);
  // eq 122: teleports the body (q normalised as the loader does); wakes it
  // and the sleepers resting on it, drops its warm-start entries.
  void set_pose(BodyId id, const Vec3d& p, const Quatd& q);
  // eq 123: replaces the body's velocities and wakes it.
  void set_velocity(BodyId id, const Vec3d& v, const Vec3d& w);
  // 5.1 on the body.
  void wake(BodyId id);
  // The index of a live body; throws std::invalid_argument for a stale or
  // unknown id.
  int index_of(BodyId id) const;
  // Whether id names a live body.
  bool contains(BodyId id) const;
  // The id of body i (0 <= i < bodies().size()).
  BodyId id_of(int index) const;
  // The id the next create_body will return.
  BodyId next_id() const;
  // The force and torque pending for the next step on body i (zero if none).
  std::pair<Vec3<T>, Vec3<T>> pending_force(int index) const;

  // Snapshots (docs/SNAPSHOTS.md): the whole state the following frames
  // depend on (the scene's constant part, every body's pose, velocities and
  // sleep state, eq 108's records, the warm-start cache, the frame and the
  // counters) as versioned little-endian bytes. Loading a snapshot and
  // stepping gives, frame for frame, the bits the saved world would have.
  std::vector<std::uint8_t> save_state() const;
  // The same into `out` (its contents replaced, its capacity reused).
  void save_state(std::vector<std::uint8_t>& out) const;
  // A world built from a snapshot alone. Throws SnapshotError for a
  // truncated, corrupt or foreign snapshot (another number type or format
  // version), naming what is wrong. Its scene() is the snapshot's scene, the
  // bodies' initial state being the saved state (converted to double).
  static World load_state(const std::uint8_t* data, std::size_t size);
  static World load_state(const std::vector<std::uint8_t>& bytes);
  // Replaces this world's state by the snapshot's. When the snapshot is of
  // this world's scene (its scene section is this world's, byte for byte)
  // only the moving state is read (the rollback case); otherwise the world is
  // rebuilt as load_state does. Throws SnapshotError; after a throw the world
  // is a world of its scene in an unspecified (valid) state.
  void restore_state(const std::uint8_t* data, std::size_t size);
  void restore_state(const std::vector<std::uint8_t>& bytes);
  // FNV-1a 64 of the scene's constants block (the snapshot header's).
  std::uint64_t constants_hash() const { return constants_hash_; }

  // Appendix B queries; results in ascending body order.
  RayHit<T> raycast(const Vec3<T>& origin, const Vec3<T>& dir, const T& max_distance) const;
  std::vector<int> overlap_aabb(const Vec3<T>& lo, const Vec3<T>& hi) const;
  std::vector<int> point_query(const Vec3<T>& p) const;

 private:
  // One file per stage under reference/src/.
  void integrate_velocities();   // integrate.hpp
  void broad_phase();            // broad_phase.hpp
  void narrow_phase();           // narrow_phase.hpp
  void wake_touched(const std::vector<ContactPoint<T>>& pair_contacts);  // sleep.hpp
  void wake_unsupported();       // sleep.hpp (eq 108)
  void record_supports(std::size_t i);  // sleep.hpp (eqs 108, 124)
  using LoadChildren = std::vector<std::pair<int, int>>;  // (load parent, child), sorted (eqs 117, 124)
  std::pair<LoadChildren::const_iterator, LoadChildren::const_iterator> form_load(
      int idx, const LoadChildren& children);  // narrow_phase.hpp (eq 117)
  void sleeper_loads();          // narrow_phase.hpp (eq 124)
  void wake_loaded();            // sleep.hpp (eq 124)
  void solve_contacts();         // contact_solver.hpp
  void settle();                 // settle.hpp
  void correct_positions();      // contact_solver.hpp
  void integrate_positions();    // integrate.hpp
  void update_sleep();           // sleep.hpp
  void update_derived(Body<T>& b);
  Vec3<T> support_normal(std::size_t i) const;  // body i's support normal (4.1), towards i
  void check_faults(int body, const char* quantity);
  // Runs body(k, part) for k in [0, count) on the world's threads, cut into
  // at most threads() contiguous ranges of at least `grain` items, part the
  // range's number (thread_pool.hpp); a RunError of the lowest k that threw
  // is rethrown.
  template <class Body>
  void parallel_for(std::size_t count, std::size_t grain, const Body& body);
  // The same for work whose items are independent and whose parts keep
  // nothing in order: chunks of `grain` items handed out in ascending order
  // to whichever thread is free (items' costs vary: asleep bodies, pairs
  // whose boxes miss), `part` the running part's number, which may index
  // only accumulators that any order fills alike (integer counts).
  template <class Body>
  void parallel_each(std::size_t count, std::size_t grain, const Body& body);
  template <class Body>
  void run_items(std::size_t count, std::size_t grain, bool chunks, const Body& body);  // both of the above
  // Runs run(k) for the items k in [0, count), where item k touches (reads
  // or writes) only the bodies bodies_of(k) (two; -1: none) and what no
  // other item writes: the items joined by shared bodies form groups that
  // run on the world's threads, each in ascending k, so the result is the
  // serial loop's. A RunError of the lowest item is rethrown.
  template <class Bodies, class Run>
  void items_by_groups(std::size_t count, const Bodies& bodies_of, const Run& run);
  // The same for the bodies of `order` in that order (reversed when
  // `reverse`), run(idx) touching only body idx and dep(idx) (-1: none).
  template <class Dep, class Run>
  void in_order_by_groups(const std::vector<int>& order, bool reverse, const Dep& dep, const Run& run);
  void check_finite();
  void read_moving_state(snap::Reader& r, std::uint32_t frame, bool derived_valid);  // snapshot.hpp
  void read_ids_and_forces(snap::Reader& r);  // snapshot_load.hpp
  // Run-time inputs (world_inputs.hpp).
  void apply_forces();                          // stage 0 (eq 121)
  void wake_resting_on(std::size_t i);          // eq 119: wakes the sleepers whose eq 108 records name body i
  void wake_all_sleepers();                     // a static body changed: every sleeper wakes
  void drop_warm(std::size_t i);                // eq 96: drops the cached impulses of body i

  Scene scene_;
  std::vector<std::uint8_t> scene_section_;  // the snapshot's scene section (snapshot_scene.hpp)
  std::uint64_t constants_hash_ = 0;
  Params<T> P_;
  std::vector<Body<T>> bodies_;
  // The SDF volumes: each grid's samples (values) and its view of them (grids,
  // eq 32), re-pointed at the copy's own samples when a world is copied.
  struct SdfVolumes {
    std::vector<std::vector<T>> values;
    std::vector<SdfGrid<T>> grids;
    SdfVolumes() = default;
    SdfVolumes(const SdfVolumes& o) : values(o.values), grids(o.grids) { point(); }
    SdfVolumes& operator=(const SdfVolumes& o) {
      values = o.values;
      grids = o.grids;
      point();
      return *this;
    }
    SdfVolumes(SdfVolumes&&) noexcept = default;  // the samples' buffers move with them
    SdfVolumes& operator=(SdfVolumes&&) noexcept = default;
    void point() {
      for (std::size_t k = 0; k < grids.size(); ++k) grids[k].values = values[k].data();
    }
  };
  SdfVolumes sdf_;
  std::vector<std::pair<int, int>> pairs_;
  std::vector<T> grow_;               // per body: its AABB growth this frame, half_tol + speculative reach (eqs 97, 107)
  std::vector<Contact<T>> contacts_;
  // eq 96: last frame's accumulated impulses, sorted by (a, b, feature).
  struct CachedImpulse { int a, b, feature; T j_n; };
  std::vector<CachedImpulse> warm_;
  // eq 108: per sleeping body, the dynamic bodies it rested on when it fell
  // asleep (at most kMaxRests, in contact order) and their support points.
  struct Rest { int body; Vec3<T> local, rest, last; };  // eq 108: last, where the point was at the frame's start
  std::vector<std::vector<Rest>> rests_;
  std::vector<int> support_;          // per body: index of its first support contact, -1 if none
  std::vector<Vec3<T>> support_n_;    // per body: its support normal (4.1), zero if none
  std::vector<T> support_gap_;        // per body: its support gap (75), the smallest gap of its supports
  std::vector<char> leaning_;         // per body: it leans on what holds it beyond its support (eq 115)
  std::vector<char> over_support_;    // per body: eq 112 lets it settle (its centre of mass is over its support contacts, or it is held by more)
  std::vector<T> settle_limit_;       // per body: eq 77 damps a relative speed up to this (m/s, eq 116)
  std::vector<char> can_rest_;        // per body: statics lets it rest (eqs 116, 117): a sleep candidate (78) only then
  // eq 124: what a body recorded as it fell asleep (read only while it sleeps):
  // its load parent and its support points' lever arms (horizontal parts).
  struct SleepSupport {
    int parent = kLoadNone;
    int count = 0;
    std::array<Vec3<T>, kMaxSupportPoints> arms{};
  };
  std::vector<SleepSupport> sleep_support_;
  std::vector<char> wake_load_;       // per body: eq 124 wakes it at the end of this frame (stage 3 to 9)
  // Stage 2 scratch (broad_phase.hpp): per body its cells and x extent, the
  // (cell, body) entries, the bodies too large for the grid, one cell's members.
  struct BroadCell { int x, y, z; };
  struct BroadEntry { std::uint64_t key; int body; };
  struct BroadScratch {
    std::vector<BroadCell> cmin, cmax;
    std::vector<T> min_x, max_x;
    std::vector<BroadEntry> entries;
    std::vector<int> large, members;
    std::vector<std::vector<BroadEntry>> part_entries;            // per part: its bodies' (cell, body) entries
    std::vector<std::vector<std::pair<int, int>>> part_pairs;     // per part: the pairs its cells found
    std::vector<std::vector<int>> part_members;                   // per part: one cell's members
  };
  // Stage 3's environment contacts of one part of the bodies (narrow_phase.hpp).
  struct EnvPart {
    std::vector<ContactPoint<T>> contacts;
    std::uint64_t ground = 0, sdf = 0;
    std::size_t first = 0;  // its first contact's place in the frame's list
  };
  // A solver visit's last outcome: whether it applied no impulse (and the
  // sides' velocity versions then), whether it changed them by less than
  // converged_speed, and the sides' velocities it left (eq 113).
  struct IdleVisit {
    bool idle = false, small = false;
    unsigned version_a = 0, version_b = 0, solver_contacts = 0;
    Vec3<T> va, wa, vb, wb;
  };
  struct SolveEdge { EdgeKey key; int visit; };  // eq 126's key of an edge, and its visit
  // The frame's scratch (not state: each stage writes what it reads within
  // the frame, so a copy of a world starts with none, and a snapshot holds
  // none), handed to every stage as scratch_:
  // - stage 2 (broad_phase.hpp): broad, the grid's cells and entries;
  // - stages 3-4 (narrow_phase.hpp): the body-pair contacts and manifolds,
  //   the supports' lever arms, eq 117's and eq 124's loads, stage 6's order;
  // - stage 5 (contact_solver.hpp): the visits as [begin, end) in contacts_,
  //   eq 99's splits, per body how many visits changed its velocity, per
  //   visit its last outcome; the order of eqs 125-127: per awake body its
  //   own visits ([body_visit_begin[b], [b + 1]) in body_visits, the body
  //   visit_bodies[b]), the edges by colour ([colour_begin[c], [c + 1]) in
  //   colour_visits);
  // - stage 7 (contact_solver.hpp): eq 110's order and eq 111's turns;
  // - stage 9 (sleep.hpp): eq 109's rests-on pairs.
  struct FrameScratch {
    std::vector<std::pair<int, int>> rests_on;  // stage 9 scratch: (body, dynamic body it rests on), sorted (eq 109)
    std::vector<char> sleep_state;              // stage 9: per body, whether eqs 78-79 ran on it and it is ready (eq 109)
    std::vector<int> group_root, group_of, group_begin, group_members;  // items_by_groups (world_impl.hpp)
    std::vector<int> settle_order;     // narrow_phase: awake supported bodies in stage 6's order (settle, eq 112's chain)
    std::vector<Vec3<T>> w_solved;     // stage 6 scratch: per body, its angular velocity as the solver left it (eqs 72-74)
    std::vector<int> load_parent;      // stage 3 scratch: per body, its load parent (eq 117) or kLoadNone
    std::vector<std::pair<int, int>> load_children;  // stage 3 scratch: (load parent, child), sorted (eq 117)
    std::vector<T> load_mass;          // stage 3 scratch: per body, its load's mass (kg, eq 117)
    std::vector<Vec3<T>> load_offset;  // stage 3 scratch: per body, its load's centre less its own (m, eq 117)
    std::vector<char> load_tips;       // stage 3 scratch: per body, something in its load tips (eq 117)
    std::vector<std::array<Vec3<T>, kMaxSupportPoints>> support_arms;  // stage 3 scratch: per body, its support contacts' lever arms (eq 112)
    std::vector<int> n_arms;           // stage 3 scratch: per body, how many (kMaxSupportPoints + 1: too many to look at)
    std::vector<std::array<Vec3<T>, kMaxHolds>> hold_arms, hold_n;  // stage 3 scratch: per body, what holds it (eqs 112, 117): lever arms, normals towards it
    std::vector<int> n_holds;          // stage 3 scratch: per body, how many (kMaxHolds + 1: too many to look at)
    std::vector<std::pair<int, int>> sleeper_children;  // stage 3 scratch: (sleeping parent, child), sorted (eq 124)
    std::vector<int> sleeper_loads;    // stage 3 scratch: the sleepers whose load eq 124 forms, top down
    std::vector<Vec3<T>> corrected_from;  // per body: its position before this frame's correction (eq 89 order)
    std::vector<int> order;            // eq 110: the pair contacts that correct, bottom up
    std::vector<std::pair<T, int>> order_keys;  // eq 110: (lower side's y, contact) of each, sorted
    std::vector<char> pair_corrected;  // eq 110: per pair of `order`, whether it was corrected (counted)
    std::vector<int> warm_first;       // eq 96's cache: per body, its first entry (the bodies in order)
    std::vector<Vec3<T>> turn;         // eq 111: per body, the turn (rad) this frame's correction gave it
    BroadScratch broad;
    std::vector<ContactPoint<T>> pair_contacts;
    std::vector<int> body_contact_begin, body_contacts;  // per body: its contacts in contact order ([begin[i], begin[i + 1]) in body_contacts)
    std::vector<ImpulseDelta<T>> warm_delta;  // stage 5: per contact, its warm start's velocity changes (eq 96)
    std::vector<char> warmed;                 // stage 5: per contact, whether it was warm started (eq 96)
    std::vector<std::uint32_t> warm_faults;   // stage 5: per contact, its warm start's Q16 flags (3 per contact: the impulse, side a, side b)
    std::vector<EnvPart> env_parts;  // per chunk of 64 bodies: its environment contacts (kept: a frame's buffers are large)
    std::vector<BoxManifold<T>> pair_manifolds;  // per pair of pairs_: its manifold (eqs 100-106; count 0: none)
    std::vector<int> pair_deepest;   // per pair with points: its deepest point, which corrects the pair (eq 110)
    std::vector<T> pair_depth;       // per pair with points: the mean depth of its points (eq 110)
    std::vector<int> pair_first;     // per pair: its first point's place in pair_contacts (and the total last)
    std::vector<std::pair<std::size_t, std::size_t>> visits;
    struct alignas(64) Version { unsigned n = 0; };  // a cache line per body: the parts on threads bump their own bodies' versions
    std::vector<Version> velocity_version;
    std::vector<IdleVisit> idle_visits;
    std::vector<T> visit_split;  // per visit: eq 99's split (manifold_split), formed once per solve
    std::vector<int> body_visit_begin, body_visits, visit_bodies;
    std::vector<int> colour_begin, colour_visits;
    std::vector<SolveEdge> edges;
    std::vector<int> colour_top;  // per body: the largest colour of its edges so far (eq 127)
    std::vector<std::pair<std::uint64_t, int>> own_visits;  // (body << 32 | other + 1, visit), sorted
    T band_inv{};                 // eq 125's 1 / band, from the bodies awake after stage 2a
    bool oriented_correction = false;  // eq 110's penetration (less what the stage moved) for pairs too
    FrameScratch() = default;
    FrameScratch(const FrameScratch&) {}
    FrameScratch& operator=(const FrameScratch&) { return *this; }
    FrameScratch(FrameScratch&&) noexcept = default;
    FrameScratch& operator=(FrameScratch&&) noexcept = default;
  };
  FrameScratch scratch_;
  T ground_y_{}, ground_e_{}, ground_mu_{};
  std::vector<T> sdf_e_, sdf_mu_;
  StageCounters counters_;
  int frame_ = 0;
  // The world's threads (7.7 "Threads"): how many, and the pool, made on the
  // first parallel region; a copy steps on as many threads of its own.
  struct Workers {
    int threads = 1;
    std::shared_ptr<ThreadPool> pool;
    Workers() = default;
    Workers(const Workers& o) : threads(o.threads) {}
    Workers& operator=(const Workers& o) {
      if (threads != o.threads) pool.reset();
      threads = o.threads;
      return *this;
    }
    Workers(Workers&&) noexcept = default;
    Workers& operator=(Workers&&) noexcept = default;
  };
  Workers workers_;
  // Run-time inputs: the id table and the forces pending for the next step
  // (eq 121), ascending body index.
  BodyIds ids_;
  struct PendingForce { int body; Vec3<T> f, tau; };
  std::vector<PendingForce> forces_;
};

}  // namespace lockstep
