#pragma once
// Whole PeriDEM grains move to the rank that owns their centre (shared/design/scale-mpi.md, section 5;
// issue 27): a grain's nodes, its record and its bond rows (partners, reference lengths, broken flags) travel
// together, so bonds, bond breaking and the per-grain sums stay on one rank. As for particles
// (core/comm/migration), a grain that left this rank's subdomain goes to the next rank along the axis it
// left by, one axis after the other; it moves at most half a subdomain between two list builds.
//
// Storage after every call: the rank's grains in increasing id of their first node (the order one process
// stores them in: grains are placed with consecutive node ids), each grain's nodes contiguous in their own
// order, every node's `grain` the index of its grain here, bond rows rebased onto the new node indices.
//
// Walls are not moved here (kind wall: they have no bonds and span the box); a store holding one is refused
// until walls are owned by position.
#include <cstddef>

#include "core/bond_list.hpp"
#include "core/comm/decomposition.hpp"
#include "core/pd_nodes.hpp"

namespace debris::comm {

/// A rank's grains: nodes (grain-contiguous), grain records and the bond rows of the nodes.
struct GrainStore {
  PdNodes& nodes;
  PdGrains& grains;
  BondList& bonds;
};

struct GrainExchangeCount {
  std::size_t sent = 0, received = 0;  // grains
};

/// Moves every grain whose centre (grains.cx, cy, cz) this rank does not own to its owner. Collective.
/// std::runtime_error naming the grain (by its first node's id) if one moved farther than the next rank:
/// only the rank that finds it throws, so a caller that can meet it must stop every rank (comm::abort).
GrainExchangeCount exchange_grains(const Decomposition& d, const Box& box, GrainStore s);

/// Start of a run where every rank holds every grain: keeps those whose centre this rank owns.
void keep_owned_grains(const Decomposition& d, const Box& box, GrainStore s);

/// Keeps the grains `which` (indices, in the order given) and drops the others: nodes, records and bond rows
/// rebuilt contiguously in that order. What exchange_grains and keep_owned_grains store by.
void select_grains(GrainStore s, const std::vector<int>& which);

}  // namespace debris::comm
