// World<double>: the double engine.
#include "world_impl.hpp"

namespace lockstep {
template class World<double>;
}  // namespace lockstep
