// The GPU engine's kernels, one functor per kernel: operator()(k) is the work
// of thread k. The device backend launches them as CUDA kernels; the host
// build calls them in a loop over k. Each thread owns one element (a body, a
// sorted grid entry) and writes only that element's outputs, reading its
// neighbours' values from buffers that no thread of the same kernel writes;
// the only atomics are integer ones whose order cannot change a result
// (counters, the wake flag and woken list, the longest neighbour list, the
// lowest failing body index).
//
// One file per stage of docs/SPEC.md 7.2, as reference/src has:
//   grid.hpp, grid_stages.hpp    the uniform grids and the kernels that build them
//   integrate_stages.hpp         stage 1 (IntegrateVelocityK)
//   gather_stages.hpp            stages 2-4: neighbour lists and eq 81's wake (GatherK)
//   contact_stages.hpp           stages 3, 5: contacts, supports, preparation (ContactsK)
//   solve_stages.hpp             stage 5: the solver's iterations (SolveK, SolveEdgeK)
//   settle_stages.hpp            stage 6: settling sweeps (SettleK)
//   correct_stages.hpp           stages 6-8: correction and integration (CorrectIntegrateK)
//   commit_stages.hpp            stages 8-9: commit and sleep (CommitSleepK)
// with what they share in scene_consts.hpp, contact_records.hpp, solver_data.hpp
// and kernel_support.hpp; the oriented-box model's sequential orders are in
// oriented_stages.hpp, eqs 117 and 124 in load_stages.hpp and
// sleeper_load_stages.hpp. This header gathers the per-stage ones.
#pragma once
#include "commit_stages.hpp"
#include "contact_stages.hpp"
#include "correct_stages.hpp"
#include "gather_stages.hpp"
#include "grid_stages.hpp"
#include "integrate_stages.hpp"
#include "settle_stages.hpp"
#include "solve_stages.hpp"
