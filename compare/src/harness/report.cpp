#include "lockstep/compare/report.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "lockstep/compare/resting.hpp"
#include "lockstep/compare/statistics.hpp"
#include "lockstep/compare/svg.hpp"

namespace lockstep::compare {
namespace {

std::string g(double v, const char* f = "%.4g") {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

// The one CSV writer of the report's tables: a header line, then rows of
// comma-separated fields; a text field holding a comma, a quote or a newline
// is quoted (RFC 4180), numbers are written as given.
class Csv {
 public:
  explicit Csv(const char* header) { o_ << header << '\n'; }
  // One row; each field is text (quoted when needed) or a number.
  template <class... Fields>
  void row(const Fields&... fields) {
    const char* sep = "";
    ((o_ << sep << field(fields), sep = ","), ...);
    o_ << '\n';
  }
  std::string str() const { return o_.str(); }

 private:
  static std::string field(const std::string& s) {
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string out = "\"";
    for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
    return out + "\"";
  }
  static std::string field(const char* s) { return field(std::string(s)); }
  template <class N>
  static std::string field(const N& n) { return std::to_string(n); }
  std::ostringstream o_;
};

std::string frames_csv(const Recording& r) {
  Csv csv("frame,engine,pos_max_m,pos_rms_m,pos_body,ori_max_rad,ori_rms_rad,ori_body,energy_J,asleep");
  for (const EngineTrack& t : r.engines)
    for (const FrameStats& f : t.frames)
      csv.row(f.frame, t.name, g(f.pos_max, "%.9g"), g(f.pos_rms, "%.9g"), f.pos_body, g(f.ori_max, "%.9g"),
              g(f.ori_rms, "%.9g"), f.ori_body, g(f.energy, "%.9g"), f.asleep);
  return csv.str();
}

std::string bodies_csv(const Recording& r, const CompareTolerances& tol) {
  Csv csv("engine,body,frame,px_m,py_m,pz_m,qw,qx,qy,qz,face_up,alignment,support,asleep,sleep_frame");
  for (const EngineTrack& t : r.engines) {
    const auto rs = resting_states(r.scene, t.final_bodies, tol.support_gap, tol.flat_alignment);
    for (std::size_t i = 0; i < t.final_bodies.size() && i < rs.size(); ++i) {
      const BodySnapshot& b = t.final_bodies[i];
      auto x = [](double v) { return g(v, "%.9g"); };
      csv.row(t.name, i, t.frames_run, x(b.p[0]), x(b.p[1]), x(b.p[2]), x(b.q[0]), x(b.q[1]), x(b.q[2]), x(b.q[3]),
              rs[i].face.label, g(rs[i].face.alignment, "%.6f"), supports_label(rs[i].supports), b.asleep ? 1 : 0,
              b.asleep ? b.sleep_frame : -1);
    }
  }
  return csv.str();
}

std::string checks_csv(const Verdict& v) {
  Csv csv("engine,baseline,check,quantity,body,frame,value,baseline_value,tolerance,pass");
  for (const EngineVerdict& e : v.engines)
    for (const Finding& f : e.findings)
      csv.row(f.engine, v.baseline, f.check, f.quantity, f.body, f.frame, f.value, f.baseline_value, f.tolerance,
              f.pass ? 1 : 0);
  return csv.str();
}

std::string sleep_csv(const Recording& r) {
  Csv csv("engine,body,asleep_from_frame,asleep_until_frame");
  for (const EngineTrack& t : r.engines)
    for (std::size_t i = 0; i < t.asleep_intervals.size(); ++i)
      for (const auto& [a, b] : t.asleep_intervals[i]) csv.row(t.name, i, a, b);
  return csv.str();
}

std::string statistics_csv(const Recording& r, const CompareTolerances& tol) {
  Csv csv("engine,statistic,key,value");
  for (const EngineTrack& t : r.engines) {
    const PileStatistics s = pile_statistics(r.scene, t.final_bodies, tol);
    for (const auto& [bin, n] : s.height_histogram) csv.row(t.name, "height_bin_from_m", g(bin * tol.height_bin, "%.9g"), n);
    for (const auto& [face, n] : s.faces) csv.row(t.name, "face_up", face, n);
    csv.row(t.name, "asleep", "", s.asleep);
    csv.row(t.name, "median_sleep_frame", "", s.median_sleep_frame);
    csv.row(t.name, "mean_height_m", "", g(s.mean_height, "%.9g"));
  }
  return csv.str();
}

std::string title(const Recording& r, const std::string& what) {
  return what + ": scene " + r.scene.name + " (" + std::to_string(r.scene.bodies.size()) + " bodies)";
}

// One series per engine (the baseline left out when skip_baseline) of a
// per-frame value: the line charts of the report.
template <class Value>
void add_frame_series(svg::Chart& c, const Recording& r, bool skip_baseline, Value value) {
  for (std::size_t e = 0; e < r.engines.size(); ++e) {
    if (skip_baseline && static_cast<int>(e) == r.baseline) continue;
    svg::Series s;
    s.name = r.engines[e].name;
    s.color = static_cast<int>(e);
    for (const FrameStats& f : r.engines[e].frames) {
      s.x.push_back(f.frame);
      s.y.push_back(value(f));
    }
    c.series.push_back(std::move(s));
  }
}

std::string divergence_svg(const Recording& r, const Verdict& v, bool position) {
  svg::Chart c;
  c.title = title(r, position ? "Position divergence from " + v.baseline : "Orientation divergence from " + v.baseline);
  c.x_label = "frame";
  c.y_label = position ? "max over bodies of |p - p_baseline| (m)" : "max over bodies of angle(q, q_baseline) (rad)";
  c.log_y = true;
  c.notes.push_back("dashed grey: the tolerance; values of 0 (bit-equal) are not drawn on the log axis");
  add_frame_series(c, r, true, [&](const FrameStats& f) { return position ? f.pos_max : f.ori_max; });
  svg::Series tol;
  tol.name = "tolerance";
  tol.color = 7;
  tol.dashed = true;
  tol.x = {0.0, static_cast<double>(r.frames)};
  const double t = position ? v.tolerances.position : v.tolerances.orientation;
  tol.y = {t, t};
  c.series.push_back(tol);
  return svg::render(c);
}

std::string energy_svg(const Recording& r) {
  svg::Chart c;
  c.title = title(r, "Energy");
  c.x_label = "frame";
  c.y_label = "kinetic + potential energy (J)";
  add_frame_series(c, r, false, [](const FrameStats& f) { return f.energy; });
  return svg::render(c);
}

constexpr std::size_t kTimelineMaxBodies = 40;

std::string sleep_svg(const Recording& r) {
  if (r.scene.bodies.size() > kTimelineMaxBodies) {
    svg::Chart c;
    c.title = title(r, "Bodies asleep");
    c.x_label = "frame";
    c.y_label = "bodies asleep";
    add_frame_series(c, r, false, [](const FrameStats& f) { return static_cast<double>(f.asleep); });
    return svg::render(c);
  }
  svg::Timeline tl;
  tl.title = title(r, "Sleep timeline");
  tl.x_label = "frame (bars: the frames a body is asleep)";
  tl.x_min = 0;
  tl.x_max = r.frames + 1;
  for (std::size_t e = 0; e < r.engines.size(); ++e) tl.legend.emplace_back(r.engines[e].name, static_cast<int>(e));
  for (std::size_t i = 0; i < r.scene.bodies.size(); ++i) {
    for (std::size_t e = 0; e < r.engines.size(); ++e) {
      svg::TimelineRow row;
      row.label = "body " + std::to_string(i) + " " + r.engines[e].name;
      row.color = static_cast<int>(e);
      if (i < r.engines[e].asleep_intervals.size())
        for (const auto& [a, b] : r.engines[e].asleep_intervals[i]) row.bars.emplace_back(a, b);
      tl.rows.push_back(std::move(row));
    }
  }
  return svg::render(tl);
}

}  // namespace

void write_file(const std::string& path, const std::string& text) {
  const std::filesystem::path p(path);
  std::error_code ec;
  if (p.has_parent_path()) std::filesystem::create_directories(p.parent_path(), ec);
  std::ofstream out(p, std::ios::binary);
  if (!out || !(out << text) || !out.flush()) throw std::runtime_error("cannot write '" + path + "'");
}

std::string summary_table(const Recording& r, const Verdict& v, int max_failures) {
  std::ostringstream o;
  const CompareTolerances& t = v.tolerances;
  o << "scene " << r.scene.name << ": " << r.scene.bodies.size() << " bodies, " << r.frames << " frames; baseline "
    << v.baseline << "; judge: " << judge_name(t.judge) << "\n";
  o << "tolerances: trajectory " << t.position << " m / " << t.orientation << " rad; rest " << t.rest_position
    << " m; sleep +-" << t.sleep_frames << " frames";
  if (t.judge == Judge::statistics)
    o << "; heights " << t.height_distance << " m (earth mover's), faces " << t.face_fraction
      << ", asleep " << t.asleep_fraction << ", median sleep +-" << t.median_sleep_frames << " frames";
  o << "\n\n";
  char line[512];
  std::snprintf(line, sizeof line, "%-8s %9s %11s %11s %11s %11s  %-30s %8s\n", "engine", "ms/step", "pos max m", "pos RMS m",
                "ori max rad", "ori RMS rad", "trajectories part", "checks");
  o << line;
  for (std::size_t e = 0; e < v.engines.size(); ++e) {
    const EngineVerdict& ev = v.engines[e];
    const EngineTrack& tr = r.engines[e];
    const double ms = tr.frames_run ? 1e3 * tr.step_seconds / tr.frames_run : 0.0;
    std::string parted = ev.is_baseline ? "(baseline)" : "never";
    if (ev.parted_frame >= 0)
      parted = "frame " + std::to_string(ev.parted_frame) + ", body " + std::to_string(ev.parted_body) + " " + ev.parted_quantity;
    std::string checks = std::to_string(ev.checks - ev.failures) + "/" + std::to_string(ev.checks);
    if (ev.is_baseline) checks = ev.failures ? "FAILED" : "-";
    const bool refused = tr.failed && tr.failure.refused;  // no frames: no divergence to show
    if (refused) {
      parted = ev.is_baseline ? "(baseline) cannot run" : "cannot run";
      checks = "FAILED";
    }
    if (ev.is_baseline || refused) {
      std::snprintf(line, sizeof line, "%-8s %9.4f %11s %11s %11s %11s  %-30s %8s\n", ev.engine.c_str(), ms, "-", "-", "-", "-",
                    parted.c_str(), checks.c_str());
    } else {
      std::snprintf(line, sizeof line, "%-8s %9.4f %11.3g %11.3g %11.3g %11.3g  %-30s %8s\n", ev.engine.c_str(), ms, ev.pos_max,
                    ev.pos_rms, ev.ori_max, ev.ori_rms, parted.c_str(), checks.c_str());
    }
    o << line;
    if (tr.failed && tr.failure.refused) o << "         FAILED, cannot run this scene: " << tr.failure.message << "\n";
    else if (tr.failed) o << "         run stopped at frame " << tr.failure.frame << ": " << tr.failure.message << "\n";
  }
  const std::vector<Finding> fails = v.failures();
  if (t.judge == Judge::statistics) {
    o << "\nTrajectories of a chaotic scene part and are not judged; statistics of the final frame are.\n";
  }
  if (!fails.empty()) {
    o << "\nDisagreements:\n";
    for (std::size_t i = 0; i < fails.size() && static_cast<int>(i) < max_failures; ++i)
      o << "  " << fails[i].message(v.baseline) << "\n";
    if (static_cast<int>(fails.size()) > max_failures)
      o << "  ... and " << fails.size() - static_cast<std::size_t>(max_failures) << " more (checks.csv lists all)\n";
  }
  o << "\n" << (v.agree() ? "AGREE" : "DISAGREE") << ": " << r.scene.name << ", " << fails.size() << " failed check"
    << (fails.size() == 1 ? "" : "s") << "\n";
  return o.str();
}

std::vector<std::string> write_report(const std::string& dir, const Recording& r, const Verdict& v) {
  const std::vector<std::pair<std::string, std::string>> files = {
      {"summary.txt", summary_table(r, v, 1000)},
      {"tolerances.json", tolerances_to_json(v.tolerances)},
      {"frames.csv", frames_csv(r)},
      {"bodies.csv", bodies_csv(r, v.tolerances)},
      {"checks.csv", checks_csv(v)},
      {"sleep.csv", sleep_csv(r)},
      {"statistics.csv", statistics_csv(r, v.tolerances)},
      {"divergence.svg", divergence_svg(r, v, true)},
      {"divergence_orientation.svg", divergence_svg(r, v, false)},
      {"energy.svg", energy_svg(r)},
      {"sleep_timeline.svg", sleep_svg(r)},
  };
  std::vector<std::string> written;
  for (const auto& [name, text] : files) {
    const std::string path = (std::filesystem::path(dir) / name).string();
    write_file(path, text);
    written.push_back(path);
  }
  return written;
}

}  // namespace lockstep::compare
