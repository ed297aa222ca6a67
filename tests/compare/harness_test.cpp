// The comparison harness on synthetic trajectories (ScriptedEngine): it must
// name body, frame and quantity of a real divergence, and must not fail on
// pure chaos in a pile whose statistics agree.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <numeric>
#include <random>
#include <sstream>
#include <stdexcept>

#include "lockstep/builtin_scenes.hpp"
#include "lockstep/compare/harness.hpp"
#include "lockstep/compare/report.hpp"
#include "lockstep/scene_json.hpp"
#include "scripted_engine.hpp"

namespace {

using namespace lockstep;
using namespace lockstep::compare;
using lockstep_test::at;
using lockstep_test::Script;
using lockstep_test::ScriptedEngine;

Scene cubes_scene(int n, int frames) {
  Scene s;
  s.name = "synthetic";
  s.frames = frames;
  s.bodies.resize(static_cast<std::size_t>(n));
  return s;
}

// Body i falls from y = 3 onto the ground at x = 2i and sleeps at frame 80.
BodySnapshot falling(int frame, int i) {
  return at(2.0 * i, std::max(0.5, 3.0 - 0.05 * frame), 0.0, frame, 80);
}

Recording run(const Scene& s, Script a, Script b, int fail_frame = -1) {
  std::vector<std::unique_ptr<EngineRun>> e;
  e.push_back(std::make_unique<ScriptedEngine>("base", static_cast<int>(s.bodies.size()), std::move(a)));
  e.push_back(std::make_unique<ScriptedEngine>("other", static_cast<int>(s.bodies.size()), std::move(b), fail_frame, 1));
  return record(s, std::move(e), 0);
}

const Finding* find(const Verdict& v, const std::string& quantity, int body = -2) {
  for (const EngineVerdict& e : v.engines)
    for (const Finding& f : e.findings)
      if (f.quantity.rfind(quantity, 0) == 0 && (body == -2 || f.body == body)) return &f;
  return nullptr;
}

TEST(HarnessTest, IdenticalEnginesAgreeOnEveryCheck) {
  const Scene s = cubes_scene(3, 200);
  const Recording r = run(s, falling, falling);
  const Verdict v = judge(r, CompareTolerances{});
  EXPECT_TRUE(v.agree());
  ASSERT_EQ(v.engines.size(), 2u);
  const EngineVerdict& o = v.engines[1];
  EXPECT_EQ(o.parted_frame, -1);
  EXPECT_EQ(o.pos_max, 0.0);
  // 2 trajectory checks + 3 rest checks and 1 sleep check per body.
  EXPECT_EQ(o.checks, 2 + 3 * 4);
  EXPECT_EQ(o.failures, 0);
  EXPECT_EQ(r.engines[1].frames.size(), 201u);
  EXPECT_EQ(r.engines[1].frames.back().asleep, 3);
}

TEST(HarnessTest, NamesBodyFrameAndQuantityOfARealDivergence) {
  const Scene s = cubes_scene(3, 200);
  // Body 2 starts sliding at frame 50: 0.01 m per frame, 0.06 m > 0.05 m at frame 56.
  const Recording r = run(s, falling, [](int f, int i) {
    BodySnapshot b = falling(f, i);
    if (i == 2 && f > 50) b.p[0] += 0.01 * (f - 50);
    return b;
  });
  CompareTolerances t;
  t.position = 0.05;
  const Verdict v = judge(r, t);
  EXPECT_FALSE(v.agree());
  const Finding* traj = find(v, "position", 2);
  ASSERT_NE(traj, nullptr);
  EXPECT_FALSE(traj->pass);
  EXPECT_EQ(traj->check, "trajectory");
  EXPECT_EQ(traj->frame, 56);
  const std::string msg = traj->message(v.baseline);
  EXPECT_NE(msg.find("body 2"), std::string::npos) << msg;
  EXPECT_NE(msg.find("frame 56"), std::string::npos) << msg;
  EXPECT_NE(msg.find("position"), std::string::npos) << msg;
  EXPECT_EQ(v.engines[1].parted_frame, 56);
  EXPECT_EQ(v.engines[1].parted_body, 2);
  // The final pose is 1.5 m off: the rest position of body 2, and only body 2, fails.
  const Finding* rest = find(v, "rest position", 2);
  ASSERT_NE(rest, nullptr);
  EXPECT_FALSE(rest->pass);
  EXPECT_EQ(rest->frame, 200);
  EXPECT_TRUE(find(v, "rest position", 0)->pass);
  EXPECT_TRUE(find(v, "rest position", 1)->pass);
  EXPECT_EQ(v.failures().size(), 2u);
}

TEST(HarnessTest, SleepFrameIsJudgedWithinPlusMinusK) {
  const Scene s = cubes_scene(2, 200);
  auto late = [](int by) {
    return [by](int f, int i) {
      BodySnapshot b = falling(f, i);
      if (i == 1) b = at(2.0, std::max(0.5, 3.0 - 0.05 * f), 0.0, f, 80 + by);
      return b;
    };
  };
  CompareTolerances t;
  t.sleep_frames = 10;
  EXPECT_TRUE(judge(run(s, falling, late(10)), t).agree());
  const Verdict v = judge(run(s, falling, late(11)), t);
  EXPECT_FALSE(v.agree());
  const Finding* f = find(v, "sleep frame", 1);
  ASSERT_NE(f, nullptr);
  EXPECT_FALSE(f->pass);
  EXPECT_EQ(f->frame, 91);
  EXPECT_EQ(f->value, "frame 91");
  EXPECT_EQ(f->baseline_value, "frame 80");
  // A body that never sleeps in one engine disagrees whatever k is.
  t.sleep_frames = 1000;
  const Verdict never = judge(run(s, falling, late(500)), t);
  EXPECT_FALSE(find(never, "sleep frame", 1)->pass);
  EXPECT_EQ(find(never, "sleep frame", 1)->value, "awake at the end");
}

TEST(HarnessTest, FaceUpAndSupportAreJudged) {
  const Scene s = cubes_scene(2, 10);
  // Baseline: body 1 rests on top of body 0. Other: body 1 lies beside it on
  // the ground, turned 90 degrees about z (its +x face up).
  const Recording r = run(s, [](int f, int i) { return i == 0 ? at(0, 0.5, 0, f) : at(0, 1.5, 0, f); },
                          [](int f, int i) {
                            if (i == 0) return at(0, 0.5, 0, f);
                            BodySnapshot b = at(0.0, 0.5, 1.2, f);
                            b.q[0] = std::sqrt(0.5);
                            b.q[3] = std::sqrt(0.5);
                            return b;
                          });
  CompareTolerances t;
  t.rest_position = 2.0;  // only face and support are under test
  t.position = t.orientation = 10.0;
  const Verdict v = judge(r, t);
  const Finding* face = find(v, "face up", 1);
  const Finding* support = find(v, "support", 1);
  ASSERT_TRUE(face && support);
  EXPECT_FALSE(face->pass);
  EXPECT_EQ(face->value.substr(0, 2), "+x");
  EXPECT_EQ(face->baseline_value.substr(0, 2), "+y");
  EXPECT_FALSE(support->pass);
  EXPECT_EQ(support->value, "ground");
  EXPECT_EQ(support->baseline_value, "body 0");
  EXPECT_TRUE(find(v, "support", 0)->pass);
  EXPECT_EQ(v.failures().size(), 2u);
}

// A pile: n bodies, each falling to a final spot drawn from a fixed set.
// `perm` assigns spots to bodies: a different permutation is pure chaos
// (every body ends elsewhere, the pile is the same).
struct Pile {
  std::vector<std::array<double, 3>> spots;
  std::vector<int> sleep;
  Pile(int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> xz(-5, 5);
    for (int i = 0; i < n; ++i) {
      const int layer = i % 4;  // heights 0.5 .. 3.5 m
      spots.push_back({xz(rng), 0.5 + layer, xz(rng)});
      sleep.push_back(100 + (i * 37) % 200);
    }
  }
  Script script(std::vector<int> perm, double lift = 0, int never_sleep_every = 0, int sleep_delay = 0) const {
    return [this, perm, lift, never_sleep_every, sleep_delay](int f, int i) {
      const auto& sp = spots[static_cast<std::size_t>(perm[static_cast<std::size_t>(i)])];
      const double y0 = 20.0 + 0.01 * i;
      const double y = f < 60 ? y0 + (sp[1] - y0) * f / 60.0 : sp[1];
      int sleep_at = sleep[static_cast<std::size_t>(perm[static_cast<std::size_t>(i)])] + sleep_delay;
      if (never_sleep_every > 0 && i % never_sleep_every == 0) sleep_at = -1;
      return at(sp[0] * std::min(1.0, f / 60.0), y + lift * std::min(1.0, f / 60.0), sp[2] * std::min(1.0, f / 60.0), f,
                sleep_at);
    };
  }
};

std::vector<int> identity(int n) {
  std::vector<int> p(static_cast<std::size_t>(n));
  std::iota(p.begin(), p.end(), 0);
  return p;
}

TEST(HarnessTest, ChaoticPileDoesNotFailWhenStatisticsAgree) {
  const int n = 200;
  const Pile pile(n, 7);
  std::vector<int> shuffled = identity(n);
  std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(11));
  const Scene s = cubes_scene(n, 400);
  const Recording r = run(s, pile.script(identity(n)), pile.script(shuffled));
  CompareTolerances t;
  t.judge = Judge::statistics;
  const Verdict v = judge(r, t);
  EXPECT_TRUE(v.agree()) << summary_table(r, v);
  // It says when the trajectories part (frame 1: the bodies head elsewhere at once).
  EXPECT_EQ(v.engines[1].parted_frame, 1);
  EXPECT_GT(v.engines[1].pos_max, 1.0);
  // The same recording judged body by body fails: the chaos is real.
  t.judge = Judge::bodies;
  EXPECT_FALSE(judge(r, t).agree());
}

TEST(HarnessTest, PileWithARealBugFailsItsStatistics) {
  const int n = 200;
  const Pile pile(n, 7);
  std::vector<int> shuffled = identity(n);
  std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(11));
  const Scene s = cubes_scene(n, 400);
  CompareTolerances t;
  t.judge = Judge::statistics;
  {  // Every body rests 0.3 m too high (e.g. a penetration sign error).
    const Verdict v = judge(run(s, pile.script(identity(n)), pile.script(shuffled, 0.3)), t);
    EXPECT_FALSE(v.agree());
    const Finding* f = find(v, "resting heights");
    ASSERT_NE(f, nullptr);
    EXPECT_FALSE(f->pass);
    EXPECT_EQ(f->frame, 400);
    EXPECT_NE(f->value.find("0.3 m"), std::string::npos) << f->value;
  }
  {  // One body in four never sleeps.
    const Verdict v = judge(run(s, pile.script(identity(n)), pile.script(shuffled, 0, 4)), t);
    EXPECT_FALSE(v.agree());
    const Finding* f = find(v, "asleep count");
    ASSERT_NE(f, nullptr);
    EXPECT_FALSE(f->pass);
    EXPECT_EQ(f->value, "150 of 200");
    EXPECT_EQ(f->baseline_value, "200 of 200");
  }
  {  // Everybody falls asleep 100 frames late (e.g. a sleep counter that restarts).
    const Verdict v = judge(run(s, pile.script(identity(n)), pile.script(shuffled, 0, 0, 100)), t);
    const Finding* f = find(v, "median sleep frame");
    ASSERT_NE(f, nullptr);
    EXPECT_FALSE(f->pass);
    EXPECT_EQ(f->value, "frame 299");  // sleep frames 100..299: lower median 199, delayed 299
    EXPECT_EQ(f->baseline_value, "frame 199");
    EXPECT_TRUE(find(v, "asleep count")->pass);
  }
  {  // Judged at frame 110, only a handful sleep: the median is not compared.
    const Scene early = cubes_scene(n, 110);
    const Verdict v = judge(run(early, pile.script(identity(n)), pile.script(shuffled, 0, 0, 5)), t);
    const Finding* f = find(v, "median sleep frame");
    ASSERT_NE(f, nullptr);
    EXPECT_TRUE(f->pass);
    EXPECT_NE(f->tolerance.find("compared when both have >= 20 asleep"), std::string::npos) << f->tolerance;
  }
  {  // A third of the bodies land on their side.
    const Verdict v = judge(run(s, pile.script(identity(n)), [&](int f, int i) {
                              BodySnapshot b = pile.script(shuffled)(f, i);
                              if (i % 3 == 0) { b.q[0] = std::sqrt(0.5); b.q[1] = std::sqrt(0.5); }
                              return b;
                            }), t);
    const Finding* f = find(v, "face up count");
    ASSERT_NE(f, nullptr);
    EXPECT_FALSE(f->pass);
    EXPECT_EQ(f->quantity, "face up count (+y)");
  }
}

TEST(HarnessTest, RunErrorIsADisagreementNamingBodyFrameQuantity) {
  const Scene s = cubes_scene(2, 100);
  const Recording r = run(s, falling, falling, 40);
  EXPECT_TRUE(r.engines[1].failed);
  EXPECT_EQ(r.engines[1].frames_run, 39);
  EXPECT_EQ(r.engines[0].frames_run, 100);
  const Verdict v = judge(r, CompareTolerances{});
  EXPECT_FALSE(v.agree());
  const Finding* f = find(v, "velocity", 1);
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->check, "run");
  EXPECT_EQ(f->frame, 40);
  EXPECT_NE(f->value.find("scripted overflow"), std::string::npos);
}

TEST(HarnessTest, RecordsEnergyAsleepCountsAndSleepIntervals) {
  const Scene s = cubes_scene(1, 120);
  // Asleep 80..99, woken at 100, asleep again from 110.
  const Recording r = run(s, falling, [](int f, int) {
    BodySnapshot b = at(0, std::max(0.5, 3.0 - 0.05 * f), 0, f, f < 100 ? 80 : 110);
    return b;
  });
  const auto& iv = r.engines[1].asleep_intervals[0];
  ASSERT_EQ(iv.size(), 2u);
  EXPECT_EQ(iv[0], std::make_pair(80, 100));
  EXPECT_EQ(iv[1], std::make_pair(110, 121));
  EXPECT_DOUBLE_EQ(r.engines[1].frames[0].energy, 9.81 * 3.0);
  EXPECT_EQ(r.engines[1].frames[85].asleep, 1);
  EXPECT_EQ(r.engines[1].frames[105].asleep, 0);
}

TEST(HarnessTest, ReportFolderHoldsDataAndPictures) {
  const Scene s = cubes_scene(3, 100);
  const Recording r = run(s, falling, [](int f, int i) {
    BodySnapshot b = falling(f, i);
    if (i == 1 && f > 20) b.p[2] += 0.02 * (f - 20);
    return b;
  });
  const Verdict v = judge(r, CompareTolerances{});
  const std::string dir = (std::filesystem::temp_directory_path() / "lockstep_harness_report_test").string();
  std::filesystem::remove_all(dir);
  const auto files = write_report(dir, r, v);
  EXPECT_EQ(files.size(), 11u);
  for (const std::string& f : files) EXPECT_TRUE(std::filesystem::file_size(f) > 0) << f;
  std::ifstream checks(dir + "/checks.csv");
  std::stringstream ss;
  ss << checks.rdbuf();
  EXPECT_NE(ss.str().find("other,base,trajectory,position,1,23,"), std::string::npos) << ss.str();
  std::ifstream frames(dir + "/frames.csv");
  std::string header;
  std::getline(frames, header);
  EXPECT_EQ(header, "frame,engine,pos_max_m,pos_rms_m,pos_body,ori_max_rad,ori_rms_rad,ori_body,energy_J,asleep");
  const std::string table = summary_table(r, v);
  EXPECT_NE(table.find("DISAGREE"), std::string::npos);
  EXPECT_NE(table.find("other vs base: position, body 1, frame 23"), std::string::npos) << table;
  std::filesystem::remove_all(dir);
}

}  // namespace

namespace {

// make_engine accepts the listed engines and the variants; a variant is not
// listed (runs over engine_names() do not include it); an unknown name is an
// error that lists every accepted name.
TEST(EngineNames, VariantsAreAcceptedOnRequestOnly) {
  const std::vector<std::string> listed = engine_names(), accepted = accepted_engine_names();
  const bool gpu = std::find(listed.begin(), listed.end(), "gpu") != listed.end();
  EXPECT_EQ(std::find(listed.begin(), listed.end(), "gpu-jacobi"), listed.end());
  EXPECT_EQ(std::find(accepted.begin(), accepted.end(), "gpu-jacobi") != accepted.end(), gpu);
  EXPECT_EQ(std::find(listed.begin(), listed.end(), "gpu-fixed"), listed.end());
  EXPECT_EQ(std::find(accepted.begin(), accepted.end(), "gpu-fixed") != accepted.end(), gpu);
  Scene scene = *builtin_scene("stack5");
  scene.pair_contacts = PairModel::kAabb;  // a model every engine runs
  for (const std::string& name : accepted) EXPECT_EQ(make_engine(name, scene)->name(), name);
  try {
    make_engine("gpu-gauss", scene);
    FAIL() << "no error for an unknown engine";
  } catch (const std::invalid_argument& e) {
    for (const std::string& name : accepted) EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << name;
  }
}

// Every engine (the GPU engine and its Jacobi variant too, where built) runs
// both pair models: none has a limitation, the default lists leave none out,
// and each one's run of a stack moves its bodies under either model and
// ends with the stack's cubes in contact (above the ground, not apart).
TEST(EngineNames, EveryEngineRunsBothPairModels) {
  for (const PairModel model : {PairModel::kOrientedBox, PairModel::kAabb}) {
    Scene scene = *builtin_scene("stack5");
    scene.pair_contacts = model;
    scene.bodies[4].position.y += 0.5;  // the top cube falls onto the stack
    EXPECT_EQ(engine_names_for(scene), engine_names());
    for (const std::string& name : accepted_engine_names()) {
      SCOPED_TRACE(name + (model == PairModel::kAabb ? " aabb" : " oriented_box"));
      EXPECT_EQ(engine_limitation(name, scene), "");
      auto run = make_engine(name, scene);
      for (int f = 0; f < 60; ++f) run->step();
      EXPECT_LT(run->body(4).p[1], scene.bodies[4].position.y - 0.3);  // it fell
      EXPECT_GT(run->body(4).p[1], run->body(3).p[1] + 0.9);           // onto the cube below, not through it
    }
  }
}

// Issue 30: an engine whose number type cannot hold the scene (fixed on a
// 1e-5 kg cube) is refused by make_engine with a SceneError naming the field;
// record() makes it a failed track from frame 0 (refused, no frames), judge()
// fails its run check, and the other engines run and are judged as usual.
TEST(Harness, EngineThatCannotRunTheSceneIsAFailedColumn) {
  Scene scene = *builtin_scene("drop");
  scene.frames = 30;
  scene.bodies[0].mass = 1e-05;
  try {
    make_engine("fixed", scene);
    FAIL() << "make_engine built a fixed engine for a 1e-5 kg cube";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.field, "bodies[0].mass");
  }
  const Recording rec = record(scene, std::vector<std::string>{"fixed", "float", "double"}, "double");
  ASSERT_EQ(rec.engines.size(), 3u);
  const EngineTrack& fixed = rec.engines[0];
  EXPECT_EQ(fixed.name, "fixed");
  EXPECT_TRUE(fixed.failed && fixed.failure.refused);
  EXPECT_EQ(fixed.failure.frame, 0);
  EXPECT_EQ(fixed.failure.body, 0);
  EXPECT_EQ(fixed.failure.quantity, "bodies[0].mass");
  EXPECT_NE(fixed.failure.message.find("inverse mass 1/m = 100000 1/kg"), std::string::npos) << fixed.failure.message;
  EXPECT_TRUE(fixed.frames.empty());
  EXPECT_FALSE(rec.engines[1].failed);
  EXPECT_EQ(rec.engines[1].frames_run, 30);
  const Verdict v = judge(rec, tolerances_for(scene));
  EXPECT_FALSE(v.agree());
  ASSERT_EQ(v.engines[0].findings.size(), 1u);
  EXPECT_EQ(v.engines[0].findings[0].check, "run");
  EXPECT_FALSE(v.engines[0].findings[0].pass);
  EXPECT_GT(v.engines[1].checks, 0);
  EXPECT_EQ(v.engines[1].failures, 0);
  const std::string table = summary_table(rec, v, 20);
  EXPECT_NE(table.find("cannot run"), std::string::npos) << table;
  EXPECT_NE(table.find("FAILED, cannot run this scene: "), std::string::npos) << table;
}

}  // namespace
