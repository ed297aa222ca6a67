// An SDF grid (docs/SPEC.md 2.4) in raw Q16.16 JSON, as both the formula
// level (the shared grid of sdf_sample) and the scene level (setup.sdfs) write
// it: {"min", "max", "n", "inv_spacing", "spacing"} then the raw "values".
#pragma once
#include <array>
#include <string>
#include <vector>

#include "lockstep/physics/sdf.hpp"
#include "lockstep/vectors/common.hpp"

namespace lockstep::vectors {

// The grid's box and resolution and the spacings World<Q16> derives from them
// (eq 32, per axis: cells = from_int(n - 1), inv_spacing = cells / (max - min),
// spacing = (max - min) / cells), in that key order.
Json sdf_grid_json(const Vec3<Q16>& min, const Vec3<Q16>& max, const std::array<int, 3>& n);

// Reads a grid written by sdf_grid_json with its "values" (nx*ny*nz raw, index
// i + nx*(j + ny*k)) into `values`, which the returned grid points into.
// Throws FormatError naming `path`.
SdfGrid<Q16> sdf_grid_at(const Json& in, const std::string& path, std::vector<Q16>& values);

}  // namespace lockstep::vectors
