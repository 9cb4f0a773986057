#pragma once
// Per-pair data of the cohesive law kept with the neighbour list, for the host pass, computed once per
// rebuild: delta_f of eq 10 (for d > d_c and s other than 0 it needs a pow) and c_N of eq 12 (a square root,
// a division and two mass gathers per pair in the loop; streaming it made a step 8% faster at N = 32,000 on
// Sapphire Rapids). The other constants of eqs 7-17 are cheaper to recompute in the vectorised pair loop than
// to stream from memory (measured: an 8-double table was slower at N = 256,000 on AMD Zen 4, and a 6-double
// one no faster than these two on Sapphire Rapids, 11% slower at N = 256,000).
// Recomputed whenever the list, the masses or the material change.
#include <vector>

#include "core/exec.hpp"
#include "kernels/dem/cohesive_material.hpp"

namespace debris {

class Particles;
class NeighborList;

struct CohesivePairTable {
  // Offload builds: computed on the device; the half-list pass that reads them runs on the host, so the
  // engine copies them back (exec::to_host) after each build.
  exec::DeviceVector<double> delta_f;   // eq 10, per neighbour-list entry
  exec::DeviceVector<double> c_n;       // eq 12 (normal damping coefficient), per entry
  CohesiveCoefficients coefficients{};  // the material constants of eqs 7-18

  void build(const CohesiveCoefficients& c, const Particles& p, const NeighborList& list);
  std::size_t bytes() const { return sizeof(double) * (delta_f.capacity() + c_n.capacity()); }
};

}  // namespace debris
