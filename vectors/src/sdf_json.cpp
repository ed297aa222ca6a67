#include "lockstep/vectors/sdf_json.hpp"

namespace lockstep::vectors {

Json sdf_grid_json(const Vec3<Q16>& min, const Vec3<Q16>& max, const std::array<int, 3>& n) {
  Vec3<Q16> inv_spacing, spacing;
  for (int a = 0; a < 3; ++a) {  // eq 32, as World<Q16>'s constructor computes them
    const Q16 cells = Q16::from_int(n[static_cast<std::size_t>(a)] - 1);
    inv_spacing[a] = cells / (max[a] - min[a]);
    spacing[a] = (max[a] - min[a]) / cells;
  }
  return Json{{"min", to_json(min)},
              {"max", to_json(max)},
              {"n", Json::array({n[0], n[1], n[2]})},
              {"inv_spacing", to_json(inv_spacing)},
              {"spacing", to_json(spacing)}};
}

SdfGrid<Q16> sdf_grid_at(const Json& in, const std::string& path, std::vector<Q16>& values) {
  SdfGrid<Q16> g;
  g.min = vec_at(in, "min", path);
  g.max = vec_at(in, "max", path);
  const Json& n = member(in, "n", path);
  if (!n.is_array() || n.size() != 3) throw FormatError(path + ".n: expected [nx, ny, nz]");
  for (int a = 0; a < 3; ++a) {
    g.n[a] = n[static_cast<std::size_t>(a)].get<int>();
    if (g.n[a] < 2) throw FormatError(path + ".n: each resolution must be >= 2");
  }
  g.inv_spacing = vec_at(in, "inv_spacing", path);
  g.spacing = vec_at(in, "spacing", path);
  const Json& vals = member(in, "values", path);
  const std::size_t count = static_cast<std::size_t>(g.n[0]) * static_cast<std::size_t>(g.n[1]) *
                            static_cast<std::size_t>(g.n[2]);
  if (!vals.is_array() || vals.size() != count) throw FormatError(path + ".values: expected nx*ny*nz raw values");
  values.clear();
  for (const Json& x : vals) values.push_back(Q16::from_raw(x.get<std::int32_t>()));
  g.values = values.data();
  return g;
}

}  // namespace lockstep::vectors
