// The replay page's data (compare/include/lockstep/compare/view.hpp): what a
// ViewRecorder keeps of an engine, where compare_runs says runs part and
// whose hashes differ, the stride that keeps a page under its budget, and a
// page whose inlined data survive hostile text.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "lockstep/builtin_scenes.hpp"
#include "lockstep/compare/view.hpp"

namespace {

using namespace lockstep;
using namespace lockstep::compare;

// A run of `bodies` bodies over frames 0..last; body b at frame f is at
// place(f, b) with orientation turn(f, b) about y (rad).
template <class Place, class Turn>
ViewRun synthetic(const std::string& label, const std::string& engine, int bodies, int last, Place place, Turn turn) {
  ViewRun r;
  r.label = label;
  r.engine = engine;
  r.bodies = bodies;
  for (int f = 0; f <= last; ++f) {
    r.frames.push_back(f);
    for (int b = 0; b < bodies; ++b) {
      const double x = place(f, b), a = turn(f, b);
      const float s[kViewFloats] = {static_cast<float>(x), 0.5f, 0, static_cast<float>(std::cos(a / 2)), 0,
                                    static_cast<float>(std::sin(a / 2)), 0, 0, 0, 0, 0, 0, 0};
      r.state.insert(r.state.end(), s, s + kViewFloats);
      r.asleep.push_back(0);
    }
    std::string hash = "h";
    hash += std::to_string(f);
    r.hashes.push_back(hash);
  }
  return r;
}

TEST(View, RecorderKeepsTheEnginesStatesHashesAndContacts) {
  const Scene scene = *builtin_scene("stack5");
  auto engine = make_engine("fixed", scene);
  ViewRecorder rec("fixed", "fixed", true);
  rec.add(*engine, true);
  std::vector<BodySnapshot> at15;
  for (int f = 1; f <= 40; ++f) {
    engine->step();
    rec.add(*engine, f % 5 == 0);
    if (f == 15)
      for (int i = 0; i < engine->body_count(); ++i) at15.push_back(engine->body(i));
    EXPECT_EQ(rec.run().hashes[static_cast<std::size_t>(f)], hash_hex(engine->state_hash())) << "frame " << f;
  }
  const ViewRun& r = rec.run();
  ASSERT_EQ(r.frames, (std::vector<int>{0, 5, 10, 15, 20, 25, 30, 35, 40}));
  ASSERT_EQ(r.state.size(), r.frames.size() * 5 * kViewFloats);
  for (int i = 0; i < 5; ++i) {
    const float* s = &r.state[(3 * 5 + static_cast<std::size_t>(i)) * kViewFloats];
    EXPECT_EQ(s[1], static_cast<float>(at15[static_cast<std::size_t>(i)].p[1])) << "body " << i;
    EXPECT_EQ(s[3], static_cast<float>(at15[static_cast<std::size_t>(i)].q[0])) << "body " << i;
  }
  EXPECT_EQ(r.energy.size(), 41u);
  EXPECT_TRUE(r.has_contacts);
  EXPECT_EQ(r.contacts.count(7), 0u) << "contacts are kept for kept frames only";
  ASSERT_EQ(r.contacts.count(5), 1u);
  EXPECT_EQ(static_cast<int>(r.contacts.at(5).size()), r.contact_count[5]);
  EXPECT_GT(r.contact_count[5], 0) << "a stack of five touches the ground and itself";
}

// A static body never sleeps (it never moves): the frame all are asleep is
// the one where every other body is (a cube resting beside a static box).
TEST(View, AllAsleepFrameLeavesStaticBodiesAside) {
  Scene scene = *builtin_scene("drop");
  BodyDesc wall;
  wall.half_extents = {0.5, 1.0, 0.5};
  wall.position = {3.0, 1.0, 0.0};
  wall.is_static = true;
  scene.bodies.push_back(wall);
  auto engine = make_engine("fixed", scene);
  ViewRecorder with("fixed", "fixed", false), without("fixed", "fixed", false);
  with.set_static_bodies(1);
  for (int f = 1; f <= 200; ++f) {
    engine->step();
    with.add(*engine, false);
    without.add(*engine, false);
  }
  EXPECT_GT(with.all_asleep_frame(), 0) << "the dropped cube sleeps by frame 200";
  EXPECT_EQ(without.all_asleep_frame(), -1) << "counted as a body that must sleep, the static box never does";
}

TEST(View, RunsPartWhereABodyLeavesThePositionTolerance) {
  const CompareTolerances tol;  // 0.05 m, 0.1 rad
  const auto still = [](int, int b) { return 2.0 * b; };
  const auto none = [](int, int) { return 0.0; };
  const ViewRun base = synthetic("double", "double", 3, 30, still, none);
  // Body 2 drifts 0.012 m a frame from frame 10: 0.048 m at frame 14, 0.06 m at 15.
  const ViewRun drift = synthetic("fixed", "fixed", 3, 30,
                                  [](int f, int b) { return 2.0 * b + (b == 2 && f > 10 ? 0.012 * (f - 10) : 0.0); }, none);
  const ViewComparison c = compare_runs({base, drift}, tol);
  EXPECT_EQ(c.parted_frame, (std::vector<int>{-1, 15}));
  EXPECT_EQ(c.parted_body, (std::vector<int>{-1, 2}));
  EXPECT_NEAR(c.divergence[1][20], 0.12, 1e-6);
  EXPECT_EQ(c.divergence[1][5], 0.0);
}

// Runs written with different --every (every frame; every 10th) are compared
// on the frames both hold, in either order: they part at the same frame.
TEST(View, RunsWithDifferentEveryAreComparedOnCommonFrames) {
  const CompareTolerances tol;  // 0.05 m
  const auto still = [](int, int b) { return 2.0 * b; };
  const auto none = [](int, int) { return 0.0; };
  const ViewRun every1 = synthetic("a", "double", 2, 40, still, none);
  ViewRun every10 = synthetic("b", "fixed", 2, 40, [](int f, int b) { return 2.0 * b + (b == 1 && f >= 15 ? 0.5 : 0.0); }, none);
  ViewRun kept;
  kept.label = every10.label;
  kept.engine = every10.engine;
  kept.bodies = every10.bodies;
  kept.hashes = every10.hashes;
  for (std::size_t k = 0; k < every10.frames.size(); ++k) {
    if (every10.frames[k] % 10 != 0) continue;
    kept.frames.push_back(every10.frames[k]);
    kept.state.insert(kept.state.end(), every10.state.begin() + static_cast<long>(k * 2 * kViewFloats),
                      every10.state.begin() + static_cast<long>((k + 1) * 2 * kViewFloats));
    kept.asleep.insert(kept.asleep.end(), {0, 0});
  }
  const ViewComparison ab = compare_runs({every1, kept}, tol);
  const ViewComparison ba = compare_runs({kept, every1}, tol);
  EXPECT_EQ(ab.parted_frame[1], 20);
  EXPECT_EQ(ba.parted_frame[1], 20);
  EXPECT_EQ(ab.common_frames[1], 5);  // 0, 10, 20, 30, 40
  EXPECT_EQ(ba.common_frames[1], 5);
  EXPECT_TRUE(std::isnan(ab.divergence[1][15]));  // not held by the second run
  EXPECT_NEAR(ab.divergence[1][30], 0.5, 1e-6);
  EXPECT_NEAR(ab.final_distance[1], 0.5, 1e-6);
  EXPECT_EQ(ab.final_body[1], 1);
  EXPECT_EQ(ab.rest_position_tolerance, tol.rest_position);
  EXPECT_NE(ab.tolerance_note.find("trajectory tolerance"), std::string::npos);
}

TEST(View, RunsPartWhereABodyTurnsBeyondTheOrientationTolerance) {
  const auto still = [](int, int b) { return 2.0 * b; };
  const ViewRun base = synthetic("double", "double", 2, 20, still, [](int, int) { return 0.0; });
  // Body 0 turns 0.03 rad a frame: beyond 0.1 rad at frame 4; positions never part.
  const ViewRun turn = synthetic("float", "float", 2, 20, still, [](int f, int b) { return b == 0 ? 0.03 * f : 0.0; });
  const ViewComparison c = compare_runs({base, turn}, CompareTolerances{});
  EXPECT_EQ(c.parted_frame[1], 4);
  EXPECT_EQ(c.parted_body[1], 0);
}

TEST(View, HashesOfTwoFixedRunsNameTheirFirstDifference) {
  const auto still = [](int, int b) { return 2.0 * b; };
  const auto none = [](int, int) { return 0.0; };
  const ViewRun d = synthetic("double", "double", 1, 20, still, none);
  const ViewRun a = synthetic("a", "fixed", 1, 20, still, none);
  ViewRun b = synthetic("b", "fixed", 1, 20, still, none);
  b.hashes[12] = "changed";
  const ViewComparison c = compare_runs({d, a, b}, CompareTolerances{});
  EXPECT_EQ(c.hash_run_a, 1);
  EXPECT_EQ(c.hash_run_b, 2);
  EXPECT_EQ(c.first_hash_difference, 12);
  EXPECT_NE(c.note.find("a and b first differ at frame 12"), std::string::npos) << c.note;
  const ViewComparison same = compare_runs({d, a, a}, CompareTolerances{});
  EXPECT_EQ(same.first_hash_difference, -1);
  EXPECT_NE(same.note.find("identical on all 21 frames"), std::string::npos) << same.note;
  // Runs of different engines differ from frame 0 by construction: not compared.
  const ViewComparison mixed = compare_runs({d, a}, CompareTolerances{});
  EXPECT_EQ(mixed.hash_run_a, -1);
  EXPECT_TRUE(mixed.note.empty());
}

TEST(View, StrideKeepsThePageUnderItsBudget) {
  const std::size_t per_body_frame = kViewFloats * 4 + 1;
  struct Case {
    int frames, bodies, runs, mb;
  };
  for (const Case& c : std::vector<Case>{
           {600, 10'000, 1, 48}, {600, 1000, 4, 48}, {600, 5, 3, 1}, {100'000, 1, 1, 1}, {599, 10'000, 2, 16}}) {
    const int frames = c.frames, bodies = c.bodies, runs = c.runs, mb = c.mb;
    const std::size_t budget = static_cast<std::size_t>(mb) << 20;
    const int s = view_stride(frames, bodies, runs, budget);
    auto bytes = [&](int stride) {
      const std::size_t kept = static_cast<std::size_t>((frames + stride) / stride);  // ceil((frames + 1) / stride)
      return kept * static_cast<std::size_t>(bodies) * static_cast<std::size_t>(runs) * per_body_frame;
    };
    EXPECT_LE(bytes(s), budget) << frames << " frames, " << bodies << " bodies, " << runs << " runs: stride " << s;
    if (s > 1) {
      EXPECT_GT(bytes(s - 1), budget) << "stride " << s << " is not the smallest";
    }
  }
  EXPECT_EQ(view_stride(600, 5, 3, 48u << 20), 1);
}

TEST(View, PageInlinesTheDataIntactWhateverTheText) {
  Scene scene = *builtin_scene("stack5");
  scene.name = "</script><script>alert(1)</script> & <b>";
  auto engine = make_engine("double", scene);
  ViewRecorder rec("run </script>", "double", false);
  rec.add(*engine, true);
  engine->step();
  rec.add(*engine, true);
  ViewPage page;
  page.title = scene.name;
  page.scene = scene;
  page.runs.push_back(rec.take());
  const std::string html = view_html(page, load_view_libraries());
  // Six scripts (error capture, three.js, OrbitControls, Chart.js, the data, the page's) and no other closing tag.
  std::size_t closes = 0;
  for (std::size_t at = html.find("</script"); at != std::string::npos; at = html.find("</script", at + 1)) ++closes;
  EXPECT_EQ(closes, 6u);
  EXPECT_NE(html.find("REVISION=\"111\""), std::string::npos) << "three.js r111 from libjs-three is inlined";
  EXPECT_NE(html.find("<title>&lt;/script&gt;&lt;script&gt;"), std::string::npos);
  const std::string open = "<script id=\"lockstep-data\" type=\"application/json\">";
  const std::size_t from = html.find(open) + open.size();
  const nlohmann::json data = nlohmann::json::parse(html.substr(from, html.find("</script>", from) - from));
  EXPECT_EQ(data["scene"]["name"], scene.name);
  EXPECT_EQ(data["runs"][0]["label"], "run </script>");
  EXPECT_EQ(data["runs"][0]["frames"], (std::vector<int>{0, 1}));
  EXPECT_EQ(data["data_bytes"], 2 * 5 * (kViewFloats * 4 + 1));
  // Bad input: a run of another body count is refused, naming both counts.
  page.runs[0].bodies = 4;
  try {
    (void)view_html(page, load_view_libraries());
    FAIL() << "a run of 4 bodies in a scene of 5 was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("has 4 bodies"), std::string::npos) << e.what();
  }
}

TEST(View, LongRunsKeepOneSeriesValueInK) {
  // 250,001 frames of per-frame series: the page keeps every 3rd (at most 100,000).
  ViewRun r = synthetic("long", "fixed", 1, 1, [](int, int) { return 0.0; }, [](int, int) { return 0.0; });
  r.hashes.clear();
  for (int f = 0; f <= 250'000; ++f) {
    r.hashes.push_back(hash_hex(static_cast<std::uint64_t>(f)));
    r.energy.push_back(f);
  }
  ViewPage page;
  page.scene.bodies.resize(1);
  page.runs.push_back(r);
  const std::string html = view_html(page, load_view_libraries());
  const std::string open = "<script id=\"lockstep-data\" type=\"application/json\">";
  const std::size_t from = html.find(open) + open.size();
  const nlohmann::json run = nlohmann::json::parse(html.substr(from, html.find("</script>", from) - from))["runs"][0];
  EXPECT_EQ(run["series_every"], 3);
  ASSERT_EQ(run["hashes"].size(), 83'334u);
  EXPECT_EQ(run["hashes"][1], hash_hex(3));
  EXPECT_EQ(run["energy"][83'333], 249'999.0);
}

// A recording's page (`lockstep view FILE.rec.json`): the inputs' frames and
// the diverged frame reach the page's data, the note intact whatever its text.
TEST(View, RecordingPageCarriesInputsAndDivergence) {
  const Scene scene = *builtin_scene("stack5");
  auto engine = make_engine("double", scene);
  ViewRecorder rec("replay on double", "double", false);
  rec.add(*engine, true);
  engine->step();
  rec.add(*engine, true);
  ViewPage page;
  page.scene = scene;
  page.runs.push_back(rec.take());
  ViewRecording r;
  r.recorded_engine = "fixed";
  r.engine = "double";
  r.inputs = {{1, "set_velocity"}, {1, "wake"}};
  r.diverged_frame = 1;
  r.note = "recording </script><b>x</b> replayed on double: DIVERGED at frame 1";
  page.recording = r;
  const std::string html = view_html(page, load_view_libraries());
  const std::string open = "<script id=\"lockstep-data\" type=\"application/json\">";
  const std::size_t from = html.find(open) + open.size();
  const nlohmann::json data = nlohmann::json::parse(html.substr(from, html.find("</script>", from) - from));
  EXPECT_EQ(data["recording"]["diverged_frame"], 1);
  EXPECT_EQ(data["recording"]["engine"], "double");
  EXPECT_EQ(data["recording"]["recorded_engine"], "fixed");
  ASSERT_EQ(data["recording"]["inputs"].size(), 2u);
  EXPECT_EQ(data["recording"]["inputs"][1]["kind"], "wake");
  EXPECT_EQ(data["recording"]["note"], r.note);
  EXPECT_NE(html.find("id=\"diverged\""), std::string::npos) << "the overlay's element";
  page.recording.reset();
  const std::string plain = view_html(page, load_view_libraries());
  const std::size_t from2 = plain.find(open) + open.size();
  EXPECT_FALSE(nlohmann::json::parse(plain.substr(from2, plain.find("</script>", from2) - from2)).contains("recording"));
}

}  // namespace
