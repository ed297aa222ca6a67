// The cross-build replayer (tests/compare/cross_replay.py, docs/RECORDINGS.md
// "Between builds"): a recording of the fixed engine replayed by a build of
// the fixed engine alone (no Boost, no GPU engine, no command-line library),
// small enough to cross-compile for aarch64 and run under qemu-user.
//   replay_tool RECORDING
// prints "no difference over N frames" (exit 0), or the first frame whose
// hash differs and, where the recording holds a snapshot of that frame, the
// first body and field that differ (exit 1); a bad recording exits 2.
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>

#include "lockstep/compare/recording.hpp"
#include "lockstep/compare/world_inputs.hpp"
#include "lockstep/fixed/q16_vec.hpp"
#include "lockstep/world.hpp"

using namespace lockstep;

namespace {

const char* arch() {
#if defined(__aarch64__)
  return "aarch64";
#elif defined(__x86_64__)
  return "x86_64";
#else
  return "another architecture";
#endif
}

// The first raw Q16.16 field of body i that differs, or "".
std::string field_difference(const Body<Q16>& a, const Body<Q16>& b) {
  const char* names[] = {"p.x", "p.y", "p.z", "q.w", "q.x", "q.y", "q.z", "v.x", "v.y", "v.z", "w.x", "w.y", "w.z"};
  const Q16 x[] = {a.p.x, a.p.y, a.p.z, a.q.w, a.q.x, a.q.y, a.q.z, a.v.x, a.v.y, a.v.z, a.w.x, a.w.y, a.w.z};
  const Q16 y[] = {b.p.x, b.p.y, b.p.z, b.q.w, b.q.x, b.q.y, b.q.z, b.v.x, b.v.y, b.v.z, b.w.x, b.w.y, b.w.z};
  for (int k = 0; k < 13; ++k)
    if (x[k].raw() != y[k].raw())
      return std::string(names[k]) + ": recorded raw " + std::to_string(x[k].raw()) + ", replayed raw " + std::to_string(y[k].raw());
  if (a.asleep != b.asleep) return "asleep";
  if (a.sleep_counter != b.sleep_counter) return "sleep_counter";
  return "";
}

int replay(const std::string& path) {
  const compare::RunRecording rec = compare::load_recording_file(path);
  if (rec.engine != "fixed") {
    std::fprintf(stderr, "replay_tool: %s: a recording of the %s engine; this tool replays the fixed engine's\n",
                 path.c_str(), rec.engine.c_str());
    return 2;
  }
  World<Q16> w(rec.scene);
  std::size_t next = 0;
  for (int f = 1; f <= rec.frames(); ++f) {
    for (; next < rec.inputs.size() && rec.inputs[next].frame == f; ++next) compare::apply_to_world(w, rec.inputs[next]);
    w.step();
    if (w.state_hash() == rec.hashes[static_cast<std::size_t>(f - 1)]) continue;
    std::printf("replay (%s): the hashes differ first at frame %d: recorded %s, replayed %s\n", arch(), f,
                compare::hash_to_hex(rec.hashes[static_cast<std::size_t>(f - 1)]).c_str(),
                compare::hash_to_hex(w.state_hash()).c_str());
    if (const compare::RecordedSnapshot* s = rec.snapshot_at(f)) {
      const World<Q16> recorded = World<Q16>::load_state(s->bytes);
      if (recorded.bodies().size() != w.bodies().size())
        std::printf("  frame %d: %zu bodies recorded, %zu replayed\n", f, recorded.bodies().size(), w.bodies().size());
      for (std::size_t i = 0; i < w.bodies().size() && i < recorded.bodies().size(); ++i) {
        const std::string d = field_difference(recorded.bodies()[i], w.bodies()[i]);
        if (!d.empty()) {
          std::printf("  frame %d: body %zu, field %s\n", f, i, d.c_str());
          break;
        }
      }
    }
    return 1;
  }
  const compare::RecordedSnapshot* last = rec.snapshot_at(rec.frames());
  if (last != nullptr && w.save_state() != last->bytes) {
    std::printf("replay (%s): the hashes agree but the final snapshot differs (sleep counters, records or the warm-start cache)\n", arch());
    return 1;
  }
  std::printf("replay (%s): no difference over %d frames (recorded by %s)\n", arch(), rec.frames(), rec.build.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: replay_tool RECORDING\n");
    return 2;
  }
  try {
    return replay(argv[1]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "replay_tool: %s\n", e.what());
    return 2;
  }
}
