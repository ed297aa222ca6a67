// GpuWorld: picks the backend, and serves snapshots, the state hash and the
// energy from a host copy of the state downloaded once per frame.
#include <cstdio>
#include <cstring>
#include <mutex>
#include <stdexcept>

#include "lockstep/fixed/q16_num.hpp"
#include "lockstep/gpu/formula_cases.hpp"
#include "lockstep/gpu/gpu_engine.hpp"
#include "gpu_snapshot.hpp"
#include "lockstep/gpu/soa.hpp"
#include "lockstep/scene_limits.hpp"
#include "gpu_inputs.hpp"
#include "pipeline_base.hpp"
#include "snapshot_bytes.hpp"
#include "snapshot_scene.hpp"

namespace lockstep {
namespace gpu {

const char* stage_name(int stage) {
  static const char* const kNames[kStageCount] = {"integrate", "broadphase", "frozen_grid", "pairs", "contacts",
                                                  "solve", "settle", "correct_integrate", "sleep"};
  return stage >= 0 && stage < kStageCount ? kNames[stage] : "?";
}

bool built_with_cuda() {
#if LOCKSTEP_GPU_HAVE_CUDA
  return true;
#else
  return false;
#endif
}

bool cuda_device_available() { return cuda_device_count() > 0; }

std::vector<float> evaluate_formula_cases_on_host(int kind, const std::vector<float>& inputs) {
  const Params<float> P = Params<float>::from(Constants{});
  const std::size_t n = inputs.size() / kFormulaInputs;
  std::vector<float> out(n * kFormulaOutputs);
  for (std::size_t k = 0; k < n; ++k) evaluate_formula_case(kind, P, inputs.data() + k * kFormulaInputs, out.data() + k * kFormulaOutputs);
  return out;
}

#if !LOCKSTEP_GPU_HAVE_CUDA
int cuda_device_count() { return 0; }
DeviceInfo device_info() { return {}; }
double measure_copy_bandwidth(std::size_t, int) { return 0.0; }
void profiler_capture(bool) {}
std::vector<float> evaluate_formula_cases_on_device(int, const std::vector<float>&) {
  throw std::runtime_error("gpu: this build has no CUDA (nvcc was not found or LOCKSTEP_CUDA is off)");
}
template <class T>
std::unique_ptr<PipelineBase<T>> make_device_pipeline(const InitialState<T>&, const GpuOptions&) {
  throw std::runtime_error("gpu: this build has no CUDA (nvcc was not found or LOCKSTEP_CUDA is off)");
}
#endif

namespace {

// The engine's name: "gpu" (float) or "gpu-fixed" (Q16).
template <class T>
const char* engine_name() { return Num<T>::kExact ? "gpu-fixed" : "gpu"; }
template <class T>
SnapshotNumber snapshot_number() { return Num<T>::kExact ? SnapshotNumber::kGpuFixed : SnapshotNumber::kGpu; }

template <class T>
std::unique_ptr<PipelineBase<T>> make_pipeline(const InitialState<T>& s, const GpuOptions& options) {
  const std::string name = engine_name<T>();
  if (options.backend == Backend::kHost) return make_host_pipeline(s, options, name + " (host build: requested)");
  const bool cuda = built_with_cuda();
  if (cuda && cuda_device_count() > 0) return make_device_pipeline(s, options);
  if (options.backend == Backend::kDevice)
    throw std::runtime_error(cuda ? name + ": no CUDA device" : name + ": this build has no CUDA");
  const std::string why = name + (cuda ? " (host build: no CUDA device)" : " (host build: built without CUDA)");
  if (!options.quiet) {
    static std::once_flag once;
    std::call_once(once, [&why] { std::fprintf(stderr, "lockstep: %s; running the same engine on the CPU\n", why.c_str()); });
  }
  return make_host_pipeline(s, options, why);
}

}  // namespace

template <class T>
struct BasicGpuWorld<T>::Impl {
  using F4 = T4<T>;
  std::unique_ptr<PipelineBase<T>> pipeline;
  Scene scene;
  GpuOptions options;
  std::vector<std::uint8_t> scene_section;  // the snapshot's scene section (snapshot_scene.hpp)
  std::uint64_t constants_hash = 0;
  InitialState<T> shape;  // the scene's initial state with every body at the origin: what a snapshot is checked against
  HostState<T> mirror;
  int mirror_frame = -1;
  std::vector<F4> half, inert;  // constants: half extents (w: e), inverse inertia (w: mu)
  Vec3d gravity;
  std::unique_ptr<GpuInputs<T>> inputs;  // run-time inputs (gpu_inputs.hpp)
  StageCounters base, total;          // base: the counters of the pipelines the inputs replaced
  const std::vector<F4>& inert_now() const { return inputs->pending() ? inputs->inert() : inert; }
  const HostState<T>& state() {
    if (inputs->pending()) return inputs->state();
    if (mirror_frame != pipeline->frame()) {
      pipeline->download(mirror);
      mirror_frame = pipeline->frame();
    }
    return mirror;
  }
};

namespace {

// The scene as a snapshot's scene section holds it: every body at the origin, at rest.
Scene at_origin(Scene scene) {
  for (BodyDesc& b : scene.bodies) {
    b.position = {};
    b.orientation = {};
    b.velocity = {};
    b.angular_velocity = {};
    b.asleep = false;
  }
  return scene;
}

template <class T>
int imm_stride_of(const InitialState<T>& s) { return (s.ground_on ? 8 : 0) + 9 * static_cast<int>(s.sdf_grids.size()); }

// The id table a snapshot holds (identity when it holds none).
template <class T>
BodyIds ids_of(const GpuState<T>& s, std::size_t bodies) {
  BodyIds ids;
  ids.reset(bodies);
  if (!s.generations.empty()) (void)ids.assign(s.generations, s.slot_of_body);  // checked by read_gpu_state
  return ids;
}

[[noreturn]] void foreign(SnapshotNumber number, const char* engine) {
  throw SnapshotError(std::string("a snapshot of the ") + snapshot_number_name(number) +
                          " engine cannot be loaded into the " + engine + " engine",
                      "header.number_type");
}

}  // namespace

template <class T>
BasicGpuWorld<T>::BasicGpuWorld(const Scene& scene, const GpuOptions& options) : impl_(std::make_unique<Impl>()) {
  const InitialState<T> s = make_initial_state<T>(scene);
  impl_->scene = scene;
  impl_->options = options;
  impl_->scene_section = snap::encode_scene_section(scene);
  impl_->constants_hash = snap::constants_hash(scene.constants);
  impl_->shape = make_initial_state<T>(at_origin(scene));
  impl_->half = s.half;
  impl_->inert = s.inert;
  impl_->gravity = scene.constants.gravity;
  impl_->inputs = std::make_unique<GpuInputs<T>>(scene);
  impl_->pipeline = make_pipeline(s, options);
}

template <class T>
BasicGpuWorld<T>::~BasicGpuWorld() = default;

namespace {
StageCounters sum(StageCounters a, const StageCounters& b) {
  std::uint64_t* x = &a.integrate_velocity;
  const std::uint64_t* y = &b.integrate_velocity;
  static_assert(sizeof(StageCounters) == 16 * sizeof(std::uint64_t), "StageCounters is 16 counters");
  for (int k = 0; k < 16; ++k) x[k] += y[k];
  return a;
}
}  // namespace

// The inputs since the last step: a new pipeline from their state (what
// step() does first, and save_state before it saves).
template <class T>
void BasicGpuWorld<T>::flush() const {
  Impl& m = *impl_;
  if (!m.inputs->pending()) return;
  const int frame = m.pipeline->frame();
  m.base = sum(m.base, m.pipeline->counters());
  m.base.wakes += m.inputs->wakes();
  const InitialState<T> s = m.inputs->take_state();
  m.half = s.half;
  m.inert = s.inert;
  GpuOptions quiet = m.options;
  quiet.quiet = true;  // the first pipeline said which backend runs
  m.pipeline = make_pipeline(s, quiet);
  m.pipeline->set_frame(frame);
  m.mirror_frame = -1;
  // The body set may have changed: the snapshot's scene section with it.
  m.scene = m.inputs->scene();
  m.scene_section = snap::encode_scene_section(m.scene);
  m.shape = make_initial_state<T>(at_origin(m.scene));
}

template <class T>
void BasicGpuWorld<T>::step() {
  flush();
  impl_->pipeline->step();
}
template <class T>
BodyId BasicGpuWorld<T>::apply(const Input& input) { return impl_->inputs->apply(input, *impl_->pipeline); }
template <class T>
int BasicGpuWorld<T>::index_of(BodyId id) const { return static_cast<int>(impl_->inputs->ids().require(id, "index_of")); }
template <class T>
BodyId BasicGpuWorld<T>::id_of(int index) const {
  if (index < 0) throw std::invalid_argument("id_of: index = " + std::to_string(index) + " is not a body index");
  return impl_->inputs->ids().id_of(static_cast<std::size_t>(index));
}
template <class T>
int BasicGpuWorld<T>::frame() const { return impl_->pipeline->frame(); }
template <class T>
int BasicGpuWorld<T>::body_count() const {
  return impl_->inputs->pending() ? impl_->inputs->body_count() : impl_->pipeline->body_count();
}
template <class T>
int BasicGpuWorld<T>::awake_count() const { return impl_->pipeline->awake_count(); }
template <class T>
bool BasicGpuWorld<T>::on_device() const { return impl_->pipeline->on_device(); }
template <class T>
std::string BasicGpuWorld<T>::description() const { return impl_->pipeline->description(); }
template <class T>
const StageCounters& BasicGpuWorld<T>::counters() const {
  impl_->total = sum(impl_->base, impl_->pipeline->counters());
  impl_->total.wakes += impl_->inputs->wakes();
  return impl_->total;
}
template <class T>
StageTimes BasicGpuWorld<T>::stage_times() const { return impl_->pipeline->stage_times(); }
template <class T>
void BasicGpuWorld<T>::reset_stage_times() { impl_->pipeline->reset_stage_times(); }

template <class T>
const Scene& BasicGpuWorld<T>::scene() const { return impl_->scene; }
template <class T>
bool BasicGpuWorld<T>::jacobi() const { return impl_->options.pair_solver == GpuOptions::PairSolver::kJacobi; }

template <class T>
std::vector<std::uint8_t> BasicGpuWorld<T>::save_state() const {
  std::vector<std::uint8_t> out;
  save_state(out);
  return out;
}

template <class T>
void BasicGpuWorld<T>::save_state(std::vector<std::uint8_t>& out) const {
  flush();
  GpuState<T> s;
  impl_->pipeline->save(s);
  s.counters = counters();
  const BodyIds& ids = impl_->inputs->ids();
  if (!ids.identity()) {
    for (std::size_t k = 0; k < ids.slots(); ++k) s.generations.push_back(ids.generation(k));
    for (std::size_t i = 0; i < ids.bodies(); ++i) s.slot_of_body.push_back(ids.slot_of(i));
  }
  out.clear();
  snap::Writer w(out);
  snap::write_header(w, snapshot_number<T>(), static_cast<std::uint32_t>(s.pos.size()), impl_->constants_hash,
                     static_cast<std::uint32_t>(s.frame));
  w.bytes(impl_->scene_section.data(), impl_->scene_section.size());
  write_gpu_state(out, s, jacobi() ? kSnapshotJacobi : 0, impl_->shape.oriented, impl_->pipeline->imm_stride());
  snap::finish(out);
}

template <class T>
std::unique_ptr<BasicGpuWorld<T>> BasicGpuWorld<T>::load_state(const std::uint8_t* data, std::size_t size,
                                                               const GpuOptions& options) {
  const SnapshotInfo info = read_snapshot_info(data, size);
  if (info.number != snapshot_number<T>()) foreign(info.number, engine_name<T>());
  snap::Reader r(data + kSnapshotHeaderSize, size - kSnapshotHeaderSize - kSnapshotChecksumSize);
  Scene scene = snap::read_checked_scene(r, info, Num<T>::kName, Num<T>::kExact ? "the gpu-fixed engine" : "the gpu engine");
  const InitialState<T> shape = make_initial_state<T>(scene);
  std::uint8_t opts = 0;
  const GpuState<T> st = read_gpu_state(data + kSnapshotHeaderSize + r.pos(), r.left(), shape, imm_stride_of(shape),
                                     info.frame, opts);
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    BodyDesc& d = scene.bodies[i];
    const T4<T> p = st.pos[i], q = st.rot[i], v = st.vel[i], w = st.ang[i];
    auto d1 = [](const T& x) { return Num<T>::to_double(x); };
    d.position = {d1(p.x), d1(p.y), d1(p.z)};
    d.orientation = {d1(q.x), d1(q.y), d1(q.z), d1(q.w)};
    d.velocity = {d1(v.x), d1(v.y), d1(v.z)};
    d.angular_velocity = {d1(w.x), d1(w.y), d1(w.z)};
    d.asleep = (st.flags[i] & kFlagAsleep) != 0;
  }
  GpuOptions o = options;
  o.pair_solver = (opts & kSnapshotJacobi) ? GpuOptions::PairSolver::kJacobi : GpuOptions::PairSolver::kColoured;
  auto world = std::make_unique<BasicGpuWorld<T>>(scene, o);
  world->impl_->pipeline->load(st);
  world->impl_->mirror_frame = -1;
  world->impl_->inputs->set_ids(ids_of(st, scene.bodies.size()));
  return world;
}

template <class T>
void BasicGpuWorld<T>::restore_state(const std::uint8_t* data, std::size_t size) {
  const SnapshotInfo info = read_snapshot_info(data, size);
  // Inputs since the last step are rolled back with the rest: the pipeline
  // (which they have not reached) is what the snapshot replaces.
  if (impl_->inputs->pending()) impl_->inputs = std::make_unique<GpuInputs<T>>(impl_->scene);
  if (info.number != snapshot_number<T>()) foreign(info.number, engine_name<T>());
  const std::vector<std::uint8_t>& section = impl_->scene_section;
  const std::size_t at = kSnapshotHeaderSize + section.size();
  if (info.body_count == static_cast<std::uint32_t>(body_count()) && info.constants_hash == impl_->constants_hash &&
      size >= at + kSnapshotChecksumSize && std::memcmp(data + kSnapshotHeaderSize, section.data(), section.size()) == 0) {
    std::uint8_t opts = 0;
    const GpuState<T> st = read_gpu_state(data + at, size - at - kSnapshotChecksumSize, impl_->shape,
                                       impl_->pipeline->imm_stride(), info.frame, opts);
    if (((opts & kSnapshotJacobi) != 0) != jacobi())
      throw SnapshotError(std::string("a snapshot of the ") + engine_name<T>() + ((opts & kSnapshotJacobi) ? "-jacobi" : "") +
                              " engine cannot be restored into the " + engine_name<T>() + (jacobi() ? "-jacobi" : "") + " engine",
                          "gpu.options");
    impl_->pipeline->load(st);
    impl_->mirror_frame = -1;
    impl_->inputs = std::make_unique<GpuInputs<T>>(impl_->scene);
    impl_->inputs->set_ids(ids_of(st, static_cast<std::size_t>(body_count())));
    impl_->base = StageCounters{};
    return;
  }
  std::unique_ptr<BasicGpuWorld> fresh = load_state(data, size, impl_->options);
  impl_ = std::move(fresh->impl_);
}

template <class T>
BodySnapshot BasicGpuWorld<T>::body(int i) const {
  const HostState<T>& s = impl_->state();
  const auto k = static_cast<std::size_t>(i);
  const T4<T> p = s.pos.at(k), q = s.rot[k], v = s.vel[k], w = s.ang[k];
  const bool asleep = (s.flags[k] & kFlagAsleep) != 0;
  auto d = [](const T& x) { return Num<T>::to_double(x); };
  return {{d(p.x), d(p.y), d(p.z)}, {d(q.x), d(q.y), d(q.z), d(q.w)}, {d(v.x), d(v.y), d(v.z)}, {d(w.x), d(w.y), d(w.z)},
          asleep, asleep ? s.sleep_frame[k] : -1};
}

// eq 92 as World<T>::state_hash computes it: FNV-1a 64 over the IEEE
// binary64 bits of each value (float) or its raw int32 (Q16), then the
// asleep byte.
template <class T>
std::uint64_t BasicGpuWorld<T>::state_hash() const {
  const HostState<T>& s = impl_->state();
  std::uint64_t h = 0xcbf29ce484222325ull;
  auto byte = [&h](std::uint8_t b) { h ^= b; h *= 0x100000001b3ull; };
  auto value = [&](const T& x) {
    if constexpr (Num<T>::kExact) {
      const auto u = static_cast<std::uint32_t>(x.raw());
      for (int sh = 0; sh < 32; sh += 8) byte(static_cast<std::uint8_t>(u >> sh));
    } else {
      const double d = static_cast<double>(x);
      std::uint64_t u;
      std::memcpy(&u, &d, sizeof u);
      for (int sh = 0; sh < 64; sh += 8) byte(static_cast<std::uint8_t>(u >> sh));
    }
  };
  for (std::size_t i = 0; i < s.pos.size(); ++i) {
    const T4<T> p = s.pos[i], q = s.rot[i], v = s.vel[i], w = s.ang[i];
    for (const T& x : {p.x, p.y, p.z, q.x, q.y, q.z, q.w, v.x, v.y, v.z, w.x, w.y, w.z}) value(x);
    byte((s.flags[i] & kFlagAsleep) ? 1 : 0);
  }
  return h;
}

// World<T>::energy: kinetic (linear and angular) plus gravitational potential, in double.
template <class T>
double BasicGpuWorld<T>::energy() const {
  const HostState<T>& s = impl_->state();
  const Vec3d& g = impl_->gravity;
  auto d = [](const T& x) { return Num<T>::to_double(x); };
  double e = 0.0;
  for (std::size_t i = 0; i < s.pos.size(); ++i) {
    if (s.flags[i] & kFlagStatic) continue;
    const T4<T> p = s.pos[i], v = s.vel[i];
    const double m = 1.0 / d(p.w);
    const double vx = d(v.x), vy = d(v.y), vz = d(v.z);
    e += 0.5 * m * (vx * vx + vy * vy + vz * vz);
    e -= m * (g.x * d(p.x) + g.y * d(p.y) + g.z * d(p.z));
    const Mat3<T> R = rotation_matrix(quat(s.rot[i]));
    const Vec3<T> wb = mat_transpose_mul(R, xyz(s.ang[i]));
    const Vec3<T> inv_i = xyz(impl_->inert_now()[i]);
    for (int a = 0; a < 3; ++a) {
      const double ii = d(inv_i[a]);
      if (ii > 0.0) e += 0.5 * d(wb[a]) * d(wb[a]) / ii;
    }
  }
  Num<T>::take_faults();  // a diagnostic: its Q16 faults are not the run's
  return e;
}

template class BasicGpuWorld<float>;
template class BasicGpuWorld<Q16>;

}  // namespace gpu

namespace {

template <class T>
class GpuRun final : public EngineRun {
 public:
  GpuRun(const Scene& scene, bool jacobi, bool quiet)
      : owned_(std::make_unique<gpu::BasicGpuWorld<T>>(scene, options(jacobi, quiet))), world_(*owned_), jacobi_(jacobi) {}
  std::string name() const override {
    const std::string base = Num<T>::kExact ? "gpu-fixed" : "gpu";
    return jacobi_ ? base + "-jacobi" : base;
  }
  std::string description() const override {
    return jacobi_ ? world_.description() + ", Jacobi pair solver" : world_.description();
  }
  void step() override { world_.step(); }
  void apply(const Input& input) override { world_.apply(input); }
  int frame() const override { return world_.frame(); }
  int body_count() const override { return world_.body_count(); }
  BodySnapshot body(int i) const override { return world_.body(i); }
  std::uint64_t state_hash() const override { return world_.state_hash(); }
  double energy() const override { return world_.energy(); }
  StageCounters counters() const override { return world_.counters(); }
  std::vector<std::uint8_t> save_state() const override { return world_.save_state(); }
  // A world loaded from a snapshot (resume_gpu_engine).
  GpuRun(std::unique_ptr<gpu::BasicGpuWorld<T>> world, bool jacobi) : owned_(std::move(world)), world_(*owned_), jacobi_(jacobi) {}

 private:
  static gpu::GpuOptions options(bool jacobi, bool quiet) {
    gpu::GpuOptions o;
    o.quiet = quiet;
    if (jacobi) o.pair_solver = gpu::GpuOptions::PairSolver::kJacobi;
    return o;
  }
  std::unique_ptr<gpu::BasicGpuWorld<T>> owned_;  // a world loaded from a snapshot
  gpu::BasicGpuWorld<T>& world_;
  bool jacobi_;
};

template <class T>
ResumedEngine resume(const std::vector<std::uint8_t>& bytes, bool quiet) {
  gpu::GpuOptions o;
  o.quiet = quiet;
  std::unique_ptr<gpu::BasicGpuWorld<T>> world = gpu::BasicGpuWorld<T>::load_state(bytes.data(), bytes.size(), o);
  Scene scene = world->scene();
  const bool jacobi = world->jacobi();
  return {std::make_unique<GpuRun<T>>(std::move(world), jacobi), std::move(scene)};
}

}  // namespace

std::unique_ptr<EngineRun> make_gpu_engine(const Scene& scene, bool jacobi, bool quiet) {
  return std::make_unique<GpuRun<float>>(scene, jacobi, quiet);
}

std::unique_ptr<EngineRun> make_gpu_fixed_engine(const Scene& scene, bool jacobi, bool quiet) {
  return std::make_unique<GpuRun<Q16>>(scene, jacobi, quiet);
}

ResumedEngine resume_gpu_engine(const std::vector<std::uint8_t>& bytes, bool quiet) {
  if (read_snapshot_info(bytes.data(), bytes.size()).number == SnapshotNumber::kGpuFixed) return resume<Q16>(bytes, quiet);
  return resume<float>(bytes, quiet);
}

}  // namespace lockstep
