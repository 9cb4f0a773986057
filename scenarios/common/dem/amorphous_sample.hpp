#pragma once
// Amorphous samples of the cohesive DEM (Pham-Ba & Molinari, section 3.2), made the way the paper makes
// them:
//
//   1. diameters from a log-normal of mode d0 and sd 0.2 (d_l - d_s), truncated to [d_s, d_l]
//      (scenarios/common/dem/truncated_lognormal.hpp), centres uniformly at random in a periodic L x L x W box, until
//      the spheres' volumes add up to the volume fraction 0.75;
//   2. relaxation phase 1: repulsive normal force only, global damping c = c_c (eq 21), 3000 steps of
//      0.1 dt_c (eq 6), fixed periodic box;
//   3. phase 2: adhesive normal force (eq 3), no tangential force, damping 0.02 c_c, the periodic box moving
//      to relieve the average virial stress until every component is below 1e-14 E;
//   4. masses rescaled so that total mass / box volume = rho.
//
// Insertion ignores overlaps. The paper inserts "at random positions until they fill it up to a given
// volume fraction of 0.75" and lets phase 1 reach "a state with no completely overlapped particles", so
// the inserted spheres do overlap (random sequential addition without overlaps jams near 0.38, far below
// 0.75). Debris draws centres and diameters from one seeded stream and keeps the last sphere when that
// brings the sum of volumes closer to the target than stopping before it.
//
// The box rule of phase 2 (a per-axis Berendsen barostat towards zero stress, with the paper's tension-
// positive virial stress sigma): every `check_every` = n steps each box length is scaled by
//
//     1 + eps_a,   eps_a = -(n dt / tau) sigma_aa / E,   |eps_a| <= max_box_strain
//
// and the particle centres follow affinely (Box::deform). Why this rule: a sample in tension
// (sigma_aa > 0) wants to contract, so the box shrinks, and one in compression grows. The work the box
// does on the sample per update, V sigma_aa eps_a = -V (n dt / tau) sigma_aa^2 / E, is never positive,
// so the box only ever takes energy out: it cannot drive the sample unstable. Its discrete gain, the
// stress removed per update relative to the stress present, is (n dt / tau) C / E for an affine stiffness
// C of order E, below the limit 2 of a discrete first-order loop for tau = one crossing time of a
// pressure wave, L_max / sqrt(E / rho): 46 steps for the 5 d0 test sample (gain 0.22 C / E), 230 for the
// default 25 d0, 920 for the paper's 100 d0. The box then follows the internal relaxation instead of
// ringing. On a 545-particle sample, tau = 0.3, 3 and 10 crossing times gave relaxed volume fractions
// within 0.5% of tau = 1 (0.852), tau = 10 taking 2.5 times the steps. The cap keeps the first updates, when the
// inserted packing still pushes hard, from moving the walls by more than a small strain at a time.
//
// Which stress: the average virial stress of the sample as it would be at rest (stress_at_rest()), the pair
// forces without their damping part and no kinetic part, that is the stress the saved sample, whose
// velocities are zeroed, starts with. The stress with the run's velocities (kinetic part and pair
// dampings) differed from it by up to 3.5e-15 E when a 118-particle sample crossed 1e-14 E, and by 4e-17 E
// for the 3,372 particles of the default input.
//
// Which components the criterion counts: the box stays orthogonal (core/box.hpp has no tilt), so it only
// drives sigma_xx, sigma_yy and sigma_zz. The shear stresses are frozen in when the adhesive network forms
// and do not relax inside a periodic orthogonal cell: measured at about 5e-3 E in a 545-particle sample
// (d0 = 0.6 d_c), unchanged from step 2,000 to step 60,000 of phase 2 while the diagonal fell to 3e-16 E.
// So the criterion counts the diagonal by default (include_shear = false) and the shear stresses left are
// reported; include_shear = true asks for all six and then ends at the step limit with that message.
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>

#include "core/box.hpp"
#include "core/error.hpp"
#include "core/particles.hpp"
#include "kernels/dem/cohesive_material.hpp"
#include "kernels/dem/virial_stress.hpp"

namespace debris {

class DemSimulation;
class InputNode;
class KeyReference;

struct AmorphousSpec {
  CohesiveMaterial material = table4_material();

  // The sample. Lengths in the units the paper states them in.
  double d0 = 1.0;         // mode of the diameters, in units of d_c (eq 18)
  double d_s = 0.75;       // smallest diameter, in units of d0
  double d_l = 1.25;       // largest diameter, in units of d0 (unused when d_l_fixed > 0)
  double d_l_fixed = 0.0;  // > 0: largest diameter in units of d_c, the same for every d0 (sections 3.3, A.4)
  double length = 30.0;    // L: box x and y, in d0 (paper: 100)
  double width = 4.0;      // W: box z, in d0 (paper: 3; see min_periodic_length())
  // A general box [Lx, Ly, Lz] instead of L x L x W (section 4's 60 x 40 x 40 nm): all zero = unused;
  // in d0, or in metres when box_absolute (an input's lengths with units: the same box for every d0).
  Vec3 box{0, 0, 0};
  bool box_absolute = false;
  double volume_fraction = 0.75;
  std::uint64_t seed = 1;

  // Relaxation.
  double time_step_fraction = 0.1;  // of dt_c (eq 6), both phases
  long phase1_steps = 3000;
  double phase1_damping = 1.0;  // fraction of c_c (eq 21)
  double phase2_damping = 0.02;
  double stress_threshold = 1e-14;  // in units of E, for every component of the average virial stress
  bool include_shear = false;       // true: the shear stresses too (an orthogonal box cannot relax them)
  long phase2_max_steps = 200000;
  long check_every = 10;             // steps between stress measurements and box updates
  double box_relaxation_time = 1.0;  // tau, in crossing times L_max / sqrt(E / rho)
  double max_box_strain = 1e-3;      // cap on |eps_a| per update
  // > 0: phase 2 stops with SampleCollapse when the box would shrink until the spheres' volume over the
  // box's passes this (a pair law whose attraction outreaches the packing pulls it together without end).
  // 1: spheres filling more than their box are no sample (without the stop, such a packing relaxed to 1.04
  // or shrank the box to the neighbour list's limit). 0: no such stop. Not part of the recipe's key: a
  // sample it lets through is the same sample.
  double collapse_fraction = 1.0;

  /// Throws InputError naming "sample.<key>" or "relaxation.<key>" (the input file's keys) for the first
  /// bad value: d0 below d_min (eq 19), a size distribution that is not d_s < 1 < d_l, a volume fraction
  /// outside (0, 1), a box too small for the engine's neighbour list or for one particle, ...
  void validate() const;

  // Absolute values (the material's units).
  double d0_absolute() const;
  double d_s_absolute() const;
  double d_l_absolute() const;
  Vec3 box_length() const;
  /// The Verlet skin the relaxation uses: 10% of the smallest possible diameter (the engine's default
  /// 20% of the smallest radius, fixed in advance so that the box limit below is known before drawing).
  double skin() const;
  /// The shortest periodic length the engine accepts: 2 (cutoff of two d_l particles + skin). Debris's
  /// neighbour list, unlike LAMMPS with its ghost images, needs it; for s = 0 the cutoff is at least
  /// 1.5 d0 (d_l = 1.25 d0), so the paper's W = 3 d0 is always too thin here and debris's samples are
  /// thicker (scenarios/amorphous/README.md).
  double min_periodic_length() const;
};

/// Spheres inserted at random (overlaps allowed): box at the origin, periodic on every axis, ids 1..N,
/// type 1, at rest, masses from the material's density.
struct InsertedSpheres {
  Box box;
  Particles particles;
  double volume_fraction = 0;  // sum of sphere volumes / box volume
};
InsertedSpheres insert_random_spheres(const AmorphousSpec& spec);

/// Reads the sample keys the input files share (debris_amorphous, and debris_patch's `kind: amorphous`):
/// d_s, d_l, d_l_fixed, length, width, box, volume_fraction, seed of `sample` (not d0, which may be a
/// sweep), into `spec`, keeping its values for absent keys. `box: [Lx, Ly, Lz]` is plain numbers (in d0) or
/// three lengths with units ("60 nm"). InputError for d_l given together with d_l_fixed, or box together
/// with length or width.
void read_amorphous_sample_keys(const InputNode& sample, AmorphousSpec& spec);
/// Reads the `relaxation` section (time_step_fraction, phase1.{steps, damping}, phase2.{damping,
/// stress_threshold, include_shear, max_steps, check_every, box_relaxation_time, max_box_strain}).
void read_amorphous_relaxation_keys(const InputNode& relaxation, AmorphousSpec& spec);

/// Describes the keys read_amorphous_sample_keys() reads under `section` ("sample"), with `defaults`' values
/// (the spec the caller's reader starts from) as their defaults. Neither the section itself nor d0, which
/// each caller reads its own way (a value, a sweep, a length), is described here.
void document_amorphous_sample(KeyReference& ref, const std::string& section, const AmorphousSpec& defaults);
/// Describes `section` ("relaxation") and the keys read_amorphous_relaxation_keys() reads under it.
void document_amorphous_relaxation(KeyReference& ref, const std::string& section, const AmorphousSpec& defaults);

/// Every value the recipe depends on, as text (doubles to 17 digits): two specs with the same key make the
/// same sample bit for bit on the same build, so the key can tell a cached sample file from a stale one.
std::string amorphous_spec_key(const AmorphousSpec& spec);

/// One progress report (the thermo-like line of debris_amorphous).
struct AmorphousProgress {
  int phase = 0;          // 1 or 2
  long step = 0;          // step within the phase
  StressTensor stress;    // average virial stress, kinetic part included (absolute units)
  double max_stress = 0;  // largest |component| counted by the criterion, in units of E
  Vec3 box_length;
  double volume_fraction = 0;
  double kinetic_energy = 0;
  double max_overlap = 0;  // deepest interpenetration over the smallest diameter d_s
};
using AmorphousObserver = std::function<void(const AmorphousProgress&)>;

/// The result: the relaxed, density-matched sample and what the relaxation did.
struct AmorphousSample {
  Box box;
  Particles particles;  // sorted by id, wrapped, image flags 0, at rest, masses rescaled
  double inserted_fraction = 0;
  double relaxed_fraction = 0;  // sum of sphere volumes / relaxed box volume
  long phase1_steps = 0, phase2_steps = 0;
  double phase1_max_overlap = 0;  // deepest interpenetration after phase 1, over d_s
  StressTensor final_stress;      // stress_at_rest() at the end of phase 2 (absolute units)
  double final_max_stress = 0;    // in units of E, as the criterion counts it
  Vec3 initial_box_length, final_box_length;
  double mass_scale = 0;    // factor applied to every mass (and inertia)
  double dt = 0, dt_c = 0;  // time step of the relaxation and eq 6 for its smallest particle
  double phase1_seconds = 0, phase2_seconds = 0;
};

/// Average virial stress of all particles over the box volume, with every velocity taken as zero (no
/// kinetic part, no pair damping): the elastic stress of the current positions. The velocities are restored.
StressTensor stress_at_rest(DemSimulation& sim);

/// Phase 1 on a simulation built from inserted spheres: switches its options and damping, runs.
/// Returns the deepest overlap left, over d_s.
double relax_phase1(DemSimulation& sim, const AmorphousSpec& spec, const AmorphousObserver& observer = {},
                    long report_every = 0);

/// Phase 2 pulled the box in past AmorphousSpec::collapse_fraction: the inputs make no sample (a property of
/// the pair law and the recipe, not of the input's keys).
struct SampleCollapse : std::runtime_error {
  SampleCollapse(const std::string& what, long step, double fraction)
      : std::runtime_error(what), step(step), volume_fraction(fraction) {}
  long step;
  double volume_fraction;
};

/// Phase 2 did not bring the stresses below the threshold within phase2_max_steps. An InputError naming
/// relaxation.phase2.max_steps (with the stress reached) where the user chose the material; a caller that
/// chose it itself (the calibration) catches it to say which of its inputs the sample did not relax with.
struct RelaxationStalled : InputError {
  RelaxationStalled(const std::string& what, long steps, double max_stress, double best_stress, long best_step)
      : InputError(what), steps(steps), max_stress(max_stress), best_stress(best_stress), best_step(best_step) {}
  long steps;          // phase 2 steps run (the limit)
  double max_stress;   // the largest component counted at the end, in units of E
  double best_stress;  // the smallest such value on the way, and the step it was met at
  long best_step;
};

/// Phase 2: runs with the moving box until the criterion holds. Returns the steps taken. Throws
/// RelaxationStalled when it does not hold within the limit, InputError naming
/// sample.length / sample.width when the box would shrink below min_periodic_length(); SampleCollapse past
/// spec.collapse_fraction (checked first); std::runtime_error if the state turns non-finite.
long relax_phase2(DemSimulation& sim, const AmorphousSpec& spec, const AmorphousObserver& observer = {},
                  long report_every = 0, StressTensor* final_stress = nullptr);

/// Scales every mass and inertia so that the total mass over the box volume equals `density`; returns
/// the factor.
double rescale_masses_to_density(Particles& p, const Box& box, double density);

/// Largest |component| of `s` over E: all six, or only the diagonal.
double max_stress_component(const StressTensor& s, double youngs_modulus, bool with_shear);

/// The whole recipe: validate, insert, phase 1, phase 2, rescale masses.
AmorphousSample make_amorphous_sample(const AmorphousSpec& spec, const AmorphousObserver& observer = {},
                                      long report_every = 0);

/// Writes `stem`.data (LAMMPS, atom_style sphere; read it with read_lammps_data and masses from the file)
/// and `stem`.h5 (ids, positions, radii, masses, box, relaxed volume fraction, relaxation record, the
/// spec's values and `input_echo`, the input file's text).
void write_amorphous_sample(const std::string& stem, const AmorphousSample& sample, const AmorphousSpec& spec,
                            const std::string& input_echo);

/// What a later scenario needs back from `stem`.h5.
struct AmorphousSampleFile {
  Box box;
  Particles particles;  // ids, positions, radii, masses, inertia (2/5 m r^2), type 1, at rest
  double relaxed_fraction = 0;
  double d0 = 0;  // absolute mode diameter
  CohesiveMaterial material;
  std::string input_echo;
};
AmorphousSampleFile read_amorphous_sample(const std::string& h5_path);

}  // namespace debris
