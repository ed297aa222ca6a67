// World<Q16>'s run-time inputs (world_inputs.hpp), apart from
// world_fixed.cpp: the certification build of the fixed engine compiles
// world_fixed.cpp alone, and inputs check their bodies with the scene loader.
#include "lockstep/fixed/q16_vec.hpp"
#include "world_impl.hpp"
#include "world_inputs.hpp"

namespace lockstep {
template BodyId World<Q16>::apply(const Input&);
template BodyId World<Q16>::create_body(const BodyDesc&);
template void World<Q16>::destroy_body(BodyId);
template void World<Q16>::apply_impulse(BodyId, const Vec3d&, const Vec3d&);
template void World<Q16>::add_force(BodyId, const Vec3d&, const Vec3d&);
template void World<Q16>::set_pose(BodyId, const Vec3d&, const Quatd&);
template void World<Q16>::set_velocity(BodyId, const Vec3d&, const Vec3d&);
template void World<Q16>::wake(BodyId);
template int World<Q16>::index_of(BodyId) const;
template bool World<Q16>::contains(BodyId) const;
template BodyId World<Q16>::id_of(int) const;
template BodyId World<Q16>::next_id() const;
template std::pair<Vec3<Q16>, Vec3<Q16>> World<Q16>::pending_force(int) const;
}  // namespace lockstep
