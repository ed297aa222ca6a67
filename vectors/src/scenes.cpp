// Level 3: scene runs on World<Q16>, frame by frame.
#include "lockstep/vectors/scenes.hpp"

#include <map>
#include <optional>
#include <set>

#include "lockstep/builtin_scenes.hpp"
#include "lockstep/fixed/q16_vec.hpp"
#include "lockstep/scene_json.hpp"
#include "lockstep/vectors/params_json.hpp"
#include "lockstep/vectors/sdf_json.hpp"
#include "lockstep/world.hpp"

namespace lockstep::vectors {
namespace {

Json world_state(const World<Q16>& w) {
  Json bodies = Json::array();
  for (const Body<Q16>& b : w.bodies()) bodies.push_back(body_state(b));
  return bodies;
}

Json effects_json(const Effects& e) {
  return Json{{"gravity", e.gravity},   {"damping", e.damping},   {"ground", e.ground},
              {"contacts", e.contacts}, {"friction", e.friction}, {"restitution", e.restitution},
              {"settling", e.settling}, {"sleep", e.sleep},       {"sdf", e.sdf}};
}

// The scene's values as the fixed engine holds them after loading (World<Q16>'s
// constructor: eq 22 for every double, eqs 10, 14-18 for the bodies, eq 32 for
// the SDF spacing).
Json setup_json(const Scene& s, const World<Q16>& w) {
  Json setup;
  setup["params"] = params_to_json(w.params());
  setup["effects"] = effects_json(s.effects);
  setup["ground"] = Json{{"present", s.ground.present},
                         {"height", Q16::from_double(s.ground.height).raw()},
                         {"restitution", Q16::from_double(s.ground.material.restitution).raw()},
                         {"friction", Q16::from_double(s.ground.material.friction).raw()}};
  Json bodies = Json::array();
  for (const Body<Q16>& b : w.bodies())
    bodies.push_back(Json{{"half", to_json(b.half)},
                          {"inv_mass", b.inv_mass.raw()},
                          {"inv_inertia", to_json(b.inv_inertia)},
                          {"restitution", b.restitution.raw()},
                          {"friction", b.friction.raw()},
                          {"static", b.is_static}});
  setup["bodies"] = std::move(bodies);
  Json sdfs = Json::array();
  for (const SdfDesc& d : s.sdfs) {
    const Vec3<Q16> lo{Q16::from_double(d.min.x), Q16::from_double(d.min.y), Q16::from_double(d.min.z)};
    const Vec3<Q16> hi{Q16::from_double(d.max.x), Q16::from_double(d.max.y), Q16::from_double(d.max.z)};
    const Json grid = sdf_grid_json(lo, hi, {d.nx, d.ny, d.nz});
    Json sdf{{"name", d.name}};
    for (auto it = grid.begin(); it != grid.end(); ++it) sdf[it.key()] = it.value();
    sdf["restitution"] = Q16::from_double(d.material.restitution).raw();
    sdf["friction"] = Q16::from_double(d.material.friction).raw();
    Json values = Json::array();
    for (double v : d.values) values.push_back(Q16::from_double(v).raw());
    sdf["values"] = std::move(values);
    sdfs.push_back(std::move(sdf));
  }
  setup["sdfs"] = std::move(sdfs);
  return setup;
}

Json counters_json(const StageCounters& c) {
  return Json{{"integrate_velocity", c.integrate_velocity},
              {"damping", c.damping},
              {"integrate_position", c.integrate_position},
              {"broadphase_bodies", c.broadphase_bodies},
              {"pairs_tested", c.pairs_tested},
              {"ground_contacts", c.ground_contacts},
              {"sdf_contacts", c.sdf_contacts},
              {"body_contacts", c.body_contacts},
              {"solver_contacts", c.solver_contacts},
              {"normal_impulses", c.normal_impulses},
              {"restitution_bounces", c.restitution_bounces},
              {"friction_steps", c.friction_steps},
              {"corrections", c.corrections},
              {"settling_bodies", c.settling_bodies},
              {"sleep_updates", c.sleep_updates},
              {"wakes", c.wakes}};
}

std::vector<int> state_frames_for(int bodies, int frames, const SceneVectorOptions& o) {
  std::set<int> f;
  if (bodies <= o.full_state_max_bodies) {
    for (int i = 0; i <= frames; ++i) f.insert(i);
  } else {
    for (int i : o.sparse_frames)
      if (i >= 0 && i <= frames) f.insert(i);
    f.insert(frames);
  }
  return {f.begin(), f.end()};
}

// Appends [frame, body, asleep] for every body whose asleep flag changed.
void record_events(const World<Q16>& w, std::vector<bool>& asleep, Json& events) {
  for (std::size_t i = 0; i < w.bodies().size(); ++i) {
    const bool now = w.bodies()[i].asleep;
    if (now != asleep[i]) {
      events.push_back(Json::array({w.frame(), static_cast<int>(i), now ? 1 : 0}));
      asleep[i] = now;
    }
  }
}

int all_asleep_frame_update(const World<Q16>& w, int current) {
  if (current >= 0) return current;
  bool any_dynamic = false;
  for (const Body<Q16>& b : w.bodies()) {
    if (b.is_static) continue;
    any_dynamic = true;
    if (!b.asleep) return -1;
  }
  return any_dynamic ? w.frame() : -1;
}

}  // namespace

Json body_state(const Body<Q16>& b) {
  return Json::array({b.p.x.raw(), b.p.y.raw(), b.p.z.raw(), b.q.w.raw(), b.q.x.raw(), b.q.y.raw(), b.q.z.raw(),
                      b.v.x.raw(), b.v.y.raw(), b.v.z.raw(), b.w.x.raw(), b.w.y.raw(), b.w.z.raw(), b.asleep ? 1 : 0,
                      b.sleep_counter});
}

const std::vector<std::string>& state_fields() {
  static const std::vector<std::string> f = {"p.x", "p.y", "p.z", "q.w", "q.x", "q.y",    "q.z",          "v.x",
                                             "v.y", "v.z", "w.x", "w.y", "w.z", "asleep", "sleep_counter"};
  return f;
}

Json generate_scene_vectors(const Scene& scene, const SceneVectorOptions& options) {
  World<Q16> world(scene);
  const std::vector<int> frames = state_frames_for(static_cast<int>(scene.bodies.size()), scene.frames, options);
  const std::set<int> stored(frames.begin(), frames.end());
  Json hashes = Json::array();
  Json states = Json::array();
  Json events = Json::array();
  std::vector<bool> asleep;
  for (const Body<Q16>& b : world.bodies()) asleep.push_back(b.asleep);
  int all_asleep = all_asleep_frame_update(world, -1);
  Json error = nullptr;
  auto record = [&] {
    hashes.push_back(hex64(world.state_hash()));
    if (stored.count(world.frame())) states.push_back(Json{{"frame", world.frame()}, {"bodies", world_state(world)}});
  };
  record();
  for (int f = 1; f <= scene.frames; ++f) {
    try {
      world.step();
    } catch (const RunError& e) {
      error = Json{{"frame", e.frame}, {"body", e.body}, {"quantity", e.quantity}, {"message", e.what()}};
      break;
    }
    record();
    record_events(world, asleep, events);
    all_asleep = all_asleep_frame_update(world, all_asleep);
  }
  Json sleep_frames = Json::array();
  for (const Body<Q16>& b : world.bodies()) sleep_frames.push_back(b.asleep ? b.sleep_frame : -1);
  const bool builtin = [&] {
    const auto b = builtin_scene(scene.name);
    return b && scenes_equal(*b, scene);
  }();

  Json doc;
  doc["algorithm"] = "lockstep scene run (Q16.16)";
  doc["level"] = 3;
  doc["schema"] = "lockstep_scene_schema_v1.json";
  doc["schemaVersion"] = kSchemaVersion;
  doc["generatorVersion"] = generator_version();
  doc["numberOfTests"] = hashes.size();
  doc["header"] = Json::array(
      {"Level 3 of the lockstep test vectors: one scene run on the fixed engine, frame by frame.",
       "hashes[f] is the state hash (eq 92) after frame f (hashes[0]: the loaded scene). states holds the full raw",
       "state at the frames listed in stateFrames: per body the 15 stateFields. sleepEvents are [frame, body,",
       "asleep] changes; sleepFrames the frame each body last fell asleep (-1: awake at the end). setup is the scene",
       "as the engine holds it after loading, in raw Q16.16. vectors/README.md is the porting guide."});
  doc["scene"] = scene.name;
  doc["builtin"] = builtin;
  doc["frames"] = scene.frames;
  doc["bodyCount"] = scene.bodies.size();
  doc["sceneDocument"] = Json::parse(scene_to_json(scene));
  doc["setup"] = setup_json(scene, World<Q16>(scene));
  doc["stateFields"] = state_fields();
  doc["stateFrames"] = frames;
  doc["hashes"] = std::move(hashes);
  doc["states"] = std::move(states);
  doc["sleepEvents"] = std::move(events);
  doc["sleepFrames"] = std::move(sleep_frames);
  doc["allAsleepFrame"] = all_asleep;
  doc["counters"] = counters_json(world.counters());
  doc["error"] = error;
  return doc;
}

Verdict verify_scene_vectors(const Json& doc, const std::string& file_name, const SceneVerifyOptions& options) {
  Verdict v;
  v.file = file_name;
  auto fail = [&](int frame, int body, const std::string& field, const std::string& msg) {
    v.ok = false;
    v.frame = frame;
    v.body = body;
    v.field = field;
    v.message = file_name + ": " + msg;
    return v;
  };
  try {
    if (int_at(doc, "schemaVersion", "") != kSchemaVersion)
      throw FormatError("schemaVersion " + member(doc, "schemaVersion", "").dump() + " is not supported");
    const std::string name = string_at(doc, "scene", "");
    const Scene scene = parse_scene(member(doc, "sceneDocument", "").dump(), file_name + " sceneDocument");
    if (bool_at(doc, "builtin", "")) {
      const auto b = builtin_scene(name);
      if (!b) return fail(-1, -1, "scene", "the file is for built-in scene '" + name + "', which no longer exists");
      if (!scenes_equal(*b, scene))
        return fail(
            -1, -1, "scene",
            "the built-in scene '" + name + "' differs from the file's sceneDocument: " + scene_difference(scene, *b));
    }
    World<Q16> world(scene);
    {
      const Difference d = first_difference(member(doc, "setup", ""), setup_json(scene, world), "setup");
      if (d.found) return fail(0, -1, d.path, d.path + ": expected " + d.expected + ", got " + d.actual);
    }
    const Json& hashes = member(doc, "hashes", "");
    const Json& states = member(doc, "states", "");
    const Json& error = member(doc, "error", "");
    std::map<int, const Json*> stored;
    for (std::size_t i = 0; i < states.size(); ++i) {
      const std::string sp = "states[" + std::to_string(i) + "]";
      stored[static_cast<int>(int_at(states[i], "frame", sp))] = &member(states[i], "bodies", sp);
    }
    const int frames = static_cast<int>(int_at(doc, "frames", ""));
    const int last_hash = static_cast<int>(hashes.size()) - 1;
    const bool full = options.max_frames < 0 || options.max_frames >= frames;
    const int limit = full ? last_hash : std::min(options.max_frames, last_hash);
    std::optional<int> bad_hash_frame;  // first frame whose hash differs, if no stored state there
    std::string bad_hash_text;
    Json events = Json::array();
    std::vector<bool> asleep;
    for (const Body<Q16>& b : world.bodies()) asleep.push_back(b.asleep);
    int all_asleep = all_asleep_frame_update(world, -1);
    for (int f = 0; f <= limit; ++f) {
      if (f > 0) {
        try {
          world.step();
        } catch (const RunError& e) {
          return fail(
              e.frame, e.body, e.quantity,
              "frame " + std::to_string(e.frame) + ": the engine stopped (" + e.what() + ") but the vectors go on");
        }
        record_events(world, asleep, events);
        all_asleep = all_asleep_frame_update(world, all_asleep);
      }
      const std::string got_hash = hex64(world.state_hash());
      const std::string want_hash = hashes[static_cast<std::size_t>(f)].get<std::string>();
      const auto it = stored.find(f);
      if (it != stored.end()) {
        const Json got = world_state(world);
        const Json& want = *it->second;
        if (bad_hash_frame && got == want)
          return fail(*bad_hash_frame, -1, "hash",
                      "frame " + std::to_string(*bad_hash_frame) + ": " + bad_hash_text +
                          " (no full state stored there); the next stored state, frame " + std::to_string(f) +
                          ", agrees in every field: the hash (eq 92) or the states in between differ");
        if (want.size() != got.size())
          return fail(f, -1, "bodies",
                      "frame " + std::to_string(f) + ": " + std::to_string(want.size()) +
                          " bodies expected, the engine has " + std::to_string(got.size()));
        for (std::size_t b = 0; b < want.size(); ++b) {
          for (std::size_t k = 0; k < state_fields().size(); ++k) {
            if (want[b][k] == got[b][k]) continue;
            std::string msg = "frame " + std::to_string(f) + ", body " + std::to_string(b) + ", field " +
                              state_fields()[k] + ": expected " + want[b][k].dump() + ", got " + got[b][k].dump();
            if (bad_hash_frame) {
              msg = "frame " + std::to_string(*bad_hash_frame) + ": " + bad_hash_text +
                    " (no full state stored there); first stored state after it: " + msg;
              return fail(*bad_hash_frame, static_cast<int>(b), state_fields()[k], msg);
            }
            return fail(f, static_cast<int>(b), state_fields()[k], msg);
          }
        }
      }
      if (got_hash != want_hash && !bad_hash_frame) {
        const std::string text = "state hash expected " + want_hash + ", got " + got_hash;
        if (it != stored.end())
          return fail(f, -1, "hash",
                      "frame " + std::to_string(f) + ": " + text +
                          " although every stored state field agrees: the hash (eq 92) itself differs");
        bad_hash_frame = f;
        bad_hash_text = text;
      }
    }
    if (bad_hash_frame)
      return fail(*bad_hash_frame, -1, "hash",
                  "frame " + std::to_string(*bad_hash_frame) + ": " + bad_hash_text +
                      " (no full state stored at or after it within the frames checked)");
    v.checked = static_cast<std::size_t>(limit + 1);
    if (!full) return v;
    if (!error.is_null())
      return fail(static_cast<int>(int_at(error, "frame", "error")), -1, "error",
                  "the vectors stop at frame " + error["frame"].dump() + " (" + error["message"].get<std::string>() +
                      ") but the engine ran on");
    auto check = [&](const char* key, const Json& got) -> bool {
      const Difference d = first_difference(member(doc, key, ""), got, key);
      if (!d.found) return true;
      fail(-1, -1, d.path,
           "after frame " + std::to_string(frames) + ": " + d.path + ": expected " + d.expected + ", got " + d.actual);
      return false;
    };
    Json sleep_frames = Json::array();
    for (const Body<Q16>& b : world.bodies()) sleep_frames.push_back(b.asleep ? b.sleep_frame : -1);
    if (!check("sleepEvents", events)) return v;
    if (!check("sleepFrames", sleep_frames)) return v;
    if (!check("allAsleepFrame", all_asleep)) return v;
    if (!check("counters", counters_json(world.counters()))) return v;
  } catch (const FormatError& e) {
    v.ok = false;
    v.message = file_name + ": malformed: " + e.what();
  } catch (const SceneError& e) {
    v.ok = false;
    v.message = file_name + ": sceneDocument: " + e.what();
  } catch (const RunError& e) {
    v.ok = false;
    v.message = file_name + ": the engine cannot load the scene: " + e.what();
  } catch (const nlohmann::json::exception& e) {
    v.ok = false;
    v.message = file_name + ": malformed: " + e.what();
  }
  return v;
}

}  // namespace lockstep::vectors
