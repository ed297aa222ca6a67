// Throughput of the Q16.16 operations against libfixmath's fix16, float and
// double: ns per operation over arrays of pre-generated inputs. Every result
// goes through benchmark::DoNotOptimize, so each operation is computed (no
// dead-code elimination, no vectorising a loop into something the engine never
// runs); the inputs are independent, so this is throughput, not latency.
//
//   ./build/tests/bench/q16_bench --benchmark_min_time=0.1
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "lockstep/fixed/q16.hpp"
#include "lockstep/fixed/q16_vec.hpp"
#include "lockstep/math/vec.hpp"

#if defined(LOCKSTEP_HAVE_LIBFIXMATH)
#include <libfixmath/fix16.h>
#endif

namespace {

using lockstep::Q16;
using lockstep::Quat;
using lockstep::Vec3;

constexpr std::size_t kN = 4096;  // inputs per array (fits L1/L2 for every type)

// The same inputs for every number type, as doubles.
struct Inputs {
  std::vector<double> a, b, nonneg;       // mul/div operands (|a|,|b| <= 100, |b| >= 1/64), sqrt operands
  std::vector<Vec3<double>> v;            // vectors, components in [-100, 100]
  std::vector<Quat<double>> q;            // unit quaternions
  Inputs() {
    std::mt19937_64 rng(20261121);
    std::uniform_real_distribution<double> u(-100.0, 100.0), pos(0.0, 1000.0), unit(-1.0, 1.0);
    for (std::size_t i = 0; i < kN; ++i) {
      a.push_back(u(rng));
      double d = u(rng);
      if (std::fabs(d) < 1.0 / 64) d = 1.0;
      b.push_back(d);
      nonneg.push_back(pos(rng));
      v.push_back({u(rng), u(rng), u(rng)});
      Quat<double> r{unit(rng), unit(rng), unit(rng), unit(rng)};
      const double n = std::sqrt(r.w * r.w + r.x * r.x + r.y * r.y + r.z * r.z);
      q.push_back({r.w / n, r.x / n, r.y / n, r.z / n});
    }
  }
};
const Inputs& inputs() {
  static const Inputs in;
  return in;
}

// ---- The four number types behind one interface ------------------------------

struct Q16Ops {
  using T = Q16;
  static T from(double x) { return Q16::from_double(x); }
  static T mul(T a, T b) { return a * b; }
  static T div(T a, T b) { return a / b; }
  static T sqrt(T a) { return lockstep::sqrt(a); }
  static Vec3<T> normalize(const Vec3<T>& v) { return lockstep::normalize(v); }
  static Vec3<T> rotate(const Quat<T>& q, const Vec3<T>& v) { return lockstep::rotate(q, v); }
};

template <class F>
struct FloatOps {
  using T = F;
  static T from(double x) { return static_cast<T>(x); }
  static T mul(T a, T b) { return a * b; }
  static T div(T a, T b) { return a / b; }
  static T sqrt(T a) { return std::sqrt(a); }
  static Vec3<T> normalize(const Vec3<T>& v) { return lockstep::normalize(v); }  // generic: a / |a|
  static Vec3<T> rotate(const Quat<T>& q, const Vec3<T>& v) { return lockstep::rotate(q, v); }  // via the matrix
};

#if defined(LOCKSTEP_HAVE_LIBFIXMATH)
// libfixmath: normalise and rotate written with fix16 operations, in the same
// shape as lockstep's (length by sqrt, three divisions; rotation matrix, then
// matrix times vector).
struct Fix16Ops {
  using T = fix16_t;
  static T from(double x) { return fix16_from_dbl(x); }
  static T mul(T a, T b) { return fix16_mul(a, b); }
  static T div(T a, T b) { return fix16_div(a, b); }
  static T sqrt(T a) { return fix16_sqrt(a); }
  static Vec3<T> normalize(const Vec3<T>& v) {
    const T len = fix16_sqrt(fix16_add(fix16_add(fix16_mul(v.x, v.x), fix16_mul(v.y, v.y)), fix16_mul(v.z, v.z)));
    if (len == 0) return v;
    return {fix16_div(v.x, len), fix16_div(v.y, len), fix16_div(v.z, len)};
  }
  static Vec3<T> rotate(const Quat<T>& q, const Vec3<T>& v) {
    const T two = fix16_from_int(2);
    const T xx = fix16_mul(q.x, q.x), yy = fix16_mul(q.y, q.y), zz = fix16_mul(q.z, q.z);
    const T xy = fix16_mul(q.x, q.y), xz = fix16_mul(q.x, q.z), yz = fix16_mul(q.y, q.z);
    const T wx = fix16_mul(q.w, q.x), wy = fix16_mul(q.w, q.y), wz = fix16_mul(q.w, q.z);
    const T m[3][3] = {
        {fix16_sub(fix16_one, fix16_mul(two, fix16_add(yy, zz))), fix16_mul(two, fix16_sub(xy, wz)),
         fix16_mul(two, fix16_add(xz, wy))},
        {fix16_mul(two, fix16_add(xy, wz)), fix16_sub(fix16_one, fix16_mul(two, fix16_add(xx, zz))),
         fix16_mul(two, fix16_sub(yz, wx))},
        {fix16_mul(two, fix16_sub(xz, wy)), fix16_mul(two, fix16_add(yz, wx)),
         fix16_sub(fix16_one, fix16_mul(two, fix16_add(xx, yy)))}};
    Vec3<T> out;
    for (int i = 0; i < 3; ++i)
      out[i] = fix16_add(fix16_add(fix16_mul(m[i][0], v.x), fix16_mul(m[i][1], v.y)), fix16_mul(m[i][2], v.z));
    return out;
  }
};
#endif

// Inputs converted to Ops::T once, outside the timed loop.
template <class Ops>
struct Typed {
  using T = typename Ops::T;
  std::vector<T> a, b, nonneg;
  std::vector<Vec3<T>> v;
  std::vector<Quat<T>> q;
  Typed() {
    const Inputs& in = inputs();
    for (std::size_t i = 0; i < kN; ++i) {
      a.push_back(Ops::from(in.a[i]));
      b.push_back(Ops::from(in.b[i]));
      nonneg.push_back(Ops::from(in.nonneg[i]));
      v.push_back({Ops::from(in.v[i].x), Ops::from(in.v[i].y), Ops::from(in.v[i].z)});
      q.push_back({Ops::from(in.q[i].w), Ops::from(in.q[i].x), Ops::from(in.q[i].y), Ops::from(in.q[i].z)});
    }
  }
  static const Typed& get() {
    static const Typed t;
    return t;
  }
};

// "per_op": CPU time per operation (printed with an SI prefix, e.g. 733.4ps).
void per_op(benchmark::State& state) {
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * kN));
  state.counters["per_op"] = benchmark::Counter(static_cast<double>(state.iterations() * kN),
                                                benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

template <class Ops>
void BM_mul(benchmark::State& state) {
  const auto& d = Typed<Ops>::get();
  for (auto _ : state)
    for (std::size_t i = 0; i < kN; ++i) {
      auto r = Ops::mul(d.a[i], d.b[i]);
      benchmark::DoNotOptimize(r);
    }
  per_op(state);
}
template <class Ops>
void BM_div(benchmark::State& state) {
  const auto& d = Typed<Ops>::get();
  for (auto _ : state)
    for (std::size_t i = 0; i < kN; ++i) {
      auto r = Ops::div(d.a[i], d.b[i]);
      benchmark::DoNotOptimize(r);
    }
  per_op(state);
}
template <class Ops>
void BM_sqrt(benchmark::State& state) {
  const auto& d = Typed<Ops>::get();
  for (auto _ : state)
    for (std::size_t i = 0; i < kN; ++i) {
      auto r = Ops::sqrt(d.nonneg[i]);
      benchmark::DoNotOptimize(r);
    }
  per_op(state);
}
template <class Ops>
void BM_normalize(benchmark::State& state) {
  const auto& d = Typed<Ops>::get();
  for (auto _ : state)
    for (std::size_t i = 0; i < kN; ++i) {
      auto r = Ops::normalize(d.v[i]);
      benchmark::DoNotOptimize(r);
    }
  per_op(state);
}
template <class Ops>
void BM_rotate(benchmark::State& state) {
  const auto& d = Typed<Ops>::get();
  for (auto _ : state)
    for (std::size_t i = 0; i < kN; ++i) {
      auto r = Ops::rotate(d.q[i], d.v[i]);
      benchmark::DoNotOptimize(r);
    }
  per_op(state);
}

#define LS_BENCH_ALL(Ops, name)                          \
  BENCHMARK_TEMPLATE(BM_mul, Ops)->Name("mul/" name);     \
  BENCHMARK_TEMPLATE(BM_div, Ops)->Name("div/" name);     \
  BENCHMARK_TEMPLATE(BM_sqrt, Ops)->Name("sqrt/" name);   \
  BENCHMARK_TEMPLATE(BM_normalize, Ops)->Name("normalize/" name); \
  BENCHMARK_TEMPLATE(BM_rotate, Ops)->Name("rotate/" name)

LS_BENCH_ALL(Q16Ops, "lockstep_q16");
#if defined(LOCKSTEP_HAVE_LIBFIXMATH)
LS_BENCH_ALL(Fix16Ops, "libfixmath");
#endif
LS_BENCH_ALL(FloatOps<float>, "float");
LS_BENCH_ALL(FloatOps<double>, "double");

}  // namespace

BENCHMARK_MAIN();
