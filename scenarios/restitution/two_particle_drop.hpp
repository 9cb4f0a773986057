#pragma once
// The two-particle restitution test of paper B, section 4.1 (Fig 5, eq 37): a bottom grain held fixed and
// a top grain dropped from a gap H0 under gravity g; C_R = sqrt(H1 / H0), H1 the largest gap after the
// first contact.
//
// Shortcut, exact for the quantity measured: before the contact the top grain is in free fall, which moves
// every node alike (uniform gravity leaves a grain undeformed), so it starts at a small gap H_s with the
// speed it would have after falling H0 - H_s; after the contact it is free again, and its centre of mass
// then rises ballistically, so H1 = H + v^2 / (2 g) from the gap H and the centre's upward speed v at any
// step after the last node pair has separated. This cuts the 0.04 s of the paper to the contact itself
// (about 1/100 of the steps) without changing what is measured; `full_drop` runs the paper's whole fall and
// rise instead, to check that claim.
//
// Which grain is which: the paper's (R_1, R_2) and (material 1, material 2) are taken as (bottom, top), the
// order of the particle list in the authors' decks (particle 0, fixed, is the bottom one).
#include <string>

#include "kernels/peridem/pd_contact.hpp"
#include "kernels/peridem/pd_material.hpp"

namespace debris {

struct TwoParticleDrop {
  PdMaterial bottom_material, top_material;
  double bottom_radius = 1e-3, top_radius = 1e-3;  // m
  double mesh_size = 2e-4;          // Gmsh characteristic length of the circle meshes (paper: h = 0.1423 mm)
  double drop_height = 1e-3;        // H0 (m)
  double initial_speed = 0.0;       // v0 (m/s), downwards at H0 (the fracture runs of section 4.1)
  double gravity = 10.0;            // g (m/s^2), downwards (-y)
  double restitution = 1.0;         // epsilon-bar_n of eqs 23/28
  double damping_factor = 100.0;    // C-bar
  double contact_radius_factor = 0.95;
  double damping_onset_factor = 1.0;   // centre damping acts from dist < factor R_c (authors' code: 1.01)
  PdDamping damping = PdDamping::grain_centres;
  double time_step = 2e-7;          // s
  bool allow_unstable_time_step = false;  // run above PeridemSimulation::stable_time_step()
  double start_gap = 2e-4;          // H_s (m): where the shortened run starts (capped at H0)
  bool full_drop = false;           // run the whole fall from H0 at rest and the whole rise
  long max_steps = 5000000;         // error when the rebound is not over by then
  std::string mesh_directory;       // where Gmsh's meshes are cached
  // Gmsh MSH files to use instead of meshing the circles here (e.g. the meshes the authors' code ran on);
  // empty: mesh at mesh_size. A file's mesh is taken about its origin, R_ref = its largest node distance
  // from the origin, and scaled to the grain's radius.
  std::string bottom_mesh_file, top_mesh_file;
  // Where the centre damping (eqs 26-30) takes each grain's centre and velocity: the volume-weighted means
  // of its nodes (false, debris's default) or its centre node, the node nearest the grain's centroid at
  // set-up (true, what the authors' code does: BaseParticle::getXCenter / getVCenter).
  bool damping_centre_node = false;
};

struct TwoParticleDropResult {
  double restitution_coefficient = 0;  // C_R of eq 37
  double rebound_height = 0;           // H1 (m)
  double contact_time = 0;             // s, from the first to the last touching node pair
  long steps = 0;
  long broken_bonds = 0;
  double max_damage = 0;               // Z of eq 14, both grains, largest over the run
  double bottom_max_damage = 0, top_max_damage = 0;  // the same per grain, over the contact
  long nodes = 0;
  double mesh_h = 0;                   // h of eq 35 (m): the smallest node spacing of the meshes
  double wall_seconds = 0;
};

/// Runs the test; InputError for bad parameters (naming them) and when the rebound has not finished within
/// max_steps. `threads` 0 keeps the current setting.
TwoParticleDropResult run_two_particle_drop(const TwoParticleDrop& spec);

}  // namespace debris
