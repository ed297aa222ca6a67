// Stages 2a, 4 and 9 of docs/SPEC.md 7.2: wake (5.1, eqs 81, 108) and sleep
// (4.7, eqs 78-80).
#pragma once
#include <algorithm>
#include <utility>
#include <vector>
#include "lockstep/physics/body_step.hpp"
#include "lockstep/world.hpp"

namespace lockstep {

// eq 81: a contact between an awake and a sleeping body wakes the sleeper when
// the approach is fast or the penetration deep. Decided in contact order with
// the velocities at the start of the solve; a body woken here does not wake
// its own sleeping neighbours before the next frame.
template <class T>
void World<T>::wake_touched(const std::vector<ContactPoint<T>>& pair_contacts) {
  for (const ContactPoint<T>& c : pair_contacts) {
    Body<T>& A = bodies_[static_cast<std::size_t>(c.a)];
    Body<T>& B = bodies_[static_cast<std::size_t>(c.b)];
    Body<T>* sleeper = A.asleep ? &A : (B.asleep ? &B : nullptr);
    if (sleeper == nullptr) continue;
    const Body<T>& other = sleeper == &A ? B : A;
    if (!other.awake()) continue;  // a sleeper touched by a sleeper or a static body
    if (wake_test(A.v, A.asleep, B.v, B.asleep, c.n, c.penetration, P_)) {
      sleeper->asleep = false;
      rests_[static_cast<std::size_t>(sleeper == &A ? c.a : c.b)].clear();
      sleeper->sleep_counter = 0;
      ++counters_.wakes;
    }
  }
}

// eq 108: before the broadphase, in index order, a sleeping body wakes when a
// dynamic body it rested on has carried its support point away by more than
// wake_support_distance, or by more than sleep_linear dt since the last
// frame's start (only an awake supporter can have moved). It then takes part
// in this frame's broadphase, contacts and solve. Each record's `last` is
// where its point is now.
template <class T>
void World<T>::wake_unsupported() {
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    Body<T>& b = bodies_[i];
    if (!b.asleep) { rests_[i].clear(); continue; }
    bool woke = false;
    for (Rest& r : rests_[i]) {
      const Body<T>& s = bodies_[static_cast<std::size_t>(r.body)];
      const Vec3<T> now = support_point(s.p, s.R, r.local);
      woke = woke || (s.awake() && support_carried_away(now, r.rest, r.last, P_));
      r.last = now;
    }
    if (woke) {
      b.asleep = false;
      b.sleep_counter = 0;
      ++counters_.wakes;
      rests_[i].clear();
    }
    check_faults(static_cast<int>(i), "support wake");
  }
}

// eq 108: what body i rests on as it falls asleep: the dynamic bodies of its
// support contacts (Part 4), or of every contact it touches when it leans
// (eq 115: what holds it), each once, in contact order, at most kMaxRests;
// the support point in the supporter's frame, and where it is now.
template <class T>
void World<T>::record_supports(std::size_t i) {
  std::vector<Rest>& rests = rests_[i];
  rests.clear();
  for (const Contact<T>& c : contacts_) {
    if (c.b < 0) continue;
    const bool is_a = c.a == static_cast<int>(i), is_b = c.b == static_cast<int>(i);
    if (!is_a && !is_b) continue;
    if (!records_rest(c.penetration, is_a ? c.n.y : -c.n.y, leaning_[i] != 0, P_)) continue;
    const int other = is_a ? c.b : c.a;
    const Body<T>& s = bodies_[static_cast<std::size_t>(other)];
    if (s.is_static) continue;
    const int slot = rest_slot(static_cast<int>(rests.size()), other,
                               [&](int r) { return rests[static_cast<std::size_t>(r)].body; });
    if (slot < 0) continue;
    if (slot == kMaxRests) break;
    const Vec3<T> local = support_local(s.p, s.R, c.point);
    const Vec3<T> at = support_point(s.p, s.R, local);
    rests.push_back({other, local, at, at});
  }
  // eq 124: its load parent and support points as it falls asleep (the
  // oriented-box model: the source's AABB model forms no loads).
  if (scene_.pair_contacts != PairModel::kOrientedBox) return;
  SleepSupport& rec = sleep_support_[i];
  rec.parent = scratch_.load_parent[i];
  rec.count = scratch_.n_arms[i];
  for (int k = 0; k < rec.count && k < kMaxSupportPoints; ++k)
    rec.arms[static_cast<std::size_t>(k)] = horizontal(scratch_.support_arms[i][static_cast<std::size_t>(k)]);
}

// eq 124: the sleepers whose load left their support this frame wake, in
// index order, as eq 81 wakes a body.
template <class T>
void World<T>::wake_loaded() {
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    if (wake_load_[i] == 0 || !bodies_[i].asleep) continue;
    bodies_[i].asleep = false;
    bodies_[i].sleep_counter = 0;
    rests_[i].clear();
    ++counters_.wakes;
  }
}

template <class T>
void World<T>::update_sleep() {
  // Eqs 78-79 for every awake body, index order. With the source's AABB
  // model a body whose counter reaches sleep_frames falls asleep at once (eq
  // 80); with the oriented-box model it is ready but stays drowsy until eq
  // 109 lets it sleep.
  const bool oriented = scene_.pair_contacts == PairModel::kOrientedBox;
  // Each body alone, on the world's threads; then the ready ones in index order.
  std::vector<char>& state = scratch_.sleep_state;  // per body: 0 not awake, 1 updated, 2 updated and ready
  state.assign(bodies_.size(), 0);
  parallel_each(bodies_.size(), 64, [&](std::size_t i, int) {
    Body<T>& b = bodies_[i];
    if (!b.awake()) return;
    state[i] = 1;
    const bool supported = support_[i] >= 0;
    const Vec3<T> up = supported ? support_normal(i) : Vec3<T>{T{}, Num<T>::from_int(1), T{}};
    // eq 112: a body not over its support may be tipping: not slowed (it sleeps only on its own counter).
    const bool over = !oriented || over_support_[i] != 0;
    if (lockstep::update_sleep(b.v, b.w, b.sleep_counter, supported, over, leaning_[i] != 0, !oriented,
                               can_rest_[i] != 0, b.R, up, length(b.half), P_)) {  // eqs 78-80, 115-117
      b.asleep = true;
      b.sleep_frame = frame_;
    } else if (b.sleep_counter >= P_.sleep_frames) {
      state[i] = 2;
    }
    check_faults(static_cast<int>(i), "sleep");
  });
  std::vector<int>& ready = scratch_.order;
  ready.clear();
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    counters_.sleep_updates += state[i] != 0 ? 1u : 0u;
    if (state[i] == 2) ready.push_back(static_cast<int>(i));
  }
  // eq 109: the ready bodies in ascending (p.y, index) order; one falls
  // asleep (eq 80) when every dynamic body it rests on (the other sides of
  // its support contacts, Part 4) is asleep, those put to sleep earlier in
  // this pass included. A still column falls asleep at once, from the bottom
  // up, and no sleeper is left on a moving support.
  if (ready.empty()) {
    wake_loaded();
    return;
  }
  std::sort(ready.begin(), ready.end(), [&](int a, int b) {
    return settles_before(bodies_[static_cast<std::size_t>(a)].p.y, a, bodies_[static_cast<std::size_t>(b)].p.y, b);
  });
  // (supported body, dynamic supporter) of every touching body-pair support contact.
  std::vector<std::pair<int, int>>& rests_on = scratch_.rests_on;
  rests_on.clear();
  for (const Contact<T>& c : contacts_) {
    if (c.b < 0) continue;
    if (rests_on_contact(c.penetration, c.n.y, P_)) rests_on.emplace_back(c.a, c.b);  // eq 109
    if (rests_on_contact(c.penetration, -c.n.y, P_)) rests_on.emplace_back(c.b, c.a);
  }
  std::sort(rests_on.begin(), rests_on.end());
  for (int idx : ready) {
    const auto i = static_cast<std::size_t>(idx);
    bool resting = true;
    for (auto it = std::lower_bound(rests_on.begin(), rests_on.end(), std::pair<int, int>{idx, -1});
         it != rests_on.end() && it->first == idx; ++it)
      resting = resting && !bodies_[static_cast<std::size_t>(it->second)].awake();
    if (!resting) continue;
    Body<T>& b = bodies_[i];
    b.v = b.w = Vec3<T>{};  // eq 80
    b.asleep = true;
    b.sleep_frame = frame_;
    record_supports(i);
  }
  wake_loaded();
}

template <class T>
void World<T>::wake(int i) {
  Body<T>& b = bodies_.at(static_cast<std::size_t>(i));
  if (b.is_static || !b.asleep) return;
  b.asleep = false;
  rests_[static_cast<std::size_t>(i)].clear();
  b.sleep_counter = 0;
  ++counters_.wakes;
}

template <class T>
void World<T>::set_velocity(int i, const Vec3<T>& v, const Vec3<T>& w) {
  Body<T>& b = bodies_.at(static_cast<std::size_t>(i));
  if (b.is_static) return;
  wake(i);
  b.v = v;
  b.w = w;
  b.sleep_counter = 0;
}

}  // namespace lockstep
