// What each number type can represent of a scene (docs/SCENES.md "Ranges per
// number type").
//
// parse_scene validates a scene once, for every engine: its ranges are the
// format's. An engine's number type narrows them: World<T> derives from each
// body its inverse mass 1/m, the squares of its half extents, the inverse
// inertia 3/(m (h_b^2 + h_c^2)) of eqs 14-18 and its AABB (eq 31), and in
// Q16.16 these overflow (|x| >= 32768) or round to 0 for masses and sizes the
// format accepts. validate_scene_for evaluates exactly what World<T>'s
// construction evaluates, in T, operation for operation, and refuses a body
// whose derived quantities T cannot hold, with a SceneError that names the
// field, the value, the limit and a fix, before any engine is built. It never
// changes what an engine computes.
#pragma once
#include <string>
#include <string_view>

#include "lockstep/scene.hpp"
#include "lockstep/scene_json.hpp"

namespace lockstep {

// Throws SceneError when `number_type` cannot represent a quantity World<T>
// derives from the scene at construction; `number_type` is Num<T>::kName:
// "fixed" (Q16.16), "float", "double" or "mp" (any other name: no check).
// The message is one line:
//   <scene NAME>: PATH = VALUE: the ENGINE engine's QUANTITY = X UNIT is
//   outside Q16.16's range |x| < 32768 (or: rounds to 0 ...); FIX, or run on
//   float or double
// and field is PATH ("bodies[3].mass", "bodies[0].half_extents"). The first
// body at fault is reported (bodies in order; per body 1/m, then h^2 and the
// sums h_b^2 + h_c^2, then 3/(h_b^2 + h_c^2), then the inverse inertia, then
// the AABB). A static body has no 1/m or inertia (eqs 14-18 give it 0); only
// its AABB is checked.
//
// A quantity is refused when it leaves the type's range (Q16.16: it
// overflows, and World<Q16> would stop at frame 0 with a RunError; float and
// double: it is not finite), and 1/m also when it rounds to 0 (a dynamic body
// that could not move; beyond the format's 10000 kg, so only for a scene built
// in code). An inverse inertia that rounds to 0 is accepted: the body turns
// less than the type resolves (docs/SCENES.md). "mp" has no limit within the
// format's ranges.
void validate_scene_for(std::string_view number_type, const Scene& scene);

// The number type an engine name runs on ("fixed" -> "fixed", "gpu" and
// "gpu-jacobi" -> "float", ...), for validate_scene_for; the name itself for
// the reference engines.
std::string number_type_of_engine(std::string_view engine_name);

}  // namespace lockstep
