// World<double>: the double engine.
#include "snapshot_load.hpp"
#include "world_impl.hpp"
#include "world_inputs.hpp"

namespace lockstep {
template class World<double>;
}  // namespace lockstep
