// Part 2.3 of docs/SPEC.md: static SDF volumes (eqs 32-37, 93).
#pragma once
#include "lockstep/math/vec.hpp"

namespace lockstep {

// A view of an SDF volume's samples (values indexed i + nx*(j + ny*k)).
template <class T>
struct SdfGrid {
  Vec3<T> min, max;
  int n[3] = {2, 2, 2};
  Vec3<T> inv_spacing;  // (n - 1) / (max - min), eq 32
  Vec3<T> spacing;      // (max - min) / (n - 1), the Delta of eq 34
  const T* values = nullptr;
};

// eq 32: a grid's spacing and its inverse from its bounds and sample counts.
template <class T>
LS_HD void set_grid_spacing(SdfGrid<T>& g) {
  for (int a = 0; a < 3; ++a) {
    const T cells = Num<T>::from_int(g.n[a] - 1);
    g.inv_spacing[a] = cells / (g.max[a] - g.min[a]);  // eq 32
    g.spacing[a] = (g.max[a] - g.min[a]) / cells;
  }
}

template <class T>
LS_HD bool sdf_contains(const SdfGrid<T>& g, const Vec3<T>& p) {
  for (int a = 0; a < 3; ++a)
    if (p[a] < g.min[a] || p[a] > g.max[a]) return false;
  return true;
}

// eqs 32-33: trilinear d(p) for p inside the volume (clamped onto it when not).
// u = (p - min) * inv_spacing; cell index floor(u) clamped to [0, n-2]; the
// interpolation runs along x, then y, then z (the weights of eq 33 factored).
template <class T>
LS_HD T sdf_distance(const SdfGrid<T>& g, const Vec3<T>& p) {
  int idx[3];
  T f[3];
  for (int a = 0; a < 3; ++a) {
    const T pa = Num<T>::min(Num<T>::max(p[a], g.min[a]), g.max[a]);
    const T u = (pa - g.min[a]) * g.inv_spacing[a];  // eq 32
    int i = Num<T>::floor_int(u);
    if (i < 0) i = 0;
    if (i > g.n[a] - 2) i = g.n[a] - 2;
    idx[a] = i;
    f[a] = u - Num<T>::from_int(i);
  }
  auto at = [&](int di, int dj, int dk) {
    return g.values[(idx[0] + di) + g.n[0] * ((idx[1] + dj) + g.n[1] * (idx[2] + dk))];
  };
  auto lerp = [](const T& a, const T& b, const T& t) { return a + (b - a) * t; };
  const T c00 = lerp(at(0, 0, 0), at(1, 0, 0), f[0]);
  const T c10 = lerp(at(0, 1, 0), at(1, 1, 0), f[0]);
  const T c01 = lerp(at(0, 0, 1), at(1, 0, 1), f[0]);
  const T c11 = lerp(at(0, 1, 1), at(1, 1, 1), f[0]);
  const T c0 = lerp(c00, c10, f[1]);
  const T c1 = lerp(c01, c11, f[1]);
  return lerp(c0, c1, f[2]);  // eq 33
}

// eq 34: central differences with one grid spacing Delta per axis, (d(p +
// Delta) - d(p - Delta)) / Delta: the common factor 1/2 is dropped since eq 36
// normalises the gradient. Points beyond the volume are clamped onto it.
template <class T>
LS_HD Vec3<T> sdf_gradient(const SdfGrid<T>& g, const Vec3<T>& p) {
  Vec3<T> grad;
  for (int a = 0; a < 3; ++a) {
    Vec3<T> hi = p, lo = p;
    hi[a] = hi[a] + g.spacing[a];
    lo[a] = lo[a] - g.spacing[a];
    grad[a] = (sdf_distance(g, hi) - sdf_distance(g, lo)) * g.inv_spacing[a];
  }
  return grad;
}

}  // namespace lockstep
