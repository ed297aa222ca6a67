// A small SVG chart writer for the comparison reports (no plotting library is
// needed: SVG renders on GitHub and in the README). Two kinds of chart: an x-y
// chart (lines and/or markers, linear or log axes, ticks, legend) and a
// timeline (horizontal bars per row, e.g. the frames a body is asleep).
#pragma once
#include <string>
#include <utility>
#include <vector>

namespace lockstep::svg {

struct Series {
  std::string name;          // legend entry
  std::vector<double> x, y;  // same length; a non-finite point (or <= 0 on a log axis) breaks the line
  bool lines = true;
  bool markers = false;
  bool dashed = false;
  double stroke_width = 1.5;  // (px)
  int color = -1;            // palette index; -1: the series' index
  std::vector<std::string> point_labels;  // optional, one per point (drawn beside the marker)
};

struct Chart {
  std::string title;
  std::string x_label, y_label;  // with units, e.g. "frame", "divergence (m)"
  bool log_x = false, log_y = false;
  int width = 800, height = 450;  // (px)
  std::vector<std::string> notes;  // lines printed under the title
  std::vector<Series> series;
  // Optional fixed ranges (when min < max); otherwise from the data.
  double x_min = 0, x_max = 0, y_min = 0, y_max = 0;
};

struct TimelineRow {
  std::string label;
  std::vector<std::pair<double, double>> bars;  // [start, end) in x units
  int color = 0;                                // palette index
};

struct Timeline {
  std::string title;
  std::string x_label;
  double x_min = 0, x_max = 1;
  int width = 800;                // (px); the height follows the row count
  std::vector<TimelineRow> rows;
  std::vector<std::pair<std::string, int>> legend;  // name, palette index
};

std::string render(const Chart& chart);
std::string render(const Timeline& timeline);

// The colour of palette index i (cycles), as "#rrggbb".
std::string color(int i);

// Tick positions for [lo, hi]: 1-2-5 steps (linear) or the powers of ten (log).
std::vector<double> ticks(double lo, double hi, bool log_scale);

}  // namespace lockstep::svg
