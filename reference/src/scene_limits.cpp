// validate_scene_for (lockstep/scene_limits.hpp): what World<T> derives from a
// body at construction (world_impl.hpp: 1/m, box_inverse_inertia, the AABB of
// update_derived), evaluated here in T operation for operation, so a body is
// refused exactly when World<T> would overflow on it (or round 1/m or the
// inverse inertia to 0). Only validation: the engines are untouched.
#include "lockstep/scene_limits.hpp"

#include <cfloat>
#include <cmath>
#include <cstdio>
#include <functional>
#include <type_traits>

#include "lockstep/fixed/q16_vec.hpp"
#include "lockstep/math/vec.hpp"
#include "lockstep/physics/aabb.hpp"
#include "lockstep/physics/integrate.hpp"

namespace lockstep {
namespace {

// What a body's check found first.
enum class Fault { none, inv_mass, half_square, inertia_sum, inertia_factor, inv_inertia, aabb };

struct Finding {
  Fault fault = Fault::none;
  bool zero = false;  // rounds to 0 (else: out of range)
  int axis = -1;      // x, y, z = 0, 1, 2
  double value = 0;   // the exact quantity, in double
};

double component(const Vec3d& v, int a) { return a == 0 ? v.x : (a == 1 ? v.y : v.z); }
void set_component(Vec3d& v, int a, double x) { (a == 0 ? v.x : (a == 1 ? v.y : v.z)) = x; }

// Whether the last operation(s) on T left its range: the Q16 fault flags
// (taken, so each check sees only its own operations), or a non-finite float.
template <class T>
bool out_of_range(const T& x) {
  if constexpr (std::is_same_v<T, Q16>) {
    (void)x;
    return Num<Q16>::take_faults() != 0;
  } else {
    return !std::isfinite(x);
  }
}

// The checks of one body, in World<T>::World's order of operations.
template <class T>
Finding check_body(const BodyDesc& d) {
  auto n = [](double x) { return Num<T>::from_double(x); };
  Num<T>::take_faults();
  const Vec3<T> h{n(d.half_extents.x), n(d.half_extents.y), n(d.half_extents.z)};
  for (int a = 0; a < 3; ++a)
    if (out_of_range(h[a])) return {Fault::half_square, false, a, component(d.half_extents, a)};
  if (!d.is_static) {
    const T inv_mass = Num<T>::from_int(1) / n(d.mass);  // World<T>::World
    if (out_of_range(inv_mass)) return {Fault::inv_mass, false, -1, 1.0 / d.mass};
    if (inv_mass == T{}) return {Fault::inv_mass, true, -1, 1.0 / d.mass};
    // box_inverse_inertia (eqs 14-18): three / (yy + zz) * inv_mass, etc.
    T sq[3];
    for (int a = 0; a < 3; ++a) {
      sq[a] = h[a] * h[a];
      if (out_of_range(sq[a])) return {Fault::half_square, false, a, component(d.half_extents, a) * component(d.half_extents, a)};
    }
    const T three = Num<T>::from_int(3);
    const T sum[3] = {sq[1] + sq[2], sq[0] + sq[2], sq[0] + sq[1]};
    if (out_of_range(sum[0]) || out_of_range(sum[1]) || out_of_range(sum[2])) {
      for (int a = 0; a < 3; ++a) {  // which one: redo them one at a time
        const T s = sq[(a + 1) % 3] + sq[(a + 2) % 3];
        const double hb = component(d.half_extents, (a + 1) % 3), hc = component(d.half_extents, (a + 2) % 3);
        if (out_of_range(s)) return {Fault::inertia_sum, false, a, hb * hb + hc * hc};
      }
    }
    for (int a = 0; a < 3; ++a) {
      const double hb = component(d.half_extents, (a + 1) % 3), hc = component(d.half_extents, (a + 2) % 3);
      const T k = three / sum[a];
      if (out_of_range(k)) return {Fault::inertia_factor, false, a, 3.0 / (hb * hb + hc * hc)};
      const T inv_inertia = k * inv_mass;
      const double exact = 3.0 / (d.mass * (hb * hb + hc * hc));
      if (out_of_range(inv_inertia)) return {Fault::inv_inertia, false, a, exact};
      // An inverse inertia that rounds to 0 is accepted: below half the
      // type's step the body turns less than the engine can resolve (the
      // hard case `large`, a 10 t cube of half extent 50 m: 6e-8, 0 in
      // Q16.16), and the engine allows for it (energy() skips such an axis).
    }
  }
  // update_derived: R of the normalised orientation (eq 10) and the AABB half
  // extents (eq 31); the broad phase adds them to the position.
  const Quat<T> q = normalize(Quat<T>{n(d.orientation.w), n(d.orientation.x), n(d.orientation.y), n(d.orientation.z)});
  const Vec3<T> ah = rotated_half_extents(rotation_matrix(q), h);
  for (int a = 0; a < 3; ++a) {
    if (out_of_range(ah[a])) return {Fault::aabb, false, a, Num<T>::to_double(ah[a])};
    if constexpr (std::is_same_v<T, Q16>) {
      const double reach = std::fabs(Num<T>::to_double(n(component(d.position, a)))) + Num<T>::to_double(ah[a]);
      if (reach >= 32768.0) return {Fault::aabb, false, a, reach};
    }
  }
  Num<T>::take_faults();
  return {};
}

// The boundary between `good` (pred true) and `bad` (pred false), by
// bisection in log space: the last good value found.
double boundary(double good, double bad, const std::function<bool(double)>& pred) {
  for (int i = 0; i < 200 && std::fabs(good - bad) > 1e-12 * std::fabs(good); ++i) {
    const double mid = std::exp(0.5 * (std::log(good) + std::log(bad)));  // no underflow for subnormal ends
    if (!(mid > std::fmin(good, bad) && mid < std::fmax(good, bad))) break;
    (pred(mid) ? good : bad) = mid;
  }
  return good;
}

// `good` rounded to 3 significant digits away from `bad`, if that still passes.
double round_suggestion(double good, double bad, const std::function<bool(double)>& pred) {
  const double scale = std::pow(10.0, std::floor(std::log10(std::fabs(good))) - 2);
  const double r = (bad < good ? std::ceil(good / scale) : std::floor(good / scale)) * scale;
  return pred(r) ? r : good;
}

std::string num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}
std::string num3(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}
std::string vec_text(const Vec3d& v) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "[%.6g, %.6g, %.6g]", v.x, v.y, v.z);
  return buf;
}

struct TypeText {
  std::string name;       // "fixed", "float"
  std::string range;      // "Q16.16's range |x| < 32768"
  std::string zero;       // "rounds to 0 in Q16.16 (its smallest step is 2^-16 = 1.5e-05)"
  std::string elsewhere;  // "run on float or double"
};

template <class T>
TypeText type_text() {
  if constexpr (std::is_same_v<T, Q16>)
    return {"fixed", "is outside Q16.16's range |x| < 32768", "rounds to 0 in Q16.16 (its smallest step is 2^-16 = 1.53e-05)",
            "or run on float or double"};
  else if constexpr (std::is_same_v<T, float>)
    return {"float", "is outside float's range |x| <= 3.40282e+38", "rounds to 0 in float", "or run on double"};
  else
    return {"double", "is outside double's range |x| <= 1.79769e+308", "rounds to 0 in double", "or run on mp"};
}

const char* kAxis[3] = {"x", "y", "z"};

template <class T>
void validate_for(const Scene& scene) {
  const TypeText tt = type_text<T>();
  const std::uint32_t saved = q16_take_status();  // the caller's Q16 flags survive the check
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const BodyDesc& d = scene.bodies[i];
    const Finding f = check_body<T>(d);
    if (f.fault == Fault::none) continue;
    const std::string body = "bodies[" + std::to_string(i) + "]";
    const std::string engine = "the " + tt.name + " engine's ";
    std::string field, message;
    // The body with one thing changed passes (no fault of this kind).
    auto passes_with = [&](const std::function<void(BodyDesc&, double)>& change) {
      return [&d, change, kind = f.fault, zero = f.zero](double x) {
        BodyDesc b = d;
        change(b, x);
        const Finding g = check_body<T>(b);
        return !(g.fault == kind && g.zero == zero);
      };
    };
    // A mass passes when neither 1/m nor the inverse inertia is out of range
    // (for 1/m rounding to 0: when it no longer does).
    const auto with_mass = [&d, zero = f.zero](double m) {
      BodyDesc b = d;
      b.mass = m;
      const Finding g = check_body<T>(b);
      if (zero) return !(g.fault == Fault::inv_mass && g.zero);
      return !((g.fault == Fault::inv_mass && !g.zero) || g.fault == Fault::inv_inertia);
    };
    switch (f.fault) {
      case Fault::inv_mass:
      case Fault::inv_inertia: {
        field = body + ".mass";
        message = field + " = " + num(d.mass) + " kg: " + engine;
        const std::string axis = f.axis >= 0 ? kAxis[f.axis] : "";
        const std::string b = f.axis >= 0 ? kAxis[(f.axis + 1) % 3] : "", c = f.axis >= 0 ? kAxis[(f.axis + 2) % 3] : "";
        if (f.fault == Fault::inv_mass)
          message += "inverse mass 1/m = " + num(f.value) + " 1/kg ";
        else
          message += "inverse inertia I_" + axis + "^-1 = 3/(m (h_" + b + "^2 + h_" + c + "^2)) = " + num(f.value) +
                     " 1/(kg m^2) (eqs 14-18) ";
        message += f.zero ? tt.zero : tt.range;
        const char* whose = f.fault == Fault::inv_mass ? "" : " for these half extents";
        if (!f.zero) {
          const double hi = 1e4;  // the format's largest mass
          if (with_mass(hi)) {
            const double m = boundary(hi, d.mass, with_mass);
            message += "; use a mass of at least " + num3(round_suggestion(m, d.mass, with_mass)) + " kg" + whose +
                       (f.fault == Fault::inv_inertia ? " (or larger half extents)" : "");
          } else {
            message += "; no mass up to 10000 kg fits these half extents: make the box larger";
          }
        } else {
          const double lo = 1e-30;
          const double m = boundary(lo, d.mass, with_mass);
          message += ": the body could not move; use a mass of at most " +
                     num3(round_suggestion(m, d.mass, with_mass)) + " kg" + whose + ", or make the body static";
        }
        message += ", " + tt.elsewhere;
        break;
      }
      case Fault::half_square:
      case Fault::inertia_sum: {
        field = body + ".half_extents";
        message = field + " = " + vec_text(d.half_extents) + " m: " + engine;
        if (f.fault == Fault::half_square)
          message += "h_" + std::string(kAxis[f.axis]) + "^2 = " + num(f.value) + " m^2 ";
        else
          message += "h_" + std::string(kAxis[(f.axis + 1) % 3]) + "^2 + h_" + kAxis[(f.axis + 2) % 3] + "^2 = " +
                     num(f.value) + " m^2 (the inertia about " + kAxis[f.axis] + " is m/3 of it, eqs 14-18) ";
        message += tt.range;
        auto capped = passes_with([](BodyDesc& b, double x) {
          for (int a = 0; a < 3; ++a) set_component(b.half_extents, a, std::fmin(component(b.half_extents, a), x));
        });
        const double big = std::fmax(d.half_extents.x, std::fmax(d.half_extents.y, d.half_extents.z));
        const double x = boundary(1.0 / 256.0, big, capped);
        message += "; keep every half extent at most " + num3(round_suggestion(x, big, capped)) +
                   " m, or make the body static (it then has no inertia), " + tt.elsewhere;
        break;
      }
      case Fault::inertia_factor: {
        field = body + ".half_extents";
        const int b = (f.axis + 1) % 3, c = (f.axis + 2) % 3;
        message = field + " = " + vec_text(d.half_extents) + " m: " + engine + "3/(h_" + kAxis[b] + "^2 + h_" + kAxis[c] +
                  "^2) = " + num(f.value) + " 1/m^2 (the inverse inertia about " + kAxis[f.axis] +
                  " is 1/m times it, eqs 14-18) " + tt.range;
        auto grown = passes_with([](BodyDesc& body_desc, double x) {
          for (int a = 0; a < 3; ++a) set_component(body_desc.half_extents, a, std::fmax(component(body_desc.half_extents, a), x));
        });
        const double small = std::fmin(component(d.half_extents, b), component(d.half_extents, c));
        const double x = boundary(1024.0, small, grown);
        message += "; make every half extent at least " + num3(round_suggestion(x, small, grown)) +
                   " m (a larger box; one axis may stay thinner), " + tt.elsewhere;
        break;
      }
      case Fault::aabb: {
        field = body + ".position";
        message = field + " = " + vec_text(d.position) + " m: " + engine + "AABB (eq 31) reaches |" + kAxis[f.axis] +
                  "| = " + num(f.value) + " m, " + tt.range + "; move the body at least " +
                  num3(std::ceil((f.value - 32767.0) * 100.0) / 100.0) + " m towards the origin or make it smaller, " +
                  tt.elsewhere;
        break;
      }
      case Fault::none: break;
    }
    q16_clear_status();
    q16detail::raise(saved);
    throw SceneError("<scene " + scene.name + ">: " + message, field);
  }
  q16_clear_status();
  q16detail::raise(saved);
}

}  // namespace

void validate_scene_for(std::string_view number_type, const Scene& scene) {
  if (number_type == "fixed") validate_for<Q16>(scene);
  else if (number_type == "float") validate_for<float>(scene);
  else if (number_type == "double") validate_for<double>(scene);
}

std::string number_type_of_engine(std::string_view engine_name) {
  if (engine_name.substr(0, 9) == "gpu-fixed") return "fixed";  // the GPU engine on Q16.16: World<Q16>'s physics
  if (engine_name.substr(0, 3) == "gpu") return "float";  // the GPU engine: World<float>'s physics (docs/GPU.md)
  return std::string(engine_name);
}

}  // namespace lockstep
