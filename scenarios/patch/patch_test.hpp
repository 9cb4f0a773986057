#pragma once
// Patch tests of the cohesive DEM (Pham-Ba & Molinari, section 3 and Fig 4): a sample periodic in x and z
// between two rigid walls made of its own particles, the bottom wall frozen and the top one driven.
//
//   elastic   confined uniaxial compression: a stress on the top wall (force-driven rigid group), run to
//             equilibrium; C11 = sigma_yy / eps_yy and C12 = sigma_xx / eps_yy (eps_xx = eps_zz = 0), and E,
//             nu from them by the isotropic relations (isotropic_from_stiffness).
//   tension   the top wall moved along +y at a constant strain rate; strength = peak sigma_yy.
//   shear     the top wall moved along +x at a constant strain rate; strength = peak sigma_xy.
//
// Stresses are the average virial stress (kernels/dem/virial_stress.hpp, pair + kinetic) of a set of free
// particles over the volume those particles own: their number times the sample's volume per particle,
// stretched with eps_yy (Cauchy stress; exact for a lattice, whose sites all own a^3 / sqrt 2). Strength
// tests use the whole deformable part and the wall displacement over the height between the innermost wall
// particle centres. The elastic test measures the bulk (free particles away from the walls, strain fitted
// to their displacements) and reports the wall-based measure beside it (see ElasticResult for why).
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/box.hpp"
#include "core/groups.hpp"
#include "core/particles.hpp"
#include "kernels/dem/cohesive_material.hpp"
#include "kernels/dem/virial_stress.hpp"

namespace debris {

/// A patch test that could not produce its result (no equilibrium within the step limit, a sample that
/// gave way under the elastic load, a blown-up state). The message names the setting that limited it.
class PatchRunError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class PatchTest { elastic, tension, shear };
const char* patch_test_name(PatchTest t);

/// A sample ready for a patch test: particles (ids 1..N), a box periodic in x and z only, and two groups,
/// "bottom" (frozen) and "top" (frozen here; each test sets its motion).
struct PatchSample {
  Box box;
  Particles particles;
  Groups groups;
  int bottom = -1, top = -1;        // group indices
  double d0 = 0;                    // mean diameter
  double area = 0;                  // box length x times z: the walls' area
  double strain_height = 0;         // inner_top - inner_bottom
  double volume_per_particle = 0;   // of the sample the particles came from (box volume / N)
  double inner_bottom = 0;          // highest bottom-wall centre (reference state)
  double inner_top = 0;             // lowest top-wall centre
  long free_count = 0;              // particles of the deformable part
  double volume_fraction = 0;       // sum of sphere volumes / box volume of the periodic sample it came from
  bool masses_from_density = true;  // false: keep the given masses (a relaxed sample rescaled to the density)
  std::string description;          // what it is, in words (orientation, size, where it came from)
};

/// An HCP lattice of touching spheres (spacing = diameter = d0), L x L x W in units of d0 (x, y, z), with
/// walls of `wall_thickness` d0 cut from its bottom and top along y.
///
/// c_axis: the stacking axis. 1 (y): c along the load, close-packed planes parallel to the walls.
/// 2 (z): load in the close-packed plane, along its a sqrt 3 direction (the orientation of LAMMPS'
/// `lattice hcp`, c along z). 0 (x): load in the close-packed plane, along the close-packed rows (period a).
struct HcpSampleSpec {
  double d0 = 0;  // absolute diameter (material length units)
  int c_axis = 1;
  double length = 25;           // L / d0, along x and y
  double thickness = 3;         // W / d0, along z
  double wall_thickness = 1.5;  // / d0, each wall
};

/// Lattice periods are whole numbers of cells as close as possible to L and W, never shorter along a periodic
/// axis than the neighbour list needs (2 (cutoff + skin), the description says when W or L was raised).
/// InputError (key "sample.d0") for d0 below d_min (eq 19), "sample.length" / "sample.thickness" /
/// "sample.wall_thickness" for sizes that leave no deformable part.
PatchSample make_hcp_sample(const HcpSampleSpec& spec, const CohesiveMaterial& material);

/// The same patch geometry cut from a sample that is periodic in x, y and z (an amorphous packing read from
/// a LAMMPS data file): particles wrapped into `box`, those within `wall_thickness` mean diameters of the
/// bottom and top of the box along y become the walls, and the y axis stops being periodic. Masses are
/// kept as given. InputError (key `key`) for a box not periodic on all axes, diameters below d_min, or
/// walls that leave no deformable part.
PatchSample make_walled_sample(const Box& box, Particles particles, double wall_thickness,
                               const CohesiveMaterial& material, const std::string& key,
                               const std::string& description);

/// "c axis along the load (y)", "load in the close-packed plane (c axis along z)", ...
std::string hcp_orientation_name(int c_axis);

// ---------------------------------------------------------------------------------------------------------

/// E and nu of an isotropic solid from its confined (uniaxial-strain) moduli:
///   C11 = E (1 - nu) / ((1 + nu)(1 - 2 nu)),  C12 = E nu / ((1 + nu)(1 - 2 nu))
///   => nu = C12 / (C11 + C12),  E = (C11 - C12)(C11 + 2 C12) / (C11 + C12).
struct IsotropicModuli {
  double E, nu;
};
IsotropicModuli isotropic_from_stiffness(double c11, double c12);

/// Target strength of a sample of mean diameter d0 (eq 20): sigma_{m,N} (d0 / d_c)^-s for tension and
/// sigma_{m,T} (d0 / d_c)^-s for shear when d0 > d_c (the paper plots the shear target with the same
/// scaling, Fig 6), the plain strengths below d_c. Elastic: 0.
double target_strength(const CohesiveMaterial& m, PatchTest test, double d0);

/// Called every few seconds of a run with (step, step limit), to print progress.
using PatchProgress = std::function<void(long step, long limit, std::size_t particles)>;

struct ElasticSettings {
  double stress = 0.01;             // compressive stress on the top wall (section 3)
  double time_step_fraction = 0.1;  // of dt_c, eq 6
  double damping = 0.2;             // global damping, fraction of c_c (eq 21)
  long sample_every = 50;           // steps between measurements
  // Stopping rule: over the last `window` steps, the spread (max - min) of each measured strain is below
  // `tolerance` times its value, and the spread of sigma_xx, sigma_yy, sigma_zz below `tolerance` times the
  // applied stress. window = 0 picks 5 time constants of the slowest mode of the overdamped column,
  // tau = 2 f_c (H / d0)^2 / (pi^2 f_t) steps (f_c = damping, f_t = time_step_fraction; for an HCP column
  // at nu = 0 the longitudinal wave crosses d0 in dt_c / 2), at least 500 steps.
  long window = 0;
  double tolerance = 1e-4;
  long max_steps = 200000;       // PatchRunError naming "elastic.max_steps" if the rule is not met by then
  double max_strain = 0.05;      // PatchRunError when |eps_yy| exceeds it: the sample gave way
  double interior_margin = 1.5;  // / d0: free particles this close to a wall are left out of the fit
  // The health check stops the run when an overlap exceeds overlap_limit times the smallest radius of the
  // sample. 0 (automatic): the deepest overlap the sample starts with plus kOverlapAllowanceElastic (see
  // patch_overlap_limit).
  double overlap_limit = 0;
};

/// How much deeper than at the start an overlap may become (in smallest radii) before the health check of
/// a patch test calls the run exploding, when the overlap limit is automatic. A lattice starts with none,
/// so its limits are these: half a radius, the engine's default (elastic), and a whole radius (strength
/// tests, see check_health in patch_test.cpp). A relaxed amorphous sample starts pre-stressed with overlaps
/// up to 1.2 smallest radii (scenarios/patch/RESULTS.md), which are its equilibrium, not an explosion.
inline constexpr double kOverlapAllowanceElastic = 0.5;
inline constexpr double kOverlapAllowanceStrength = 1.0;

/// The overlap limit (in smallest radii) a test uses: `setting` when > 0, else the sample's deepest initial
/// overlap over its smallest radius plus `allowance`.
double patch_overlap_limit(double setting, double initial_overlap_over_r_min, double allowance);

struct ElasticResult {
  double applied = 0;  // sigma_yy the wall imposes (negative: compression)
  // The bulk: free particles at least interior_margin d0 from both walls. Strain = least-squares slope of
  // their displacement u_y against their reference height; stress = their virial over the volume they own.
  // A rigid wall that two rows of the lattice touch (every orientation but c along y) forces a non-affine
  // layer next to it, so the wall displacement over H is off the bulk strain by a fraction of a row spacing
  // over H (1% at L = 25 d0, more in small samples); the bulk measure is free of it.
  double eps = 0;
  StressTensor sigma;
  double c11 = 0, c12 = 0, c13 = 0;  // sigma_yy / eps, sigma_xx / eps (the paper's C12), sigma_zz / eps
  IsotropicModuli moduli{};          // from c11, c12
  // The whole deformable part and the walls, as section 3 describes it: strain = top-wall displacement /
  // strain_height, stress = virial of every free particle.
  double eps_walls = 0;
  StressTensor sigma_part;
  double c11_walls = 0, c12_walls = 0;
  IsotropicModuli moduli_walls{};
  // The stresses of the same particle sets before the load (the frozen-in stress of a relaxed amorphous
  // sample; zero for a lattice). The moduli use the stress changes sigma - sigma0.
  StressTensor sigma0, sigma_part0;
  long interior_count = 0;
  double initial_overlap = 0;  // deepest overlap at the start, over the smallest radius
  double overlap_limit = 0;    // the health check's limit used, in smallest radii
  double dt = 0;
  long steps = 0, window = 0;
  double wall_seconds = 0;
};

/// Throws InputError naming "elastic.<key>" for the first setting out of range.
void validate(const ElasticSettings& settings);
/// Also checks that the sample has an interior (free particles interior_margin d0 from both walls).
void validate(const ElasticSettings& settings, const PatchSample& sample);

ElasticResult run_elastic_test(const PatchSample& sample, const CohesiveMaterial& material,
                               const ElasticSettings& settings, const PatchProgress& progress = {});

struct StrengthSettings {
  double strain_rate = 1e-5;  // per time step (section 3)
  double time_step_fraction = 0.1;
  double damping = 0.01;   // fraction of c_c
  long sample_every = 20;  // steps between points of the stress-strain curve
  // Stopping rule. The sample broke once its stress has stayed below fall_fraction of the peak over
  // fall_strain more strain (staying below over a strain interval tells a failure from the dips of the
  // start-up stress wave, which last about two wave crossings of the sample, ~0.002 strain for 25 d0). A
  // lattice may instead yield, slipping and re-bonding with its stress on a sawtooth below the peak: the
  // run stops when the peak has stood for hold_strain more strain. Otherwise it stops at max_strain.
  double fall_fraction = 0.5;
  double fall_strain = 0.02;
  double hold_strain = 0.1;
  double max_strain = 0.8;
  // Shear: the top wall keeps its height (fixed_height = true, the default), or moves along x at the same
  // rate while free along y under a constant compressive normal stress (0: free to open or close).
  bool shear_fixed_height = true;
  double shear_normal_stress = 0;
  // Health check limit in smallest radii; 0: the sample's deepest initial overlap + kOverlapAllowanceStrength.
  double overlap_limit = 0;
};

/// How a strength test ended: broke (stress fell below fall_fraction of the peak and stayed there), peak
/// held (the peak stood for hold_strain without a fracture: yield and plastic flow), or max strain (the
/// stress was still rising: the reported strength is a lower bound).
enum class StrengthOutcome { broke, peak_held, max_strain };
const char* strength_outcome_name(StrengthOutcome o);

struct StressStrainPoint {
  long step;
  double strain;  // wall displacement / strain_height (tension: along y, shear: along x)
  double eps_yy;  // top-wall displacement along y / strain_height (tension: = strain)
  StressTensor stress;
  double kinetic_energy;  // of the deformable part
};

struct StrengthResult {
  double strength = 0;  // peak sigma_yy (tension) or sigma_xy (shear)
  double strain_at_peak = 0;
  StrengthOutcome outcome = StrengthOutcome::max_strain;
  double final_over_peak = 0;  // stress at the stop / peak
  std::vector<StressStrainPoint> curve;
  double initial_overlap = 0;  // deepest overlap at the start, over the smallest radius
  double overlap_limit = 0;    // the health check's limit used, in smallest radii
  double dt = 0;
  long steps = 0;
  double wall_seconds = 0;
};

/// Throws InputError naming "strength.<key>" for the first setting out of range.
void validate(const StrengthSettings& settings);

StrengthResult run_strength_test(const PatchSample& sample, const CohesiveMaterial& material, PatchTest test,
                                 const StrengthSettings& settings, const PatchProgress& progress = {});

}  // namespace debris
