// World<Mp>: the mp engine.
#include "lockstep/math/num_mp.hpp"
#include "snapshot_mp.hpp"
#include "snapshot_load.hpp"
#include "world_impl.hpp"
#include "world_inputs.hpp"

namespace lockstep {
template class World<Mp>;
}  // namespace lockstep
