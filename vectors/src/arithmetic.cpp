// Level 1: the Q16.16 operations. Each operation has one compute function,
// used both to generate the expected outputs and to verify them.
#include "lockstep/vectors/arithmetic.hpp"

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>

namespace lockstep::vectors {
namespace {

using In = const Json&;
using Fn = std::function<Json(In, const std::string&)>;

struct Operation {
  const char* name;
  std::vector<int> equations;  // SPEC equation numbers (empty: 0.3's rules only)
  Json signature;              // {"in": {name: type}, "out": {"r": type}}
  const char* rule;            // the exact rule, one line
  Fn compute;                  // in -> r (status read afterwards)
};

Json sig(std::initializer_list<std::pair<const char*, const char*>> in, const char* out) {
  Json s{{"in", Json::object()}, {"out", Json::object()}};
  for (const auto& [k, t] : in) s["in"][k] = t;
  s["out"]["r"] = out;
  return s;
}

const std::vector<Operation>& operations() {
  static const std::vector<Operation> ops = [] {
    std::vector<Operation> v;
    auto a = [](In in, const std::string& p) { return q16_at(in, "a", p); };
    auto b = [](In in, const std::string& p) { return q16_at(in, "b", p); };
    auto va = [](In in, const std::string& p) { return vec_at(in, "a", p); };
    auto vb = [](In in, const std::string& p) { return vec_at(in, "b", p); };
    auto qa = [](In in, const std::string& p) { return quat_at(in, "a", p); };
    const auto q2 = sig({{"a", "q16"}, {"b", "q16"}}, "q16");
    const auto q1 = sig({{"a", "q16"}}, "q16");
    v.push_back({"from_int",
                 {20},
                 sig({{"i", "int"}}, "q16"),
                 "R = i * 2^16 for |i| <= 32767 (and -32768), else clamped",
                 [](In in, const std::string& p) { return to_json(Q16::from_int(int_at(in, "i", p))); }});
    v.push_back({"from_double",
                 {22},
                 sig({{"x", "double"}}, "q16"),
                 "R = round(x * 2^16), to nearest, ties to even; NaN -> 0 (invalid); beyond int32 clamped",
                 [](In in, const std::string& p) {
                   return to_json(Q16::from_double(double_from_bits(string_at(in, "x", p), p + ".x")));
                 }});
    v.push_back({"add", {}, q2, "R = Ra + Rb exact, clamped", [=](In in, const std::string& p) {
                   return to_json(a(in, p) + b(in, p));
                 }});
    v.push_back({"sub", {}, q2, "R = Ra - Rb exact, clamped", [=](In in, const std::string& p) {
                   return to_json(a(in, p) - b(in, p));
                 }});
    v.push_back({"neg", {}, q1, "R = -Ra, clamped (-INT32_MIN -> INT32_MAX)", [=](In in, const std::string& p) {
                   return to_json(-a(in, p));
                 }});
    v.push_back(
        {"mul", {21}, q2, "R = round(Ra * Rb / 2^16), to nearest, ties to even, clamped", [=](In in, const std::string& p) {
           return to_json(a(in, p) * b(in, p));
         }});
    v.push_back({"div",
                 {},
                 q2,
                 "R = round(Ra * 2^16 / Rb), to nearest, ties to even, clamped; Rb = 0: INT32_MAX if Ra >= 0 else INT32_MIN, div_by_zero",
                 [=](In in, const std::string& p) { return to_json(a(in, p) / b(in, p)); }});
    v.push_back({"reciprocal", {}, q1, "div(1.0, a)", [=](In in, const std::string& p) {
                   return to_json(reciprocal(a(in, p)));
                 }});
    v.push_back({"sqrt",
                 {},
                 q1,
                 "R = round(sqrt(Ra * 2^16)) exactly, to nearest (never a tie); Ra < 0: 0, sqrt_negative",
                 [=](In in, const std::string& p) { return to_json(sqrt(a(in, p))); }});
    v.push_back({"abs", {}, q1, "R = |Ra|, clamped (|INT32_MIN| -> INT32_MAX)", [=](In in, const std::string& p) {
                   return to_json(abs(a(in, p)));
                 }});
    v.push_back({"min", {}, q2, "the smaller raw value", [=](In in, const std::string& p) {
                   return to_json(min(a(in, p), b(in, p)));
                 }});
    v.push_back({"max", {}, q2, "the larger raw value", [=](In in, const std::string& p) {
                   return to_json(max(a(in, p), b(in, p)));
                 }});
    v.push_back({"floor_to_int",
                 {26},
                 sig({{"a", "q16"}}, "int"),
                 "floor(Ra / 2^16) as an integer (arithmetic shift)",
                 [=](In in, const std::string& p) { return Json(floor_to_int(a(in, p))); }});
    v.push_back({"dot",
                 {},
                 sig({{"a", "vec3"}, {"b", "vec3"}}, "q16"),
                 "round(sum Ra_i * Rb_i / 2^16): exact sum, one rounding to nearest (ties to even), clamped",
                 [=](In in, const std::string& p) { return to_json(dot(va(in, p), vb(in, p))); }});
    v.push_back({"cross",
                 {51},
                 sig({{"a", "vec3"}, {"b", "vec3"}}, "vec3"),
                 "each component round((Ra_j Rb_k - Ra_k Rb_j) / 2^16), to nearest, ties to even, clamped",
                 [=](In in, const std::string& p) { return to_json(cross(va(in, p), vb(in, p))); }});
    v.push_back({"length_sq",
                 {},
                 sig({{"a", "vec3"}}, "q16"),
                 "round(sum Ra_i^2 / 2^16), to nearest, ties to even, clamped",
                 [=](In in, const std::string& p) { return to_json(length_sq(va(in, p))); }});
    v.push_back({"length",
                 {57},
                 sig({{"a", "vec3"}}, "q16"),
                 "round(sqrt(sum Ra_i^2)) exactly, to nearest, clamped",
                 [=](In in, const std::string& p) { return to_json(length(va(in, p))); }});
    v.push_back(
        {"normalize",
         {36, 60, 68},
         sig({{"a", "vec3"}}, "vec3"),
         "L = round(sqrt(sum Ra_i^2)); R_i = round(Ra_i * 2^16 / L) (to nearest, ties to even), clamped; L = 0: zero vector, normalize_zero",
         [=](In in, const std::string& p) { return to_json(normalize(va(in, p))); }});
    v.push_back({"quat_mul",
                 {8},
                 sig({{"a", "quat"}, {"b", "quat"}}, "quat"),
                 "Hamilton product, each component an exact sum of 4 raw products rounded once by 2^16 (to nearest, ties to even), clamped",
                 [=](In in, const std::string& p) { return to_json(qa(in, p) * quat_at(in, "b", p)); }});
    v.push_back({"quat_length_sq",
                 {},
                 sig({{"a", "quat"}}, "q16"),
                 "round(sum Ra_i^2 / 2^16), to nearest, ties to even, clamped",
                 [=](In in, const std::string& p) { return to_json(quat_length_sq(qa(in, p))); }});
    v.push_back({"quat_normalize",
                 {10},
                 sig({{"a", "quat"}}, "quat"),
                 "components INT32_MIN -> -INT32_MAX; L = round(sqrt(sum R_i^2)); R_i = round(R_i * 2^16 / L); L = 0: "
                 "identity, normalize_zero",
                 [=](In in, const std::string& p) { return to_json(normalize(qa(in, p))); }});
    v.push_back({"rotation_matrix",
                 {31},
                 sig({{"a", "quat"}}, "mat3"),
                 "mat3(q): 1 - 2(y^2 + z^2) = round((2^32 - 2Ry^2 - 2Rz^2) / 2^16), 2(xy - wz) = round((2RxRy - 2RwRz) "
                 "/ 2^16), ...",
                 [=](In in, const std::string& p) { return to_json(rotation_matrix(qa(in, p))); }});
    v.push_back({"mat_mul_vec",
                 {90},
                 sig({{"m", "mat3"}, {"v", "vec3"}}, "vec3"),
                 "row i: dot(m[i], v)",
                 [](In in, const std::string& p) { return to_json(mat_at(in, "m", p) * vec_at(in, "v", p)); }});
    v.push_back({"mat_transpose_mul_vec",
                 {90},
                 sig({{"m", "mat3"}, {"v", "vec3"}}, "vec3"),
                 "component i: round(sum_j Rm[j][i] * Rv_j / 2^16), to nearest, ties to even, clamped",
                 [](In in, const std::string& p) {
                   return to_json(mat_transpose_mul(mat_at(in, "m", p), vec_at(in, "v", p)));
                 }});
    v.push_back({"rotate",
                 {31},
                 sig({{"q", "quat"}, {"v", "vec3"}}, "vec3"),
                 "mat_mul_vec(rotation_matrix(q), v)",
                 [](In in, const std::string& p) { return to_json(rotate(quat_at(in, "q", p), vec_at(in, "v", p))); }});
    return v;
  }();
  return ops;
}

const Operation* find_op(const std::string& name) {
  for (const Operation& o : operations())
    if (name == o.name) return &o;
  return nullptr;
}

// ---------------------------------------------------------------------------
// Case generation
// ---------------------------------------------------------------------------

constexpr std::int32_t kMax = std::numeric_limits<std::int32_t>::max();
constexpr std::int32_t kMin = std::numeric_limits<std::int32_t>::min();
constexpr std::int32_t kOne = 65536;

// Edge operands: 0, +-1 ulp, +-0.5, +-1, 1 + ulp, 2, sqrt(32768) (the largest
// square that fits), +-INT32_MAX, INT32_MIN.
const std::int32_t kEdges[] = {0, 1, -1, 32768, -32768, kOne, -kOne, kOne + 1, 2 * kOne, 11863283, kMax, -kMax, kMin};

// A random raw value: one of five magnitude classes (full int32, |x| < 16,
// |x| < 2, near 1.0, tiny).
std::int32_t random_raw(Rng& rng) {
  switch (rng.range(0, 4)) {
    case 0:
      return static_cast<std::int32_t>(rng.range(kMin, kMax));
    case 1:
      return static_cast<std::int32_t>(rng.range(-(1 << 20), 1 << 20));
    case 2:
      return static_cast<std::int32_t>(rng.range(-(1 << 17), 1 << 17));
    case 3: {
      const auto near_one = static_cast<std::int32_t>(kOne + rng.range(-256, 256));
      return rng.range(0, 1) ? near_one : -near_one;
    }
    default:
      return static_cast<std::int32_t>(rng.range(-256, 256));
  }
}

// A random vector of one magnitude class for all three components (so that
// both exact-sum and overflow cases occur).
Json random_vec(Rng& rng) {
  const auto cls = rng.range(0, 3);
  auto comp = [&]() -> std::int32_t {
    switch (cls) {
      case 0:
        return static_cast<std::int32_t>(rng.range(-(1 << 18), 1 << 18));
      case 1:
        return static_cast<std::int32_t>(rng.range(-(1 << 23), 1 << 23));
      case 2:
        return static_cast<std::int32_t>(rng.range(kMin, kMax));
      default:
        return static_cast<std::int32_t>(rng.range(-64, 64));
    }
  };
  const std::int32_t x = comp(), y = comp(), z = comp();
  return Json::array({x, y, z});
}

Json random_quat(Rng& rng, bool unit) {
  if (unit) return to_json(rng.unit_quat());
  const std::int32_t w = random_raw(rng), x = random_raw(rng), y = random_raw(rng), z = random_raw(rng);
  return Json::array({w, x, y, z});
}

Json random_mat(Rng& rng, bool rotation) {
  if (rotation) return to_json(rotation_matrix(rng.unit_quat()));
  Json m = Json::array();
  for (int r = 0; r < 3; ++r) m.push_back(random_vec(rng));
  return m;
}

struct CaseList {
  struct Case {
    Json in;
    std::string comment;
    Json flags = Json::array();
  };
  std::vector<Case> cases;
  void add(Json in, std::string comment, std::initializer_list<const char*> flags = {}) {
    Case c{std::move(in), std::move(comment), Json::array()};
    for (const char* f : flags) c.flags.push_back(f);
    cases.push_back(std::move(c));
  }
};

std::string decimal(double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

void scalar_cases(const std::string& op, CaseList& L, Rng& rng) {
  const bool binary = op == "add" || op == "sub" || op == "mul" || op == "div" || op == "min" || op == "max";
  if (op == "from_int") {
    for (std::int64_t i : {0LL, 1LL, -1LL, 2LL, 100LL, -100LL, 32767LL, -32767LL, -32768LL})
      L.add({{"i", i}}, "exact integer", {"EdgeValue"});
    for (std::int64_t i : {32768LL, -32769LL, 100000LL, -100000LL, 9223372036854775807LL, -9223372036854775807LL - 1})
      L.add({{"i", i}}, "beyond Q16.16: clamped", {"EdgeValue"});
    for (int k = 0; k < 16; ++k) {
      const std::int64_t i = rng.range(-40000, 40000);
      L.add({{"i", i}}, "", {"Random"});
    }
    return;
  }
  if (op == "from_double") {
    const double u = 1.0 / 65536.0;  // 1 ulp
    struct D {
      double x;
      const char* comment;
      const char* flag;
    };
    const D ds[] = {
        {0.0, "zero", "EdgeValue"},
        {-0.0, "negative zero: raw 0", "EdgeValue"},
        {1.0, "one", "EdgeValue"},
        {-1.0, "minus one", "EdgeValue"},
        {u, "1 ulp", "EdgeValue"},
        {-u, "-1 ulp", "EdgeValue"},
        {0.5 * u, "0.5 ulp: tie, to even (0)", "TiesToEven"},
        {1.5 * u, "1.5 ulp: tie, to even (2)", "TiesToEven"},
        {2.5 * u, "2.5 ulp: tie, to even (2)", "TiesToEven"},
        {-0.5 * u, "-0.5 ulp: tie, to even (0)", "TiesToEven"},
        {-1.5 * u, "-1.5 ulp: tie, to even (-2)", "TiesToEven"},
        {-2.5 * u, "-2.5 ulp: tie, to even (-2)", "TiesToEven"},
        {std::nextafter(0.5 * u, 1.0), "just above 0.5 ulp: 1", "TiesToEven"},
        {std::nextafter(0.5 * u, 0.0), "just below 0.5 ulp: 0", "TiesToEven"},
        {std::nextafter(-0.5 * u, -1.0), "just below -0.5 ulp: -1", "TiesToEven"},
        {0.1, "0.1 = 6553.6 ulp: 6554", "Constant"},
        {1.0 / 60.0, "dt = 1/60: raw 1092 (eq 91)", "Constant"},
        {-9.81, "g = -9.81: raw -642908", "Constant"},
        {0.005, "linear damping 0.005", "Constant"},
        {0.998, "align_fine 0.998", "Constant"},
        {1.0 / 4096.0, "2^-12", "Constant"},
        {32767.0, "largest integer", "EdgeValue"},
        {32768.0 - u, "INT32_MAX raw", "EdgeValue"},
        {32768.0 - 0.5 * u, "INT32_MAX + 0.5: tie to even 2^31: clamped", "Overflow"},
        {std::nextafter(32768.0 - 0.5 * u, 0.0), "just below INT32_MAX + 0.5: INT32_MAX", "EdgeValue"},
        {32768.0, "2^15: clamped", "Overflow"},
        {-32768.0, "INT32_MIN raw, exact", "EdgeValue"},
        {-32768.0 - 0.5 * u, "INT32_MIN - 0.5: tie to even INT32_MIN, not clamped", "TiesToEven"},
        {std::nextafter(-32768.0 - 0.5 * u, -1e9), "just below INT32_MIN - 0.5: clamped", "Overflow"},
        {-32768.0 - u, "INT32_MIN - 1 ulp: clamped", "Overflow"},
        {1e300, "huge: clamped", "Overflow"},
        {-1e300, "huge negative: clamped", "Overflow"},
        {std::numeric_limits<double>::infinity(), "+infinity: clamped", "Overflow"},
        {-std::numeric_limits<double>::infinity(), "-infinity: clamped", "Overflow"},
        {std::numeric_limits<double>::quiet_NaN(), "NaN: 0, invalid", "Invalid"},
        {std::numeric_limits<double>::denorm_min(), "smallest subnormal: 0", "EdgeValue"},
        {-std::numeric_limits<double>::denorm_min(), "negative smallest subnormal: 0 (rounds to -0 ulp)", "EdgeValue"},
    };
    for (const D& d : ds) L.add({{"x", double_bits(d.x)}}, decimal(d.x) + ": " + d.comment, {d.flag});
    for (int k = 0; k < 64; ++k) {
      // raw + an eighth-multiple fraction (ties included) or a random double in range.
      // One draw per statement (operand evaluation order is unspecified).
      const auto first = static_cast<double>(k % 2 == 0 ? random_raw(rng) : rng.range(-4000000000LL, 4000000000LL));
      const auto second = static_cast<double>(k % 2 == 0 ? rng.range(0, 7) : rng.range(1, 1000));
      const double x = k % 2 == 0 ? (first + second / 8.0) / 65536.0 : first / 65536.0 / second;
      L.add({{"x", double_bits(x)}}, decimal(x), {"Random"});
    }
    return;
  }
  // Named edge cases first.
  auto one = [&](std::int32_t x, const char* c, const char* f) { L.add({{"a", x}}, c, {f}); };
  auto two = [&](std::int32_t x, std::int32_t y, const char* c, const char* f) { L.add({{"a", x}, {"b", y}}, c, {f}); };
  if (op == "mul") {
    two(1, 1, "2^-16 ulp rounds to 0", "Rounding");
    two(-1, 1, "-2^-16 ulp rounds to 0 (floor would give -1 ulp)", "Rounding");
    two(1, 0x8000, "0.5 ulp: a tie, to even (0)", "Rounding");
    two(-1, 0x8000, "-0.5 ulp: a tie, to even (0), sign-symmetric", "Rounding");
    two(3, 0x8000, "1.5 ulp: a tie, to even (2)", "Rounding");
    two(-3, 0x8000, "-1.5 ulp: a tie, to even (-2)", "Rounding");
    two(11863283, 11863283, "largest square below 2^15: INT32_MAX region", "EdgeValue");
    two(11863284, 11863284, "smallest square beyond 2^15: clamped", "Overflow");
    two(kMin, -kOne, "INT32_MIN * -1: clamped", "Overflow");
    two(kMin, kMin, "INT32_MIN^2: clamped", "Overflow");
  } else if (op == "div") {
    two(kOne, 3 * kOne, "1/3 rounds to nearest", "Rounding");
    two(-kOne, 3 * kOne, "-1/3 rounds to nearest: -(1/3)", "Rounding");
    two(-1, 2 * kOne, "-1 ulp / 2: a tie, to even (0)", "Rounding");
    two(kOne, 0, "x / 0 for x > 0: INT32_MAX", "DivByZero");
    two(0, 0, "0 / 0: INT32_MAX (numerator >= 0)", "DivByZero");
    two(-kOne, 0, "x / 0 for x < 0: INT32_MIN", "DivByZero");
    two(kOne, 1, "1 / 1 ulp = 2^16: clamped", "Overflow");
    two(kMin, -kOne, "INT32_MIN / -1: clamped", "Overflow");
  } else if (op == "add") {
    two(kMax, 1, "INT32_MAX + 1 ulp: clamped", "Overflow");
    two(kMin, -1, "INT32_MIN - 1 ulp: clamped", "Overflow");
  } else if (op == "sub") {
    two(0, kMin, "0 - INT32_MIN: clamped", "Overflow");
    two(kMin, 1, "INT32_MIN - 1 ulp: clamped", "Overflow");
  } else if (op == "neg" || op == "abs") {
    one(kMin, "INT32_MIN: clamped to INT32_MAX", "Overflow");
  } else if (op == "sqrt") {
    one(1, "sqrt(1 ulp) = 2^-8 exactly (raw 256)", "EdgeValue");
    one(2, "sqrt(2 ulp) to nearest (raw 362)", "Rounding");
    one(2 * kOne, "sqrt(2) to nearest (raw 92682)", "Rounding");
    one(-1, "sqrt(-1 ulp): 0", "SqrtNegative");
    one(kMin, "sqrt(INT32_MIN): 0", "SqrtNegative");
  } else if (op == "reciprocal") {
    one(0, "1 / 0: INT32_MAX", "DivByZero");
    one(3 * kOne, "1/3 to nearest", "Rounding");
    one(-3 * kOne, "-1/3 to nearest: -(1/3)", "Rounding");
    one(1, "1 / 1 ulp: clamped", "Overflow");
  } else if (op == "floor_to_int") {
    one(-1, "-1 ulp floors to -1", "Floor");
    one(kOne - 1, "1 - 1 ulp floors to 0", "Floor");
  }
  // Every edge operand (pair).
  for (std::int32_t x : kEdges) {
    if (binary) {
      for (std::int32_t y : kEdges) L.add({{"a", x}, {"b", y}}, "edge operands", {"EdgeValue"});
    } else {
      L.add({{"a", x}}, "edge operand", {"EdgeValue"});
    }
  }
  for (int k = 0; k < 64; ++k) {
    if (binary) {
      const std::int32_t x = random_raw(rng), y = random_raw(rng);
      L.add({{"a", x}, {"b", y}}, "", {"Random"});
    } else {
      const std::int32_t x = random_raw(rng);
      L.add({{"a", x}}, "", {"Random"});
    }
  }
}

void vector_cases(const std::string& op, CaseList& L, Rng& rng) {
  const Json zero = Json::array({0, 0, 0});
  const Json big = Json::array({kMax, kMax, kMax});
  const Json low = Json::array({kMin, kMin, kMin});
  const Json unit_x = Json::array({kOne, 0, 0});
  const Json mixed = Json::array({kMin, kMax, -1});
  const Json qid = Json::array({kOne, 0, 0, 0});
  const Json qzero = Json::array({0, 0, 0, 0});
  const Json qmin = Json::array({kMin, kMin, kMin, kMin});
  const Json qbig = Json::array({kMax, kMax, kMax, kMax});
  const Json qtilt = Json::array({kOne, 1, -1, 0});
  const int n_random = 48;
  if (op == "dot" || op == "cross") {
    for (const Json* a : {&zero, &big, &low, &unit_x, &mixed})
      for (const Json* b : {&zero, &big, &low, &unit_x, &mixed})
        L.add({{"a", *a}, {"b", *b}}, "edge vectors", {"EdgeValue"});
    for (int k = 0; k < n_random; ++k) {
      Json a = random_vec(rng);
      Json b = random_vec(rng);
      L.add({{"a", a}, {"b", b}}, "", {"Random"});
    }
  } else if (op == "length_sq" || op == "length" || op == "normalize") {
    L.add({{"a", zero}}, "zero vector", {op == "normalize" ? "NormalizeZero" : "EdgeValue"});
    for (const Json* a : {&big, &low, &unit_x, &mixed}) L.add({{"a", *a}}, "edge vector", {"EdgeValue"});
    L.add({{"a", Json::array({1, 0, 0})}}, "1 ulp long", {"EdgeValue"});
    L.add({{"a", Json::array({-1, -1, -1})}}, "tiny negative", {"EdgeValue"});
    L.add({{"a", Json::array({3, 4, 0})}}, "3-4-5 in ulps", {"EdgeValue"});
    for (int k = 0; k < n_random; ++k) L.add({{"a", random_vec(rng)}}, "", {"Random"});
  } else if (op == "quat_mul") {
    for (const Json* a : {&qid, &qzero, &qbig, &qmin, &qtilt})
      for (const Json* b : {&qid, &qzero, &qbig, &qmin, &qtilt})
        L.add({{"a", *a}, {"b", *b}}, "edge quaternions", {"EdgeValue"});
    for (int k = 0; k < n_random; ++k) {
      const bool unit = k % 2 == 0;
      Json a = random_quat(rng, unit);
      Json b = random_quat(rng, unit);
      L.add({{"a", a}, {"b", b}}, unit ? "unit quaternions" : "", {"Random"});
    }
  } else if (op == "quat_length_sq" || op == "quat_normalize" || op == "rotation_matrix") {
    L.add({{"a", qzero}}, "zero quaternion", {op == "quat_normalize" ? "NormalizeZero" : "EdgeValue"});
    for (const Json* a : {&qid, &qbig, &qmin, &qtilt}) L.add({{"a", *a}}, "edge quaternion", {"EdgeValue"});
    L.add({{"a", Json::array({kMin, 0, 0, 0})}}, "INT32_MIN component (raised to -INT32_MAX by quat_normalize)",
          {"EdgeValue"});
    L.add({{"a", Json::array({0, 0, 0, 1})}}, "1 ulp long", {"EdgeValue"});
    L.add({{"a", Json::array({-kOne, 0, 0, 0})}}, "-identity", {"EdgeValue"});
    for (int k = 0; k < n_random; ++k) {
      const bool unit = k % 2 == 0;
      L.add({{"a", random_quat(rng, unit)}}, unit ? "unit quaternion" : "", {"Random"});
    }
  } else if (op == "mat_mul_vec" || op == "mat_transpose_mul_vec") {
    const Json ident = Json::array({Json::array({kOne, 0, 0}), Json::array({0, kOne, 0}), Json::array({0, 0, kOne})});
    const Json mbig = Json::array({big, big, big});
    for (const Json* m : {&ident, &mbig})
      for (const Json* v : {&zero, &big, &low, &unit_x, &mixed})
        L.add({{"m", *m}, {"v", *v}}, "edge operands", {"EdgeValue"});
    for (int k = 0; k < n_random; ++k) {
      const bool rot = k % 2 == 0;
      Json m = random_mat(rng, rot);
      Json v = random_vec(rng);
      L.add({{"m", m}, {"v", v}}, rot ? "rotation matrix" : "", {"Random"});
    }
  } else if (op == "rotate") {
    for (const Json* q : {&qid, &qzero, &qtilt, &qbig})
      for (const Json* v : {&zero, &big, &unit_x, &mixed})
        L.add({{"q", *q}, {"v", *v}}, "edge operands", {"EdgeValue"});
    for (int k = 0; k < n_random; ++k) {
      Json q = random_quat(rng, true);
      Json v = random_vec(rng);
      L.add({{"q", q}, {"v", v}}, "unit quaternion", {"Random"});
    }
  }
}

// Tags derived from the result: the status flags raised, and for mul/div an
// inexact result (where the rounding to nearest decides).
void derived_flags(const std::string& op, const Json& in, const Json& result, Json& flags) {
  auto add = [&](const char* f) {
    for (const Json& x : flags)
      if (x == f) return;
    flags.push_back(f);
  };
  static const char* const kTag[] = {"Overflow", "DivByZero", "SqrtNegative", "NormalizeZero", "Invalid"};
  static const char* const kName[] = {"overflow", "div_by_zero", "sqrt_negative", "normalize_zero", "invalid"};
  for (const Json& s : result["status"])
    for (int i = 0; i < 5; ++i)
      if (s == kName[i]) add(kTag[i]);
  if ((op == "mul" || op == "div") && result["status"].empty()) {
    const std::int64_t a = in["a"].get<std::int64_t>(), b = in["b"].get<std::int64_t>();
    const bool inexact = op == "mul" ? (((a * b) & 0xFFFF) != 0) : (b != 0 && ((a * 65536) % b) != 0);
    if (inexact) add("Rounding");
  }
}

}  // namespace

std::vector<std::string> arithmetic_operations() {
  std::vector<std::string> names;
  for (const Operation& o : operations()) names.emplace_back(o.name);
  return names;
}

Json compute_arithmetic(const std::string& op, const Json& in, const std::string& path) {
  const Operation* o = find_op(op);
  if (o == nullptr) throw FormatError(path + ": unknown operation \"" + op + "\"");
  q16_clear_status();
  Json r = o->compute(in, path + ".in");
  const std::uint32_t status = q16_take_status();
  return Json{{"out", Json{{"r", std::move(r)}}}, {"status", status_to_json(status)}};
}

Json generate_arithmetic() {
  Json groups = Json::array();
  long id = 0;
  Rng rng(0x61726974686d6574ULL);  // "arithmet"
  for (const Operation& o : operations()) {
    CaseList L;
    const std::string op = o.name;
    if (o.signature["in"].contains("a") && (o.signature["in"]["a"] == "vec3" || o.signature["in"]["a"] == "quat"))
      vector_cases(op, L, rng);
    else if (o.signature["in"].contains("m") || o.signature["in"].contains("q"))
      vector_cases(op, L, rng);
    else
      scalar_cases(op, L, rng);
    Json tests = Json::array();
    for (auto& c : L.cases) {
      Json res = compute_arithmetic(op, c.in, op);
      derived_flags(op, c.in, res, c.flags);
      Json t;
      t["tcId"] = ++id;
      t["comment"] = c.comment;
      t["flags"] = c.flags;
      t["in"] = c.in;
      t["out"] = res["out"];
      t["status"] = res["status"];
      tests.push_back(std::move(t));
    }
    Json g;
    g["type"] = "Q16Operation";
    g["operation"] = op;
    g["equations"] = o.equations;
    g["signature"] = o.signature;
    g["rule"] = o.rule;
    g["tests"] = std::move(tests);
    groups.push_back(std::move(g));
  }
  Json doc;
  doc["algorithm"] = "lockstep Q16.16 arithmetic";
  doc["level"] = 1;
  doc["schema"] = "lockstep_arithmetic_schema_v1.json";
  doc["schemaVersion"] = kSchemaVersion;
  doc["generatorVersion"] = generator_version();
  doc["numberOfTests"] = id;
  doc["header"] = Json::array(
      {"Level 1 of the lockstep test vectors: every Q16.16 operation of the fixed engine, bit for bit.",
       "A Q16.16 value is its raw int32 R (value R / 2^16). Vectors are [x, y, z], quaternions [w, x, y, z],",
       "matrices [[row 0], [row 1], [row 2]], doubles the 16 hex digits of their IEEE binary64 bits.",
       "Each test gives the inputs (in), the raw outputs (out) and the status flags raised (status; sticky",
       "flags cleared before the operation). vectors/README.md is the porting guide; docs/SPEC.md 0.3 the rules."});
  doc["notes"] = Json{
      {"EdgeValue",
       "Operands from the edge set (0, +-1 ulp, +-0.5, +-1, 1 + 1 ulp, 2, 181.02 = sqrt(32768), "
       "+-INT32_MAX, INT32_MIN), every pair for binary operations."},
      {"Random", "Pseudo-random operands (the LCG of vectors/README.md), magnitudes from 1 ulp to the int32 range."},
      {"Rounding",
       "The exact result is not a multiple of 2^-16: it rounds to the nearest multiple, ties to "
       "the even one (docs/SPEC.md Fix 11), so round(-x) = -round(x)."},
      {"Floor", "floor_to_int: the grid cell of eq 26 rounds toward minus infinity (an arithmetic shift)."},
      {"TiesToEven",
       "from_double: the scaled value x * 2^16 is exactly halfway (or next to halfway) between two "
       "integers; ties go to the even integer."},
      {"Constant", "A constant of Appendix A converted by eq 22."},
      {"Overflow", "The exact result is outside int32: clamped to INT32_MIN or INT32_MAX, status overflow."},
      {"DivByZero", "Division by zero: INT32_MAX for a numerator >= 0, INT32_MIN otherwise, status div_by_zero."},
      {"SqrtNegative", "Square root of a negative value: 0, status sqrt_negative."},
      {"NormalizeZero",
       "Normalising a zero vector (result 0) or quaternion (result the identity): status "
       "normalize_zero."},
      {"Invalid", "Conversion of NaN: 0, status invalid."}};
  doc["statusFlags"] =
      Json{{"overflow", 1}, {"div_by_zero", 2}, {"sqrt_negative", 4}, {"normalize_zero", 8}, {"invalid", 16}};
  doc["testGroups"] = std::move(groups);
  return doc;
}

Verdict verify_arithmetic(const Json& doc, const std::string& file_name) {
  Verdict v;
  v.file = file_name;
  try {
    if (int_at(doc, "schemaVersion", "") != kSchemaVersion)
      throw FormatError("schemaVersion " + member(doc, "schemaVersion", "").dump() +
                        " is not supported (this reader: " + std::to_string(kSchemaVersion) + ")");
    const Json& groups = member(doc, "testGroups", "");
    std::size_t count = 0;
    for (std::size_t g = 0; g < groups.size(); ++g) {
      const std::string gp = "testGroups[" + std::to_string(g) + "]";
      const std::string op = string_at(groups[g], "operation", gp);
      const Json& tests = member(groups[g], "tests", gp);
      for (std::size_t t = 0; t < tests.size(); ++t) {
        const std::string tp = gp + ".tests[" + std::to_string(t) + "]";
        const Json& test = tests[t];
        const long id = static_cast<long>(int_at(test, "tcId", tp));
        const Json got = compute_arithmetic(op, member(test, "in", tp), tp);
        const Json expected{{"out", member(test, "out", tp)}, {"status", member(test, "status", tp)}};
        const Difference d = first_difference(expected, got, "");
        ++count;
        if (d.found) {
          v.ok = false;
          v.tc_id = id;
          v.field = d.path;
          v.message = file_name + ": tcId " + std::to_string(id) + " (" + op + ", in " + test["in"].dump() +
                      "): " + d.path + " expected " + d.expected + ", got " + d.actual;
          v.checked = count;
          return v;
        }
      }
    }
    if (count != static_cast<std::size_t>(int_at(doc, "numberOfTests", "")))
      throw FormatError("numberOfTests is " + doc["numberOfTests"].dump() + " but the file holds " +
                        std::to_string(count) + " tests");
    v.checked = count;
  } catch (const FormatError& e) {
    v.ok = false;
    v.message = file_name + ": malformed: " + e.what();
  }
  return v;
}

}  // namespace lockstep::vectors
