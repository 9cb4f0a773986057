#pragma once
// Average virial stress of a set of particles (paper section 3: "the stresses are obtained by computing the
// average virial stress inside the deformable part of the system", ref 35). Convention of LAMMPS
// `compute stress/atom`: each particle i carries a stress times volume
//
//   W_ab(i) = -[ m_i v_i,a v_i,b  +  1/2 sum_j r_ij,a F_ij,b ],    r_ij = x_i - x_j (minimum image),
//
// with F_ij the force of eq 2 on i from j (normal, tangential spring from the stored history, and both
// dampings), and the sample stress is sigma_ab = sum over the selected i of W_ab(i), divided by the volume
// V the caller assigns to them.
//
// Sign: tension is positive. A pair stretched along y pulls i back toward j (F_ij,y < 0 while r_ij,y > 0),
// so W_yy > 0: a sample stretched along y has sigma_yy > 0, and sigma = -p I for a hydrostatic pressure p.
// Thermal motion counts as compression (-m v v), as in the pressure of a gas.
//
// Off-diagonal components are stored as LAMMPS stores them: xy = -[m v_x v_y + 1/2 sum r_x F_y], and so on
// (first index on r). Central forces make W symmetric. The tangential force of eq 2 does not, but since the
// two moment arms of a pair add up to |r_ij| (cohesive_pair_force.hpp), the antisymmetric part of W summed
// over all particles is their total pair torque (W_yz - W_zy = T_x, ...; for equal radii particle by
// particle): it vanishes in rotational equilibrium, where the stored components are the whole stress.
//
// The kinetic part uses the whole translational velocity (no streaming velocity removed) and no spin, like
// LAMMPS. For a periodic sample at rest the pair part summed over all particles is exact: with central
// forces it equals (1/V) dU/d eps for a strain increment eps applied to the current state
// (tests/test_virial_stress.cpp).
#include "core/box.hpp"
#include "kernels/dem/cohesive_material.hpp"
#include "kernels/dem/cohesive_pair_force.hpp"

namespace debris {

class Particles;
class NeighborList;
class ContactHistory;

/// A symmetric-layout stress tensor (stress units; tension positive).
struct StressTensor {
  double xx = 0, yy = 0, zz = 0, xy = 0, xz = 0, yz = 0;
};

/// Sum over the selected particles of W(i) (above), divided by `volume`. `list` is a full or a half list
/// and `history` its per-entry tangential springs (as the contact pass of that kind keeps them): each pair
/// force is recomputed with cohesive_pair_force from a copy of its history, without advancing it (the
/// state is not modified). `select` may be nullptr (all particles) or a per-particle mask, nonzero =
/// summed; the pair part of a selected i counts all its neighbours, selected or not. kinetic = false
/// leaves out the m v v part. Throws std::logic_error when the history does not match the list and
/// std::invalid_argument for volume <= 0. The sums are
/// exact (core/block_sums): the same bits for any thread count or storage order. `across_ranks`: every
/// rank's sum is added (a run cut among ranks passes as `select` its owned particles, selected: each half
/// of a pair is then counted on one rank, the one that owns its end).
StressTensor virial_stress(const CohesiveCoefficients& c, const CohesiveOptions& opt, const BoxView& box,
                           const Particles& p, const NeighborList& list, const ContactHistory& history,
                           const int* select, double volume, bool kinetic = true, bool across_ranks = false);

}  // namespace debris
