// judge(): each engine against the baseline, per docs/COMPARE.md.
#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>

#include "lockstep/compare/harness.hpp"
#include "lockstep/compare/resting.hpp"
#include "lockstep/compare/statistics.hpp"

namespace lockstep::compare {
namespace {

#if defined(__GNUC__)
std::string fmt(const char* f, ...) __attribute__((format(printf, 1, 2)));
#endif
std::string fmt(const char* f, ...) {
  char buf[256];
  va_list ap;
  va_start(ap, f);
  std::vsnprintf(buf, sizeof buf, f, ap);
  va_end(ap);
  return buf;
}

std::string sleep_text(int frame) { return frame < 0 ? "awake at the end" : fmt("frame %d", frame); }

class Judging {
 public:
  Judging(const Recording& r, const CompareTolerances& t, std::size_t e)
      : rec_(r), tol_(t), base_(r.engines[static_cast<std::size_t>(r.baseline)]), mine_(r.engines[e]) {
    v_.engine = mine_.name;
  }

  EngineVerdict run() {
    // An engine that refused the scene (or a refused baseline) has no frames
    // to measure: only its run check is reported.
    const bool refused = (mine_.failed && mine_.failure.refused) || (base_.failed && base_.failure.refused);
    if (!refused) trajectory();
    if (mine_.failed || base_.failed) {
      run_failures();
    } else if (tol_.judge == Judge::bodies) {
      rest();
      sleep();
    } else {
      statistics();
    }
    for (const Finding& f : v_.findings) {
      ++v_.checks;
      v_.failures += f.pass ? 0 : 1;
    }
    return v_;
  }

 private:
  void add(std::string check, std::string quantity, int body, int frame, std::string value, std::string base,
           std::string tolerance, bool pass) {
    v_.findings.push_back({mine_.name, std::move(check), std::move(quantity), body, frame, std::move(value), std::move(base),
                           std::move(tolerance), pass});
  }

  // Max and RMS divergence, and the first frame above a tolerance.
  void trajectory() {
    const std::size_t n = std::min(mine_.frames.size(), base_.frames.size());
    double pos_sq = 0, ori_sq = 0;
    int pos_frame = 0, ori_frame = 0, pos_body = -1, ori_body = -1;
    for (std::size_t f = 0; f < n; ++f) {
      const FrameStats& s = mine_.frames[f];
      pos_sq += s.pos_rms * s.pos_rms;
      ori_sq += s.ori_rms * s.ori_rms;
      if (s.pos_max > v_.pos_max) { v_.pos_max = s.pos_max; pos_frame = s.frame; pos_body = s.pos_body; }
      if (s.ori_max > v_.ori_max) { v_.ori_max = s.ori_max; ori_frame = s.frame; ori_body = s.ori_body; }
      if (v_.parted_frame < 0 && (s.pos_max > tol_.position || s.ori_max > tol_.orientation)) {
        v_.parted_frame = s.frame;
        const bool pos = s.pos_max / tol_.position >= s.ori_max / tol_.orientation;
        v_.parted_body = pos ? s.pos_body : s.ori_body;
        v_.parted_quantity = pos ? "position" : "orientation";
      }
    }
    if (n > 0) {
      v_.pos_rms = std::sqrt(pos_sq / static_cast<double>(n));
      v_.ori_rms = std::sqrt(ori_sq / static_cast<double>(n));
    }
    if (tol_.judge != Judge::bodies || &mine_ == &base_) return;
    // Judge::bodies: a failure names the first frame above the tolerance; a
    // pass names the frame of the largest divergence.
    auto first_above = [&](bool pos, double tol) -> const FrameStats* {
      for (std::size_t f = 0; f < n; ++f)
        if ((pos ? mine_.frames[f].pos_max : mine_.frames[f].ori_max) > tol) return &mine_.frames[f];
      return nullptr;
    };
    if (const FrameStats* s = first_above(true, tol_.position))
      add("trajectory", "position", s->pos_body, s->frame, fmt("%.4g m from the baseline", s->pos_max), "-",
          fmt("<= %g m", tol_.position), false);
    else
      add("trajectory", "position", pos_body, pos_frame, fmt("%.4g m from the baseline (max)", v_.pos_max), "-",
          fmt("<= %g m", tol_.position), true);
    if (const FrameStats* s = first_above(false, tol_.orientation))
      add("trajectory", "orientation", s->ori_body, s->frame, fmt("%.4g rad from the baseline", s->ori_max), "-",
          fmt("<= %g rad", tol_.orientation), false);
    else
      add("trajectory", "orientation", ori_body, ori_frame, fmt("%.4g rad from the baseline (max)", v_.ori_max), "-",
          fmt("<= %g rad", tol_.orientation), true);
  }

  // This engine stopped; the baseline's own stop is reported in its verdict.
  void run_failures() {
    if (!mine_.failed) return;
    add("run", mine_.failure.quantity, mine_.failure.body, mine_.failure.frame,
        (mine_.failure.refused ? "cannot run this scene: " : "stopped: ") + mine_.failure.message, "ran", "no run error",
        false);
  }

  void rest() {
    const Scene& s = rec_.scene;
    const auto a = resting_states(s, mine_.final_bodies, tol_.support_gap, tol_.flat_alignment);
    const auto b = resting_states(s, base_.final_bodies, tol_.support_gap, tol_.flat_alignment);
    const int frame = mine_.frames_run;
    for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
      const int body = static_cast<int>(i);
      const double d = std::sqrt((a[i].p[0] - b[i].p[0]) * (a[i].p[0] - b[i].p[0]) + (a[i].p[1] - b[i].p[1]) * (a[i].p[1] - b[i].p[1]) +
                                 (a[i].p[2] - b[i].p[2]) * (a[i].p[2] - b[i].p[2]));
      add("rest", "rest position", body, frame,
          fmt("(%.4f, %.4f, %.4f) m, %.4g m apart", a[i].p[0], a[i].p[1], a[i].p[2], d),
          fmt("(%.4f, %.4f, %.4f) m", b[i].p[0], b[i].p[1], b[i].p[2]), fmt("<= %g m", tol_.rest_position),
          d <= tol_.rest_position);
      add("rest", "face up", body, frame, fmt("%s (alignment %.4f)", a[i].face.label.c_str(), a[i].face.alignment),
          fmt("%s (alignment %.4f)", b[i].face.label.c_str(), b[i].face.alignment), "same face", a[i].face.label == b[i].face.label);
      add("rest", "support", body, frame, supports_label(a[i].supports), supports_label(b[i].supports),
          fmt("same supports (gap %g m)", tol_.support_gap), a[i].supports == b[i].supports);
    }
  }

  void sleep() {
    for (std::size_t i = 0; i < mine_.final_bodies.size() && i < base_.final_bodies.size(); ++i) {
      const int a = mine_.final_bodies[i].asleep ? mine_.final_bodies[i].sleep_frame : -1;
      const int b = base_.final_bodies[i].asleep ? base_.final_bodies[i].sleep_frame : -1;
      const bool pass = (a < 0 && b < 0) || (a >= 0 && b >= 0 && std::abs(a - b) <= tol_.sleep_frames);
      add("sleep", "sleep frame", static_cast<int>(i), a >= 0 ? a : (b >= 0 ? b : mine_.frames_run), sleep_text(a),
          sleep_text(b), fmt("+-%d frames", tol_.sleep_frames), pass);
    }
  }

  void statistics() {
    const PileStatistics a = pile_statistics(rec_.scene, mine_.final_bodies, tol_);
    const PileStatistics b = pile_statistics(rec_.scene, base_.final_bodies, tol_);
    const int frame = mine_.frames_run;
    const int n = std::max(1, b.bodies);
    const double hd = height_distance(a.heights, b.heights);
    add("statistics", "resting heights", -1, frame, fmt("earth mover's distance %.4g m (mean height %.4f m)", hd, a.mean_height),
        fmt("mean height %.4f m", b.mean_height), fmt("<= %g m", tol_.height_distance), hd <= tol_.height_distance);
    std::string label;
    const int dface = max_count_difference(a.faces, b.faces, &label);
    auto count = [](const std::map<std::string, int>& m, const std::string& k) {
      auto it = m.find(k);
      return it == m.end() ? 0 : it->second;
    };
    add("statistics", "face up count" + (label.empty() ? std::string() : " (" + label + ")"), -1, frame,
        fmt("%d of %d", count(a.faces, label), a.bodies), fmt("%d of %d", count(b.faces, label), b.bodies),
        fmt("differ by <= %g of the bodies", tol_.face_fraction), dface <= tol_.face_fraction * n);
    add("statistics", "asleep count", -1, frame, fmt("%d of %d", a.asleep, a.bodies), fmt("%d of %d", b.asleep, b.bodies),
        fmt("differ by <= %g of the bodies", tol_.asleep_fraction), std::abs(a.asleep - b.asleep) <= tol_.asleep_fraction * n);
    // A median of a handful of sleepers is noise: it is compared when both
    // engines have at least asleep_fraction of the bodies (and one) asleep;
    // below that the asleep count above is what is judged.
    const int min_asleep = std::max(1, static_cast<int>(std::ceil(tol_.asleep_fraction * n)));
    if (a.asleep < min_asleep || b.asleep < min_asleep) {
      add("statistics", "median sleep frame", -1, frame,
          fmt("%s (%d asleep)", sleep_text(a.median_sleep_frame).c_str(), a.asleep),
          fmt("%s (%d asleep)", sleep_text(b.median_sleep_frame).c_str(), b.asleep),
          fmt("compared when both have >= %d asleep", min_asleep), true);
      return;
    }
    add("statistics", "median sleep frame", -1, frame, sleep_text(a.median_sleep_frame), sleep_text(b.median_sleep_frame),
        fmt("+-%d frames", tol_.median_sleep_frames),
        std::abs(a.median_sleep_frame - b.median_sleep_frame) <= tol_.median_sleep_frames);
  }

  const Recording& rec_;
  const CompareTolerances& tol_;
  const EngineTrack& base_;
  const EngineTrack& mine_;
  EngineVerdict v_;
};

}  // namespace

std::string Finding::message(const std::string& baseline_name) const {
  std::string m = engine + " vs " + baseline_name + ": " + quantity;
  if (body >= 0) m += ", body " + std::to_string(body);
  if (frame >= 0) m += ", frame " + std::to_string(frame);
  m += ": " + value;
  if (baseline_value != "-") m += " vs " + baseline_value;
  m += " (tolerance " + tolerance + ")";
  return m;
}

bool Verdict::agree() const {
  for (const EngineVerdict& e : engines)
    if (e.failures > 0) return false;
  return true;
}

std::vector<Finding> Verdict::failures() const {
  std::vector<Finding> out;
  for (const EngineVerdict& e : engines)
    for (const Finding& f : e.findings)
      if (!f.pass) out.push_back(f);
  return out;
}

Verdict judge(const Recording& rec, const CompareTolerances& t) {
  Verdict v;
  v.tolerances = t;
  v.baseline = rec.engines.at(static_cast<std::size_t>(rec.baseline)).name;
  for (std::size_t e = 0; e < rec.engines.size(); ++e) {
    if (static_cast<int>(e) == rec.baseline) {
      EngineVerdict b;
      b.engine = rec.engines[e].name;
      b.is_baseline = true;
      if (rec.engines[e].failed) {
        const RunFailure& f = rec.engines[e].failure;
        b.findings.push_back({b.engine, "run", f.quantity, f.body, f.frame,
                              (f.refused ? "cannot run this scene: " : "stopped: ") + f.message, "-", "no run error", false});
        b.checks = b.failures = 1;
      }
      v.engines.push_back(b);
      continue;
    }
    v.engines.push_back(Judging(rec, t, e).run());
  }
  return v;
}

}  // namespace lockstep::compare
