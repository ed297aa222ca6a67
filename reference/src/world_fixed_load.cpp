// World<Q16>'s snapshot loading (snapshot_load.hpp), apart from
// world_fixed.cpp: the certification build of the fixed engine
// (vectors/certify) compiles world_fixed.cpp alone, which steps and saves
// without the scene loader that a load validates with.
#include "lockstep/fixed/q16_vec.hpp"
#include "snapshot_load.hpp"
#include "world_impl.hpp"

namespace lockstep {
template World<Q16> World<Q16>::load_state(const std::uint8_t* data, std::size_t size);
template void World<Q16>::restore_state(const std::uint8_t* data, std::size_t size);
template void World<Q16>::read_moving_state(snap::Reader& r, std::uint32_t frame, bool derived_valid);
template void World<Q16>::read_ids_and_forces(snap::Reader& r);
template World<Q16> World<Q16>::load_state(const std::vector<std::uint8_t>& bytes);
template void World<Q16>::restore_state(const std::vector<std::uint8_t>& bytes);
}  // namespace lockstep
