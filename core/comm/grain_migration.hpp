#pragma once
// Whole PeriDEM grains move to the rank that owns their centre (shared/design/scale-mpi.md, section 5):
// a grain's nodes, its record and its bond rows (partners, reference lengths, broken flags) travel
// together, so bonds, bond breaking and the per-grain sums stay on one rank. As for particles
// (core/comm/migration), a grain that left this rank's subdomain goes to the next rank along the axis it
// left by, one axis after the other; it moves at most half a subdomain between two list builds.
//
// Walls (rigid, no bonds, often as wide as the box) are owned by position instead: each wall node on the
// rank whose subdomain holds it, so a rank holds a piece of a wall (the wall's record and some of its
// nodes), and a node crossing a cut moves alone.
//
// Storage after every call (sort_store): nodes in increasing id, grains (and pieces of walls) in increasing
// PdGrains::id, each grain's nodes contiguous: the order one process stores them in (its grains are placed
// with consecutive node ids, grain after grain). Every node's `grain` is the index of its grain here, bond
// rows rebased onto the new node indices.
#include <array>
#include <cstddef>
#include <vector>

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

/// A grain's record beside its node range (kind, material, id, volume, centre, mean velocity, wall
/// velocity): what travels with a grain or a piece of a wall, and what a ghost grain holds (core/comm/pd_halo).
struct GrainRecord {
  std::array<int, 3> ints{};
  std::array<double, 10> doubles{};
  static GrainRecord of(const PdGrains& g, std::size_t k);
  void store(PdGrains& g, std::size_t k) const;
};

struct GrainExchangeCount {
  std::size_t sent = 0, received = 0;  // grains
};

/// Moves every grain whose centre (grains.cx, cy, cz) this rank does not own, and every wall node whose
/// position it does not own, to its owner. Collective. Counts particle grains (not wall nodes).
/// std::runtime_error naming the grain (by its first node's id) or wall node if one moved past the next rank:
/// only the rank that finds it throws, so a caller that can meet it must stop every rank (comm::abort).
GrainExchangeCount exchange_grains(const Decomposition& d, const Box& box, GrainStore s);

/// Start of a run where every rank holds every grain: keeps those whose centre this rank owns, and the wall
/// nodes whose position it owns.
void keep_owned_grains(const Decomposition& d, const Box& box, GrainStore s);

/// Keeps the grains `which` (indices) whole and drops the others.
void select_grains(GrainStore s, const std::vector<int>& which);

/// Keeps the nodes flagged 1 (a particle grain's all or none; any of a wall's) and drops the others.
void keep_nodes(GrainStore s, const std::vector<unsigned char>& keep);

/// The whole system on rank 0, in one process's order (collective; a checkpoint's gather): every rank sends
/// its nodes flagged in `owned` (ghost copies are not sent) with their grains or pieces of walls and bond
/// rows, and rank 0 stores them all in `whole` (emptied first), pieces of one wall merged. `whole` stays
/// empty on the other ranks.
void gather_to_root(const GrainStore& s, const std::vector<unsigned char>& owned, GrainStore whole);

/// Puts the store in one process's order (above), merging grains of one id (pieces of a wall). Returns the
/// order: new node i was node order[i].
std::vector<int> sort_store(GrainStore s);

}  // namespace debris::comm
