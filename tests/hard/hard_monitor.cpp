#include "hard_monitor.hpp"

#include "lockstep/physics/box_box.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numeric>
#include <sstream>

namespace lockstep::hard {

namespace {

bool finite(const BodySnapshot& s) {
  for (double x : s.p) if (!std::isfinite(x)) return false;
  for (double x : s.q) if (!std::isfinite(x)) return false;
  for (double x : s.v) if (!std::isfinite(x)) return false;
  for (double x : s.w) if (!std::isfinite(x)) return false;
  return true;
}

bool same_state(const BodySnapshot& a, const BodySnapshot& b) {
  return std::memcmp(a.p, b.p, sizeof a.p) == 0 && std::memcmp(a.q, b.q, sizeof a.q) == 0 &&
         std::memcmp(a.v, b.v, sizeof a.v) == 0 && std::memcmp(a.w, b.w, sizeof a.w) == 0;
}

double norm3(const double* x) { return std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]); }

double half_diagonal(const Vec3d& h) { return std::sqrt(h.x * h.x + h.y * h.y + h.z * h.z); }

// 1/2 w_b . I w_b, w_b = R^T w (J).
double rotational_energy(const double (&R)[3][3], const std::array<double, 3>& I, const double* w) {
  double e = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double wb = R[0][a] * w[0] + R[1][a] * w[1] + R[2][a] * w[2];
    e += 0.5 * I[static_cast<std::size_t>(a)] * wb * wb;
  }
  return e;
}

}  // namespace

Monitor::Monitor(const Scene& scene, EngineRun& run) : scene_(scene), run_(run) {
  g_up_ = scene.effects.gravity ? -scene.constants.gravity.y : 0.0;
  start_ = snapshot();
  prev_ = start_;
  prev_geom_ = geometries(prev_);
  const std::size_t n = start_.size();
  max_misalign_.assign(n, 0.0);
  max_lift_.assign(n, 0.0);
  was_awake_.assign(n, 0);
  stats_.first_awake_frame.assign(n, -1);
  for (std::size_t i = 0; i < n; ++i) {
    was_awake_[i] = !start_[i].asleep && !scene_.bodies[i].is_static;
    if (was_awake_[i]) stats_.first_awake_frame[i] = 0;
  }
  stats_.max_horizontal.assign(n, 0.0);
  stats_.max_distance.assign(n, 0.0);
  stats_.e0 = energy_of(prev_, prev_geom_);
  stats_.e_last = stats_.e0;
  // Tolerance (docs/HARD_CASES.md): kPositionRounding (2^-12 m) of height and
  // 2^-12 J/kg of kinetic energy per body, plus 1e-9 of |E(0)|.
  double mass = 0.0;
  for (std::size_t i = 0; i < n; ++i)
    if (!scene_.bodies[i].is_static) mass += scene_.bodies[i].mass;
  stats_.tolerance = mass * (std::fabs(g_up_) + 1.0) * kPositionRounding + 1e-9 * std::fabs(stats_.e0);
  stats_.final_pair_overlap = contacts_of(prev_, prev_geom_).deepest_pair;
}

std::vector<BodySnapshot> Monitor::snapshot() const {
  std::vector<BodySnapshot> s;
  s.reserve(static_cast<std::size_t>(run_.body_count()));
  for (int i = 0; i < run_.body_count(); ++i) s.push_back(run_.body(i));
  return s;
}

std::vector<BodyGeometry> Monitor::geometries(const std::vector<BodySnapshot>& s) const {
  std::vector<BodyGeometry> g;
  g.reserve(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) g.push_back(geometry_of(s[i], scene_.bodies[i].half_extents));
  return g;
}

double Monitor::energy_of(const std::vector<BodySnapshot>& s, const std::vector<BodyGeometry>& g) const {
  double e = 0.0;
  // With the gravity effect off there is no field, so no potential energy.
  const Vec3d gravity = scene_.effects.gravity ? scene_.constants.gravity : Vec3d{};
  for (std::size_t i = 0; i < s.size(); ++i) e += body_energy(s[i], g[i], scene_.bodies[i], gravity);
  return e;
}

Monitor::ContactView Monitor::contacts_of(const std::vector<BodySnapshot>& s, const std::vector<BodyGeometry>& g) const {
  const std::size_t n = s.size();
  ContactView view;
  view.lift.assign(n, 0.0);
  view.load.assign(n, 0.0);
  view.touching.assign(n, 0);
  view.misalign.assign(n, 0.0);
  // Per body, the sum of its support normals (the ground's and its box-box
  // pairs'): eq 66's alignment is taken against the body's support normal,
  // the normalised mean of some of them (4.1); the misalignment is bounded
  // here by the largest against each of them and against their mean.
  std::vector<std::array<double, 3>> normal_sum(n, {0.0, 0.0, 0.0});
  auto misalign_against = [&](std::size_t i, double nx, double ny, double nz) {
    double best = 0.0;
    for (int k = 0; k < 3; ++k)
      best = std::max(best, std::fabs(g[i].R[0][k] * nx + g[i].R[1][k] * ny + g[i].R[2][k] * nz));
    return 1.0 - best;
  };
  auto add_support_normal = [&](std::size_t i, double nx, double ny, double nz) {
    view.misalign[i] = std::max(view.misalign[i], misalign_against(i, nx, ny, nz));
    normal_sum[i][0] += nx;
    normal_sum[i][1] += ny;
    normal_sum[i][2] += nz;
  };
  // Points within contact_tolerance of touching are (speculative) contacts
  // (eq 97): they count as touching, for the righting allowance.
  const double tol = scene_.constants.contact_tolerance;
  // Ground (eq 84): the deepest corner's contact lifts the body (eq 89).
  if (scene_.effects.ground && scene_.ground.present) {
    for (std::size_t i = 0; i < n; ++i) {
      if (scene_.bodies[i].is_static) continue;
      const double depth = scene_.ground.height - g[i].lowest_y;
      if (depth > -tol) {
        view.touching[i] = 1;  // a (speculative, eq 97) contact
        add_support_normal(i, 0.0, 1.0, 0.0);
      }
      view.lift[i] = std::max(view.lift[i], depth);
    }
  }
  // Body pairs: AABB overlap (eqs 38-43) of the boxes grown by
  // contact_tolerance / 2 each (eq 97), found by a sweep along x. A pair
  // whose least-overlap axis is (or ties with) y lifts the upper body and
  // loads the lower one; the lift is counted as if the upper body took the
  // whole correction (an upper bound: with both bodies awake the split of
  // eq 89 adds no potential energy at all).
  // Eq 110 corrects a box-box pair by its depth less what the stage has
  // already moved its two sides apart: a lower side lifted first (by the
  // ground, which is corrected first, or by its own pair below) lifts the
  // upper side by that much more (a body placed 0.32 m deep into a box that
  // the box below it lifts by 0.1 m rises 0.42 m in one frame). The lift of
  // the upper side of a support pair is therefore bounded by its own depth
  // plus the lift of its lower side, carried up the chain below.
  struct Carried {
    std::size_t upper, lower;
    double own;  // deepest point times |n_y| (m); < 0: a speculative pair's gap
  };
  std::vector<Carried> carried;
  if (scene_.effects.contacts && n >= 2) {
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), std::size_t{0});
    // A pair is a (speculative) contact of the frame only within eq 107's
    // reach of its bodies: (|v|inf + |g| dt + 3 |w|inf h_max) dt each, an
    // upper bound (eq 107 caps both speeds at 64 m/s).
    std::vector<double> reach(n, 0.0);
    const double g_dt = std::sqrt(scene_.constants.gravity.x * scene_.constants.gravity.x +
                                  scene_.constants.gravity.y * scene_.constants.gravity.y +
                                  scene_.constants.gravity.z * scene_.constants.gravity.z) * scene_.constants.dt;
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3d& h = scene_.bodies[i].half_extents;
      double v = 0, w = 0;
      for (int k = 0; k < 3; ++k) {
        v = std::max(v, std::fabs(s[i].v[k]));
        w = std::max(w, std::fabs(s[i].w[k]));
      }
      reach[i] = (v + g_dt + 3.0 * w * std::max(h.x, std::max(h.y, h.z))) * scene_.constants.dt;
    }
    auto lo_x = [&](std::size_t i) { return s[i].p[0] - g[i].aabb_half[0] - 0.5 * tol - reach[i]; };
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return lo_x(a) < lo_x(b); });
    for (std::size_t a = 0; a < n; ++a) {
      const std::size_t i = order[a];
      const double hi_x = s[i].p[0] + g[i].aabb_half[0] + 0.5 * tol + reach[i];
      for (std::size_t b = a + 1; b < n; ++b) {
        const std::size_t j = order[b];
        if (lo_x(j) > hi_x) break;
        if (scene_.bodies[i].is_static && scene_.bodies[j].is_static) continue;
        double overlap[3];
        for (int k = 0; k < 3; ++k) overlap[k] = g[i].aabb_half[k] + g[j].aabb_half[k] - std::fabs(s[i].p[k] - s[j].p[k]);
        const double ext = tol + reach[i] + reach[j];
        if (!(overlap[0] > -ext && overlap[1] > -ext && overlap[2] > -ext)) continue;
        const bool near = overlap[0] > -tol && overlap[1] > -tol && overlap[2] > -tol;
        if (scene_.pair_contacts == PairModel::kOrientedBox) {
          // The oriented-box model (eqs 100-110): the manifold's normal and
          // depths; its correction can lift the side the normal points to by
          // at most the deepest point's depth times n.y.
          const std::size_t a_ = std::min(i, j), b_ = std::max(i, j);
          auto mat = [&](std::size_t k) {
            Mat3<double> R;
            for (int r = 0; r < 3; ++r) R.row[r] = {g[k].R[r][0], g[k].R[r][1], g[k].R[r][2]};
            return R;
          };
          auto vec = [](const double* v) { return Vec3<double>{v[0], v[1], v[2]}; };
          auto half = [&](std::size_t k) {
            const Vec3d& h = scene_.bodies[k].half_extents;
            return Vec3<double>{h.x, h.y, h.z};
          };
          // The chain (below): any pair the frame may make a contact, a
          // speculative one included (its gap, a negative depth, is what a
          // lower side lifted into it must first close).
          const BoxManifold<double> reachable =
              box_box_manifold(vec(s[a_].p), mat(a_), half(a_), vec(s[b_].p), mat(b_), half(b_), ext);
          if (reachable.count > 0 && reachable.n.y != 0.0) {
            double deepest = reachable.penetration[0];
            for (int k = 1; k < reachable.count; ++k) deepest = std::max(deepest, reachable.penetration[k]);
            carried.push_back({reachable.n.y > 0.0 ? a_ : b_, reachable.n.y > 0.0 ? b_ : a_,
                               deepest * std::fabs(reachable.n.y)});
          }
          if (!near) continue;
          const BoxManifold<double> m =
              box_box_manifold(vec(s[a_].p), mat(a_), half(a_), vec(s[b_].p), mat(b_), half(b_), tol);
          if (m.count == 0) continue;
          view.touching[i] = view.touching[j] = 1;
          if (std::fabs(m.n.y) >= scene_.constants.support_normal_min) {
            // A support contact of its upper side (4.1): the righting torque
            // (67-71) aligns that body with the support normal, not with y.
            const std::size_t up_side = m.n.y > 0.0 ? a_ : b_;
            const double sgn = m.n.y > 0.0 ? 1.0 : -1.0;
            add_support_normal(up_side, sgn * m.n.x, sgn * m.n.y, sgn * m.n.z);
          }
          double deepest = m.penetration[0];
          for (int k = 1; k < m.count; ++k) deepest = std::max(deepest, m.penetration[k]);
          if (deepest <= 0.0) continue;
          view.deepest_pair = std::max(view.deepest_pair, deepest);
          if (m.n.y == 0.0) continue;
          const std::size_t upper = m.n.y > 0.0 ? a_ : b_, lower = m.n.y > 0.0 ? b_ : a_;
          view.lift[upper] = std::max(view.lift[upper], deepest * std::fabs(m.n.y));
          view.load[lower] = std::max(view.load[lower], deepest);
          continue;
        }
        if (!near) continue;
        view.touching[i] = view.touching[j] = 1;
        const double pen = std::min(overlap[0], std::min(overlap[1], overlap[2]));  // < 0: a gap
        if (pen <= 0.0) continue;
        view.deepest_pair = std::max(view.deepest_pair, pen);
        if (overlap[1] > std::min(overlap[0], overlap[2]) + 1e-6) continue;  // not along y
        const bool i_upper = s[i].p[1] >= s[j].p[1];
        const std::size_t upper = i_upper ? i : j, lower = i_upper ? j : i;
        view.lift[upper] = std::max(view.lift[upper], pen);
        view.load[lower] = std::max(view.load[lower], pen);
      }
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    const double len = std::sqrt(normal_sum[i][0] * normal_sum[i][0] + normal_sum[i][1] * normal_sum[i][1] +
                                 normal_sum[i][2] * normal_sum[i][2]);
    if (len > 0.0)
      view.misalign[i] = std::max(view.misalign[i], misalign_against(i, normal_sum[i][0] / len, normal_sum[i][1] / len,
                                                                     normal_sum[i][2] / len));
  }
  // The chain (eq 110 visits the pairs bottom up; a lift the pair sees is at
  // most the lower side's own lift, max(0, lift - slop) * baumgarte): passes
  // until no bound grows, at most one per body (each pass carries a lift one
  // pair further up).
  const Constants& c = scene_.constants;
  for (std::size_t pass = 0; pass < n && !carried.empty(); ++pass) {
    bool grew = false;
    for (const Carried& k : carried) {
      const double bound = k.own + std::max(0.0, view.lift[k.lower] - c.slop) * c.baumgarte;
      if (bound > view.lift[k.upper]) {
        view.lift[k.upper] = bound;
        grew = true;
      }
    }
    if (!grew) break;
  }
  return view;
}

void Monitor::step() {
  // What this frame's narrow phase sees: the state it starts from.
  const ContactView before = contacts_of(prev_, prev_geom_);
  for (std::size_t i = 0; i < prev_.size(); ++i) {
    max_lift_[i] = std::max(max_lift_[i], before.lift[i]);
    if (before.touching[i] && scene_.effects.settling)
      max_misalign_[i] = std::max(max_misalign_[i], std::max(1.0 - prev_geom_[i].alignment, before.misalign[i]));
  }
  run_.step();
  const int frame = ++stats_.frames;
  std::vector<BodySnapshot> now = snapshot();
  for (std::size_t i = 0; i < now.size(); ++i) {
    if (!finite(now[i]) && stats_.nonfinite_frame < 0) {
      stats_.nonfinite_frame = frame;
      stats_.nonfinite_body = static_cast<int>(i);
    }
  }
  if (stats_.nonfinite_frame >= 0) {
    prev_ = std::move(now);
    return;
  }
  std::vector<BodyGeometry> geom = geometries(now);
  const Constants& c = scene_.constants;
  const std::size_t n = now.size();

  // Energy against its allowance.
  double correction = 0.0, righting = 0.0;
  const double w_scale = c.kp * std::max(c.speed_factor_min, c.speed_factor_max);
  for (std::size_t i = 0; i < n; ++i) {
    const BodyDesc& d = scene_.bodies[i];
    if (d.is_static) continue;
    if (scene_.effects.gravity && g_up_ > 0.0)
      correction += d.mass * g_up_ * std::max(0.0, max_lift_[i] - c.slop) * c.baumgarte;
    const std::array<double, 3> I = box_inertia(d);
    const double wd = w_scale * max_misalign_[i];
    righting += 0.5 * std::max(I[0], std::max(I[1], I[2])) * wd * wd;
    // The frame turned the body from R(n-1) to R(n) at its final w (eq 11:
    // w constant in the world frame): its rotational energy changed by
    // 1/2 w.(I_world(n) - I_world(n-1)) w (0 for a cube).
    spin_sum_ += rotational_energy(geom[i].R, I, now[i].w) - rotational_energy(prev_geom_[i].R, I, now[i].w);
  }
  const double gyro = std::max(0.0, spin_sum_);
  const double e = energy_of(now, geom);
  const double allowance = correction + righting + gyro + stats_.tolerance;
  if (e - (stats_.e0 + allowance) > stats_.worst_excess) {
    stats_.worst_excess = e - (stats_.e0 + allowance);
    stats_.worst_excess_frame = frame;
    stats_.worst_energy = e;
    stats_.worst_allowance = allowance;
  }
  stats_.e_last = e;
  stats_.correction_allowance = correction;
  stats_.righting_allowance = righting;
  stats_.spin_allowance = gyro;

  // Kinematics, rest and sleep.
  const ContactView after = contacts_of(now, geom);
  stats_.max_pair_overlap = std::max(stats_.max_pair_overlap, after.deepest_pair);
  stats_.final_pair_overlap = after.deepest_pair;
  const bool ground = scene_.ground.present;
  bool all_asleep = true;
  for (std::size_t i = 0; i < n; ++i) {
    const BodySnapshot& b = now[i];
    const BodyDesc& d = scene_.bodies[i];
    if (d.is_static) continue;
    const int body = static_cast<int>(i);
    all_asleep = all_asleep && b.asleep;
    if (!b.asleep) {
      was_awake_[i] = 1;
      if (stats_.first_awake_frame[i] < 0) stats_.first_awake_frame[i] = frame;
    }
    stats_.max_speed = std::max(stats_.max_speed, norm3(b.v));
    stats_.max_spin = std::max(stats_.max_spin, norm3(b.w));
    if (std::fabs(geom[i].q_norm - 1.0) > stats_.max_q_dev) {
      stats_.max_q_dev = std::fabs(geom[i].q_norm - 1.0);
      stats_.max_q_dev_frame = frame;
    }
    if (ground) {
      const double depth = scene_.ground.height - geom[i].lowest_y;
      if (depth > stats_.max_depth) {
        stats_.max_depth = depth;
        stats_.max_depth_frame = frame;
        stats_.max_depth_body = body;
      }
      stats_.min_centre_height = std::min(stats_.min_centre_height, b.p[1] - scene_.ground.height);
      if (b.asleep && was_awake_[i] && scene_.effects.ground) {
        const double bound = c.slop + (c.sleep_linear + c.sleep_angular * half_diagonal(d.half_extents)) * c.dt +
                             after.load[i] + kPositionRounding;
        if (depth - bound > stats_.resting_excess) {
          stats_.resting_excess = depth - bound;
          stats_.resting_excess_frame = frame;
          stats_.resting_excess_body = body;
          stats_.resting_excess_depth = depth;
        }
      }
    }
    const double dx = b.p[0] - start_[i].p[0], dy = b.p[1] - start_[i].p[1], dz = b.p[2] - start_[i].p[2];
    stats_.max_horizontal[i] = std::max(stats_.max_horizontal[i], std::sqrt(dx * dx + dz * dz));
    stats_.max_distance[i] = std::max(stats_.max_distance[i], std::sqrt(dx * dx + dy * dy + dz * dz));
    // A body asleep before and after the frame has not changed at all, and a
    // body put to sleep by eq 80 has v = w = 0 (one the scene starts asleep
    // keeps the scene's velocities until it wakes).
    const bool moved = prev_[i].asleep && b.asleep && !same_state(prev_[i], b);
    const bool moving = b.asleep && was_awake_[i] && (norm3(b.v) != 0.0 || norm3(b.w) != 0.0);
    if (moved || moving) {
      if (stats_.asleep_moved++ == 0) {
        stats_.first_asleep_moved_frame = frame;
        stats_.first_asleep_moved_body = body;
      }
    }
  }
  if (all_asleep && stats_.all_asleep_frame < 0) stats_.all_asleep_frame = frame;
  if (!all_asleep) stats_.all_asleep_frame = -1;
  prev_ = std::move(now);
  prev_geom_ = std::move(geom);
}

void Monitor::run_to(int frames) {
  while (stats_.frames < frames && stats_.nonfinite_frame < 0) step();
}

int Monitor::awake_count() const {
  int count = 0;
  for (std::size_t i = 0; i < prev_.size(); ++i) count += (!scene_.bodies[i].is_static && !prev_[i].asleep) ? 1 : 0;
  return count;
}

bool Monitor::all_asleep() const { return awake_count() == 0; }

std::string Monitor::summary() const {
  const MonitorStats& s = stats_;
  std::ostringstream o;
  o.precision(6);
  o << run_.name() << ": frames " << s.frames << ", E(0) " << s.e0 << " J, E " << s.e_last << " J, worst E - bound "
    << s.worst_excess << " J at frame " << s.worst_excess_frame << " (E " << s.worst_energy << ", allowance "
    << s.worst_allowance << " = C " << s.correction_allowance << " + S " << s.righting_allowance << " + W "
    << s.spin_allowance << " + tol "
    << s.tolerance << " at the end), max |v| " << s.max_speed << " m/s, max |w| " << s.max_spin
    << " rad/s, max ground depth " << s.max_depth << " m (frame " << s.max_depth_frame << ", body "
    << s.max_depth_body << "), resting depth - bound " << s.resting_excess << " m (frame " << s.resting_excess_frame
    << ", body " << s.resting_excess_body << "), max pair overlap " << s.max_pair_overlap << " m (now "
    << s.final_pair_overlap << "), max ||q|-1| " << s.max_q_dev << ", asleep bodies moved " << s.asleep_moved
    << ", awake " << awake_count() << "/" << prev_.size();
  if (s.nonfinite_frame >= 0) o << ", NON-FINITE state at frame " << s.nonfinite_frame << " body " << s.nonfinite_body;
  return o.str();
}

}  // namespace lockstep::hard
