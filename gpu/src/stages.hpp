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
//   manifold_stages.hpp          stage 3, oriented-box model: each pair's manifold, once (PairManifoldK)
//   contact_stages.hpp           stages 3, 5: contacts, supports, preparation (ContactsK);
//                                eq 112's chain (TipChainK)
//   solve_stages.hpp             stage 5: the solver's iterations (SolveK, SolveEdgeK; gpu-fixed's rows, ImmRowsK, EdgeRowsK)
//   settle_stages.hpp            stage 6: settling sweeps (SettleK)
//   correct_stages.hpp           stages 6-8: correction and integration (CorrectIntegrateK)
//   pair_correct_stages.hpp      stages 7-8, oriented-box model: eqs 110-111, integration
//   commit_stages.hpp            stages 8-9: commit and sleep (CommitSleepK)
//   sleep_stages.hpp             stages 2a and 9, oriented-box model: eqs 108-109
//   load_stages.hpp, sleeper_load_stages.hpp   eqs 117 and 124
// with what they share in scene_consts.hpp, contact_records.hpp, solver_data.hpp,
// kernel_support.hpp and fault_notes.hpp (gpu-fixed's Q16 faults); oriented_stages.hpp says how the oriented-box
// model's sequential orders become sweeps. This header gathers the stages.
#pragma once
#include "commit_stages.hpp"
#include "contact_stages.hpp"
#include "correct_stages.hpp"
#include "gather_stages.hpp"
#include "manifold_stages.hpp"
#include "grid_stages.hpp"
#include "integrate_stages.hpp"
#include "oriented_stages.hpp"
#include "settle_stages.hpp"
#include "solve_stages.hpp"
