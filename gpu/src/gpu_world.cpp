// GpuWorld: picks the backend, and serves snapshots, the state hash and the
// energy from a host copy of the state downloaded once per frame.
#include <cstdio>
#include <cstring>
#include <mutex>
#include <stdexcept>

#include "lockstep/gpu/formula_cases.hpp"
#include "lockstep/gpu/gpu_engine.hpp"
#include "lockstep/gpu/soa.hpp"
#include "gpu_inputs.hpp"
#include "pipeline_base.hpp"

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
std::unique_ptr<PipelineBase> make_device_pipeline(const InitialState&, const GpuOptions&) {
  throw std::runtime_error("gpu: this build has no CUDA (nvcc was not found or LOCKSTEP_CUDA is off)");
}
#endif

namespace {

std::unique_ptr<PipelineBase> make_pipeline(const InitialState& s, const GpuOptions& options) {
  if (options.backend == Backend::kHost) return make_host_pipeline(s, options, "gpu (host build: requested)");
  const bool cuda = built_with_cuda();
  if (cuda && cuda_device_count() > 0) return make_device_pipeline(s, options);
  if (options.backend == Backend::kDevice)
    throw std::runtime_error(cuda ? "gpu: no CUDA device" : "gpu: this build has no CUDA");
  const char* why = cuda ? "gpu (host build: no CUDA device)" : "gpu (host build: built without CUDA)";
  if (!options.quiet) {
    static std::once_flag once;
    std::call_once(once, [why] { std::fprintf(stderr, "lockstep: %s; running the same engine on the CPU\n", why); });
  }
  return make_host_pipeline(s, options, why);
}

}  // namespace

struct GpuWorld::Impl {
  std::unique_ptr<PipelineBase> pipeline;
  HostState mirror;
  int mirror_frame = -1;
  std::vector<F4> half, inert;  // constants: half extents (w: e), inverse inertia (w: mu)
  Vec3d gravity;
  GpuOptions options;
  std::unique_ptr<GpuInputs> inputs;  // run-time inputs (gpu_inputs.hpp)
  StageCounters base, total;          // base: the counters of the pipelines the inputs replaced
  const std::vector<F4>& inert_now() const { return inputs->pending() ? inputs->inert() : inert; }
  const HostState& state() {
    if (inputs->pending()) return inputs->state();
    if (mirror_frame != pipeline->frame()) {
      pipeline->download(mirror);
      mirror_frame = pipeline->frame();
    }
    return mirror;
  }
};

GpuWorld::GpuWorld(const Scene& scene, const GpuOptions& options) : impl_(std::make_unique<Impl>()) {
  const InitialState s = make_initial_state(scene);
  impl_->half = s.half;
  impl_->inert = s.inert;
  impl_->gravity = scene.constants.gravity;
  impl_->options = options;
  impl_->inputs = std::make_unique<GpuInputs>(scene);
  impl_->pipeline = make_pipeline(s, options);
}

GpuWorld::~GpuWorld() = default;

namespace {
StageCounters sum(StageCounters a, const StageCounters& b) {
  std::uint64_t* x = &a.integrate_velocity;
  const std::uint64_t* y = &b.integrate_velocity;
  static_assert(sizeof(StageCounters) == 16 * sizeof(std::uint64_t), "StageCounters is 16 counters");
  for (int k = 0; k < 16; ++k) x[k] += y[k];
  return a;
}
}  // namespace

void GpuWorld::step() {
  Impl& m = *impl_;
  if (m.inputs->pending()) {  // the inputs since the last step: a new pipeline from their state
    const int frame = m.pipeline->frame();
    m.base = sum(m.base, m.pipeline->counters());
    m.base.wakes += m.inputs->wakes();
    const InitialState s = m.inputs->take_state();
    m.half = s.half;
    m.inert = s.inert;
    GpuOptions quiet = m.options;
    quiet.quiet = true;  // the first pipeline said which backend runs
    m.pipeline = make_pipeline(s, quiet);
    m.pipeline->set_frame(frame);
    m.mirror_frame = -1;
  }
  m.pipeline->step();
}
BodyId GpuWorld::apply(const Input& input) { return impl_->inputs->apply(input, *impl_->pipeline); }
int GpuWorld::index_of(BodyId id) const { return static_cast<int>(impl_->inputs->ids().require(id, "index_of")); }
BodyId GpuWorld::id_of(int index) const {
  if (index < 0) throw std::invalid_argument("id_of: index = " + std::to_string(index) + " is not a body index");
  return impl_->inputs->ids().id_of(static_cast<std::size_t>(index));
}
int GpuWorld::frame() const { return impl_->pipeline->frame(); }
int GpuWorld::body_count() const {
  return impl_->inputs->pending() ? impl_->inputs->body_count() : impl_->pipeline->body_count();
}
int GpuWorld::awake_count() const { return impl_->pipeline->awake_count(); }
bool GpuWorld::on_device() const { return impl_->pipeline->on_device(); }
std::string GpuWorld::description() const { return impl_->pipeline->description(); }
const StageCounters& GpuWorld::counters() const {
  impl_->total = sum(impl_->base, impl_->pipeline->counters());
  impl_->total.wakes += impl_->inputs->wakes();
  return impl_->total;
}
StageTimes GpuWorld::stage_times() const { return impl_->pipeline->stage_times(); }
void GpuWorld::reset_stage_times() { impl_->pipeline->reset_stage_times(); }

BodySnapshot GpuWorld::body(int i) const {
  const HostState& s = impl_->state();
  const auto k = static_cast<std::size_t>(i);
  const F4 p = s.pos.at(k), q = s.rot[k], v = s.vel[k], w = s.ang[k];
  const bool asleep = (s.flags[k] & kFlagAsleep) != 0;
  return {{p.x, p.y, p.z}, {q.x, q.y, q.z, q.w}, {v.x, v.y, v.z}, {w.x, w.y, w.z}, asleep,
          asleep ? s.sleep_frame[k] : -1};
}

// eq 92 as World<float>::state_hash computes it: FNV-1a 64 over the IEEE
// binary64 bits of each value, then the asleep byte.
std::uint64_t GpuWorld::state_hash() const {
  const HostState& s = impl_->state();
  std::uint64_t h = 0xcbf29ce484222325ull;
  auto byte = [&h](std::uint8_t b) { h ^= b; h *= 0x100000001b3ull; };
  auto value = [&](float x) {
    const double d = static_cast<double>(x);
    std::uint64_t u;
    std::memcpy(&u, &d, sizeof u);
    for (int sh = 0; sh < 64; sh += 8) byte(static_cast<std::uint8_t>(u >> sh));
  };
  for (std::size_t i = 0; i < s.pos.size(); ++i) {
    const F4 p = s.pos[i], q = s.rot[i], v = s.vel[i], w = s.ang[i];
    for (float x : {p.x, p.y, p.z, q.x, q.y, q.z, q.w, v.x, v.y, v.z, w.x, w.y, w.z}) value(x);
    byte((s.flags[i] & kFlagAsleep) ? 1 : 0);
  }
  return h;
}

// World<T>::energy: kinetic (linear and angular) plus gravitational potential, in double.
double GpuWorld::energy() const {
  const HostState& s = impl_->state();
  const Vec3d& g = impl_->gravity;
  double e = 0.0;
  for (std::size_t i = 0; i < s.pos.size(); ++i) {
    if (s.flags[i] & kFlagStatic) continue;
    const F4 p = s.pos[i], v = s.vel[i];
    const double m = 1.0 / static_cast<double>(p.w);
    const double vx = v.x, vy = v.y, vz = v.z;
    e += 0.5 * m * (vx * vx + vy * vy + vz * vz);
    e -= m * (g.x * p.x + g.y * p.y + g.z * p.z);
    const Mat3<float> R = rotation_matrix(quat(s.rot[i]));
    const Vec3<float> wb = mat_transpose_mul(R, xyz(s.ang[i]));
    const Vec3<float> inv_i = xyz(impl_->inert_now()[i]);
    for (int a = 0; a < 3; ++a) {
      const double ii = inv_i[a];
      if (ii > 0.0) e += 0.5 * static_cast<double>(wb[a]) * static_cast<double>(wb[a]) / ii;
    }
  }
  return e;
}

}  // namespace gpu

namespace {

class GpuRun final : public EngineRun {
 public:
  GpuRun(const Scene& scene, bool jacobi, bool quiet) : world_(scene, options(jacobi, quiet)), jacobi_(jacobi) {}
  std::string name() const override { return jacobi_ ? "gpu-jacobi" : "gpu"; }
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

 private:
  static gpu::GpuOptions options(bool jacobi, bool quiet) {
    gpu::GpuOptions o;
    o.quiet = quiet;
    if (jacobi) o.pair_solver = gpu::GpuOptions::PairSolver::kJacobi;
    return o;
  }
  gpu::GpuWorld world_;
  bool jacobi_;
};

}  // namespace

std::unique_ptr<EngineRun> make_gpu_engine(const Scene& scene, bool jacobi, bool quiet) {
  return std::make_unique<GpuRun>(scene, jacobi, quiet);
}

}  // namespace lockstep
