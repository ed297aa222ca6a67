// World<float>: the float engine.
#include "world_impl.hpp"

namespace lockstep {
template class World<float>;
}  // namespace lockstep
