#include "lockstep/compare/svg.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace lockstep::svg {
namespace {

constexpr const char* kPalette[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
                                    "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};

std::string esc(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1f", v);
  return b;
}

std::string tick_label(double v, bool log_scale) {
  char b[32];
  if (log_scale) {
    const int k = static_cast<int>(std::lround(std::log10(v)));
    if (k >= -2 && k <= 3) std::snprintf(b, sizeof b, "%g", v);
    else std::snprintf(b, sizeof b, "1e%d", k);
  } else {
    std::snprintf(b, sizeof b, "%g", std::fabs(v) < 1e-12 ? 0.0 : v);
  }
  return b;
}

double nice_step(double range) {
  const double raw = range / 6.0;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double f = raw / mag;
  return (f < 1.5 ? 1.0 : f < 3.5 ? 2.0 : f < 7.5 ? 5.0 : 10.0) * mag;
}

bool usable(double v, bool log_scale) { return std::isfinite(v) && (!log_scale || v > 0); }

// The axis range [lo, hi] in plot units (log10 on a log axis), widened to ticks.
std::pair<double, double> axis_range(double lo, double hi, bool log_scale, bool have) {
  if (!have) return log_scale ? std::pair{0.0, 1.0} : std::pair{0.0, 1.0};
  if (log_scale) {
    double a = std::floor(std::log10(lo)), b = std::ceil(std::log10(hi));
    if (b <= a) b = a + 1;
    return {a, b};
  }
  if (hi <= lo) { lo -= 0.5; hi += 0.5; }
  const double step = nice_step(hi - lo);
  return {std::floor(lo / step) * step, std::ceil(hi / step) * step};
}

}  // namespace

std::string color(int i) { return kPalette[static_cast<unsigned>(i) % (sizeof kPalette / sizeof kPalette[0])]; }

std::vector<double> ticks(double lo, double hi, bool log_scale) {
  std::vector<double> out;
  if (!(hi > lo)) return out;
  if (log_scale) {
    const int a = static_cast<int>(std::ceil(std::log10(lo) - 1e-9)), b = static_cast<int>(std::floor(std::log10(hi) + 1e-9));
    const int every = std::max(1, (b - a + 9) / 10);
    for (int k = a; k <= b; k += every) out.push_back(std::pow(10.0, k));
    return out;
  }
  const double step = nice_step(hi - lo);
  for (double t = std::ceil(lo / step - 1e-9) * step; t <= hi + step * 1e-9; t += step) out.push_back(t);
  return out;
}

std::string render(const Chart& c) {
  // Data ranges.
  double xlo = INFINITY, xhi = -INFINITY, ylo = INFINITY, yhi = -INFINITY;
  for (const Series& s : c.series) {
    for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      if (!usable(s.x[i], c.log_x) || !usable(s.y[i], c.log_y)) continue;
      xlo = std::min(xlo, s.x[i]); xhi = std::max(xhi, s.x[i]);
      ylo = std::min(ylo, s.y[i]); yhi = std::max(yhi, s.y[i]);
    }
  }
  if (c.x_min < c.x_max) { xlo = c.x_min; xhi = c.x_max; }
  if (c.y_min < c.y_max) { ylo = c.y_min; yhi = c.y_max; }
  const auto [ax0, ax1] = axis_range(xlo, xhi, c.log_x, xlo <= xhi);
  const auto [ay0, ay1] = axis_range(ylo, yhi, c.log_y, ylo <= yhi);

  const double top = 40.0 + 16.0 * static_cast<double>(c.notes.size());
  const double left = 80, right = 180, bottom = 55;
  const double W = c.width, H = c.height + 16.0 * static_cast<double>(c.notes.size());
  const double pw = W - left - right, ph = H - top - bottom;
  auto to_x = [&](double x) { return left + ((c.log_x ? std::log10(x) : x) - ax0) / (ax1 - ax0) * pw; };
  auto to_y = [&](double y) { return top + ph - ((c.log_y ? std::log10(y) : y) - ay0) / (ay1 - ay0) * ph; };

  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H << "\" viewBox=\"0 0 " << W << " "
    << H << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  o << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  o << "<text x=\"" << W / 2 << "\" y=\"22\" text-anchor=\"middle\" font-size=\"15\">" << esc(c.title) << "</text>\n";
  for (std::size_t i = 0; i < c.notes.size(); ++i)
    o << "<text x=\"" << W / 2 << "\" y=\"" << 40 + 16 * i << "\" text-anchor=\"middle\" fill=\"#555\">" << esc(c.notes[i])
      << "</text>\n";
  // Grid, ticks and labels.
  const double rx0 = c.log_x ? std::pow(10.0, ax0) : ax0, rx1 = c.log_x ? std::pow(10.0, ax1) : ax1;
  const double ry0 = c.log_y ? std::pow(10.0, ay0) : ay0, ry1 = c.log_y ? std::pow(10.0, ay1) : ay1;
  for (double t : ticks(rx0, rx1, c.log_x)) {
    const double x = to_x(t);
    o << "<line x1=\"" << num(x) << "\" y1=\"" << num(top) << "\" x2=\"" << num(x) << "\" y2=\"" << num(top + ph)
      << "\" stroke=\"#ddd\"/>\n<text x=\"" << num(x) << "\" y=\"" << num(top + ph + 16) << "\" text-anchor=\"middle\">"
      << tick_label(t, c.log_x) << "</text>\n";
  }
  for (double t : ticks(ry0, ry1, c.log_y)) {
    const double y = to_y(t);
    o << "<line x1=\"" << num(left) << "\" y1=\"" << num(y) << "\" x2=\"" << num(left + pw) << "\" y2=\"" << num(y)
      << "\" stroke=\"#ddd\"/>\n<text x=\"" << num(left - 6) << "\" y=\"" << num(y + 4) << "\" text-anchor=\"end\">"
      << tick_label(t, c.log_y) << "</text>\n";
  }
  o << "<rect x=\"" << left << "\" y=\"" << top << "\" width=\"" << pw << "\" height=\"" << ph
    << "\" fill=\"none\" stroke=\"#333\"/>\n";
  o << "<text x=\"" << num(left + pw / 2) << "\" y=\"" << num(H - 15) << "\" text-anchor=\"middle\">" << esc(c.x_label)
    << "</text>\n";
  o << "<text transform=\"translate(18," << num(top + ph / 2) << ") rotate(-90)\" text-anchor=\"middle\">" << esc(c.y_label)
    << "</text>\n";
  // Series, clipped to the plot area.
  o << "<clipPath id=\"plot\"><rect x=\"" << left << "\" y=\"" << top << "\" width=\"" << pw << "\" height=\"" << ph
    << "\"/></clipPath>\n<g clip-path=\"url(#plot)\">\n";
  for (std::size_t si = 0; si < c.series.size(); ++si) {
    const Series& s = c.series[si];
    const std::string col = color(s.color >= 0 ? s.color : static_cast<int>(si));
    const std::size_t n = std::min(s.x.size(), s.y.size());
    if (s.lines) {
      std::string pts;
      auto flush = [&] {
        if (pts.find(' ') != std::string::npos)
          o << "<polyline fill=\"none\" stroke=\"" << col << "\" stroke-width=\"" << s.stroke_width << "\""
            << (s.dashed ? " stroke-dasharray=\"6,4\"" : "") << " points=\"" << pts << "\"/>\n";
        pts.clear();
      };
      for (std::size_t i = 0; i < n; ++i) {
        if (!usable(s.x[i], c.log_x) || !usable(s.y[i], c.log_y)) { flush(); continue; }
        if (!pts.empty()) pts += ' ';
        pts += num(to_x(s.x[i]));
        pts += ',';
        pts += num(to_y(s.y[i]));
      }
      flush();
    }
    for (std::size_t i = 0; i < n; ++i) {
      if (!s.markers || !usable(s.x[i], c.log_x) || !usable(s.y[i], c.log_y)) continue;
      o << "<circle cx=\"" << num(to_x(s.x[i])) << "\" cy=\"" << num(to_y(s.y[i])) << "\" r=\"3.5\" fill=\"" << col << "\"/>\n";
    }
  }
  o << "</g>\n";
  // Point labels, unclipped (a point on the edge keeps its label).
  for (std::size_t si = 0; si < c.series.size(); ++si) {
    const Series& s = c.series[si];
    const std::string col = color(s.color >= 0 ? s.color : static_cast<int>(si));
    for (std::size_t i = 0; i < s.point_labels.size() && i < s.x.size() && i < s.y.size(); ++i) {
      if (s.point_labels[i].empty() || !usable(s.x[i], c.log_x) || !usable(s.y[i], c.log_y)) continue;
      o << "<text x=\"" << num(to_x(s.x[i]) + 5) << "\" y=\"" << num(to_y(s.y[i]) - 4) << "\" font-size=\"9\" fill=\"" << col
        << "\">" << esc(s.point_labels[i]) << "</text>\n";
    }
  }
  // Legend.
  int row = 0;
  for (std::size_t si = 0; si < c.series.size(); ++si) {
    const Series& s = c.series[si];
    if (s.name.empty()) continue;
    const std::string col = color(s.color >= 0 ? s.color : static_cast<int>(si));
    const double y = top + 10 + 18.0 * row++;
    const double x = left + pw + 12;
    if (s.lines) o << "<line x1=\"" << num(x) << "\" y1=\"" << num(y) << "\" x2=\"" << num(x + 22) << "\" y2=\"" << num(y)
                   << "\" stroke=\"" << col << "\" stroke-width=\"2\"" << (s.dashed ? " stroke-dasharray=\"6,4\"" : "") << "/>\n";
    if (s.markers) o << "<circle cx=\"" << num(x + 11) << "\" cy=\"" << num(y) << "\" r=\"3.5\" fill=\"" << col << "\"/>\n";
    o << "<text x=\"" << num(x + 28) << "\" y=\"" << num(y + 4) << "\">" << esc(s.name) << "</text>\n";
  }
  o << "</svg>\n";
  return o.str();
}

std::string render(const Timeline& t) {
  const double left = 130, right = 20, top = 48, row_h = 14, bottom = 50;
  const double W = t.width, pw = W - left - right;
  const double ph = row_h * static_cast<double>(std::max<std::size_t>(t.rows.size(), 1));
  const double H = top + ph + bottom;
  const double x0 = t.x_min, x1 = t.x_max > t.x_min ? t.x_max : t.x_min + 1;
  auto to_x = [&](double x) { return left + (std::clamp(x, x0, x1) - x0) / (x1 - x0) * pw; };
  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H << "\" viewBox=\"0 0 " << W << " "
    << H << "\" font-family=\"sans-serif\" font-size=\"11\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  o << "<text x=\"" << W / 2 << "\" y=\"18\" text-anchor=\"middle\" font-size=\"15\">" << esc(t.title) << "</text>\n";
  double lx = left;
  for (const auto& [name, ci] : t.legend) {
    o << "<rect x=\"" << num(lx) << "\" y=\"28\" width=\"14\" height=\"10\" fill=\"" << color(ci) << "\"/>\n<text x=\""
      << num(lx + 18) << "\" y=\"37\">" << esc(name) << "</text>\n";
    lx += 30 + 7.0 * static_cast<double>(name.size());
  }
  for (double tk : ticks(x0, x1, false)) {
    o << "<line x1=\"" << num(to_x(tk)) << "\" y1=\"" << num(top) << "\" x2=\"" << num(to_x(tk)) << "\" y2=\""
      << num(top + ph) << "\" stroke=\"#ddd\"/>\n<text x=\"" << num(to_x(tk)) << "\" y=\"" << num(top + ph + 15)
      << "\" text-anchor=\"middle\">" << tick_label(tk, false) << "</text>\n";
  }
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    const TimelineRow& row = t.rows[r];
    const double y = top + row_h * static_cast<double>(r);
    o << "<text x=\"" << num(left - 6) << "\" y=\"" << num(y + row_h - 3) << "\" text-anchor=\"end\">" << esc(row.label)
      << "</text>\n";
    for (const auto& [a, b] : row.bars) {
      const double xa = to_x(a), xb = std::max(to_x(b), xa + 1.0);
      o << "<rect x=\"" << num(xa) << "\" y=\"" << num(y + 2) << "\" width=\"" << num(xb - xa) << "\" height=\""
        << num(row_h - 4) << "\" fill=\"" << color(row.color) << "\"/>\n";
    }
  }
  o << "<rect x=\"" << left << "\" y=\"" << top << "\" width=\"" << pw << "\" height=\"" << ph
    << "\" fill=\"none\" stroke=\"#333\"/>\n<text x=\"" << num(left + pw / 2) << "\" y=\"" << num(H - 12)
    << "\" text-anchor=\"middle\">" << esc(t.x_label) << "</text>\n</svg>\n";
  return o.str();
}

}  // namespace lockstep::svg
