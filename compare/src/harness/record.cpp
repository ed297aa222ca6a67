// record(): the engines side by side, one frame at a time.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

#include "lockstep/compare/harness.hpp"
#include "lockstep/compare/resting.hpp"
#include "lockstep/scene_json.hpp"

namespace lockstep::compare {
namespace {

std::vector<BodySnapshot> snapshots(const EngineRun& e) {
  std::vector<BodySnapshot> out;
  out.reserve(static_cast<std::size_t>(e.body_count()));
  for (int i = 0; i < e.body_count(); ++i) out.push_back(e.body(i));
  return out;
}

FrameStats frame_stats(int frame, const std::vector<BodySnapshot>& mine, const std::vector<BodySnapshot>* base, double energy) {
  FrameStats f;
  f.frame = frame;
  f.energy = energy;
  for (const BodySnapshot& b : mine) f.asleep += b.asleep ? 1 : 0;
  if (!base) return f;
  const std::size_t n = std::min(mine.size(), base->size());
  double pos_sq = 0, ori_sq = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const BodySnapshot& a = mine[i];
    const BodySnapshot& b = (*base)[i];
    const double dp = std::sqrt((a.p[0] - b.p[0]) * (a.p[0] - b.p[0]) + (a.p[1] - b.p[1]) * (a.p[1] - b.p[1]) +
                                (a.p[2] - b.p[2]) * (a.p[2] - b.p[2]));
    const double dq = orientation_angle(b.q, a.q);
    pos_sq += dp * dp;
    ori_sq += dq * dq;
    if (dp > f.pos_max || f.pos_body < 0) { f.pos_max = dp; f.pos_body = static_cast<int>(i); }
    if (dq > f.ori_max || f.ori_body < 0) { f.ori_max = dq; f.ori_body = static_cast<int>(i); }
  }
  if (n > 0) {
    f.pos_rms = std::sqrt(pos_sq / static_cast<double>(n));
    f.ori_rms = std::sqrt(ori_sq / static_cast<double>(n));
  }
  return f;
}

void track_sleep(EngineTrack& t, const std::vector<BodySnapshot>& bodies, int frame) {
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    auto& iv = t.asleep_intervals[i];
    const bool open = !iv.empty() && iv.back().second < 0;
    if (bodies[i].asleep && !open) iv.emplace_back(frame, -1);
    if (!bodies[i].asleep && open) iv.back().second = frame;
  }
}

// An engine that refused the scene (make_engine threw SceneError): body is
// the index in the field's path "bodies[N]...", -1 without one.
RunFailure refusal(const SceneError& err) {
  int body = -1;
  if (err.field.rfind("bodies[", 0) == 0) body = std::atoi(err.field.c_str() + 7);
  return {0, body, err.field, err.what(), true};
}

// record(): engines[e] null means the engine refused the scene
// (refused[e] says why): its track is failed from frame 0 and holds no frames.
Recording record_engines(const Scene& scene, std::vector<std::unique_ptr<EngineRun>> engines,
                         const std::vector<std::string>& names, const std::vector<RunFailure>& refused, int baseline,
                         const RecordOptions& options) {
  if (engines.empty()) throw std::invalid_argument("record: no engines");
  if (baseline < 0 || baseline >= static_cast<int>(engines.size()))
    throw std::invalid_argument("record: baseline index out of range");
  Recording rec;
  rec.scene = scene;
  rec.frames = options.frames >= 0 ? options.frames : scene.frames;
  rec.baseline = baseline;
  const std::size_t ne = engines.size();
  rec.engines.resize(ne);
  std::vector<std::vector<BodySnapshot>> now(ne);
  for (std::size_t e = 0; e < ne; ++e) {
    EngineTrack& t = rec.engines[e];
    if (!engines[e]) {
      t.name = names.at(e);
      t.description = names.at(e) + ": cannot run this scene";
      t.failed = true;
      t.failure = refused.at(e);
      continue;
    }
    t.name = engines[e]->name();
    t.description = engines[e]->description();
    t.asleep_intervals.resize(static_cast<std::size_t>(engines[e]->body_count()));
    t.frames.reserve(static_cast<std::size_t>(rec.frames) + 1);
    now[e] = snapshots(*engines[e]);
  }
  const std::size_t b = static_cast<std::size_t>(baseline);
  auto compare_all = [&](int frame) {
    for (std::size_t e = 0; e < ne; ++e) {
      EngineTrack& t = rec.engines[e];
      if (t.failed) continue;
      const bool vs_base = e != b && !rec.engines[b].failed;
      t.frames.push_back(frame_stats(frame, now[e], vs_base ? &now[b] : nullptr, engines[e]->energy()));
      track_sleep(t, now[e], frame);
      if (options.observe) options.observe(static_cast<int>(e), *engines[e]);
    }
  };
  compare_all(0);
  for (int f = 1; f <= rec.frames; ++f) {
    bool any = false;
    for (std::size_t e = 0; e < ne; ++e) {
      EngineTrack& t = rec.engines[e];
      if (t.failed) continue;
      const auto t0 = std::chrono::steady_clock::now();
      try {
        engines[e]->step();
      } catch (const RunError& err) {
        t.failed = true;
        t.failure = {err.frame, err.body, err.quantity, err.what()};
        continue;
      }
      t.step_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      t.frames_run = f;
      now[e] = snapshots(*engines[e]);
      any = true;
    }
    if (!any) break;
    compare_all(f);
    if (options.progress) options.progress(f, rec.frames);
  }
  for (std::size_t e = 0; e < ne; ++e) {
    EngineTrack& t = rec.engines[e];
    t.final_bodies = now[e];
    for (auto& iv : t.asleep_intervals)
      if (!iv.empty() && iv.back().second < 0) iv.back().second = t.frames_run + 1;
  }
  return rec;
}

}  // namespace

Recording record(const Scene& scene, std::vector<std::unique_ptr<EngineRun>> engines, int baseline,
                 const RecordOptions& options) {
  for (const auto& e : engines)
    if (!e) throw std::invalid_argument("record: a null engine");
  return record_engines(scene, std::move(engines), {}, {}, baseline, options);
}

Recording record(const Scene& scene, const std::vector<std::string>& names, const std::string& baseline,
                 const RecordOptions& options) {
  std::vector<std::unique_ptr<EngineRun>> engines;
  std::vector<RunFailure> refused(names.size());
  int base = -1;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (names[i] == baseline) base = static_cast<int>(i);
    try {
      engines.push_back(make_engine(names[i], scene));
    } catch (const SceneError& err) {  // the engine's number type cannot hold the scene (scene_limits.hpp)
      engines.push_back(nullptr);
      refused[i] = refusal(err);
    }
  }
  if (base < 0) throw std::invalid_argument("--baseline: '" + baseline + "' is not among the engines compared");
  return record_engines(scene, std::move(engines), names, refused, base, options);
}

}  // namespace lockstep::compare
