// The constants of Appendix A (doubles, as a scene gives them) and the
// derived Params<Q16> (raw) in JSON, field by field.
#pragma once
#include <vector>

#include "lockstep/physics/params.hpp"
#include "lockstep/scene.hpp"
#include "lockstep/vectors/common.hpp"

namespace lockstep::vectors {

// One field of Params<Q16>: exactly one of the three pointers is set.
struct ParamField {
  const char* name;
  Q16 Params<Q16>::*q16;
  Vec3<Q16> Params<Q16>::*vec;
  int Params<Q16>::*integer;
};
const std::vector<ParamField>& param_fields();
// True when param_fields() names every member of Params<Q16> (their sizes add
// up to sizeof(Params<Q16>)); a test checks it, so a new constant is not
// silently left out of the vectors.
bool param_fields_complete();

// {"dt": raw, "half_dt": raw, "gravity_dt": [x, y, z], ..., "solver_iterations": int, ...}
Json params_to_json(const Params<Q16>& p);

// {"dt": "<binary64 bits>", "gravity": [bits, bits, bits], ..., "solver_iterations": int, ...}
Json constants_to_json(const Constants& c);
// Reads every field of constants_to_json; throws FormatError naming a missing one.
Constants constants_from_json(const Json& j, const std::string& path);

}  // namespace lockstep::vectors
