#include "lockstep/vectors/params_json.hpp"

namespace lockstep::vectors {
namespace {

using P = Params<Q16>;

struct ConstantField {
  const char* name;
  double Constants::*d;
  Vec3d Constants::*v;
  int Constants::*i;
};

const std::vector<ConstantField>& constant_fields() {
  static const std::vector<ConstantField> f = {
      {"dt", &Constants::dt, nullptr, nullptr},
      {"gravity", nullptr, &Constants::gravity, nullptr},
      {"linear_damping", &Constants::linear_damping, nullptr, nullptr},
      {"angular_damping", &Constants::angular_damping, nullptr, nullptr},
      {"cell_size", &Constants::cell_size, nullptr, nullptr},
      {"slop", &Constants::slop, nullptr, nullptr},
      {"baumgarte", &Constants::baumgarte, nullptr, nullptr},
      {"solver_iterations", nullptr, nullptr, &Constants::solver_iterations},
      {"contact_tolerance", &Constants::contact_tolerance, nullptr, nullptr},
      {"converged_speed", &Constants::converged_speed, nullptr, nullptr},
      {"kp", &Constants::kp, nullptr, nullptr},
      {"kd", &Constants::kd, nullptr, nullptr},
      {"speed_factor_min", &Constants::speed_factor_min, nullptr, nullptr},
      {"speed_factor_max", &Constants::speed_factor_max, nullptr, nullptr},
      {"support_normal_min", &Constants::support_normal_min, nullptr, nullptr},
      {"align_fine", &Constants::align_fine, nullptr, nullptr},
      {"align_good", &Constants::align_good, nullptr, nullptr},
      {"align_fair", &Constants::align_fair, nullptr, nullptr},
      {"damp_fine", &Constants::damp_fine, nullptr, nullptr},
      {"damp_good", &Constants::damp_good, nullptr, nullptr},
      {"damp_fair", &Constants::damp_fair, nullptr, nullptr},
      {"rest_speed", &Constants::rest_speed, nullptr, nullptr},
      {"restitution_min_speed", &Constants::restitution_min_speed, nullptr, nullptr},
      {"settle_speed", &Constants::settle_speed, nullptr, nullptr},
      {"settle_damping", &Constants::settle_damping, nullptr, nullptr},
      {"sleep_linear", &Constants::sleep_linear, nullptr, nullptr},
      {"sleep_angular", &Constants::sleep_angular, nullptr, nullptr},
      {"sleep_alignment", &Constants::sleep_alignment, nullptr, nullptr},
      {"drowsy_frames", nullptr, nullptr, &Constants::drowsy_frames},
      {"drowsy_damping", &Constants::drowsy_damping, nullptr, nullptr},
      {"sleep_frames", nullptr, nullptr, &Constants::sleep_frames},
      {"wake_speed", &Constants::wake_speed, nullptr, nullptr},
      {"wake_penetration", &Constants::wake_penetration, nullptr, nullptr},
      {"wake_support_distance", &Constants::wake_support_distance, nullptr, nullptr},
  };
  return f;
}

}  // namespace

const std::vector<ParamField>& param_fields() {
  static const std::vector<ParamField> f = {
      {"dt", &P::dt, nullptr, nullptr},
      {"half_dt", &P::half_dt, nullptr, nullptr},
      {"inv_dt", &P::inv_dt, nullptr, nullptr},
      {"gravity", nullptr, &P::gravity, nullptr},
      {"gravity_dt", nullptr, &P::gravity_dt, nullptr},
      {"linear_damping_factor", &P::linear_damping_factor, nullptr, nullptr},
      {"angular_damping_factor", &P::angular_damping_factor, nullptr, nullptr},
      {"inv_cell_size", &P::inv_cell_size, nullptr, nullptr},
      {"slop", &P::slop, nullptr, nullptr},
      {"baumgarte", &P::baumgarte, nullptr, nullptr},
      {"solver_iterations", nullptr, nullptr, &P::solver_iterations},
      {"converged_pass", nullptr, nullptr, &P::converged_pass},
      {"converged_speed", &P::converged_speed, nullptr, nullptr},
      {"contact_tolerance", &P::contact_tolerance, nullptr, nullptr},
      {"support_fade", &P::support_fade, nullptr, nullptr},
      {"kp", &P::kp, nullptr, nullptr},
      {"kd_dt", &P::kd_dt, nullptr, nullptr},
      {"speed_factor_min", &P::speed_factor_min, nullptr, nullptr},
      {"speed_factor_max", &P::speed_factor_max, nullptr, nullptr},
      {"support_normal_min", &P::support_normal_min, nullptr, nullptr},
      {"align_fine", &P::align_fine, nullptr, nullptr},
      {"align_good", &P::align_good, nullptr, nullptr},
      {"align_fair", &P::align_fair, nullptr, nullptr},
      {"damp_fine", &P::damp_fine, nullptr, nullptr},
      {"damp_good", &P::damp_good, nullptr, nullptr},
      {"damp_fair", &P::damp_fair, nullptr, nullptr},
      {"rest_speed", &P::rest_speed, nullptr, nullptr},
      {"restitution_min_speed", &P::restitution_min_speed, nullptr, nullptr},
      {"settle_speed", &P::settle_speed, nullptr, nullptr},
      {"settle_factor", &P::settle_factor, nullptr, nullptr},
      {"sleep_linear", &P::sleep_linear, nullptr, nullptr},
      {"sleep_angular", &P::sleep_angular, nullptr, nullptr},
      {"sleep_small_radius", &P::sleep_small_radius, nullptr, nullptr},
      {"sleep_corner_speed", &P::sleep_corner_speed, nullptr, nullptr},
      {"sleep_alignment", &P::sleep_alignment, nullptr, nullptr},
      {"drowsy_damping", &P::drowsy_damping, nullptr, nullptr},
      {"drowsy_frames", nullptr, nullptr, &P::drowsy_frames},
      {"sleep_frames", nullptr, nullptr, &P::sleep_frames},
      {"wake_speed", &P::wake_speed, nullptr, nullptr},
      {"wake_penetration", &P::wake_penetration, nullptr, nullptr},
      {"wake_support_distance", &P::wake_support_distance, nullptr, nullptr},
      {"righting_min_axis", &P::righting_min_axis, nullptr, nullptr},
  };
  return f;
}

bool param_fields_complete() {
  std::size_t bytes = 0;
  for (const ParamField& f : param_fields()) bytes += f.q16 ? sizeof(Q16) : f.vec ? sizeof(Vec3<Q16>) : sizeof(int);
  return bytes == sizeof(Params<Q16>);
}

Json params_to_json(const Params<Q16>& p) {
  Json j = Json::object();
  for (const ParamField& f : param_fields()) {
    if (f.q16 != nullptr)
      j[f.name] = to_json(p.*(f.q16));
    else if (f.vec != nullptr)
      j[f.name] = to_json(p.*(f.vec));
    else
      j[f.name] = p.*(f.integer);
  }
  return j;
}

Json constants_to_json(const Constants& c) {
  Json j = Json::object();
  for (const ConstantField& f : constant_fields()) {
    if (f.d != nullptr) {
      j[f.name] = double_bits(c.*(f.d));
    } else if (f.v != nullptr) {
      const Vec3d& v = c.*(f.v);
      j[f.name] = Json::array({double_bits(v.x), double_bits(v.y), double_bits(v.z)});
    } else {
      j[f.name] = c.*(f.i);
    }
  }
  return j;
}

Constants constants_from_json(const Json& j, const std::string& path) {
  Constants c;
  for (const ConstantField& f : constant_fields()) {
    const std::string p = path + "." + f.name;
    if (f.d != nullptr) {
      c.*(f.d) = double_from_bits(string_at(j, f.name, path), p);
    } else if (f.v != nullptr) {
      const Json& a = member(j, f.name, path);
      if (!a.is_array() || a.size() != 3 || !a[0].is_string() || !a[1].is_string() || !a[2].is_string())
        throw FormatError(p + ": expected three binary64 bit strings");
      c.*(f.v) = {double_from_bits(a[0].get<std::string>(), p + "[0]"),
                  double_from_bits(a[1].get<std::string>(), p + "[1]"),
                  double_from_bits(a[2].get<std::string>(), p + "[2]")};
    } else {
      c.*(f.i) = static_cast<int>(int_at(j, f.name, path));
    }
  }
  return c;
}

}  // namespace lockstep::vectors
