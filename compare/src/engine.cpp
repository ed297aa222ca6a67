#include "lockstep/compare/engine.hpp"

#include <algorithm>
#include <stdexcept>
#include <type_traits>

#include "lockstep/fixed/q16_vec.hpp"
#include "lockstep/math/num_mp.hpp"
#include "lockstep/scene_limits.hpp"
#if LOCKSTEP_HAVE_GPU_ENGINE
#include "lockstep/gpu/gpu_engine.hpp"
#endif

namespace lockstep {

template <class T>
std::string WorldRun<T>::description() const {
  if constexpr (std::is_same_v<T, Q16>) return "fixed: Q16.16, bit-exact";
  else if constexpr (std::is_same_v<T, float>) return "float: IEEE binary32, reference engine";
  else if constexpr (std::is_same_v<T, double>) return "double: IEEE binary64, reference engine";
  else return "mp: Boost.Multiprecision 113-bit binary float (the truth)";
}

template <class T>
BodySnapshot WorldRun<T>::body(int i) const { return snapshot_of(world_.body(i)); }

template <class T>
std::vector<StageState> WorldRun<T>::step_stages() {
  std::vector<StageState> out;
  out.reserve(kFrameStageCount);
  world_.step([&out](FrameStage s, World<T>& w) {
    StageState st{frame_stage_name(s), {}};
    st.bodies.reserve(w.bodies().size());
    for (const Body<T>& b : w.bodies()) st.bodies.push_back(snapshot_of(b));
    out.push_back(std::move(st));
  });
  return out;
}

template <class T>
std::vector<std::int32_t> WorldRun<T>::raw_state(int i) const {
  if constexpr (std::is_same_v<T, Q16>) {
    const Body<T>& b = world_.body(i);
    std::vector<std::int32_t> out;
    for (const Q16& x : {b.p.x, b.p.y, b.p.z, b.q.w, b.q.x, b.q.y, b.q.z, b.v.x, b.v.y, b.v.z, b.w.x, b.w.y, b.w.z})
      out.push_back(x.raw());
    return out;
  } else {
    (void)i;
    return {};
  }
}

template <class T>
std::vector<ContactSnapshot> WorldRun<T>::contacts() const {
  auto d = [](const T& x) { return Num<T>::to_double(x); };
  std::vector<ContactSnapshot> out;
  out.reserve(world_.contacts().size());
  for (const Contact<T>& c : world_.contacts())
    out.push_back({c.a, c.b, {d(c.point.x), d(c.point.y), d(c.point.z)}, {d(c.n.x), d(c.n.y), d(c.n.z)}, d(c.penetration)});
  return out;
}

namespace {
bool quiet_engines = false;

template <class T>
ResumedEngine resumed(const std::vector<std::uint8_t>& bytes) {
  World<T> w = World<T>::load_state(bytes);
  Scene scene = w.scene();
  return {std::make_unique<WorldRun<T>>(std::move(w)), std::move(scene)};
}
}  // namespace

ResumedEngine engine_from_snapshot(const std::vector<std::uint8_t>& bytes) {
  switch (read_snapshot_info(bytes.data(), bytes.size()).number) {
    case SnapshotNumber::kFixed: return resumed<Q16>(bytes);
    case SnapshotNumber::kFloat: return resumed<float>(bytes);
    case SnapshotNumber::kDouble: return resumed<double>(bytes);
    case SnapshotNumber::kMp: return resumed<Mp>(bytes);
    case SnapshotNumber::kGpu:
    case SnapshotNumber::kGpuFixed:
#if LOCKSTEP_HAVE_GPU_ENGINE
      return resume_gpu_engine(bytes, quiet_engines);
#else
      throw SnapshotError("a snapshot of the gpu engine, which this build lacks", "header.number_type");
#endif
  }
  throw SnapshotError("unknown number type", "header.number_type");
}

template class WorldRun<Q16>;
template class WorldRun<float>;
template class WorldRun<double>;
template class WorldRun<Mp>;

std::vector<std::string> engine_names() {
  std::vector<std::string> names{"fixed", "float", "double", "mp"};
#if LOCKSTEP_HAVE_GPU_ENGINE
  names.emplace_back("gpu");
#endif
  return names;
}

std::vector<std::string> engine_variants() {
#if LOCKSTEP_HAVE_GPU_ENGINE
  return {"gpu-jacobi", "gpu-fixed"};
#else
  return {};
#endif
}

std::vector<std::string> accepted_engine_names() {
  std::vector<std::string> names = engine_names();
  for (std::string& v : engine_variants()) names.push_back(std::move(v));
  return names;
}

std::string engine_limitation(std::string_view, const Scene&) {
  // Every engine runs both pair models (the GPU engine's oriented-box model:
  // issue 12, docs/GPU.md "Pair models"); an engine that implements part of
  // the spec says here which scenes it cannot run, and why.
  return "";
}

std::vector<std::string> engine_names_for(const Scene& scene) {
  std::vector<std::string> out;
  for (std::string& n : engine_names())
    if (engine_limitation(n, scene).empty()) out.push_back(std::move(n));
  return out;
}

void set_quiet_engines(bool quiet) { quiet_engines = quiet; }

std::string gpu_build_description() {
#if LOCKSTEP_HAVE_GPU_ENGINE
  if (!gpu::built_with_cuda()) return "host build only (built without CUDA)";
  return gpu::cuda_device_available() ? "CUDA (a device is present)" : "CUDA (no device found: runs the host build)";
#else
  return "not built";
#endif
}

std::unique_ptr<EngineRun> make_engine(std::string_view name, const Scene& scene) {
  if (const std::string why = engine_limitation(name, scene); !why.empty()) throw std::invalid_argument(why);
  // A body whose derived quantities the engine's number type cannot hold
  // (docs/SCENES.md "Ranges per number type"): refused here with the field
  // and a fix, not at frame 0 with a RunError.
  const auto accepted = accepted_engine_names();
  if (std::find(accepted.begin(), accepted.end(), name) != accepted.end())
    validate_scene_for(number_type_of_engine(name), scene);
  if (name == "fixed") return std::make_unique<WorldRun<Q16>>(scene);
  if (name == "float") return std::make_unique<WorldRun<float>>(scene);
  if (name == "double") return std::make_unique<WorldRun<double>>(scene);
  if (name == "mp") return std::make_unique<WorldRun<Mp>>(scene);
#if LOCKSTEP_HAVE_GPU_ENGINE
  if (name == "gpu") return make_gpu_engine(scene, false, quiet_engines);
  if (name == "gpu-jacobi") return make_gpu_engine(scene, true, quiet_engines);
  if (name == "gpu-fixed") return make_gpu_fixed_engine(scene, false, quiet_engines);
#endif
  std::string allowed;
  for (const std::string& n : accepted_engine_names()) allowed += (allowed.empty() ? "" : ", ") + n;
  throw std::invalid_argument("--engine: unknown engine '" + std::string(name) + "'; allowed: " + allowed);
}

}  // namespace lockstep
