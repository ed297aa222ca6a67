// World<float>: the float engine.
#include "snapshot_load.hpp"
#include "world_impl.hpp"
#include "world_inputs.hpp"

namespace lockstep {
template class World<float>;
}  // namespace lockstep
