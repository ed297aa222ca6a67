// World<T>'s run-time inputs (docs/SPEC.md "Run-time inputs", eqs 118-123):
// creating and destroying bodies, impulses, forces, poses, velocities and
// wakes between frames, and the id table that names bodies across them.
// Stage 0 (the pending forces) is input_forces.hpp. Included by the
// world_*.cpp that instantiate World<T> (world_fixed_inputs.cpp for the fixed
// engine, whose certification build applies no inputs).
#pragma once
#include <algorithm>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

#include "lockstep/input_check.hpp"
#include "lockstep/physics/integrate.hpp"
#include "lockstep/scene_json.hpp"
#include "lockstep/world.hpp"
#include "snapshot_scene.hpp"
#include "world_impl.hpp"

namespace lockstep {

namespace world_detail {
template <class T>
bool finite3(const Vec3<T>& v) { return Num<T>::finite(v.x) && Num<T>::finite(v.y) && Num<T>::finite(v.z); }
}  // namespace world_detail

template <class T>
int World<T>::index_of(BodyId id) const { return static_cast<int>(ids_.require(id, "index_of")); }

template <class T>
bool World<T>::contains(BodyId id) const { return ids_.contains(id); }

template <class T>
BodyId World<T>::id_of(int index) const {
  if (index < 0) throw std::invalid_argument("id_of: index = " + std::to_string(index) + " is not a body index");
  return ids_.id_of(static_cast<std::size_t>(index));
}

template <class T>
BodyId World<T>::next_id() const { return ids_.next(); }

template <class T>
std::pair<Vec3<T>, Vec3<T>> World<T>::pending_force(int index) const {
  for (const PendingForce& f : forces_)
    if (f.body == index) return {f.f, f.tau};
  return {};
}

template <class T>
BodyId World<T>::apply(const Input& input) {
  input_check::frame(input.frame, frame_);
  switch (input.kind) {
    case InputKind::create: return create_body(input.body);
    case InputKind::destroy: destroy_body(input.id); break;
    case InputKind::impulse: apply_impulse(input.id, input.a, input.b); break;
    case InputKind::force: add_force(input.id, input.a, input.b); break;
    case InputKind::set_pose: set_pose(input.id, input.a, input.q); break;
    case InputKind::set_velocity: set_velocity(input.id, input.a, input.b); break;
    case InputKind::wake: wake(input.id); break;
    default:
      throw std::invalid_argument("apply: input.kind = " + std::to_string(static_cast<int>(input.kind)) +
                                  " is not an InputKind (create .. wake, 0.." +
                                  std::to_string(static_cast<int>(InputKind::wake)) + ")");
  }
  return input.id;
}

// eq 118.
template <class T>
BodyId World<T>::create_body(const BodyDesc& desc) {
  if (bodies_.size() >= kMaxSceneBodies)
    throw std::invalid_argument("create_body: the world has " + std::to_string(bodies_.size()) +
                                " bodies, the most a scene may hold; destroy one first");
  input_check::body(scene_, desc, Num<T>::kName, "create_body", "input.body");
  Num<T>::take_faults();
  Body<T> b = world_detail::body_from_desc<T>(desc, scene_.effects.sleep);
  update_derived(b);
  if (Num<T>::take_faults() != 0)  // validate_scene_for refuses what would overflow: kept as a guard
    throw std::invalid_argument("create_body: the body's derived quantities overflow the " + std::string(Num<T>::kName) +
                                " engine's range; use the sizes and masses of docs/SCENES.md");
  bodies_.push_back(b);
  scene_.bodies.push_back(desc);
  support_.push_back(-1);
  rests_.emplace_back();
  support_n_.push_back(Vec3<T>{});
  support_gap_.push_back(T{});
  over_support_.push_back(1);
  leaning_.push_back(0);
  settle_limit_.push_back(T{});
  can_rest_.push_back(1);
  sleep_support_.emplace_back();
  wake_load_.push_back(0);
  scene_section_ = snap::encode_scene_section(scene_);
  return ids_.add();
}

// eq 119.
template <class T>
void World<T>::destroy_body(BodyId id) {
  const std::size_t k = ids_.require(id, "destroy_body");
  if (bodies_[k].is_static) wake_all_sleepers();
  else wake_resting_on(k);
  drop_warm(k);
  const int gone = static_cast<int>(k);
  for (std::size_t i = 0; i < bodies_.size(); ++i)  // eq 124: a sleeper whose recorded load parent goes wakes
    if (bodies_[i].asleep && sleep_support_[i].parent == gone) wake(static_cast<int>(i));
  auto down = [gone](int& x) { if (x > gone) --x; };
  for (SleepSupport& rec : sleep_support_)
    if (rec.parent == gone) rec.parent = kLoadNone;
    else down(rec.parent);
  for (CachedImpulse& e : warm_) { down(e.a); down(e.b); }  // a monotone map: the (a, b, feature) order holds
  for (std::vector<Rest>& rests : rests_) {  // the sleepers on k woke (records cleared); no other record may name it
    std::erase_if(rests, [gone](const Rest& r) { return r.body == gone; });
    for (Rest& r : rests) down(r.body);
  }
  std::erase_if(forces_, [gone](const PendingForce& f) { return f.body == gone; });
  for (PendingForce& f : forces_) down(f.body);
  ids_.remove(k);  // the id goes stale
  const auto at = static_cast<std::ptrdiff_t>(k);
  bodies_.erase(bodies_.begin() + at);
  scene_.bodies.erase(scene_.bodies.begin() + at);
  support_.erase(support_.begin() + at);
  rests_.erase(rests_.begin() + at);
  support_n_.erase(support_n_.begin() + at);
  support_gap_.erase(support_gap_.begin() + at);
  over_support_.erase(over_support_.begin() + at);
  leaning_.erase(leaning_.begin() + at);
  settle_limit_.erase(settle_limit_.begin() + at);
  can_rest_.erase(can_rest_.begin() + at);
  sleep_support_.erase(sleep_support_.begin() + at);
  wake_load_.erase(wake_load_.begin() + at);
  contacts_.clear();  // the last step's contacts name old indices (not state: stage 3 rebuilds them)
  pairs_.clear();
  scene_section_ = snap::encode_scene_section(scene_);
}

// eq 120.
template <class T>
void World<T>::apply_impulse(BodyId id, const Vec3d& J, const Vec3d& point) {
  const std::size_t i = ids_.require(id, "apply_impulse");
  const std::string what = "apply_impulse on body " + std::to_string(i) + " (" + input_check::id_text(id.slot, id.generation) + ")";
  input_check::vector(J, input_check::kMaxImpulse, "N s", what, "input.a (J)", "give each component within +-1e6 N s");
  input_check::vector(point, input_check::kMaxPoint, "m", what, "input.b (point)",
                      "give a world point within +-32000 m (normally on or in the body)");
  Body<T>& b = bodies_[i];
  if (b.is_static) return;  // infinite mass: no change
  Num<T>::take_faults();
  const Vec3<T> j = world_detail::to_vec<T>(J);
  const Vec3<T> r = world_detail::to_vec<T>(point) - b.p;
  const Vec3<T> v = b.v + j * b.inv_mass;
  const Vec3<T> w = b.w + apply_inverse_inertia(b.R, b.inv_inertia, cross(r, j));  // eqs 87, 90
  if (Num<T>::take_faults() != 0 || !world_detail::finite3(v) || !world_detail::finite3(w))
    throw std::invalid_argument(what + ": the body's velocity would leave the " + std::string(Num<T>::kName) +
                                " engine's range; give a smaller impulse, or a point nearer the body");
  wake(static_cast<int>(i));
  b.v = v;
  b.w = w;
  b.sleep_counter = 0;
}

// eq 121 (applied by apply_forces, stage 0 of the next step).
template <class T>
void World<T>::add_force(BodyId id, const Vec3d& F, const Vec3d& torque) {
  const std::size_t i = ids_.require(id, "add_force");
  const std::string what = "add_force on body " + std::to_string(i) + " (" + input_check::id_text(id.slot, id.generation) + ")";
  input_check::vector(F, input_check::kMaxForce, "N", what, "input.a (F)", "give each component within +-1e7 N");
  input_check::vector(torque, input_check::kMaxForce, "N m", what, "input.b (torque)", "give each component within +-1e7 N m");
  if (bodies_[i].is_static) return;
  Num<T>::take_faults();
  const int body = static_cast<int>(i);
  auto it = std::lower_bound(forces_.begin(), forces_.end(), body, [](const PendingForce& f, int x) { return f.body < x; });
  const bool summed = it != forces_.end() && it->body == body;
  PendingForce next{body, world_detail::to_vec<T>(F), world_detail::to_vec<T>(torque)};
  if (summed) { next.f = it->f + next.f; next.tau = it->tau + next.tau; }
  if (Num<T>::take_faults() != 0 || !world_detail::finite3(next.f) || !world_detail::finite3(next.tau))
    throw std::invalid_argument(what + ": the summed force or torque would leave the " + std::string(Num<T>::kName) +
                                " engine's range; give smaller values");
  if (summed) *it = next;
  else forces_.insert(it, next);
  wake(body);
  bodies_[i].sleep_counter = 0;
}

// eq 122.
template <class T>
void World<T>::set_pose(BodyId id, const Vec3d& p, const Quatd& q) {
  const std::size_t i = ids_.require(id, "set_pose");
  const std::string what = "set_pose on body " + std::to_string(i) + " (" + input_check::id_text(id.slot, id.generation) + ")";
  BodyDesc desc = scene_.bodies[i];
  desc.position = p;
  desc.orientation = q;
  input_check::body(scene_, desc, Num<T>::kName, what, "input");
  Body<T>& b = bodies_[i];
  Num<T>::take_faults();
  Body<T> moved = b;
  moved.p = world_detail::to_vec<T>(p);
  moved.q = world_detail::to_quat<T>(q);  // eq 10
  update_derived(moved);
  if (Num<T>::take_faults() != 0)
    throw std::invalid_argument(what + ": the pose leaves the " + std::string(Num<T>::kName) + " engine's range");
  b = moved;
  if (b.is_static) {
    wake_all_sleepers();
  } else {
    wake_resting_on(i);
    wake(static_cast<int>(i));
    b.sleep_counter = 0;
  }
  drop_warm(i);
}

// eq 123.
template <class T>
void World<T>::set_velocity(BodyId id, const Vec3d& v, const Vec3d& w) {
  const std::size_t i = ids_.require(id, "set_velocity");
  const std::string what = "set_velocity on body " + std::to_string(i) + " (" + input_check::id_text(id.slot, id.generation) + ")";
  if (bodies_[i].is_static) {  // no effect; the values are still checked
    input_check::vector(v, 1000.0, "m/s", what, "input.a (v)", "give each component within +-1000 m/s");
    input_check::vector(w, 1000.0, "rad/s", what, "input.b (omega)", "give each component within +-1000 rad/s");
    return;
  }
  BodyDesc desc = scene_.bodies[i];
  desc.velocity = v;
  desc.angular_velocity = w;
  input_check::body(scene_, desc, Num<T>::kName, what, "input");
  set_velocity(static_cast<int>(i), world_detail::to_vec<T>(v), world_detail::to_vec<T>(w));
}

template <class T>
void World<T>::wake(BodyId id) { wake(static_cast<int>(ids_.require(id, "wake"))); }

template <class T>
void World<T>::wake_resting_on(std::size_t i) {
  for (std::size_t j = 0; j < bodies_.size(); ++j) {
    if (!bodies_[j].asleep) continue;
    bool rests_on_i = false;
    for (const Rest& r : rests_[j]) rests_on_i = rests_on_i || r.body == static_cast<int>(i);
    if (rests_on_i) wake(static_cast<int>(j));
  }
}

template <class T>
void World<T>::wake_all_sleepers() {
  for (std::size_t j = 0; j < bodies_.size(); ++j) wake(static_cast<int>(j));
}

template <class T>
void World<T>::drop_warm(std::size_t i) {
  const int k = static_cast<int>(i);
  std::erase_if(warm_, [k](const CachedImpulse& e) { return e.a == k || e.b == k; });
}

}  // namespace lockstep
