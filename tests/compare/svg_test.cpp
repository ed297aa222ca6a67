// The SVG chart writer: ticks, log axes, broken lines, legend, escaping.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "lockstep/compare/svg.hpp"

namespace {

using namespace lockstep::svg;

int count(const std::string& s, const std::string& needle) {
  int n = 0;
  for (std::size_t p = s.find(needle); p != std::string::npos; p = s.find(needle, p + 1)) ++n;
  return n;
}

TEST(SvgTest, TicksAreOneTwoFiveStepsOrPowersOfTen) {
  EXPECT_EQ(ticks(0, 10, false), (std::vector<double>{0, 2, 4, 6, 8, 10}));
  EXPECT_EQ(ticks(0, 600, false), (std::vector<double>{0, 100, 200, 300, 400, 500, 600}));
  const auto log = ticks(1e-3, 10, true);
  ASSERT_EQ(log.size(), 5u);
  EXPECT_DOUBLE_EQ(log.front(), 1e-3);
  EXPECT_DOUBLE_EQ(log.back(), 10);
  // Many decades: every other one, at most about ten labels.
  EXPECT_LE(ticks(1e-16, 1e4, true).size(), 11u);
  EXPECT_TRUE(ticks(5, 5, false).empty());
}

TEST(SvgTest, LineChartHasAxesLegendAndBrokenLines) {
  Chart c;
  c.title = "Energy <J> & more";
  c.x_label = "frame";
  c.y_label = "energy (J)";
  Series a;
  a.name = "fixed";
  a.x = {0, 1, 2, 3, 4};
  a.y = {1, 2, NAN, 4, 5};  // the NaN breaks the line in two
  Series b;
  b.name = "double";
  b.x = {0, 4};
  b.y = {0, 5};
  b.dashed = true;
  c.series = {a, b};
  const std::string svg = render(c);
  EXPECT_EQ(svg.rfind("<svg xmlns=\"http://www.w3.org/2000/svg\"", 0), 0u);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  EXPECT_NE(svg.find("Energy &lt;J&gt; &amp; more"), std::string::npos);
  EXPECT_EQ(count(svg, "<polyline"), 3);
  EXPECT_EQ(count(svg, "stroke-dasharray"), 2);  // the line and its legend entry
  EXPECT_NE(svg.find(">fixed</text>"), std::string::npos);
  EXPECT_NE(svg.find(">double</text>"), std::string::npos);
}

TEST(SvgTest, LogAxisDropsNonPositivePointsAndLabelsDecades) {
  Chart c;
  c.log_y = true;
  Series s;
  s.name = "err";
  s.x = {1, 2, 3, 4};
  s.y = {1e-6, 0.0, 1e-4, 1e-2};
  s.markers = true;
  s.point_labels = {"a", "b", "c", "d"};  // "b" labels the dropped point
  c.series = {s};
  const std::string svg = render(c);
  EXPECT_EQ(count(svg, "<circle"), 3 + 1);  // three points and the legend marker
  EXPECT_NE(svg.find(">1e-6</text>"), std::string::npos);
  EXPECT_NE(svg.find(">0.01</text>"), std::string::npos);
  EXPECT_NE(svg.find(">a</text>"), std::string::npos);
  EXPECT_EQ(svg.find(">b</text>"), std::string::npos);
}

TEST(SvgTest, TimelineDrawsOneBarPerInterval) {
  Timeline t;
  t.title = "sleep";
  t.x_max = 100;
  t.rows = {{"body 0 fixed", {{10, 20}, {50, 101}}, 0}, {"body 0 double", {}, 1}};
  t.legend = {{"fixed", 0}, {"double", 1}};
  const std::string svg = render(t);
  EXPECT_EQ(count(svg, "<rect"), 1 + 2 + 2 + 1);  // background, legend, bars, frame
  EXPECT_NE(svg.find(">body 0 double</text>"), std::string::npos);
}

}  // namespace
