// Shared pieces of the test-vector files (vectors/README.md documents the
// format): JSON forms of raw Q16.16 values, the generator's random numbers,
// and the verdict a verification returns.
#pragma once
#include <cstdint>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "lockstep/fixed/q16_vec.hpp"

namespace lockstep::vectors {

// Key order is kept as written, so files read in a fixed, documented order.
using Json = nlohmann::ordered_json;

// Version of the file layout (the "schemaVersion" of every file). A change to
// the layout that an existing reader would misread bumps it.
inline constexpr int kSchemaVersion = 1;
// Version of the generator (its choice of cases); informative.
inline constexpr const char* kGeneratorRevision = "1.0";
// "lockstep-vectors 1.0 (lockstep 0.1.0)": the generatorVersion of every file.
std::string generator_version();

// A vector file that cannot be read: a missing or mistyped field, named by
// its path inside the file (e.g. "testGroups[2].tests[5].in.a").
struct FormatError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// JSON forms: a Q16 is its raw int32, a Vec3 [x, y, z], a Quat [w, x, y, z], a
// Mat3 [[row 0], [row 1], [row 2]], a uint64 hash 16 lower-case hex digits.
Json to_json(Q16 x);
Json to_json(const Vec3<Q16>& v);
Json to_json(const Quat<Q16>& q);
Json to_json(const Mat3<Q16>& m);
std::string hex64(std::uint64_t h);
// The IEEE binary64 bits of x as 16 lower-case hex digits (how a double input is given).
std::string double_bits(double x);
double double_from_bits(const std::string& hex16, const std::string& path);

// Readers: throw FormatError naming `path` when the value is missing or of the wrong type/range.
const Json& member(const Json& obj, const std::string& key, const std::string& path);
Q16 q16_at(const Json& obj, const std::string& key, const std::string& path);
Vec3<Q16> vec_at(const Json& obj, const std::string& key, const std::string& path);
Quat<Q16> quat_at(const Json& obj, const std::string& key, const std::string& path);
Mat3<Q16> mat_at(const Json& obj, const std::string& key, const std::string& path);
std::int64_t int_at(const Json& obj, const std::string& key, const std::string& path);
bool bool_at(const Json& obj, const std::string& key, const std::string& path);
std::string string_at(const Json& obj, const std::string& key, const std::string& path);

// Q16 status flags as names, in bit order: "overflow", "div_by_zero",
// "sqrt_negative", "normalize_zero", "invalid".
Json status_to_json(std::uint32_t flags);

// The generator's deterministic random numbers: the 64-bit LCG of the
// built-in scenes (Knuth's MMIX constants), high 32 bits used.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : x_(seed) {}
  std::uint32_t next32() {
    x_ = x_ * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<std::uint32_t>(x_ >> 32);
  }
  // Uniform in [lo, hi] (hi - lo < 2^63; the 64-bit draw is reduced modulo the span).
  std::int64_t range(std::int64_t lo, std::int64_t hi) {
    const std::uint64_t span = static_cast<std::uint64_t>(hi - lo) + 1;
    // Two statements: the order in which operands of one expression are
    // evaluated is unspecified, so draws never share an expression.
    const std::uint64_t high = next32();
    const std::uint64_t r = (high << 32) | next32();
    return lo + static_cast<std::int64_t>(r % span);
  }
  Q16 q16(double lo, double hi) {
    return Q16::from_raw(static_cast<std::int32_t>(
        range(static_cast<std::int64_t>(lo * 65536.0), static_cast<std::int64_t>(hi * 65536.0))));
  }
  Vec3<Q16> vec(double lo, double hi) {
    Vec3<Q16> v;
    v.x = q16(lo, hi);
    v.y = q16(lo, hi);
    v.z = q16(lo, hi);
    return v;
  }
  // A random unit quaternion (normalised in Q16, eq 10).
  Quat<Q16> unit_quat() {
    Quat<Q16> q;
    q.w = q16(-1, 1);
    q.x = q16(-1, 1);
    q.y = q16(-1, 1);
    q.z = q16(-1, 1);
    return normalize(q);
  }

 private:
  std::uint64_t x_;
};

// The outcome of verifying one file. When !ok, message names the first
// difference completely (file, test or frame, body, field, expected, actual).
struct Verdict {
  bool ok = true;
  std::string file;         // the file's name relative to the vector directory
  std::size_t checked = 0;  // tests or frames checked
  std::string message;      // empty when ok
  // Where the first difference is, when it has that kind of place:
  long tc_id = -1;    // arithmetic and formula levels
  int frame = -1;     // scene level
  int body = -1;      // scene level
  std::string field;  // output or state field ("r", "v", "p.y", "hash", ...)
};

// The first place where two JSON values differ (depth first, in key order).
struct Difference {
  bool found = false;
  std::string path;      // e.g. "out.v[1]"
  std::string expected;  // the expected value there, as JSON text
  std::string actual;
};
Difference first_difference(const Json& expected, const Json& actual, const std::string& path);

}  // namespace lockstep::vectors
