// The GPU engine's kernels of the oriented-box pair model's sequential
// orders (docs/SPEC.md 2.4, eqs 108-110; docs/GPU.md "Pair models"):
// World<T> decides the support wake (eq 108) in index order, the eq 110
// corrections in height order and the sleep of eq 109 in height order, each
// step seeing the ones before it. Here each is a sweep that every element
// computes from the previous sweep's results of the elements before it in
// that order; sweeps repeat until one reproduces its input bit for bit. An
// element's result depends only on elements before it, so the sweeps reach
// the one fixed point, World<T>'s result, after as many sweeps as the longest
// chain of dependencies (a column's height) plus one.
//
// The sweeps live with their stages: eq 112's chain (TipChainK) in
// contact_stages.hpp, the support wake (eq 108) and the sleep (eq 109) in
// sleep_stages.hpp, the corrections of eqs 110-111 in pair_correct_stages.hpp.
#pragma once
#include "contact_stages.hpp"
#include "pair_correct_stages.hpp"
#include "sleep_stages.hpp"
