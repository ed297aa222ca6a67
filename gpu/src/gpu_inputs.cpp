#include "gpu_inputs.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "lockstep/fixed/q16_num.hpp"
#include "lockstep/input_check.hpp"
#include "lockstep/scene_json.hpp"
#include "lockstep/physics/aabb.hpp"
#include "lockstep/physics/integrate.hpp"
#include "lockstep/physics/sleep.hpp"

namespace lockstep::gpu {
namespace {

template <class T>
Vec3<T> to_vec(const Vec3d& v) {
  return {Num<T>::from_double(v.x), Num<T>::from_double(v.y), Num<T>::from_double(v.z)};
}
template <class T>
bool finite3(const Vec3<T>& v) { return Num<T>::finite(v.x) && Num<T>::finite(v.y) && Num<T>::finite(v.z); }
std::string body_text(std::size_t i, BodyId id) {
  return "body " + std::to_string(i) + " (" + input_check::id_text(id.slot, id.generation) + ")";
}
}  // namespace

// The host copy: the pipeline's state after its last step, with the
// constants of every body. An input marks it dirty (a rebuild before the
// next step) only once it is checked and applied, so that a refused input
// changes nothing.
template <class T>
void GpuInputs<T>::begin(PipelineBase<T>& pipeline) {
  if (dirty_ || copy_frame_ == pipeline.frame()) return;
  pipeline.download(edit_, true);
  const InitialState<T> s = make_initial_state<T>(scene_);
  half_ = s.half;
  inert_ = s.inert;
  if (edit_.rest_count.empty()) {  // the AABB model keeps no records
    edit_.rest_count.assign(edit_.pos.size(), 0);
    edit_.rest_body.assign(kMaxRests * edit_.pos.size(), -1);
  }
  copy_frame_ = pipeline.frame();
}

template <class T>
void GpuInputs<T>::wake(std::size_t i) {
  if ((edit_.flags[i] & kFlagAsleep) == 0 || (edit_.flags[i] & kFlagStatic) != 0) return;
  edit_.flags[i] = static_cast<std::uint8_t>(edit_.flags[i] & ~kFlagAsleep);
  edit_.sleep_counter[i] = 0;
  edit_.rest_count[i] = 0;
  ++wakes_;
}

template <class T>
void GpuInputs<T>::wake_resting_on(std::size_t i) {
  for (std::size_t j = 0; j < edit_.flags.size(); ++j) {
    if ((edit_.flags[j] & kFlagAsleep) == 0) continue;
    bool on_i = false;
    for (int r = 0; r < edit_.rest_count[j]; ++r) on_i = on_i || edit_.rest_body[kMaxRests * j + static_cast<std::size_t>(r)] == static_cast<int>(i);
    if (on_i) wake(j);
  }
}

template <class T>
void GpuInputs<T>::wake_all() {
  for (std::size_t j = 0; j < edit_.flags.size(); ++j) wake(j);
}

template <class T>
void GpuInputs<T>::erase(std::size_t k) {
  const auto at = static_cast<std::ptrdiff_t>(k);
  for (auto* v : {&edit_.pos, &edit_.rot, &edit_.vel, &edit_.ang, &half_, &inert_}) v->erase(v->begin() + at);
  edit_.flags.erase(edit_.flags.begin() + at);
  for (auto* v : {&edit_.sleep_frame, &edit_.sleep_counter, &edit_.rest_count}) v->erase(v->begin() + at);
  edit_.rest_body.erase(edit_.rest_body.begin() + kMaxRests * at, edit_.rest_body.begin() + kMaxRests * (at + 1));
  for (int& b : edit_.rest_body)
    if (b > static_cast<int>(k)) --b;
  scene_.bodies.erase(scene_.bodies.begin() + at);
  std::erase_if(forces_, [k](const Force& f) { return f.body == static_cast<int>(k); });
  for (Force& f : forces_)
    if (f.body > static_cast<int>(k)) --f.body;
  ids_.remove(k);
}

template <class T>
BodyId GpuInputs<T>::apply(const Input& in, PipelineBase<T>& pipeline) {
  const int frame = pipeline.frame();
  input_check::frame(in.frame, frame);
  if (in.kind == InputKind::create) {
    if (scene_.bodies.size() >= kMaxSceneBodies)
      throw std::invalid_argument("create_body: the world has " + std::to_string(scene_.bodies.size()) +
                                  " bodies, the most a scene may hold; destroy one first");
    input_check::body(scene_, in.body, Num<T>::kName, "create_body", "input.body");
    begin(pipeline);
    Scene one;  // the body alone, with the scene's constants and effects
    one.constants = scene_.constants;
    one.effects = scene_.effects;
    one.bodies = {in.body};
    const InitialState<T> s = make_initial_state<T>(one);  // World<float>'s body, term by term
    edit_.pos.push_back(s.pos[0]); edit_.rot.push_back(s.rot[0]); edit_.vel.push_back(s.vel[0]);
    edit_.ang.push_back(s.ang[0]); half_.push_back(s.half[0]); inert_.push_back(s.inert[0]);
    edit_.flags.push_back(static_cast<std::uint8_t>(s.flags[0] & (scene_.effects.sleep ? 0xff : ~kFlagAsleep)));
    edit_.sleep_frame.push_back(-1);
    edit_.sleep_counter.push_back(0);
    edit_.rest_count.push_back(0);
    for (int r = 0; r < kMaxRests; ++r) edit_.rest_body.push_back(-1);
    scene_.bodies.push_back(in.body);
    dirty_ = true;
    return ids_.add();
  }
  const char* name = input_kind_name(in.kind);
  const std::size_t i = ids_.require(in.id, name);
  const std::string what = std::string(name) + " on " + body_text(i, in.id);
  const bool is_static = (scene_.bodies[i].is_static);
  switch (in.kind) {
    case InputKind::destroy: {
      begin(pipeline);
      dirty_ = true;
      if (is_static) wake_all();
      else wake_resting_on(i);
      erase(i);
      break;
    }
    case InputKind::impulse: {
      input_check::vector(in.a, input_check::kMaxImpulse, "N s", what, "input.a (J)", "give each component within +-1e6 N s");
      input_check::vector(in.b, input_check::kMaxPoint, "m", what, "input.b (point)",
                          "give a world point within +-32000 m (normally on or in the body)");
      if (is_static) break;
      begin(pipeline);
      const T4<T> p = edit_.pos[i];
      const Mat3<T> R = rotation_matrix(quat(edit_.rot[i]));
      const Vec3<T> j = to_vec<T>(in.a), r = to_vec<T>(in.b) - xyz(p);
      const Vec3<T> v = xyz(edit_.vel[i]) + j * p.w;
      const Vec3<T> w = xyz(edit_.ang[i]) + apply_inverse_inertia(R, xyz(inert_[i]), cross(r, j));  // eqs 87, 90
      if (!finite3(v) || !finite3(w))
        throw std::invalid_argument(what + ": the body's velocity would leave the engine's range; give a smaller impulse");
      dirty_ = true;
      wake(i);
      edit_.vel[i] = f4(v, T{});
      edit_.ang[i] = f4(w, T{});
      edit_.sleep_counter[i] = 0;
      break;
    }
    case InputKind::force: {
      input_check::vector(in.a, input_check::kMaxForce, "N", what, "input.a (F)", "give each component within +-1e7 N");
      input_check::vector(in.b, input_check::kMaxForce, "N m", what, "input.b (torque)", "give each component within +-1e7 N m");
      if (is_static) break;
      begin(pipeline);
      dirty_ = true;
      const int body = static_cast<int>(i);
      auto it = std::lower_bound(forces_.begin(), forces_.end(), body, [](const Force& f, int x) { return f.body < x; });
      if (it != forces_.end() && it->body == body) {
        it->f = it->f + to_vec<T>(in.a);
        it->tau = it->tau + to_vec<T>(in.b);
      } else {
        forces_.insert(it, Force{body, to_vec<T>(in.a), to_vec<T>(in.b)});
      }
      wake(i);
      edit_.sleep_counter[i] = 0;
      break;
    }
    case InputKind::set_pose: {
      BodyDesc desc = scene_.bodies[i];
      desc.position = in.a;
      desc.orientation = in.q;
      input_check::body(scene_, desc, Num<T>::kName, what, "input");
      begin(pipeline);
      dirty_ = true;
      edit_.pos[i] = f4(to_vec<T>(in.a), edit_.pos[i].w);
      const auto n = [](double x) { return Num<T>::from_double(x); };
      edit_.rot[i] = f4(normalize(Quat<T>{n(in.q.w), n(in.q.x), n(in.q.y), n(in.q.z)}));  // eq 10
      if (is_static) {
        wake_all();
      } else {
        wake_resting_on(i);
        wake(i);
        edit_.sleep_counter[i] = 0;
      }
      break;
    }
    case InputKind::set_velocity: {
      if (is_static) {
        input_check::vector(in.a, 1000.0, "m/s", what, "input.a (v)", "give each component within +-1000 m/s");
        input_check::vector(in.b, 1000.0, "rad/s", what, "input.b (omega)", "give each component within +-1000 rad/s");
        break;
      }
      BodyDesc desc = scene_.bodies[i];
      desc.velocity = in.a;
      desc.angular_velocity = in.b;
      input_check::body(scene_, desc, Num<T>::kName, what, "input");
      begin(pipeline);
      dirty_ = true;
      wake(i);
      edit_.vel[i] = f4(to_vec<T>(in.a), T{});
      edit_.ang[i] = f4(to_vec<T>(in.b), T{});
      edit_.sleep_counter[i] = 0;
      break;
    }
    case InputKind::wake: {
      if (is_static) break;
      begin(pipeline);
      if ((edit_.flags[i] & kFlagAsleep) == 0) break;  // awake: nothing to do
      dirty_ = true;
      wake(i);
      break;
    }
    default:
      throw std::invalid_argument("apply: input.kind = " + std::to_string(static_cast<int>(in.kind)) +
                                  " is not an InputKind");
  }
  return in.id;
}

// The rebuilt pipeline's state: the edited bodies, exactly (q is not
// normalised again), and eq 121's pending forces.
template <class T>
InitialState<T> GpuInputs<T>::take_state() {
  Scene now = scene_;
  for (std::size_t i = 0; i < now.bodies.size(); ++i) {
    BodyDesc& d = now.bodies[i];
    const T4<T> p = edit_.pos[i], v = edit_.vel[i], w = edit_.ang[i];
    auto d3 = [](const T& x, const T& y, const T& z) { return Vec3d{Num<T>::to_double(x), Num<T>::to_double(y), Num<T>::to_double(z)}; };
    d.position = d3(p.x, p.y, p.z);  // T -> double -> T: exact
    d.velocity = d3(v.x, v.y, v.z);
    d.angular_velocity = d3(w.x, w.y, w.z);
    d.asleep = (edit_.flags[i] & kFlagAsleep) != 0;
  }
  InitialState<T> s = make_initial_state<T>(now);
  const T dt = s.P.dt;
  for (std::size_t i = 0; i < now.bodies.size(); ++i) {
    s.rot[i] = edit_.rot[i];
    const Vec3<T> a = rotated_half_extents(rotation_matrix(quat(s.rot[i])), xyz(s.half[i]));  // eq 31
    s.aabb[i] = f4(a, Num<T>::max(a.x, Num<T>::max(a.y, a.z)));
    s.sleep_counter[i] = edit_.sleep_counter[i];
    s.sleep_frame[i] = edit_.sleep_frame[i];
  }
  for (const Force& f : forces_) {  // eq 121, as World<T>'s stage 0
    const auto i = static_cast<std::size_t>(f.body);
    const Mat3<T> R = rotation_matrix(quat(s.rot[i]));
    s.vel[i] = f4(xyz(s.vel[i]) + (f.f * dt) * s.pos[i].w, T{});
    s.ang[i] = f4(xyz(s.ang[i]) + apply_inverse_inertia(R, xyz(s.inert[i]), f.tau * dt), T{});
  }
  forces_.clear();
  dirty_ = false;
  copy_frame_ = -1;
  wakes_ = 0;
  return s;
}

template class GpuInputs<float>;
template class GpuInputs<Q16>;

}  // namespace lockstep::gpu
