// lockstep_certify_driver: runs built-in scenes on the fixed engine and prints
// the state hash (eq 92) after every frame, for vectors/certify/certify.py.
//
// Built from the fixed engine's sources only (fixed/src/q16.cpp,
// reference/src/{run_error,world_fixed,builtin_scenes,sdf_generators}.cpp and
// this file): no Boost, no JSON library, so every cross compiler builds it.
// With -DLOCKSTEP_CERTIFY_GPU_FIXED (and gpu/src/{host,initial_state}.cpp) it
// runs gpu-fixed instead, the GPU engine's pipeline on Q16.16, host build
// (docs/GPU.md "gpu-fixed"): certify.py's gpu-fixed rows, the same records.
//
// usage: lockstep_certify_driver [--frames SCENE=N]... [--dump SCENE FRAME] [--info] [SCENE...]
//   SCENE...          scenes to run (default: every built-in scene)
//   --frames S=N      run scene S for N frames only (default: the scene's own count)
//   --dump S F        print the full raw state of scene S after frame F, then exit
//   --info            print what the binary knows about its build, then exit
//
// Output (one record per line, fields separated by one space):
//   build <key>=<value>...                    (--info; also first line of a run)
//   scene <name> bodies <n> frames <n>
//   h <frame> <hash as 16 hex digits>         frame 0 = the loaded scene
//   sleep <body> <frame>                      the frame each body last fell asleep, -1 if awake at the end
//   end <name>
//   error <name> frame <f> body <b> <quantity>: <message>   (a RunError)
//   state <frame> <body> px py pz qw qx qy qz vx vy vz wx wy wz asleep sleep_counter
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "lockstep/builtin_scenes.hpp"
#include "lockstep/fixed/q16_vec.hpp"
#include "lockstep/world.hpp"
#if defined(LOCKSTEP_CERTIFY_GPU_FIXED)
#include "gpu_fixed_engine.hpp"
#endif

namespace {

using lockstep::Q16;
#if defined(LOCKSTEP_CERTIFY_GPU_FIXED)
using World = lockstep::certify::GpuFixedEngine;  // World<Q16>'s interface, as the driver uses it
constexpr const char* kEngine = "gpu-fixed";
#else
using World = lockstep::World<Q16>;
constexpr const char* kEngine = "fixed";
#endif

const char* compiler() {
#if defined(__clang__)
  return "clang-" __clang_version__;
#elif defined(__GNUC__)
  return "gcc-" __VERSION__;
#else
  return "unknown";
#endif
}

bool little_endian() {
  const std::uint32_t one = 1;
  unsigned char b = 0;
  std::memcpy(&b, &one, 1);
  return b == 1;
}

void print_build() {
  std::string opt = "none";
#if defined(__OPTIMIZE__)
  opt = "on";
#endif
#if defined(__FAST_MATH__)
  const char* fast = "yes";
#else
  const char* fast = "no";
#endif
  std::string cc = compiler();
  while (!cc.empty() && cc.back() == ' ') cc.pop_back();
  for (char& c : cc)
    if (c == ' ') c = '_';
  std::printf("build compiler=%s pointer_bits=%zu endian=%s optimize=%s fast_math=%s engine=%s\n", cc.c_str(),
              sizeof(void*) * 8, little_endian() ? "little" : "big", opt.c_str(), fast, kEngine);
}

void print_state(const World& w) {
  for (std::size_t i = 0; i < w.bodies().size(); ++i) {
    const auto& b = w.bodies()[i];
    std::printf("state %d %zu %" PRId32 " %" PRId32 " %" PRId32 " %" PRId32 " %" PRId32 " %" PRId32 " %" PRId32
                " %" PRId32 " %" PRId32 " %" PRId32 " %" PRId32 " %" PRId32 " %" PRId32 " %d %d\n",
                w.frame(), i, b.p.x.raw(), b.p.y.raw(), b.p.z.raw(), b.q.w.raw(), b.q.x.raw(), b.q.y.raw(), b.q.z.raw(),
                b.v.x.raw(), b.v.y.raw(), b.v.z.raw(), b.w.x.raw(), b.w.y.raw(), b.w.z.raw(), b.asleep ? 1 : 0,
                b.sleep_counter);
  }
}

int usage(const char* why) {
  std::fprintf(stderr,
               "lockstep_certify_driver: %s\n"
               "usage: lockstep_certify_driver [--frames SCENE=N]... [--dump SCENE FRAME] [--info] [SCENE...]\n",
               why);
  return 2;
}

bool parse_int(const char* s, long lo, long hi, long& out) {
  char* end = nullptr;
  const long v = std::strtol(s, &end, 10);
  if (end == s || *end != '\0' || v < lo || v > hi) return false;
  out = v;
  return true;
}

// Runs one scene for `frames` frames; prints hashes, sleep frames (or the error).
// With dump_frame >= 0 prints only the state after that frame.
int run_scene(const std::string& name, long frames, long dump_frame) {
  const auto scene = lockstep::builtin_scene(name);
  if (!scene) return usage(("unknown scene '" + name + "'").c_str());
  if (frames < 0) frames = scene->frames;
  try {
    World world(*scene);
    if (dump_frame >= 0) {
      while (world.frame() < dump_frame) world.step();
      print_state(world);
      return 0;
    }
    std::printf("scene %s bodies %zu frames %ld\n", name.c_str(), world.bodies().size(), frames);
    std::printf("h 0 %016" PRIx64 "\n", world.state_hash());
    for (long f = 1; f <= frames; ++f) {
      world.step();
      std::printf("h %ld %016" PRIx64 "\n", f, world.state_hash());
    }
    for (std::size_t i = 0; i < world.bodies().size(); ++i) {
      const auto& b = world.bodies()[i];
      std::printf("sleep %zu %d\n", i, b.asleep ? b.sleep_frame : -1);
    }
    std::printf("end %s\n", name.c_str());
  } catch (const lockstep::RunError& e) {
    std::printf("error %s frame %d body %d %s: %s\n", name.c_str(), e.frame, e.body, e.quantity.c_str(), e.what());
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::pair<std::string, long>> frame_limits;
  std::vector<std::string> scenes;
  std::string dump_scene;
  long dump_frame = -1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--info") {
      print_build();
      return 0;
    }
    if (a == "--frames") {
      if (i + 1 >= argc) return usage("--frames needs SCENE=N");
      const std::string v = argv[++i];
      const auto eq = v.find('=');
      long n = 0;
      if (eq == std::string::npos || !parse_int(v.c_str() + eq + 1, 0, 10'000'000, n))
        return usage("--frames needs SCENE=N with N in [0, 10000000]");
      frame_limits.emplace_back(v.substr(0, eq), n);
    } else if (a == "--dump") {
      if (i + 2 >= argc) return usage("--dump needs SCENE FRAME");
      dump_scene = argv[++i];
      if (!parse_int(argv[++i], 0, 10'000'000, dump_frame)) return usage("--dump: FRAME must be an integer >= 0");
    } else if (!a.empty() && a[0] == '-') {
      return usage(("unknown option '" + a + "'").c_str());
    } else {
      scenes.push_back(a);
    }
  }
  if (!dump_scene.empty()) return run_scene(dump_scene, -1, dump_frame);
  if (scenes.empty()) scenes = lockstep::builtin_scene_names();
  print_build();
  int rc = 0;
  for (const std::string& s : scenes) {
    long frames = -1;
    for (const auto& [name, n] : frame_limits)
      if (name == s) frames = n;
    const int r = run_scene(s, frames, -1);
    if (r == 2) return r;
    if (r != 0) rc = 1;
  }
  return rc;
}
