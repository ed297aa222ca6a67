// Snapshots: the scene section, the constants hash, the header and the
// checksum (docs/SNAPSHOTS.md), the parts that do not depend on the number type.
#include "snapshot_scene.hpp"

#include <array>
#include <cstdint>
#include <cstring>
#include <map>
#include <string>

#include "lockstep/scene_json.hpp"

namespace lockstep {

const char* snapshot_number_name(SnapshotNumber n) {
  switch (n) {
    case SnapshotNumber::kFixed: return "fixed";
    case SnapshotNumber::kFloat: return "float";
    case SnapshotNumber::kDouble: return "double";
    case SnapshotNumber::kMp: return "mp";
    case SnapshotNumber::kGpu: return "gpu";
    case SnapshotNumber::kGpuFixed: return "gpu-fixed";
  }
  return "?";
}

namespace snap {

using detail::each_constant;

namespace {

constexpr std::uint64_t kFnvOffset = 0xcbf29ce484222325ull;
constexpr std::uint64_t kFnvPrime = 0x100000001b3ull;

void write_constants(Writer& w, const Constants& c) {
  each_constant(c, [&](double x) { w.f64(x); }, [&](int i) { w.i32(i); });
}

std::uint16_t effect_bits(const Effects& fx) {
  const bool bits[] = {fx.gravity, fx.damping, fx.ground, fx.contacts, fx.friction, fx.restitution, fx.settling, fx.sleep, fx.sdf};
  std::uint16_t v = 0;
  for (int i = 0; i < 9; ++i) v = static_cast<std::uint16_t>(v | (bits[i] ? 1u << i : 0u));
  return v;
}

using ShapeKey = std::array<std::uint64_t, 7>;

ShapeKey shape_key(const BodyDesc& b) {
  ShapeKey k{};
  const double v[6] = {b.half_extents.x, b.half_extents.y, b.half_extents.z, b.mass, b.material.restitution, b.material.friction};
  for (int i = 0; i < 6; ++i) std::memcpy(&k[static_cast<std::size_t>(i)], &v[i], sizeof(double));
  k[6] = b.is_static ? 1 : 0;
  return k;
}

}  // namespace

std::uint64_t fnv1a(const std::uint8_t* data, std::size_t size, std::uint64_t h) {
  for (std::size_t i = 0; i < size; ++i) {
    h ^= data[i];
    h *= kFnvPrime;
  }
  return h;
}

std::uint64_t checksum(const std::uint8_t* data, std::size_t size) {
  std::uint64_t lane[4] = {kFnvOffset, kFnvOffset, kFnvOffset, kFnvOffset};
  auto word_at = [&](std::size_t at, std::size_t n) {
    std::uint8_t b[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    std::memcpy(b, data + at, n);
    std::uint64_t w = 0;
    for (int i = 0; i < 8; ++i) w |= static_cast<std::uint64_t>(b[i]) << (8 * i);
    return w;
  };
  const std::size_t words = size / 8;
  std::size_t k = 0;
  for (; k + 4 <= words; k += 4)
    for (std::size_t l = 0; l < 4; ++l) lane[l] = (lane[l] ^ word_at(8 * (k + l), 8)) * kFnvPrime;
  for (; k < words; ++k) lane[k % 4] = (lane[k % 4] ^ word_at(8 * k, 8)) * kFnvPrime;
  if (size % 8 != 0) lane[k % 4] = (lane[k % 4] ^ word_at(8 * k, size % 8)) * kFnvPrime;
  std::uint8_t tail[40];
  for (int l = 0; l < 4; ++l)
    for (int i = 0; i < 8; ++i) tail[8 * l + i] = static_cast<std::uint8_t>(lane[l] >> (8 * i));
  for (int i = 0; i < 8; ++i) tail[32 + i] = static_cast<std::uint8_t>(static_cast<std::uint64_t>(size) >> (8 * i));
  return fnv1a(tail, sizeof tail);
}

std::uint64_t constants_hash(const Constants& c) {
  std::vector<std::uint8_t> bytes;
  bytes.reserve(sizeof(Constants) + 16);
  Writer w(bytes);
  write_constants(w, c);
  return fnv1a(bytes.data(), bytes.size());
}

std::vector<std::uint8_t> encode_scene_section(const Scene& s) {
  std::vector<std::uint8_t> out;
  std::size_t sdf_values = 0;
  for (const SdfDesc& d : s.sdfs) sdf_values += d.values.size();
  out.reserve(512 + s.name.size() + 8 * sdf_values + 64 * s.sdfs.size() + 4 * s.bodies.size());
  Writer w(out);
  w.string(s.name);
  w.i32(s.frames);
  w.u8(s.pair_contacts == PairModel::kAabb ? 1 : 0);
  w.u16(effect_bits(s.effects));
  write_constants(w, s.constants);
  w.u8(s.ground.present ? 1 : 0);
  w.f64(s.ground.height);
  w.f64(s.ground.material.restitution);
  w.f64(s.ground.material.friction);
  w.u32(static_cast<std::uint32_t>(s.sdfs.size()));
  for (const SdfDesc& d : s.sdfs) {
    w.string(d.name);
    for (const Vec3d* v : {&d.min, &d.max}) {
      w.f64(v->x); w.f64(v->y); w.f64(v->z);
    }
    w.i32(d.nx); w.i32(d.ny); w.i32(d.nz);
    w.u32(static_cast<std::uint32_t>(d.values.size()));
    for (double v : d.values) w.f64(v);
    w.f64(d.material.restitution);
    w.f64(d.material.friction);
  }
  // The distinct shapes, in order of first use; each body's shape as runs.
  std::map<ShapeKey, std::uint32_t> index;
  std::vector<const BodyDesc*> shapes;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> runs;  // (shape, length)
  for (const BodyDesc& b : s.bodies) {
    const auto [it, added] = index.emplace(shape_key(b), static_cast<std::uint32_t>(shapes.size()));
    if (added) shapes.push_back(&b);
    if (!runs.empty() && runs.back().first == it->second) ++runs.back().second;
    else runs.emplace_back(it->second, 1u);
  }
  w.u32(static_cast<std::uint32_t>(shapes.size()));
  for (const BodyDesc* b : shapes) {
    w.f64(b->half_extents.x); w.f64(b->half_extents.y); w.f64(b->half_extents.z);
    w.f64(b->mass);
    w.f64(b->material.restitution);
    w.f64(b->material.friction);
    w.u8(b->is_static ? 1 : 0);
  }
  w.u32(static_cast<std::uint32_t>(runs.size()));
  for (const auto& [shape, length] : runs) {
    w.varint(shape);
    w.varint(length);
  }
  return out;
}

void write_header(Writer& w, SnapshotNumber number, std::uint32_t body_count, std::uint64_t constants_hash,
                  std::uint32_t frame) {
  w.bytes(kSnapshotMagic, sizeof kSnapshotMagic);
  w.u16(kSnapshotVersion);
  w.u8(static_cast<std::uint8_t>(number));
  w.u8(0);
  w.u32(body_count);
  w.u64(constants_hash);
  w.u64(0);  // the total size, patched by finish()
  w.u32(frame);
  w.u32(0);
}

void finish(std::vector<std::uint8_t>& out) {
  const std::uint64_t total = out.size() + kSnapshotChecksumSize;
  for (int i = 0; i < 8; ++i) out[24 + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(total >> (8 * i));
  const std::uint64_t sum = checksum(out.data(), out.size());
  Writer w(out);
  w.u64(sum);
}

}  // namespace snap

SnapshotInfo read_snapshot_info(const std::uint8_t* data, std::size_t size) {
  constexpr std::size_t kMin = kSnapshotHeaderSize + kSnapshotChecksumSize;
  if (data == nullptr || size < kMin)
    throw SnapshotError("truncated: " + std::to_string(size) + " bytes; a snapshot has at least " + std::to_string(kMin) +
                            " (header and checksum)",
                        "header");
  if (std::memcmp(data, kSnapshotMagic, sizeof kSnapshotMagic) != 0)
    throw SnapshotError("not a lockstep snapshot (the first 8 bytes are not \"LKSTSNAP\")", "header.magic");
  snap::Reader r(data + 8, kSnapshotHeaderSize - 8);
  SnapshotInfo info;
  info.version = r.u16("header.version");
  if (info.version != kSnapshotVersion)
    throw SnapshotError("format version " + std::to_string(info.version) + "; this build reads version " +
                            std::to_string(kSnapshotVersion),
                        "header.version");
  const std::uint8_t number = r.u8("header.number_type");
  if (number < 1 || number > 6)
    throw SnapshotError("unknown number type " + std::to_string(number) + " (1 fixed, 2 float, 3 double, 4 mp, 5 gpu, 6 gpu-fixed)",
                        "header.number_type");
  info.number = static_cast<SnapshotNumber>(number);
  if (r.u8("header.reserved") != 0) throw SnapshotError("corrupt: reserved header byte 11 is not 0", "header.reserved");
  info.body_count = r.u32("header.body_count");
  info.constants_hash = r.u64("header.constants_hash");
  info.size = r.u64("header.size");
  info.frame = r.u32("header.frame");
  if (r.u32("header.reserved") != 0) throw SnapshotError("corrupt: reserved header bytes 36-39 are not 0", "header.reserved");
  if (info.size > size)
    throw SnapshotError("truncated: " + std::to_string(size) + " bytes of the " + std::to_string(info.size) +
                            " the header declares",
                        "header.size");
  if (info.size < size)
    throw SnapshotError(std::to_string(size - info.size) + " bytes after the end the header declares (" +
                            std::to_string(info.size) + " bytes)",
                        "header.size");
  if (info.frame > static_cast<std::uint32_t>(INT32_MAX / 2))
    throw SnapshotError("frame " + std::to_string(info.frame) + " is beyond 2^30", "header.frame");
  std::uint64_t stored = 0;
  for (int i = 0; i < 8; ++i) stored |= static_cast<std::uint64_t>(data[size - 8 + static_cast<std::size_t>(i)]) << (8 * i);
  if (snap::checksum(data, size - kSnapshotChecksumSize) != stored)
    throw SnapshotError("corrupt: the checksum does not match the bytes (changed in storage or transit)", "checksum");
  return info;
}

}  // namespace lockstep
