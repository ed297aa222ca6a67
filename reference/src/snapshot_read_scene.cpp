// A snapshot's scene section read back (docs/SNAPSHOTS.md), checked as the
// scene loader checks a scene (validate_scene): apart from
// snapshot_scene.cpp, whose writer the fixed engine's certification build
// (vectors/certify) links without the scene loader.
#include <string>
#include <utility>
#include <vector>

#include "lockstep/scene_json.hpp"
#include "lockstep/scene_limits.hpp"
#include "snapshot_scene.hpp"

namespace lockstep::snap {

namespace {
[[noreturn]] void fail(const std::string& field, const std::string& what) { throw SnapshotError(field + ": " + what, field); }
}  // namespace

using detail::each_constant;
using detail::effects_of;
using detail::kMaxNameBytes;

Scene read_scene_section(Reader& r, std::uint32_t body_count) {
  Scene s;
  s.name = r.string("scene.name", kMaxNameBytes);
  s.frames = r.i32("scene.frames");
  const std::uint8_t model = r.u8("scene.pair_contacts");
  if (model > 1) fail("scene.pair_contacts", std::to_string(model) + " is not 0 (oriented_box) or 1 (aabb)");
  s.pair_contacts = model == 1 ? PairModel::kAabb : PairModel::kOrientedBox;
  const std::uint16_t fx = r.u16("scene.effects");
  if (fx >= (1u << 9)) fail("scene.effects", "unknown effect bits " + std::to_string(fx));
  s.effects = effects_of(fx);
  each_constant(s.constants, [&](double& x) { x = r.f64("scene.constants"); }, [&](int& i) { i = r.i32("scene.constants"); });
  const std::uint8_t present = r.u8("scene.ground.present");
  if (present > 1) fail("scene.ground.present", std::to_string(present) + " is not 0 or 1");
  s.ground.present = present == 1;
  s.ground.height = r.f64("scene.ground.height");
  s.ground.material.restitution = r.f64("scene.ground.material");
  s.ground.material.friction = r.f64("scene.ground.material");
  const std::uint32_t sdfs = r.u32("scene.sdfs");
  if (sdfs > 256) fail("scene.sdfs", std::to_string(sdfs) + " SDF volumes: at most 256");
  for (std::uint32_t k = 0; k < sdfs; ++k) {
    SdfDesc d;
    d.name = r.string("scene.sdfs.name", kMaxNameBytes);
    for (Vec3d* v : {&d.min, &d.max}) {
      v->x = r.f64("scene.sdfs.bounds"); v->y = r.f64("scene.sdfs.bounds"); v->z = r.f64("scene.sdfs.bounds");
    }
    d.nx = r.i32("scene.sdfs.resolution"); d.ny = r.i32("scene.sdfs.resolution"); d.nz = r.i32("scene.sdfs.resolution");
    const std::uint32_t n = r.u32("scene.sdfs.values");
    // Checked before anything is allocated: the count against the bytes left.
    if (n > kMaxSdfValues || std::size_t{n} * 8 > r.left())
      fail("scene.sdfs[" + std::to_string(k) + "].values", std::to_string(n) + " values, " + std::to_string(r.left()) + " bytes left");
    d.values.resize(n);
    for (double& v : d.values) v = r.f64("scene.sdfs.values");
    d.material.restitution = r.f64("scene.sdfs.material");
    d.material.friction = r.f64("scene.sdfs.material");
    s.sdfs.push_back(std::move(d));
  }
  const std::uint32_t shapes = r.u32("scene.shapes");
  if (shapes > body_count || std::size_t{shapes} * 49 > r.left())
    fail("scene.shapes", std::to_string(shapes) + " shapes for " + std::to_string(body_count) + " bodies, " +
                             std::to_string(r.left()) + " bytes left");
  std::vector<BodyDesc> table(shapes);
  for (BodyDesc& b : table) {
    b.half_extents.x = r.f64("scene.shapes.half_extents");
    b.half_extents.y = r.f64("scene.shapes.half_extents");
    b.half_extents.z = r.f64("scene.shapes.half_extents");
    b.mass = r.f64("scene.shapes.mass");
    b.material.restitution = r.f64("scene.shapes.material");
    b.material.friction = r.f64("scene.shapes.material");
    const std::uint8_t st = r.u8("scene.shapes.static");
    if (st > 1) fail("scene.shapes.static", std::to_string(st) + " is not 0 or 1");
    b.is_static = st == 1;
  }
  // Every body needs at least 29 bytes of state (flags, position,
  // orientation, sleep counter): the count is checked before allocating.
  if (body_count > kMaxSceneBodies || std::size_t{body_count} * 30 > r.left())
    fail("header.body_count", std::to_string(body_count) + " bodies cannot fit in the " + std::to_string(r.left()) +
                                  " bytes left");
  s.bodies.reserve(body_count);
  const std::uint32_t runs = r.u32("scene.shape_runs");
  for (std::uint32_t k = 0; k < runs; ++k) {
    const std::uint64_t shape = r.varint("scene.shape_runs");
    const std::uint64_t length = r.varint("scene.shape_runs");
    if (shape >= shapes || length == 0 || length > body_count - s.bodies.size())
      fail("scene.shape_runs[" + std::to_string(k) + "]", "shape " + std::to_string(shape) + " of " + std::to_string(shapes) +
                                                             ", " + std::to_string(length) + " bodies: past the table or the body count");
    s.bodies.insert(s.bodies.end(), length, table[shape]);
  }
  if (s.bodies.size() != body_count)
    fail("scene.shape_runs", "the runs give " + std::to_string(s.bodies.size()) + " bodies, the header " +
                                 std::to_string(body_count));
  // A run may be given fewer frames than a scene file may ask for (`lockstep
  // run --frames 0`): the loader's range for frames is not the snapshot's.
  const int frames = s.frames;
  if (frames < 0 || frames > kMaxSceneFrames)
    fail("scene.frames", std::to_string(frames) + " is outside [0, " + std::to_string(kMaxSceneFrames) + "]");
  // Checked as the scene loader checks a scene, with one body per distinct
  // shape (the bodies are their shapes at the origin: checking each once is
  // checking them all, and keeps a large pile's load fast).
  std::vector<BodyDesc> bodies = std::move(s.bodies);
  s.bodies = std::move(table);
  s.frames = frames == 0 ? 1 : frames;
  try {
    validate_scene(s);
    s.frames = frames;
    s.bodies = std::move(bodies);
  } catch (const SceneError& e) {
    throw SnapshotError(std::string("the scene section is not a valid scene: ") + e.what(),
                        "scene." + (e.field.rfind("bodies[", 0) == 0 ? "shapes" + e.field.substr(6) : e.field));
  }
  return s;
}

Scene read_checked_scene(Reader& r, const SnapshotInfo& info, const char* number_type, const char* engine) {
  Scene scene = read_scene_section(r, info.body_count);
  if (constants_hash(scene.constants) != info.constants_hash)
    throw SnapshotError("corrupt: the constants do not match the header's constants hash", "header.constants_hash");
  try {
    validate_scene_for(number_type, scene);
  } catch (const SceneError& e) {
    throw SnapshotError(std::string("the scene section cannot run on ") + engine + ": " + e.what(), "scene." + e.field);
  }
  return scene;
}

}  // namespace lockstep::snap
