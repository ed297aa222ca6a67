// World<float>: the float engine.
#include "snapshot_load.hpp"
#include "world_impl.hpp"

namespace lockstep {
template class World<float>;
}  // namespace lockstep
