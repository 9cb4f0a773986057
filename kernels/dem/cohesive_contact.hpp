#pragma once
// The cohesive contact pass: eqs 2-5 (kernels/dem/cohesive_pair_force.hpp) over a full neighbour list. Each
// pair is evaluated from both ends and written only to i, so no atomics are needed on host or GPU; both
// ends advance bit-identical (opposite) histories, so forces stay exactly antisymmetric.
#include "core/block_sums.hpp"
#include "core/box.hpp"
#include "kernels/dem/cohesive_material.hpp"
#include "kernels/dem/cohesive_pair_force.hpp"

namespace debris {

class Particles;
class NeighborList;
class ContactHistory;

/// Adds the pair forces and torques to f and t. update_history = 0 only for the set-up evaluation.
/// `energy` (nullptr: none) is set to each particle's sums of its pairs' energy parts.
void cohesive_contact_pass(const CohesiveCoefficients& c, const CohesiveOptions& opt, const BoxView& box,
                           Particles& p, const NeighborList& list, ContactHistory& history, double dt,
                           int update_history, const PairEnergyOut* energy = nullptr);

/// Diagnostics over a full or half list (no history update). `scope` (core/block_sums.hpp): a run cut among
/// ranks counts a pair on the rank that owns its end of lower id (one rank of the two that hold it), and
/// every rank gets the whole system's figures.
struct CohesiveDiagnostics {
  double elastic_energy = 0;  // sum over pairs of eq 3's potential plus the tangential spring energy
  double max_overlap = 0;     // largest interpenetration -dN over interacting pairs (0 if none)
  long interacting_pairs = 0;
};
CohesiveDiagnostics cohesive_diagnostics(const CohesiveCoefficients& c, const CohesiveOptions& opt,
                                         const BoxView& box, const Particles& p, const NeighborList& list,
                                         const ContactHistory& history, SumScope scope = {});

}  // namespace debris
