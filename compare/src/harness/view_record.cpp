// The replay page's data: collected from engines (ViewRecorder), written and
// read back as `lockstep run`'s run record and CSV (load_run), compared
// (compare_runs).
#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "lockstep/compare/resting.hpp"
#include "lockstep/compare/view.hpp"
#include "lockstep/scene_json.hpp"

namespace lockstep::compare {

std::string hash_hex(std::uint64_t h) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "%016" PRIx64, h);
  return buf;
}

ViewRecorder::ViewRecorder(std::string label, std::string engine, bool record_contacts, bool keep_states)
    : record_contacts_(record_contacts), keep_states_(keep_states) {
  run_.label = std::move(label);
  run_.engine = std::move(engine);
}

void ViewRecorder::add(const EngineRun& e, bool keep_state) {
  const int n = e.body_count();
  run_.bodies = n;
  const int frame = e.frame();
  auto at = [frame](auto& v, auto value) {
    v.resize(static_cast<std::size_t>(frame) + 1);
    v[static_cast<std::size_t>(frame)] = value;
  };
  at(run_.hashes, hash_hex(e.state_hash()));
  at(run_.energy, e.energy());
  int asleep = 0;
  std::vector<BodySnapshot> bodies;
  bodies.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    bodies.push_back(e.body(i));
    asleep += bodies.back().asleep ? 1 : 0;
  }
  at(run_.asleep_count, asleep);
  if (frame > 0 && all_asleep_frame_ < 0 && n > static_bodies_ && asleep + static_bodies_ == n) all_asleep_frame_ = frame;
  run_.has_contacts = e.has_contacts();
  std::vector<ContactSnapshot> contacts;
  if (run_.has_contacts) {
    contacts = e.contacts();
    double deepest = 0;
    for (const ContactSnapshot& c : contacts) deepest = std::max(deepest, c.penetration);
    worst_penetration_ = std::max(worst_penetration_, deepest);
    at(run_.contact_count, static_cast<int>(contacts.size()));
    at(run_.penetration, deepest);
  }
  if (!keep_state) return;
  if (keep_states_) {
    run_.frames.push_back(frame);
    for (const BodySnapshot& b : bodies) {
      for (double x : {b.p[0], b.p[1], b.p[2], b.q[0], b.q[1], b.q[2], b.q[3], b.v[0], b.v[1], b.v[2], b.w[0], b.w[1], b.w[2]})
        run_.state.push_back(static_cast<float>(x));
      run_.asleep.push_back(b.asleep ? 1 : 0);
    }
  }
  if (record_contacts_ && run_.has_contacts) {
    auto& list = run_.contacts[frame];
    for (const ContactSnapshot& c : contacts)
      list.push_back({c.a, c.b,
                      {static_cast<float>(c.point[0]), static_cast<float>(c.point[1]), static_cast<float>(c.point[2])},
                      {static_cast<float>(c.normal[0]), static_cast<float>(c.normal[1]), static_cast<float>(c.normal[2])},
                      static_cast<float>(c.penetration)});
  }
}

int view_stride(int frames, int bodies, int runs, std::size_t max_bytes) {
  const double per_frame = static_cast<double>(bodies) * runs * (kViewFloats * 4 + 1);
  const double kept = std::max(1.0, std::floor(static_cast<double>(max_bytes) / std::max(1.0, per_frame)));
  const double all = static_cast<double>(frames) + 1;
  return static_cast<int>(std::max(1.0, std::ceil(all / kept)));
}

std::string run_record_json(const Scene& scene, const ViewRun& run, int every, bool raw) {
  nlohmann::json j;
  j["format"] = "lockstep-run";
  j["version"] = 1;
  j["engine"] = run.engine;
  j["bodies"] = run.bodies;
  j["frames_run"] = run.hashes.empty() ? 0 : static_cast<int>(run.hashes.size()) - 1;
  j["every"] = every;
  j["raw"] = raw;
  j["hash"] = run.hashes;
  j["energy"] = run.energy;
  j["asleep"] = run.asleep_count;
  if (run.has_contacts) {
    j["contacts"] = run.contact_count;
    j["penetration"] = run.penetration;
  }
  if (!run.contacts.empty()) {
    nlohmann::json lists = nlohmann::json::array();
    for (const auto& [frame, list] : run.contacts) {
      nlohmann::json cs = nlohmann::json::array();
      for (const ViewContact& c : list)
        cs.push_back({c.a, c.b, c.point[0], c.point[1], c.point[2], c.normal[0], c.normal[1], c.normal[2], c.penetration});
      lists.push_back({{"frame", frame}, {"contacts", std::move(cs)}});
    }
    j["contact_lists"] = std::move(lists);
  }
  j["scene"] = nlohmann::json::parse(scene_to_json(scene));
  return j.dump() + "\n";
}

namespace {

struct Record {
  Scene scene;
  nlohmann::json j;
  int frames_run = 0, every = 1;
  bool raw = false;
};

Record read_record(const std::string& csv_path) {
  const std::string path = csv_path + kRunRecordSuffix;
  std::ifstream in(path);
  if (!in)
    throw std::runtime_error("'" + path + "' not found: view reads the run record `lockstep run` writes beside a CSV "
                             "trajectory; re-run `lockstep run SCENE --engine E --out " + csv_path + "`");
  Record r;
  try {
    r.j = nlohmann::json::parse(in);
    if (r.j.value("format", "") != "lockstep-run")
      throw std::runtime_error("field \"format\" must be \"lockstep-run\"");
    r.frames_run = r.j.at("frames_run").get<int>();
    r.every = r.j.at("every").get<int>();
    r.raw = r.j.at("raw").get<bool>();
    if (r.every < 1 || r.frames_run < 0) throw std::runtime_error("\"every\" must be >= 1 and \"frames_run\" >= 0");
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(path + ": not a run record (" + e.what() + "); re-run `lockstep run` to write it");
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(path + ": " + e.what() + "; re-run `lockstep run` to write it");
  }
  // A run of 0 frames (`lockstep run --frames 0`) records a scene of 0
  // frames, which a scene file may not have; frames_run says how many ran.
  nlohmann::json scene = r.j.at("scene");
  if (scene.is_object() && scene.value("frames", 1) < 1) scene["frames"] = 1;
  r.scene = parse_scene(scene.dump(), path + " scene");
  r.scene.frames = r.frames_run;
  return r;
}

// The frames `lockstep run --every K` writes: 0, K, 2K, ... and the last.
std::vector<int> written_frames(int frames_run, int every) {
  std::vector<int> out;
  for (int f = 0; f <= frames_run; f += every) out.push_back(f);
  if (out.back() != frames_run) out.push_back(frames_run);
  return out;
}

}  // namespace

RunShape run_shape(const std::string& csv_path) {
  const Record r = read_record(csv_path);
  return {static_cast<int>(written_frames(r.frames_run, r.every).size()), static_cast<int>(r.scene.bodies.size())};
}

LoadedRun load_run(const std::string& csv_path, int stride) {
  Record r = read_record(csv_path);
  LoadedRun out;
  out.scene = r.scene;
  ViewRun& run = out.run;
  run.label = csv_path.substr(csv_path.find_last_of('/') == std::string::npos ? 0 : csv_path.find_last_of('/') + 1);
  run.engine = r.j.value("engine", "");
  run.bodies = static_cast<int>(r.scene.bodies.size());
  const nlohmann::json& j = r.j;
  run.hashes = j.value("hash", std::vector<std::string>{});
  run.energy = j.value("energy", std::vector<double>{});
  run.asleep_count = j.value("asleep", std::vector<int>{});
  run.has_contacts = j.contains("contacts");
  run.contact_count = j.value("contacts", std::vector<int>{});
  run.penetration = j.value("penetration", std::vector<double>{});
  const std::vector<int> written = written_frames(r.frames_run, r.every);
  std::vector<char> keep(static_cast<std::size_t>(r.frames_run) + 1, 0);
  for (std::size_t i = 0; i < written.size(); ++i)
    if (i % static_cast<std::size_t>(std::max(1, stride)) == 0 || i + 1 == written.size())
      keep[static_cast<std::size_t>(written[i])] = 1;
  if (j.contains("contact_lists"))
    for (const nlohmann::json& l : j.at("contact_lists")) {
      const int f = l.at("frame").get<int>();
      if (f < 0 || f > r.frames_run || !keep[static_cast<std::size_t>(f)]) continue;
      auto& list = run.contacts[f];
      for (const nlohmann::json& c : l.at("contacts"))
        list.push_back({c.at(0).get<int>(), c.at(1).get<int>(),
                        {c.at(2).get<float>(), c.at(3).get<float>(), c.at(4).get<float>()},
                        {c.at(5).get<float>(), c.at(6).get<float>(), c.at(7).get<float>()},
                        c.at(8).get<float>()});
    }

  std::ifstream in(csv_path);
  if (!in) throw std::runtime_error("cannot read '" + csv_path + "'");
  std::string line;
  const std::string header = "frame,body,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz,asleep";
  if (!std::getline(in, line) || line != header)
    throw std::runtime_error(csv_path + ":1: expected the header '" + header +
                             "' of a `lockstep run --format csv` trajectory");
  const double scale = r.raw ? 1.0 / 65536.0 : 1.0;
  const std::size_t n = static_cast<std::size_t>(run.bodies);
  long long line_no = 1;
  int current = -1;
  std::size_t body_rows = 0;
  while (std::getline(in, line)) {
    ++line_no;
    auto fail = [&](const std::string& why) {
      throw std::runtime_error(csv_path + ":" + std::to_string(line_no) + ": " + why + " (line '" + line.substr(0, 80) + "')");
    };
    const char* s = line.c_str();
    char* end = nullptr;
    const long frame = std::strtol(s, &end, 10);
    if (end == s || *end != ',' || frame < 0 || frame > r.frames_run) fail("frame must be in [0, " + std::to_string(r.frames_run) + "]");
    if (frame != current) {
      if (current >= 0 && keep[static_cast<std::size_t>(current)] && body_rows != n)
        fail("frame " + std::to_string(current) + " has " + std::to_string(body_rows) + " bodies; the scene has " + std::to_string(n));
      if (frame < current) fail("frames must ascend");
      current = static_cast<int>(frame);
      body_rows = 0;
      if (keep[static_cast<std::size_t>(current)]) {
        run.frames.push_back(current);
        run.state.resize(run.state.size() + n * kViewFloats);
        run.asleep.resize(run.asleep.size() + n);
      }
    }
    if (!keep[static_cast<std::size_t>(current)]) { ++body_rows; continue; }
    s = end + 1;
    const long body = std::strtol(s, &end, 10);
    if (end == s || *end != ',' || body != static_cast<long>(body_rows) || body >= static_cast<long>(n))
      fail("body must be " + std::to_string(body_rows) + " (rows in body order, " + std::to_string(n) + " bodies)");
    float* dst = &run.state[(run.frames.size() - 1) * n * kViewFloats + static_cast<std::size_t>(body) * kViewFloats];
    for (int k = 0; k < kViewFloats; ++k) {
      s = end + 1;
      const double v = std::strtod(s, &end);
      if (end == s || *end != ',') fail("column " + std::to_string(k + 3) + " must be a number");
      dst[k] = static_cast<float>(v * scale);
    }
    s = end + 1;
    const long asleep = std::strtol(s, &end, 10);
    if (end == s || (asleep != 0 && asleep != 1)) fail("asleep must be 0 or 1");
    run.asleep[(run.frames.size() - 1) * n + static_cast<std::size_t>(body)] = static_cast<std::uint8_t>(asleep);
    ++body_rows;
  }
  if (current >= 0 && keep[static_cast<std::size_t>(current)] && body_rows != n)
    throw std::runtime_error(csv_path + ": frame " + std::to_string(current) + " has " + std::to_string(body_rows) +
                             " bodies; the scene has " + std::to_string(n) + " (a cut-off file?)");
  if (current != r.frames_run)
    throw std::runtime_error(csv_path + ": ends at frame " + std::to_string(current) + "; its run record says " +
                             std::to_string(r.frames_run) + " (a cut-off file? re-run `lockstep run`)");
  return out;
}

ViewComparison compare_runs(const std::vector<ViewRun>& runs, const CompareTolerances& tol) {
  ViewComparison c;
  c.position_tolerance = tol.position;
  c.orientation_tolerance = tol.orientation;
  c.rest_position_tolerance = tol.rest_position;
  const ViewRun& base = runs.at(0);
  const std::size_t n = static_cast<std::size_t>(base.bodies);
  for (const ViewRun& r : runs) {
    std::vector<double> div;
    int parted = -1, parted_body = -1, common = 0;
    for (std::size_t k = 0; k < base.frames.size(); ++k) {
      // Runs written with different --every: compared on the frames both hold
      // (NaN, null in the page, on the others).
      const auto it = std::lower_bound(r.frames.begin(), r.frames.end(), base.frames[k]);
      if (static_cast<std::size_t>(r.bodies) != n || it == r.frames.end() || *it != base.frames[k]) {
        div.push_back(std::numeric_limits<double>::quiet_NaN());
        continue;
      }
      ++common;
      const std::size_t kr = static_cast<std::size_t>(it - r.frames.begin());
      double worst = 0;
      for (std::size_t i = 0; i < n; ++i) {
        const float* a = &base.state[(k * n + i) * kViewFloats];
        const float* b = &r.state[(kr * n + i) * kViewFloats];
        const double dp = std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
        const double qa[4] = {a[3], a[4], a[5], a[6]}, qb[4] = {b[3], b[4], b[5], b[6]};
        const double dq = orientation_angle(qa, qb);
        worst = std::max(worst, dp);
        if (parted < 0 && (dp > tol.position || dq > tol.orientation)) {
          parted = base.frames[k];
          parted_body = static_cast<int>(i);
        }
      }
      div.push_back(worst);
    }
    c.divergence.push_back(std::move(div));
    c.parted_frame.push_back(parted);
    c.parted_body.push_back(parted_body);
    c.common_frames.push_back(common);
    // The final pose, as compare's rest check: both runs' last frame.
    double final_distance = -1;
    int final_body = -1;
    if (!r.frames.empty() && !base.frames.empty() && r.frames.back() == base.frames.back() &&
        static_cast<std::size_t>(r.bodies) == n) {
      final_distance = 0;
      const std::size_t kb = base.frames.size() - 1, kr = r.frames.size() - 1;
      for (std::size_t i = 0; i < n; ++i) {
        const float* a = &base.state[(kb * n + i) * kViewFloats];
        const float* b = &r.state[(kr * n + i) * kViewFloats];
        const double dp = std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
        if (dp > final_distance || final_body < 0) { final_distance = dp; final_body = static_cast<int>(i); }
      }
    }
    c.final_distance.push_back(final_distance);
    c.final_body.push_back(final_body);
  }
  {
    std::ostringstream os;
    os << "Runs part where a body is more than " << tol.position << " m or " << tol.orientation
       << " rad from " << base.label << " (the trajectory tolerance `lockstep compare` judges trajectories by); "
       << "compare also judges the final pose against its rest tolerance of " << tol.rest_position << " m.";
    c.tolerance_note = os.str();
  }
  // Which two runs' hashes to compare: two fixed runs (expected to match bit
  // for bit) first, then two runs of one engine. Runs of different engines
  // differ from frame 0 (their numbers differ), so are not compared.
  for (int pass = 0; pass < 2 && c.hash_run_a < 0; ++pass)
    for (std::size_t a = 0; a < runs.size() && c.hash_run_a < 0; ++a)
      for (std::size_t b = a + 1; b < runs.size() && c.hash_run_a < 0; ++b) {
        const ViewRun& ra = runs[a];
        const ViewRun& rb = runs[b];
        if (ra.hashes.empty() || rb.hashes.empty()) continue;
        if (pass == 0 && (ra.engine != "fixed" || rb.engine != "fixed")) continue;
        if (pass == 1 && ra.engine != rb.engine) continue;
        c.hash_run_a = static_cast<int>(a);
        c.hash_run_b = static_cast<int>(b);
      }
  if (c.hash_run_a >= 0) {
    const auto& ha = runs[static_cast<std::size_t>(c.hash_run_a)].hashes;
    const auto& hb = runs[static_cast<std::size_t>(c.hash_run_b)].hashes;
    c.hash_frames_compared = static_cast<int>(std::min(ha.size(), hb.size()));
    for (int f = 0; f < c.hash_frames_compared; ++f)
      if (ha[static_cast<std::size_t>(f)] != hb[static_cast<std::size_t>(f)]) { c.first_hash_difference = f; break; }
    const std::string pair = runs[static_cast<std::size_t>(c.hash_run_a)].label + " and " + runs[static_cast<std::size_t>(c.hash_run_b)].label;
    c.note = c.first_hash_difference >= 0
                 ? "hashes of " + pair + " first differ at frame " + std::to_string(c.first_hash_difference)
                 : "hashes of " + pair + " are identical on all " + std::to_string(c.hash_frames_compared) + " frames";
  }
  return c;
}

}  // namespace lockstep::compare
