// Resting states read from poses (face up, orientation angle, support) and
// the pile statistics.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "lockstep/builtin_scenes.hpp"
#include "lockstep/compare/resting.hpp"
#include "lockstep/compare/statistics.hpp"
#include "scripted_engine.hpp"

namespace {

using namespace lockstep;
using namespace lockstep::compare;
using lockstep_test::at;

TEST(RestingTest, FaceUpNamesTheAxisPointingUp) {
  const double s = std::sqrt(0.5);
  const double identity[4] = {1, 0, 0, 0};
  const double flipped[4] = {0, 1, 0, 0};        // 180 deg about x: -y up
  const double about_z[4] = {s, 0, 0, s};        // +90 deg about z: body +x points up
  const double about_x[4] = {s, s, 0, 0};        // +90 deg about x: body -z points up
  const double edge[4] = {std::cos(std::numbers::pi / 8), 0, 0, std::sin(std::numbers::pi / 8)};  // 45 deg: on an edge
  EXPECT_EQ(face_up(identity, 0.99).label, "+y");
  EXPECT_EQ(face_up(flipped, 0.99).label, "-y");
  EXPECT_EQ(face_up(about_z, 0.99).label, "+x");
  EXPECT_EQ(face_up(about_x, 0.99).label, "-z");
  const FaceUp e = face_up(edge, 0.99);
  EXPECT_EQ(e.label, "none");
  EXPECT_NEAR(e.alignment, std::sqrt(0.5), 1e-12);
  // Unnormalised quaternions (Q16 rounding) read the same.
  const double scaled[4] = {2, 0, 0, 0};
  EXPECT_EQ(face_up(scaled, 0.99).label, "+y");
}

TEST(RestingTest, OrientationAngleIsTheRotationBetween) {
  const double s = std::sqrt(0.5);
  const double a[4] = {1, 0, 0, 0};
  const double b[4] = {s, 0, s, 0};    // 90 deg about y
  const double nb[4] = {-s, 0, -s, 0}; // the same rotation
  EXPECT_NEAR(orientation_angle(a, b), std::numbers::pi / 2, 1e-12);
  EXPECT_NEAR(orientation_angle(a, nb), std::numbers::pi / 2, 1e-12);
  EXPECT_NEAR(orientation_angle(b, nb), 0.0, 1e-12);
  const double c[4] = {0, 1, 0, 0};    // 180 deg about x
  EXPECT_NEAR(orientation_angle(a, c), std::numbers::pi, 1e-12);
}

TEST(RestingTest, SupportIsGroundBodyOrNothing) {
  Scene s;
  s.bodies.resize(4);
  const std::vector<BodySnapshot> poses = {
      at(0, 0.5, 0),      // on the ground
      at(0.3, 1.505, 0),  // on body 0 (5 mm gap, footprints overlap)
      at(5, 3.0, 0),      // in the air
      at(1.2, 1.5, 0),    // beside body 0's top, no overlap with it, touches nothing below
  };
  const auto r = resting_states(s, poses, 0.02, 0.99);
  ASSERT_EQ(r.size(), 4u);
  EXPECT_EQ(supports_label(r[0].supports), "ground");
  EXPECT_EQ(supports_label(r[1].supports), "body 0");
  EXPECT_EQ(supports_label(r[2].supports), "none");
  EXPECT_EQ(supports_label(r[3].supports), "none");
  EXPECT_NEAR(r[1].lowest, 1.005, 1e-12);
  // Without the ground effect there is no ground support.
  s.effects.ground = false;
  EXPECT_EQ(supports_label(resting_states(s, poses, 0.02, 0.99)[0].supports), "none");
}

TEST(RestingTest, ABodyOnTwoBodiesRestsOnBoth) {
  Scene s;
  s.bodies.resize(4);
  // A pyramid's upper cube over two lower ones, the second 3 mm lower; a
  // fourth body's footprint only touches body 0's edge (no overlap).
  const std::vector<BodySnapshot> poses = {at(0, 0.5, 0), at(1.05, 0.497, 0), at(0.525, 1.5, 0), at(-1.0, 1.5, 0)};
  const auto r = resting_states(s, poses, 0.02, 0.99);
  EXPECT_EQ(supports_label(r[2].supports), "body 0 + body 1");
  EXPECT_EQ(supports_label(r[3].supports), "none");
  // Beyond the gap, body 1 no longer supports it.
  EXPECT_EQ(supports_label(resting_states(s, poses, 0.002, 0.99)[2].supports), "body 0");
}

// A cube resting on a tilted cube (as in a heap): its bottom face lies on the
// lower cube's top face, 17 cm below the lower cube's axis-aligned bounds, so
// comparing bounding boxes alone found no support ("none").
TEST(RestingTest, ACubeOnATiltedCubeRestsOnIt) {
  Scene s;
  s.bodies.resize(2);
  const double a = 10 * std::numbers::pi / 180;  // both turned 10 degrees about z
  BodySnapshot lower = at(0, 0.5, 0), upper = at(-std::sin(a) * 1.003, 0.5 + std::cos(a) * 1.003, 0);
  for (BodySnapshot* b : {&lower, &upper}) {
    b->q[0] = std::cos(a / 2);
    b->q[3] = std::sin(a / 2);
  }
  const auto r = resting_states(s, {lower, upper}, 0.02, 0.99);
  EXPECT_EQ(supports_label(r[1].supports), "body 0");
  // 3 mm apart: beyond a 2 mm gap, no support.
  EXPECT_EQ(supports_label(resting_states(s, {lower, upper}, 0.002, 0.99)[1].supports), "none");
}

TEST(RestingTest, SdfSupportInTheBowl) {
  const Scene bowl = *builtin_scene("bowl");
  Scene s = bowl;
  s.bodies.resize(2);
  // The bowl is a sphere of radius 6 about (0, 7, 0): a flat unit cube at its
  // bottom rests on its four lower corners, |corner - centre| = 6, so its
  // centre is at y = 7 - sqrt(35.5) + 0.5 = 1.5418 m.
  const std::vector<BodySnapshot> poses = {at(0, 7 - std::sqrt(35.5) + 0.5, 0), at(0, 4.0, 0)};
  const auto r = resting_states(s, poses, 0.02, 0.99);
  EXPECT_EQ(supports_label(r[0].supports), "sdf 0");
  EXPECT_EQ(supports_label(r[1].supports), "none");
}

TEST(StatisticsTest, PileStatisticsCountDynamicBodies) {
  Scene s;
  s.bodies.resize(5);
  s.bodies[4].is_static = true;
  const double sq = std::sqrt(0.5);
  std::vector<BodySnapshot> b = {at(0, 0.5, 0, 100, 40), at(2, 0.5, 0, 100, 60), at(4, 1.5, 0, 100, 90), at(6, 0.5, 0),
                                 at(9, 9, 9)};
  b[3].q[0] = sq;
  b[3].q[3] = sq;  // +x up
  CompareTolerances t;
  t.height_bin = 1.0;
  const PileStatistics p = pile_statistics(s, b, t);
  EXPECT_EQ(p.bodies, 4);
  EXPECT_EQ(p.asleep, 3);
  EXPECT_EQ(p.median_sleep_frame, 60);
  EXPECT_EQ(p.faces.at("+y"), 3);
  EXPECT_EQ(p.faces.at("+x"), 1);
  EXPECT_EQ(p.height_histogram.at(0), 3);
  EXPECT_EQ(p.height_histogram.at(1), 1);
  EXPECT_DOUBLE_EQ(p.mean_height, 0.75);
  EXPECT_EQ(p.heights, (std::vector<double>{0.5, 0.5, 0.5, 1.5}));
}

TEST(StatisticsTest, HeightDistanceIsTheMeanGapOfSortedHeights) {
  EXPECT_DOUBLE_EQ(height_distance({0.5, 1.5, 2.5}, {0.5, 1.5, 2.5}), 0.0);
  EXPECT_DOUBLE_EQ(height_distance({0.5, 1.5, 2.5}, {0.5, 1.5, 3.4}), 0.3);
  EXPECT_DOUBLE_EQ(height_distance({}, {}), 0.0);
  EXPECT_THROW(height_distance({1.0}, {}), std::invalid_argument);
  std::string label;
  EXPECT_EQ(max_count_difference({{"+y", 5}, {"none", 1}}, {{"+y", 3}, {"-x", 3}}, &label), 3);
  EXPECT_EQ(label, "-x");
}

}  // namespace
