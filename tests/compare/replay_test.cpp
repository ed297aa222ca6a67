// Recordings and replays (docs/RECORDINGS.md, issue 32): the inputs file and
// the recording read back bit for bit and refused with the field named; a
// replay on the recording's engine finds no difference, one on another number
// type parts at frame 1 and says why; and a deliberately perturbed engine (a
// test-only variant of the fixed engine that nudges one body's velocity after
// one stage of one frame) is named exactly: frame, body, field and stage.
#include <gtest/gtest.h>

#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "lockstep/builtin_scenes.hpp"
#include "lockstep/compare/recording.hpp"
#include "lockstep/compare/replay.hpp"
#include "lockstep/fixed/q16_vec.hpp"

namespace {

using namespace lockstep;
using namespace lockstep::compare;

std::vector<Input> kicks() {
  Input a;
  a.frame = 12;
  a.kind = InputKind::set_velocity;
  a.id = {3, 0};
  a.a = {1.5, 0, 0.25};
  a.b = {0, 2, 0};
  Input b;
  b.frame = 30;
  b.kind = InputKind::wake;
  b.id = {1, 0};
  return {a, b};
}

RunRecording record(const std::string& engine, int frames, int every, bool inputs = true) {
  const Scene scene = *builtin_scene("pyramid");
  auto e = make_engine(engine, scene);
  RecordRunOptions o;
  o.snapshot_every = every;
  o.build = "replay_test";
  return record_run(*e, engine, scene, inputs ? kicks() : std::vector<Input>{}, frames, o);
}

EngineFactory engines() {
  return [](const std::string& name, const Scene& scene) { return make_engine(name, scene); };
}

template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const RecordingError& e) {
    return std::string(e.field) + " | " + e.what();
  }
  return "no error";
}

TEST(RecordingFormat, InputsRoundTripBitForBit) {
  std::vector<Input> in = kicks();
  Input create;
  create.frame = 40;
  create.kind = InputKind::create;
  create.body.position = {0.1, 3.3, -0.7};
  create.body.mass = 2.25;
  Input pose;
  pose.frame = 41;
  pose.kind = InputKind::set_pose;
  pose.id = {7, 2};
  pose.a = {1.0 / 3.0, 2, 0};
  pose.q = {0.5, 0.5, 0.5, 0.5};
  Input impulse;
  impulse.frame = 41;
  impulse.kind = InputKind::impulse;
  impulse.id = {2, 0};
  impulse.a = {0.1, 0.2, 0.3};
  impulse.b = {-1, 0.5, 0};
  in.insert(in.end(), {create, pose, impulse});
  const std::vector<Input> back = parse_inputs(inputs_to_json(in), "test");
  ASSERT_EQ(back.size(), in.size());
  for (std::size_t k = 0; k < in.size(); ++k) {
    EXPECT_EQ(back[k].frame, in[k].frame);
    EXPECT_EQ(back[k].kind, in[k].kind);
    EXPECT_EQ(back[k].id, in[k].id);
    EXPECT_EQ(back[k].a.x, in[k].a.x);
    EXPECT_EQ(back[k].b.y, in[k].b.y);
    EXPECT_EQ(back[k].q.z, in[k].q.z);
  }
  EXPECT_EQ(back[2].body.mass, 2.25);
  EXPECT_EQ(back[2].body.position.y, 3.3);
}

TEST(RecordingFormat, BadInputsNameFieldValueAndFix) {
  auto parse = [](const std::string& inputs) {
    return error_of([&] { parse_inputs(R"({"format": "lockstep-inputs", "version": 1, "inputs": )" + inputs + "}", "in.json"); });
  };
  EXPECT_NE(parse(R"([{"frame": 3, "kind": "kick", "id": 1}])").find("inputs[0].kind | in.json: inputs[0].kind: \"kick\" is not an input kind; use one of create"), std::string::npos);
  EXPECT_NE(parse(R"([{"frame": 0, "kind": "wake", "id": 1}])").find("inputs[0].frame"), std::string::npos);
  EXPECT_NE(parse(R"([{"frame": 3, "kind": "wake"}])").find("inputs[0].id: missing"), std::string::npos);
  EXPECT_NE(parse(R"([{"frame": 3, "kind": "wake", "id": 1, "velocity": [1, 0, 0]}])").find("inputs[0].velocity: unknown field"), std::string::npos);
  EXPECT_NE(parse(R"([{"frame": 3, "kind": "set_velocity", "id": 1, "velocity": [1, 0]}])").find("inputs[0].velocity: [1,0] is not an array of 3 numbers"), std::string::npos);
  EXPECT_NE(parse(R"([{"frame": 3, "kind": "set_velocity", "id": 1, "velocity": [1, 0, 1e9]}])").find("inputs[0].velocity[2]: 1000000000.0 is outside the Q16.16 range"), std::string::npos);
  EXPECT_NE(parse(R"([{"frame": 3, "kind": "set_pose", "id": 1, "position": [0, 1, 0], "orientation": [0, 0, 0, 0]}])").find("zero quaternion"), std::string::npos);
  EXPECT_NE(parse(R"([{"frame": 3, "kind": "create", "body": {"mass": -1}}])").find("inputs[0].body.mass"), std::string::npos);
  EXPECT_NE(error_of([] { parse_inputs("{\"format\": \"lockstep-scene\", \"version\": 1}", "x"); }).find("is not \"lockstep-inputs\""), std::string::npos);
  EXPECT_NE(error_of([] { parse_inputs("{", "x"); }).find("not valid JSON"), std::string::npos);
  const Scene scene = *builtin_scene("pyramid");
  Input far;
  far.frame = 5;
  far.id = {40, 0};
  EXPECT_NE(error_of([&] { validate_inputs({far}, scene, 100, "in.json"); }).find("inputs[0].id | in.json: inputs[0].id: body 40 does not exist at frame 5"), std::string::npos);
  far.id = {1, 0};
  far.frame = 101;
  EXPECT_NE(error_of([&] { validate_inputs({far}, scene, 100, "in.json"); }).find("outside the run's frames [1, 100]"), std::string::npos);
  Input early = far;
  early.frame = 4;
  far.frame = 9;
  EXPECT_NE(error_of([&] { validate_inputs({far, early}, scene, 100, "in.json"); }).find("inputs[1].frame: 4 comes after an input of frame 9"), std::string::npos);
}

TEST(RecordingFormat, RecordingRoundTripAndRefusals) {
  const RunRecording rec = record("fixed", 60, 20);
  ASSERT_EQ(rec.frames(), 60);
  ASSERT_EQ(rec.snapshots.size(), 3u);  // 20, 40, 60
  const std::string text = recording_to_json(rec);
  const RunRecording back = parse_recording(text, "rec.json");
  EXPECT_EQ(back.hashes, rec.hashes);
  EXPECT_EQ(back.engine, "fixed");
  EXPECT_EQ(back.build, "replay_test");
  EXPECT_EQ(back.inputs.size(), 2u);
  ASSERT_EQ(back.snapshots.size(), 3u);
  EXPECT_EQ(back.snapshots[1].frame, 40);
  EXPECT_EQ(back.snapshots[1].bytes, rec.snapshots[1].bytes);
  EXPECT_EQ(recording_to_json(back), text);
  auto bad = [&](const std::string& from, const std::string& to) {
    std::string t = text;
    const auto at = t.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    t.replace(at, from.size(), to);
    return error_of([&] { parse_recording(t, "rec.json"); });
  };
  EXPECT_NE(bad("\"frames\": 60", "\"frames\": 61").find("scene.frames"), std::string::npos);
  EXPECT_NE(bad("\"" + hash_to_hex(rec.hashes[4]) + "\"", "\"xyz\"").find("hashes[4]: \"xyz\" is not 16 hex digits"), std::string::npos);
  EXPECT_NE(bad("\"frame\":40", "\"frame\":41").find("snapshots[1].state: a snapshot of frame 40, not of frame 41"), std::string::npos);
  EXPECT_NE(bad("\"version\": 1", "\"version\": 2").find("version: 2 is outside [1, 1]"), std::string::npos);
}

TEST(Replay, SameEngineNoDifference) {
  const RunRecording rec = record("fixed", 90, 30);
  const ReplayReport r = replay(rec, "fixed", engines());
  EXPECT_TRUE(r.same());
  EXPECT_EQ(r.frames, 90);
  EXPECT_EQ(replay_text(r), "replay: no difference over 90 frames (the fixed engine against the fixed engine's recording)\n");
  const ReplayReport d = replay(record("double", 40, 0), "double", engines());
  EXPECT_TRUE(d.same());
}

TEST(Replay, AnotherNumberTypePartsAtFrameOneAndSaysWhy) {
  const RunRecording rec = record("fixed", 30, 0);
  const ReplayReport r = replay(rec, "double", engines());
  EXPECT_EQ(r.first_frame, 1);
  EXPECT_NE(r.note.find("different number types (fixed, double)"), std::string::npos);
  EXPECT_EQ(r.diff_frame, 1);
  EXPECT_GE(r.body.body, 0);
  EXPECT_FALSE(r.stage.empty());
  EXPECT_NE(replay_text(r).find("expected, not a fault"), std::string::npos);
}

TEST(Replay, TamperedHashNamesItsFrame) {
  RunRecording rec = record("fixed", 40, 10);
  rec.hashes[24] ^= 1;  // frame 25
  const ReplayReport r = replay(rec, "fixed", engines());
  EXPECT_EQ(r.first_frame, 25);
  // The fixed engine of this build does not reproduce the tampered frame: the
  // recorder's state comes from the recording's first snapshot at or after it.
  EXPECT_EQ(r.diff_frame, 30);
  EXPECT_NE(r.recorder_state.find("snapshot of frame 30"), std::string::npos);
  EXPECT_EQ(r.body.body, -1);  // the snapshot's bodies are the replay's
  EXPECT_NE(r.stage_note.find("cannot be re-run here"), std::string::npos);
}

// The perturbed engine: World<Q16> as the fixed engine, but after stage
// `stage` of frame `frame` body `body`'s v.x grows by one Q16.16 unit (2^-16
// m/s) through the public set_velocity. A test-only engine: nothing of it is
// in the library.
class PerturbedRun final : public EngineRun {
 public:
  PerturbedRun(const Scene& scene, int frame, FrameStage stage, int body)
      : world_(scene), frame_(frame), stage_(stage), body_(body) {}
  std::string name() const override { return "fixed-perturbed"; }
  std::string description() const override { return "fixed, perturbed (test)"; }
  void step() override { world_.step(perturb()); }
  void apply(const Input& input) override { world_.apply(input); }
  std::vector<StageState> step_stages() override {
    std::vector<StageState> out;
    const World<Q16>::StageObserver p = perturb();
    world_.step([&](FrameStage s, World<Q16>& w) {
      p(s, w);
      StageState st{frame_stage_name(s), {}};
      for (const Body<Q16>& b : w.bodies()) st.bodies.push_back(snapshot_of(b));
      out.push_back(std::move(st));
    });
    return out;
  }
  int frame() const override { return world_.frame(); }
  int body_count() const override { return static_cast<int>(world_.bodies().size()); }
  BodySnapshot body(int i) const override { return snapshot_of(world_.body(i)); }
  std::uint64_t state_hash() const override { return world_.state_hash(); }
  double energy() const override { return world_.energy(); }
  StageCounters counters() const override { return world_.counters(); }
  std::vector<std::uint8_t> save_state() const override { return world_.save_state(); }

 private:
  World<Q16>::StageObserver perturb() const {
    return [f = frame_, s = stage_, i = body_](FrameStage at, World<Q16>& w) {
      if (w.frame() != f || at != s) return;
      const Body<Q16>& b = w.body(i);
      Vec3<Q16> v = b.v;
      v.x = Q16::from_raw(v.x.raw() + 1);
      w.set_velocity(i, v, b.w);
    };
  }
  World<Q16> world_;
  int frame_;
  FrameStage stage_;
  int body_;
};

struct Perturbation {
  int frame;
  FrameStage stage;
  int body;
  const char* frame_field;  // the first field that differs at the end of the frame; null: several bodies differ by then
};

void PrintTo(const Perturbation& p, std::ostream* os) {
  *os << "frame " << p.frame << ", after stage " << frame_stage_name(p.stage) << ", body " << p.body;
}

class ReplayPerturbed : public ::testing::TestWithParam<Perturbation> {};

TEST_P(ReplayPerturbed, NamesFrameBodyFieldAndStage) {
  const Perturbation p = GetParam();
  const RunRecording rec = record("fixed", 60, 0);
  const EngineFactory make = [p](const std::string& name, const Scene& scene) -> std::unique_ptr<EngineRun> {
    if (name == "fixed-perturbed") return std::make_unique<PerturbedRun>(scene, p.frame, p.stage, p.body);
    return make_engine(name, scene);
  };
  const ReplayReport r = replay(rec, "fixed-perturbed", make);
  const std::string text = replay_text(r);
  RecordProperty("replay", text);  // the report, in --gtest_output=xml (docs/RECORDINGS.md quotes one)
  EXPECT_EQ(r.first_frame, p.frame) << text;
  EXPECT_EQ(r.diff_frame, p.frame) << text;
  if (p.frame_field != nullptr) {  // the nudge stays in its body until the frame ends
    EXPECT_EQ(r.body.body, p.body) << text;
    EXPECT_EQ(r.body.field, p.frame_field) << text;
    EXPECT_EQ(r.body.bodies_differing, 1) << text;
  } else {  // the rest of the frame carries it to the bodies in contact
    EXPECT_GE(r.body.body, 0) << text;
  }
  EXPECT_EQ(r.stage, frame_stage_name(p.stage)) << text;
  EXPECT_EQ(r.stage_body.body, p.body) << text;
  EXPECT_EQ(r.stage_body.field, "v.x") << text;
  EXPECT_EQ(r.stage_body.replayed - r.stage_body.recorded, 1.0 / 65536) << text;
  EXPECT_EQ(r.stage_body.bodies_differing, 1) << text;
  EXPECT_TRUE(r.note.empty()) << text;  // one number type: no excuse
  EXPECT_NE(text.find("stage: " + std::string(frame_stage_name(p.stage))), std::string::npos) << text;
}

// After stage 8 the nudged velocity is the frame's only change (v.x); after
// stage 1 or 5 the rest of the frame carries it into other bodies; the stage
// names the origin.
INSTANTIATE_TEST_SUITE_P(Stages, ReplayPerturbed,
                         ::testing::Values(Perturbation{17, FrameStage::integrate_positions, 6, "v.x"},
                                           Perturbation{23, FrameStage::solve, 4, nullptr},
                                           Perturbation{9, FrameStage::integrate_velocities, 9, nullptr},
                                           Perturbation{31, FrameStage::settle, 2, nullptr}),
                         [](const ::testing::TestParamInfo<Perturbation>& param) {
                           return "Frame" + std::to_string(param.param.frame) + "Stage" +
                                  std::to_string(static_cast<int>(param.param.stage)) + "Body" +
                                  std::to_string(param.param.body);
                         });

}  // namespace
