// The GPU engine: the physics of World<T>, scheduled data-parallel
// (docs/GPU.md), on float ("gpu": World<float>'s bits) or on Q16.16
// ("gpu-fixed": World<Q16>'s bits, docs/GPU.md "gpu-fixed"). One source serves two builds: CUDA kernels on a device, and
// the host build, whose loops call the same per-element functions. A
// GpuWorld picks the device when one is present and the library was built
// with CUDA, and otherwise runs the host build and says so in description().
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "lockstep/compare/engine.hpp"
#include "lockstep/fixed/q16.hpp"
#include "lockstep/input.hpp"
#include "lockstep/scene.hpp"
#include "lockstep/world.hpp"

namespace lockstep {

// The "gpu" engine behind the EngineRun interface (name() is "gpu"); with
// `jacobi`, the same engine with the Jacobi pair solver
// (GpuOptions::PairSolver::kJacobi, name() "gpu-jacobi").
// `quiet`: no note on stderr when it falls back to the host build.
std::unique_ptr<EngineRun> make_gpu_engine(const Scene& scene, bool jacobi = false, bool quiet = false);
// The "gpu-fixed" engine: the same pipeline on Q16.16 (GpuFixedWorld),
// World<Q16>'s bits; with `jacobi`, "gpu-fixed-jacobi".
std::unique_ptr<EngineRun> make_gpu_fixed_engine(const Scene& scene, bool jacobi = false, bool quiet = false);
// The "gpu" or "gpu-fixed" engine (or its Jacobi variant) resumed from its
// snapshot (number type 5 or 6; BasicGpuWorld::load_state), and the
// snapshot's scene. Throws SnapshotError.
ResumedEngine resume_gpu_engine(const std::vector<std::uint8_t>& bytes, bool quiet = false);

namespace gpu {

enum class Backend {
  kAuto,    // the device when present, else the host build (with a message on stderr)
  kHost,    // the host build of the same engine
  kDevice,  // the CUDA device; throws std::runtime_error when there is none
};

struct GpuOptions {
  Backend backend = Backend::kAuto;
  // Settling sweeps: eq 75 reads the support's settled velocity when the
  // support is lower (World<T> settles bottom-up in one ordered pass); sweep k
  // settles the bodies k + 1 high in their chain of supports exactly. Sweeps
  // run in batches of this many, each followed by a check (one host
  // synchronisation), until every body's settled velocity is final, plus the
  // last sweep (fused with the correction): World<T>'s result for any stack.
  int settle_batch = 4;
  // How contacts between two awake bodies are resolved (docs/GPU.md "Contact
  // resolution"). kColoured: Gauss-Seidel over a colouring of the contact
  // graph (contacts of one colour share no body and are solved in parallel,
  // the colours one after the other, each contact updating both bodies as
  // World<T> does). kJacobi: each body against its neighbours' velocities at
  // the start of the iteration, with mass splitting: fewer launches, softer
  // stacks, taller stacks topple.
  enum class PairSolver { kColoured, kJacobi };
  PairSolver pair_solver = PairSolver::kColoured;
  // Jacobi relaxation of body-body impulses (kJacobi): a body adds relaxation / m times
  // the sum of its m approaching body-body contacts' velocity changes.
  float relaxation = 1.0f;
  // From this many awake bodies on, the solver's iterations run their
  // bodies in an order of their work (within segments of 2048 slots: bodies
  // near the ground first, then by neighbour count, so that the threads of a
  // warp take the same path), at the cost of one radix sort per frame. A
  // scheduling choice only: the results are the same bits either way.
  int work_order_min = 32768;
  bool stage_timing = false;  // per-stage times (CUDA events on the device)
  bool quiet = false;         // no stderr message when falling back to the host build
};

// Stages timed by stage_times() (docs/GPU.md "Stages").
enum Stage : int {
  kStageIntegrate = 0,  // velocity integration (eqs 1, 5, 6, 13)
  kStageBroadphase,     // awake grid: keys, radix sort, cell table
  kStageFrozenGrid,     // sleeping/static grid, rebuilt only when that set changes
  kStagePairs,          // neighbour count, wake (81), scan
  kStageContacts,       // neighbour lists, ground/SDF contacts, supports
  kStageSolve,          // solver iterations
  kStageSettle,         // settling sweeps
  kStageCorrect,        // position correction and integration (63, 89, 2, 7-10)
  kStageSleep,          // sleep update (78-80), awake-set compaction
  kStageCount
};
const char* stage_name(int stage);

struct StageTimes {
  std::array<double, kStageCount> ms{};  // summed over `frames` frames (milliseconds)
  int frames = 0;
};

// True when the library was built with CUDA and a CUDA device is present.
bool cuda_device_available();
// True when the library was built with CUDA (nvcc found, LOCKSTEP_CUDA on).
bool built_with_cuda();

// The CUDA device the engine uses (empty name when there is none).
struct DeviceInfo {
  std::string name;
  int multiprocessors = 0;
  double memory_gib = 0.0;
};
DeviceInfo device_info();
// Device-to-device copy bandwidth (GB/s, bytes read plus bytes written) of
// cudaMemcpy over a buffer of `bytes`, the median of `repetitions` timed
// copies (CUDA events); 0 without a device.
double measure_copy_bandwidth(std::size_t bytes, int repetitions);
// Starts or stops the CUDA profiler's capture (cudaProfilerStart/Stop), so
// that `ncu --profile-from-start off` measures only the frames in between;
// no effect without a device.
void profiler_capture(bool on);

// The engine on the number type T: float (GpuWorld, "gpu") or Q16
// (GpuFixedWorld, "gpu-fixed"); one pipeline source for both (gpu/src).
template <class T>
class BasicGpuWorld {
 public:
  explicit BasicGpuWorld(const Scene& scene, const GpuOptions& options = {});
  ~BasicGpuWorld();
  BasicGpuWorld(const BasicGpuWorld&) = delete;
  BasicGpuWorld& operator=(const BasicGpuWorld&) = delete;

  // Throws RunError on a non-finite value (float, like World<float>) or a
  // Q16 fault (Q16, like World<Q16>: the frame, the first body by index
  // with a fault in the first stage that had one, and its quantity).
  void step();
  int frame() const;
  int body_count() const;
  int awake_count() const;  // awake bodies after the last step
  bool on_device() const;
  std::string description() const;  // "gpu[-fixed]: CUDA on <device>" or "gpu[-fixed] (host build: ...)"
  const StageCounters& counters() const;
  StageTimes stage_times() const;
  void reset_stage_times();

  // Run-time inputs (docs/GPU.md "Run-time inputs"): as World<T>::apply,
  // with World<T>'s body order and ids; taken up by rebuilding the pipeline
  // before the next step (without the warm-start cache and eq 108's
  // records). Throws std::invalid_argument for a bad input.
  BodyId apply(const Input& input);
  int index_of(BodyId id) const;
  BodyId id_of(int index) const;

  // State of body i after the last step (downloaded once per frame), or as
  // the inputs since left it.
  BodySnapshot body(int i) const;
  std::uint64_t state_hash() const;  // eq 92 as World<T>: binary64 bits (float), raw int32 (Q16)
  double energy() const;             // (J), evaluated in double like World<T>
  // The scene (after load_state: the snapshot's, its bodies' initial state
  // the saved state).
  const Scene& scene() const;
  bool jacobi() const;  // the Jacobi pair solver (GpuOptions::PairSolver::kJacobi)

  // Snapshots (docs/SNAPSHOTS.md "The GPU engine"): the header and scene
  // section of World<T>'s snapshots (number type 5, gpu; 6, gpu-fixed), then everything the
  // engine's following frames read: per body its pose, velocities, AABB,
  // sleep state, growth and eq 108's records; the awake list in its order;
  // the last frame's contacts by slot with their impulses (the warm start,
  // eq 96); the id table; the counters. Restoring and stepping gives the
  // hashes the saved engine would have, on the host build and on the device
  // (one code path). Inputs applied since the last step are taken up first,
  // as the next step would (the pipeline is rebuilt from them).
  std::vector<std::uint8_t> save_state() const;
  void save_state(std::vector<std::uint8_t>& out) const;
  // A world from a snapshot alone (the pair solver is the snapshot's; the
  // backend as `options` asks). Throws SnapshotError for a truncated,
  // corrupt or foreign snapshot, naming the field.
  static std::unique_ptr<BasicGpuWorld> load_state(const std::uint8_t* data, std::size_t size, const GpuOptions& options = {});
  // Replaces this world's state; when the snapshot's scene section is this
  // world's, only the state is read (rollback), else the world is rebuilt.
  // Throws SnapshotError (then this world is unchanged).
  void restore_state(const std::uint8_t* data, std::size_t size);

 private:
  void flush() const;  // takes up the inputs since the last step (a new pipeline)
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

using GpuWorld = BasicGpuWorld<float>;
using GpuFixedWorld = BasicGpuWorld<Q16>;
extern template class BasicGpuWorld<float>;
extern template class BasicGpuWorld<Q16>;

}  // namespace gpu
}  // namespace lockstep
