// World<Q16>: the fixed engine.
#include "lockstep/fixed/q16_vec.hpp"
#include "world_impl.hpp"

namespace lockstep {
template class World<Q16>;
}  // namespace lockstep
