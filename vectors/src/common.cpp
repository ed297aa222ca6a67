#include "lockstep/vectors/common.hpp"

#include <cinttypes>
#include <cstdio>
#include <cstring>

namespace lockstep::vectors {

std::string generator_version() {
  return std::string("lockstep-vectors ") + kGeneratorRevision + " (lockstep " LOCKSTEP_VERSION ")";
}

Json to_json(Q16 x) { return x.raw(); }
Json to_json(const Vec3<Q16>& v) { return Json::array({v.x.raw(), v.y.raw(), v.z.raw()}); }
Json to_json(const Quat<Q16>& q) { return Json::array({q.w.raw(), q.x.raw(), q.y.raw(), q.z.raw()}); }
Json to_json(const Mat3<Q16>& m) { return Json::array({to_json(m.row[0]), to_json(m.row[1]), to_json(m.row[2])}); }

std::string hex64(std::uint64_t h) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%016" PRIx64, h);
  return buf;
}

std::string double_bits(double x) {
  std::uint64_t u = 0;
  std::memcpy(&u, &x, sizeof u);
  return hex64(u);
}

double double_from_bits(const std::string& hex16, const std::string& path) {
  if (hex16.size() != 16 || hex16.find_first_not_of("0123456789abcdef") != std::string::npos)
    throw FormatError(path + ": expected 16 lower-case hex digits (IEEE binary64 bits), got \"" + hex16 + "\"");
  const std::uint64_t u = std::stoull(hex16, nullptr, 16);
  double x = 0;
  std::memcpy(&x, &u, sizeof x);
  return x;
}

const Json& member(const Json& obj, const std::string& key, const std::string& path) {
  if (!obj.is_object()) throw FormatError(path + ": expected an object");
  const auto it = obj.find(key);
  if (it == obj.end()) throw FormatError(path + ": missing field \"" + key + "\"");
  return *it;
}

namespace {
std::string join(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }

std::int32_t raw_of(const Json& j, const std::string& path) {
  if (!j.is_number_integer()) throw FormatError(path + ": expected an integer (raw Q16.16)");
  const auto v = j.get<std::int64_t>();
  if (v < INT32_MIN || v > INT32_MAX) throw FormatError(path + ": raw Q16.16 value out of int32 range");
  return static_cast<std::int32_t>(v);
}

const Json& array_of(const Json& obj, const std::string& key, const std::string& path, std::size_t n) {
  const Json& a = member(obj, key, path);
  if (!a.is_array() || a.size() != n)
    throw FormatError(join(path, key) + ": expected an array of " + std::to_string(n) + " values");
  return a;
}
}  // namespace

Q16 q16_at(const Json& obj, const std::string& key, const std::string& path) {
  return Q16::from_raw(raw_of(member(obj, key, path), join(path, key)));
}

Vec3<Q16> vec_at(const Json& obj, const std::string& key, const std::string& path) {
  const Json& a = array_of(obj, key, path, 3);
  const std::string p = join(path, key);
  return {Q16::from_raw(raw_of(a[0], p + "[0]")), Q16::from_raw(raw_of(a[1], p + "[1]")),
          Q16::from_raw(raw_of(a[2], p + "[2]"))};
}

Quat<Q16> quat_at(const Json& obj, const std::string& key, const std::string& path) {
  const Json& a = array_of(obj, key, path, 4);
  const std::string p = join(path, key);
  return {Q16::from_raw(raw_of(a[0], p + "[0]")), Q16::from_raw(raw_of(a[1], p + "[1]")),
          Q16::from_raw(raw_of(a[2], p + "[2]")), Q16::from_raw(raw_of(a[3], p + "[3]"))};
}

Mat3<Q16> mat_at(const Json& obj, const std::string& key, const std::string& path) {
  const Json& a = array_of(obj, key, path, 3);
  Mat3<Q16> m;
  for (std::size_t r = 0; r < 3; ++r) {
    const Json row = Json{{"row", a[r]}};
    m.row[r] = vec_at(row, "row", join(path, key) + "[" + std::to_string(r) + "]");
  }
  return m;
}

std::int64_t int_at(const Json& obj, const std::string& key, const std::string& path) {
  const Json& j = member(obj, key, path);
  if (!j.is_number_integer()) throw FormatError(join(path, key) + ": expected an integer");
  return j.get<std::int64_t>();
}

bool bool_at(const Json& obj, const std::string& key, const std::string& path) {
  const Json& j = member(obj, key, path);
  if (!j.is_boolean()) throw FormatError(join(path, key) + ": expected true or false");
  return j.get<bool>();
}

std::string string_at(const Json& obj, const std::string& key, const std::string& path) {
  const Json& j = member(obj, key, path);
  if (!j.is_string()) throw FormatError(join(path, key) + ": expected a string");
  return j.get<std::string>();
}

Json status_to_json(std::uint32_t flags) {
  static const char* const kNames[] = {"overflow", "div_by_zero", "sqrt_negative", "normalize_zero", "invalid"};
  Json out = Json::array();
  for (int b = 0; b < 5; ++b)
    if (flags & (1u << b)) out.push_back(kNames[b]);
  return out;
}

Difference first_difference(const Json& expected, const Json& actual, const std::string& path) {
  if (expected.is_object() && actual.is_object()) {
    for (auto it = expected.begin(); it != expected.end(); ++it) {
      const auto other = actual.find(it.key());
      if (other == actual.end()) return {true, join(path, it.key()), it.value().dump(), "(missing)"};
      Difference d = first_difference(it.value(), *other, join(path, it.key()));
      if (d.found) return d;
    }
    for (auto it = actual.begin(); it != actual.end(); ++it)
      if (expected.find(it.key()) == expected.end())
        return {true, join(path, it.key()), "(missing)", it.value().dump()};
    return {};
  }
  if (expected.is_array() && actual.is_array() && expected.size() == actual.size()) {
    for (std::size_t i = 0; i < expected.size(); ++i) {
      Difference d = first_difference(expected[i], actual[i], path + "[" + std::to_string(i) + "]");
      if (d.found) return d;
    }
    return {};
  }
  if (expected == actual) return {};
  return {true, path, expected.dump(), actual.dump()};
}

}  // namespace lockstep::vectors
