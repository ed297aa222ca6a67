// Level 2 vectors: single-equation cases in raw Q16.16, each naming its
// equation numbers (docs/SPEC.md): integration, the quaternion step, the
// rotated AABB, AABB overlap and normal, ground and two-body impulses,
// friction, Baumgarte, righting, SDF sample and normal, the state hash, the
// derived constants, the contact target velocity (eq 97) and a solver visit
// of a manifold with its split factor (eq 99). File: formulas.json.
#pragma once
#include <string>
#include <vector>

#include "lockstep/vectors/common.hpp"

namespace lockstep::vectors {

// The formula functions in file order.
std::vector<std::string> formula_functions();

// The whole formulas.json document.
Json generate_formulas();

// The outputs of formula `function` on inputs `in` (the group's "shared"
// inputs merged in): {"out": {...}, "status": [...]}. Throws FormatError.
Json compute_formula(const std::string& function, const Json& in, const std::string& path);

// Recomputes every test of a formulas.json document; the first difference is
// named by tcId, function and output field.
Verdict verify_formulas(const Json& doc, const std::string& file_name);

}  // namespace lockstep::vectors
