#include "scenarios/amorphous/amorphous_keys.hpp"

#include "scenarios/amorphous/amorphous_input.hpp"
#include "scenarios/common/dem/cohesive_material_input.hpp"

namespace debris {

const KeyReference& amorphous_keys() {
  static const KeyReference ref = [] {
    KeyReference r("debris_amorphous");
    const AmorphousConfig d;  // what the reader starts from
    document_cohesive_material(r, "material", cohesive_material_presets(), true, "optional: the preset table4");

    r.key("sample").is(KeyKind::section).means("the sample of paper A section 3.2: sizes, box, insertion");
    r.key("sample.d0")
        .is(KeyKind::quantity)
        .in(units::dimensionless)
        .allowed("> 0; d0 >= d_min / d_c")
        .means("mode d0 of the diameters, in units of d_c (sweep.d0 replaces it)")
        .eq("A eqs 18-19");
    document_amorphous_sample(r, "sample", d.base);
    document_amorphous_relaxation(r, "relaxation", d.base);

    r.key("sweep").is(KeyKind::section).fallback_is("optional: one sample").means("one sample per pair of a d0 and an s (paper A Fig 7)");
    r.key("sweep.d0")
        .is(KeyKind::numbers)
        .in(units::dimensionless)
        .fallback_is("[sample.d0]")
        .allowed("at least one; each as sample.d0")
        .means("the mode diameters d0 of the samples, in units of d_c; run in increasing order")
        .eq("A eq 18");
    r.key("sweep.scaling")
        .is(KeyKind::numbers)
        .in(units::dimensionless)
        .fallback_is("[material.scaling]")
        .allowed("at least one; each in [0, 1]")
        .means("the coarse-graining exponents s of the samples, each swept over every d0")
        .eq("A eqs 10, 20");

    r.key("output").is(KeyKind::section).fallback_is("optional").means("where and what to write");
    r.key("output.directory")
        .is(KeyKind::text)
        .fallback(d.directory)
        .means("the output directory (created; -o replaces it)");
    r.key("output.thermo_every")
        .is(KeyKind::integer)
        .fallback(std::to_string(d.thermo_every))
        .allowed(">= 1")
        .means("steps between progress lines and rows of relax_<tag>.csv");
    r.key("output.save_samples")
        .is(KeyKind::boolean)
        .fallback(d.save_samples ? "true" : "false")
        .means("write each sample as samples/<tag>.data and samples/<tag>.h5");
    r.key("output.plot")
        .is(KeyKind::boolean)
        .fallback(d.plot ? "true" : "false")
        .means("draw volume_fraction_vs_d0.png with gnuplot (when installed)");

    r.key("run").is(KeyKind::section).fallback_is("optional").means("how to run");
    r.key("run.threads")
        .is(KeyKind::integer)
        .fallback(std::to_string(d.threads))
        .allowed(">= 0")
        .means("host threads; 0: OMP_NUM_THREADS, else tuned while stepping (--threads replaces it)");
    return r;
  }();
  return ref;
}

const ColumnTable& amorphous_relax_table() {
  static const ColumnTable t{
      "relax_<tag>.csv",
      "The relaxation of one sample (`<tag>` = `d0_<d0>_s_<s>`): a row at the start of each phase, every "
      "`output.thermo_every` steps, at the end of phase 1 and when phase 2 ends. SI, or the input's own units "
      "when it gives none.",
      {
          {"phase", "-", "1 (repulsion only, fixed box) or 2 (adhesion, moving box)", ""},
          {"step", "-", "step within the phase", ""},
          {"max_stress_over_E", "-",
           "largest |component| of the stress at rest over E: all six in phase 1 (and in phase 2 with "
           "include_shear), the three normal ones in phase 2",
           ""},
          {"sxx_over_E", "-", "xx component of the average virial stress at rest (tension positive) over E", ""},
          {"syy_over_E", "-", "yy component over E", ""},
          {"szz_over_E", "-", "zz component over E", ""},
          {"sxy_over_E", "-", "xy component over E", ""},
          {"sxz_over_E", "-", "xz component over E", ""},
          {"syz_over_E", "-", "yz component over E", ""},
          {"Lx", "m", "box length along x", ""},
          {"Ly", "m", "box length along y", ""},
          {"Lz", "m", "box length along z", ""},
          {"volume_fraction", "-", "the spheres' volumes summed over the box volume", ""},
          {"kinetic_energy", "J", "translational plus rotational kinetic energy of all particles", ""},
          {"max_overlap_over_d_s", "-", "deepest interpenetration of a pair over the smallest diameter d_s", ""},
      }};
  return t;
}

const ColumnTable& amorphous_summary_table() {
  static const ColumnTable t{
      "summary.csv",
      "One row per sample, written when it is made, in the order run (s outer, d0 inner). SI, or the input's "
      "own units when it gives none.",
      {
          {"d0_over_dc", "-", "mode diameter d0 over d_c", ""},
          {"scaling", "-", "coarse-graining exponent s", ""},
          {"d0", "m", "mode diameter d0", ""},
          {"particles", "-", "number of particles", ""},
          {"volume_fraction_inserted", "-", "volume fraction after insertion", ""},
          {"volume_fraction_relaxed", "-", "volume fraction of the relaxed box (paper A Fig 7)", ""},
          {"phase1_steps", "-", "steps of phase 1", ""},
          {"phase2_steps", "-", "steps of phase 2 until the stress fell below the threshold", ""},
          {"phase1_max_overlap_over_d_s", "-", "deepest interpenetration left by phase 1, over d_s", ""},
          {"sxx_over_E", "-", "final xx stress at rest over E", ""},
          {"syy_over_E", "-", "final yy stress over E", ""},
          {"szz_over_E", "-", "final zz stress over E", ""},
          {"sxy_over_E", "-", "final xy stress over E (not relaxed by the orthogonal box)", ""},
          {"sxz_over_E", "-", "final xz stress over E", ""},
          {"syz_over_E", "-", "final yz stress over E", ""},
          {"max_stress_over_E", "-", "largest final component counted by the criterion, over E", ""},
          {"box_strain_x", "-", "relaxed over inserted box length along x, minus 1", ""},
          {"box_strain_y", "-", "the same along y", ""},
          {"box_strain_z", "-", "the same along z", ""},
          {"mass_scale", "-", "factor applied to every mass so that the total mass over the box volume is rho", ""},
          {"dt", "s", "time step of the relaxation", ""},
          {"wall_seconds", "s", "wall-clock time to make the sample", ""},
      }};
  return t;
}

std::vector<ColumnTable> amorphous_output_columns() { return {amorphous_relax_table(), amorphous_summary_table()}; }

}  // namespace debris
