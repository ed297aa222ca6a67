// `lockstep run --record` and `lockstep replay` (replay.hpp,
// docs/RECORDINGS.md): the run that records, and the bisection of a replay
// that differs: frame (the hashes), body and field (the states at that
// frame), stage (the frame re-run stage by stage on both sides).
#include "lockstep/compare/replay.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "lockstep/fixed/q16_vec.hpp"
#include "lockstep/math/num_mp.hpp"
#include "lockstep/scene_limits.hpp"

namespace lockstep::compare {

namespace {

// The fields compared, in order.
struct Field {
  const char* name;
  double (*get)(const BodySnapshot&);
};
const Field kFields[] = {
    {"p.x", [](const BodySnapshot& b) { return b.p[0]; }},   {"p.y", [](const BodySnapshot& b) { return b.p[1]; }},
    {"p.z", [](const BodySnapshot& b) { return b.p[2]; }},   {"q.w", [](const BodySnapshot& b) { return b.q[0]; }},
    {"q.x", [](const BodySnapshot& b) { return b.q[1]; }},   {"q.y", [](const BodySnapshot& b) { return b.q[2]; }},
    {"q.z", [](const BodySnapshot& b) { return b.q[3]; }},   {"v.x", [](const BodySnapshot& b) { return b.v[0]; }},
    {"v.y", [](const BodySnapshot& b) { return b.v[1]; }},   {"v.z", [](const BodySnapshot& b) { return b.v[2]; }},
    {"w.x", [](const BodySnapshot& b) { return b.w[0]; }},   {"w.y", [](const BodySnapshot& b) { return b.w[1]; }},
    {"w.z", [](const BodySnapshot& b) { return b.w[2]; }},
    {"asleep", [](const BodySnapshot& b) { return b.asleep ? 1.0 : 0.0; }},
    {"sleep_frame", [](const BodySnapshot& b) { return static_cast<double>(b.sleep_frame); }},
};

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// An engine at frame `to` of the recording (inputs applied), with the
// recorded hashes checked on the way: agrees_to is the last frame whose hash
// equals the recording's.
struct Rerun {
  std::unique_ptr<EngineRun> engine;
  int agrees_to = 0;
  std::size_t next_input = 0;
};

void advance(Rerun& r, const RunRecording& rec, int to) {
  while (r.engine->frame() < to) {
    const int f = r.engine->frame() + 1;
    for (; r.next_input < rec.inputs.size() && rec.inputs[r.next_input].frame == f; ++r.next_input)
      apply_input(*r.engine, rec.inputs[r.next_input]);
    r.engine->step();
    if (r.agrees_to == f - 1 && r.engine->state_hash() == rec.hashes[static_cast<std::size_t>(f - 1)]) r.agrees_to = f;
  }
}

void apply_inputs_of(Rerun& r, const RunRecording& rec, int f) {
  for (; r.next_input < rec.inputs.size() && rec.inputs[r.next_input].frame == f; ++r.next_input)
    apply_input(*r.engine, rec.inputs[r.next_input]);
}

std::vector<BodySnapshot> bodies_of(const EngineRun& e) {
  std::vector<BodySnapshot> out;
  out.reserve(static_cast<std::size_t>(e.body_count()));
  for (int i = 0; i < e.body_count(); ++i) out.push_back(e.body(i));
  return out;
}

std::string value_text(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

}  // namespace

void apply_input(EngineRun& e, const Input& in) { e.apply(in); }

RunRecorder::RunRecorder(const std::string& engine_name, const Scene& scene, std::vector<Input> inputs, int frames,
                         const RecordRunOptions& o) {
  validate_inputs(inputs, scene, frames, "--inputs");
  rec_.engine = engine_name;
  rec_.build = o.build;
  rec_.scene = scene;
  rec_.scene.frames = frames;
  rec_.inputs = std::move(inputs);
  rec_.snapshot_every = o.snapshot_every;
  rec_.hashes.reserve(static_cast<std::size_t>(frames));
}

void RunRecorder::before_step(EngineRun& engine) {
  const int f = engine.frame() + 1;
  for (; next_ < rec_.inputs.size() && rec_.inputs[next_].frame == f; ++next_) apply_input(engine, rec_.inputs[next_]);
}

void RunRecorder::after_step(const EngineRun& engine) {
  const int f = engine.frame();
  rec_.hashes.push_back(engine.state_hash());
  if (f == rec_.scene.frames || (rec_.snapshot_every > 0 && f % rec_.snapshot_every == 0))
    rec_.snapshots.push_back({f, engine.save_state()});
}

RunRecording record_run(EngineRun& engine, const std::string& engine_name, const Scene& scene,
                        const std::vector<Input>& inputs, int frames, const RecordRunOptions& o) {
  RunRecorder recorder(engine_name, scene, inputs, frames, o);
  if (o.after_frame) o.after_frame(engine);
  for (int f = 1; f <= frames; ++f) {
    recorder.before_step(engine);
    engine.step();
    recorder.after_step(engine);
    if (o.after_frame) o.after_frame(engine);
  }
  return recorder.recording();
}

BodyDifference first_body_difference(const std::vector<BodySnapshot>& a, const std::vector<BodySnapshot>& b) {
  BodyDifference d;
  if (a.size() != b.size()) {
    d.field = "body count";
    d.recorded = static_cast<double>(a.size());
    d.replayed = static_cast<double>(b.size());
    d.bodies_differing = -1;
    return d;
  }
  for (std::size_t i = 0; i < a.size(); ++i) {
    for (const Field& f : kFields) {
      if (same_bits(f.get(a[i]), f.get(b[i]))) continue;
      if (d.body < 0) {
        d.body = static_cast<int>(i);
        d.field = f.name;
        d.recorded = f.get(a[i]);
        d.replayed = f.get(b[i]);
      }
      ++d.bodies_differing;
      break;
    }
  }
  return d;
}

ReplayReport replay(const RunRecording& rec, const std::string& engine, const EngineFactory& make) {
  ReplayReport r;
  r.recorded_engine = rec.engine;
  r.engine = engine;
  r.recorded_build = rec.build;
  // 1: the frame. The replay, its hashes against the recording's.
  Rerun run{make(engine, rec.scene), 0, 0};
  try {
    advance(run, rec, rec.frames());
  } catch (const RunError& e) {
    r.first_frame = e.frame;
    r.replay_stopped = e.what();
  }
  if (r.first_frame < 0 && run.agrees_to == rec.frames()) {
    r.frames = rec.frames();
    return r;
  }
  if (r.first_frame < 0 || run.agrees_to + 1 < r.first_frame) r.first_frame = run.agrees_to + 1;
  const int f = r.first_frame;
  r.frames = f;
  r.recorded_hash = rec.hashes[static_cast<std::size_t>(f - 1)];
  // "gpu-jacobi" is a gpu engine (float), "gpu-fixed" one on Q16.16 (fixed);
  // a test's "fixed-perturbed" a fixed one.
  auto number_type = [](const std::string& name) {
    return number_type_of_engine(name.rfind("gpu", 0) == 0 ? name : name.substr(0, name.find('-')));
  };
  if (number_type(engine) != number_type(rec.engine))
    r.note = "the engines compute in different number types (" + number_type(rec.engine) + ", " +
             number_type(engine) + "): their bits part at the first frame that computes anything; "
             "this is expected, not a fault (lockstep compare judges such runs against tolerances)";
  // 2 and 3: both sides at frame f - 1, then frame f stage by stage.
  Rerun mine{make(engine, rec.scene), 0, 0};
  Rerun theirs{make(rec.engine, rec.scene), 0, 0};
  std::vector<StageState> my_stages, their_stages;
  std::vector<BodySnapshot> before_mine, before_theirs;  // frame f - 1, the inputs of frame f applied
  bool mine_ok = true;
  try {
    advance(mine, rec, f - 1);
    apply_inputs_of(mine, rec, f);
    before_mine = bodies_of(*mine.engine);
    my_stages = mine.engine->step_stages();
    r.replayed_hash = mine.engine->state_hash();
  } catch (const RunError& e) {
    mine_ok = false;
    r.replay_stopped = e.what();
  }
  bool reproduced = false;
  try {
    advance(theirs, rec, f - 1);
    apply_inputs_of(theirs, rec, f);
    before_theirs = bodies_of(*theirs.engine);
    their_stages = theirs.engine->step_stages();
    reproduced = theirs.agrees_to == f - 1 && theirs.engine->state_hash() == r.recorded_hash;
  } catch (const RunError&) {
    reproduced = false;
  }
  if (reproduced && mine_ok) {
    r.diff_frame = f;
    r.recorder_state = "the " + rec.engine + " engine re-run in this build (its hashes equal the recording's to frame " +
                       std::to_string(f) + ")";
    r.body = first_body_difference(bodies_of(*theirs.engine), bodies_of(*mine.engine));
    if (my_stages.empty() || their_stages.empty()) {
      r.stage_note = "the " + (my_stages.empty() ? engine : rec.engine) +
                     " engine cannot stop between the stages of a frame (the CPU engines can)";
    } else if (const BodyDifference d0 = first_body_difference(before_theirs, before_mine); d0.body >= 0 || d0.bodies_differing < 0) {
      r.stage = f == 1 ? "before frame 1: the initial states differ (the scene's values in each engine's number type)"
                       : "before frame " + std::to_string(f) + ": the bodies differ at frame " + std::to_string(f - 1) +
                             " already, in a field its hash does not cover";
      r.stage_body = d0;
    } else {
      for (std::size_t s = 0; s < my_stages.size() && s < their_stages.size(); ++s) {
        const BodyDifference d = first_body_difference(their_stages[s].bodies, my_stages[s].bodies);
        if (d.body >= 0 || d.bodies_differing < 0) {
          r.stage = their_stages[s].stage;
          r.stage_body = d;
          break;
        }
      }
      if (r.stage.empty())
        r.stage_note = "every stage leaves the bodies equal: the runs part in state the hash covers but the stages' "
                       "body states do not show (e.g. the frame's end)";
    }
    return r;
  }
  // The recorder's state is out of this build's reach (another build): the
  // recording's first snapshot at or after frame f, against the replay there.
  r.stage_note = "the recorder's frame cannot be re-run here: the " + rec.engine + " engine of this build " +
                 (theirs.agrees_to < f - 1 ? "differs from the recording from frame " + std::to_string(theirs.agrees_to + 1)
                                           : "differs from the recording at frame " + std::to_string(f)) +
                 " too: the recording comes from another build, or was changed since (recorded by: " + rec.build + ")";
  for (const RecordedSnapshot& s : rec.snapshots) {
    if (s.frame < f) continue;
    try {
      ResumedEngine recorded = engine_from_snapshot(s.bytes);
      Rerun at{make(engine, rec.scene), 0, 0};
      advance(at, rec, s.frame);
      r.diff_frame = s.frame;
      r.recorder_state = "the recording's snapshot of frame " + std::to_string(s.frame) +
                         (s.frame == f ? "" : " (the first at or after frame " + std::to_string(f) +
                                                  "; record with --snapshot-every 1 for every frame)");
      r.body = first_body_difference(bodies_of(*recorded.engine), bodies_of(*at.engine));
    } catch (const std::exception& e) {
      r.recorder_state = "the recording's snapshot of frame " + std::to_string(s.frame) + " cannot be compared: " + e.what();
    }
    break;
  }
  if (r.diff_frame < 0 && r.recorder_state.empty())
    r.recorder_state = "no recorded snapshot at or after frame " + std::to_string(f) +
                       " (record with --snapshot-every K to compare states)";
  return r;
}

std::string replay_text(const ReplayReport& r) {
  std::string s;
  const std::string who = "the " + r.engine + " engine";
  if (r.same()) {
    return "replay: no difference over " + std::to_string(r.frames) + " frames (" + who + " against the " +
           r.recorded_engine + " engine's recording)\n";
  }
  s += "replay: the hashes differ first at frame " + std::to_string(r.first_frame) + " (" + who + " against the " +
       r.recorded_engine + " engine's recording)\n";
  if (!r.replay_stopped.empty()) s += "  the replay stopped there: " + r.replay_stopped + "\n";
  else s += "  hash: recorded " + hash_to_hex(r.recorded_hash) + ", replayed " + hash_to_hex(r.replayed_hash) + "\n";
  if (!r.note.empty()) s += "  note: " + r.note + "\n";
  auto body_line = [](const BodyDifference& d) {
    if (d.bodies_differing < 0)
      return "the body count: recorded " + value_text(d.recorded) + ", replayed " + value_text(d.replayed);
    if (d.body < 0) return std::string("no body differs there (the runs' states meet again, or the recorded hash is not that of a state)");
    return "body " + std::to_string(d.body) + ", field " + d.field + ": recorded " + value_text(d.recorded) +
           ", replayed " + value_text(d.replayed) + " (" + std::to_string(d.bodies_differing) + " bod" +
           (d.bodies_differing == 1 ? "y differs)" : "ies differ)");
  };
  if (r.diff_frame >= 0) s += "  frame " + std::to_string(r.diff_frame) + ": " + body_line(r.body) + "\n";
  if (!r.recorder_state.empty()) s += "    recorder's state: " + r.recorder_state + "\n";
  if (!r.stage.empty() && r.stage[0] >= '0' && r.stage[0] <= '9')
    s += "  stage: " + r.stage + " (docs/SPEC.md 7.2): " + body_line(r.stage_body) + " after it\n";
  else if (!r.stage.empty()) s += "  stage: " + r.stage + ": " + body_line(r.stage_body) + "\n";
  else if (!r.stage_note.empty()) s += "  stage: not found: " + r.stage_note + "\n";
  return s;
}

}  // namespace lockstep::compare
