#include "scenarios/patch/patch_keys.hpp"

#include "scenarios/common/dem/amorphous_sample.hpp"
#include "scenarios/common/dem/cohesive_material_input.hpp"
#include "scenarios/patch/patch_test.hpp"

namespace debris {

namespace {

KeyDoc& number(KeyReference& r, const std::string& path, double fallback) {
  return r.key(path).is(KeyKind::quantity).in(units::dimensionless).fallback(shortest_text(fallback));
}

KeyDoc& integer(KeyReference& r, const std::string& path, long fallback) {
  return r.key(path).is(KeyKind::integer).fallback(std::to_string(fallback));
}

void document_elastic(KeyReference& r) {
  const ElasticSettings d;
  r.key("elastic").is(KeyKind::section).fallback_is("optional").means("the elastic test: confined uniaxial compression under a stress on "
                                              "the top wall, run to equilibrium (paper A section 3, Fig 4a)");
  r.key("elastic.stress")
      .is(KeyKind::quantity)
      .in(units::pressure)
      .fallback(shortest_text(d.stress))
      .allowed("> 0")
      .means("compressive stress on the top wall (the paper: 0.01 with E = 1)");
  number(r, "elastic.time_step_fraction", d.time_step_fraction)
      .allowed("> 0")
      .means("time step as a fraction of the critical time step dt_c")
      .eq("A eq 6");
  number(r, "elastic.damping", d.damping)
      .allowed(">= 0")
      .means("global damping as a fraction of the critical damping c_c")
      .eq("A eq 21");
  integer(r, "elastic.sample_every", d.sample_every).allowed(">= 1").means("steps between measurements");
  integer(r, "elastic.window", d.window)
      .allowed(">= 0")
      .means("steps over which strains and stresses must settle; 0: five time constants of the column's slowest "
             "mode, at least 500");
  number(r, "elastic.tolerance", d.tolerance)
      .allowed("> 0")
      .means("equilibrium: over the window, each strain's spread below this times its value and each normal "
             "stress's below this times the applied stress");
  integer(r, "elastic.max_steps", d.max_steps)
      .allowed(">= 1")
      .means("most steps; a case not at equilibrium by then fails with a message naming this key");
  number(r, "elastic.max_strain", d.max_strain)
      .allowed("> 0")
      .means("a case whose |eps_yy| passes this fails: the sample gave way");
  number(r, "elastic.interior_margin", d.interior_margin)
      .allowed(">= 0")
      .means("free particles closer than this many d0 to a wall are left out of the bulk measure");
  r.key("elastic.overlap_limit")
      .is(KeyKind::quantity)
      .in(units::dimensionless)
      .fallback_is("`auto`")
      .allowed("> 0, or `auto`")
      .means("the health check stops a run whose deepest overlap passes this many smallest radii; auto: the "
             "sample's deepest initial overlap + 0.5");
}

void document_strength(KeyReference& r) {
  const StrengthSettings d;
  r.key("strength").is(KeyKind::section).fallback_is("optional").means("the tension and shear tests: the top wall moved at a constant "
                                               "strain rate until the sample breaks (paper A section 3, Fig 4b-c)");
  number(r, "strength.strain_rate", d.strain_rate).allowed("> 0").means("strain per time step");
  number(r, "strength.time_step_fraction", d.time_step_fraction)
      .allowed("> 0")
      .means("time step as a fraction of the critical time step dt_c")
      .eq("A eq 6");
  number(r, "strength.damping", d.damping)
      .allowed(">= 0")
      .means("global damping as a fraction of the critical damping c_c")
      .eq("A eq 21");
  integer(r, "strength.sample_every", d.sample_every)
      .allowed(">= 1")
      .means("steps between points of the stress-strain curve");
  number(r, "strength.fall_fraction", d.fall_fraction)
      .allowed("(0, 1)")
      .means("broke: the stress stayed below this fraction of the peak over fall_strain more strain");
  number(r, "strength.fall_strain", d.fall_strain)
      .allowed(">= 0")
      .means("strain over which the stress must stay below fall_fraction of the peak");
  number(r, "strength.hold_strain", d.hold_strain)
      .allowed("> 0")
      .means("peak held (yield): the peak stood for this much more strain without a fracture");
  number(r, "strength.max_strain", d.max_strain)
      .allowed("> 0")
      .means("the run stops at this strain (the strength is then a lower bound)");
  r.key("strength.shear_top")
      .one_of({"fixed_height", "normal_stress"})
      .fallback(d.shear_fixed_height ? "fixed_height" : "normal_stress")
      .means("shear: the top wall keeps its height, or is free along y under shear_normal_stress");
  r.key("strength.shear_normal_stress")
      .is(KeyKind::quantity)
      .in(units::pressure)
      .fallback(shortest_text(d.shear_normal_stress))
      .allowed(">= 0")
      .means("shear_top normal_stress: compressive stress on the top wall (0: free to open or close)");
  r.key("strength.overlap_limit")
      .is(KeyKind::quantity)
      .in(units::dimensionless)
      .fallback_is("`auto`")
      .allowed("> 0, or `auto`")
      .means("the health check stops a run whose deepest overlap passes this many smallest radii; auto: the "
             "sample's deepest initial overlap + 1");
}

}  // namespace

const KeyReference& patch_keys() {
  static const KeyReference ref = [] {
    KeyReference r("debris_patch");
    r.key("test")
        .is(KeyKind::list)
        .allowed("`elastic`, `tension`, `shear`, or a list of them")
        .means("the patch test, or a list of them: elastic (C11, C12, E, nu), tension, shear (strengths)")
        .eq("A Fig 4");

    const CohesiveMaterial table4 = table4_material(0.0);
    document_cohesive_material(r, "material", &table4, false, "optional: Table 4");
    r.key("material.poisson_ratio")
        .is(KeyKind::quantity)
        .or_a_list()
        .in(units::dimensionless)
        .fallback(shortest_text(table4.poisson_ratio))
        .allowed("each in (-1, 0.25]")
        .means("Poisson's ratio nu, or a list of them (a sweep); sets the areas A_N and A_T")
        .eq("A eqs 15-16");
    r.key("material.scaling")
        .is(KeyKind::quantity)
        .or_a_list()
        .in(units::dimensionless)
        .fallback("0")
        .allowed("each in [0, 1]")
        .means("coarse-graining exponent s, or a list of them (a sweep): 0 keeps the strength, 0.5 the surface "
               "energy")
        .eq("A eqs 10, 20");

    r.key("sample").is(KeyKind::section).means("the sample the tests run on, walled at its bottom and top along y");
    r.describe_section(
        "sample",
        "kind `hcp` reads d0, c_axis, length, thickness and wall_thickness: its lengths are rounded to whole "
        "lattice periods, x and z raised to what the neighbour list needs. kind `lammps_data` reads lammps_data "
        "and wall_thickness. kind `amorphous` makes each sample by the recipe of paper A section 3.2 (the keys of "
        "debris_amorphous, `relaxation` included) from d0 or discretisation, d_s, d_l or d_l_fixed, length, width "
        "(raised per case to what the neighbour list needs, plus 6%), box, volume_fraction, seed, and keeps it "
        "in cache.");
    r.key("sample.kind")
        .one_of({"hcp", "lammps_data", "amorphous"})
        .fallback("hcp")
        .means("an HCP lattice of touching spheres, periodic samples read from LAMMPS data files, or amorphous "
               "samples made here");
    r.key("sample.wall_thickness")
        .is(KeyKind::quantity)
        .in(units::dimensionless)
        .fallback(shortest_text(HcpSampleSpec{}.wall_thickness))
        .allowed("> 0, leaving particles in each wall and between them")
        .means("thickness of each wall, in d0 (hcp) or mean diameters (lammps_data, amorphous)");
    r.key("sample.d0")
        .is(KeyKind::quantity)
        .or_a_list()
        .in(units::dimensionless)
        .fallback_is("required by hcp, and by amorphous without discretisation")
        .allowed("each > 0 and >= d_min / d_c; not with discretisation")
        .means("hcp: the particle diameter; amorphous: the mode d0; in units of d_c, or a list of them (a sweep)")
        .eq("A eqs 18-19");
    r.key("sample.c_axis")
        .is(KeyKind::list)
        .fallback("y")
        .allowed("`x`, `y`, `z`, or a list of them")
        .means("hcp: the stacking axis; y puts the close-packed planes parallel to the walls, x and z load "
               "along the close-packed rows and along a sqrt 3 in the close-packed plane");
    const HcpSampleSpec hcp;
    AmorphousSpec amorphous;
    amorphous.length = 25;  // as the reader: the lattice tests' L
    amorphous.width = 3;    // the paper's W
    document_amorphous_sample(r, "sample", amorphous);
    r.key("sample.thickness")
        .is(KeyKind::quantity)
        .in(units::dimensionless)
        .fallback(shortest_text(hcp.thickness))
        .allowed("> 0")
        .means("hcp: W, the lattice's length along z, in units of d0");
    r.key("sample.cache")
        .is(KeyKind::text)
        .fallback_is("`<output directory>/samples`")
        .means("amorphous: the directory of the made samples; a sample whose recipe is there already is read "
               "from it instead of made again");
    r.key("sample.discretisation")
        .is(KeyKind::section)
        .fallback_is("optional")
        .means("amorphous: the study of paper A appendix A.4, systems of size L cut into d0 = L / n (instead of d0 "
               "and length, and of d_l_fixed)");
    r.key("sample.discretisation.size")
        .is(KeyKind::quantity)
        .or_a_list()
        .in(units::dimensionless)
        .allowed("each > 0")
        .means("the system sizes L, in units of d_c");
    r.key("sample.discretisation.divisions")
        .is(KeyKind::quantity)
        .or_a_list()
        .in(units::dimensionless)
        .allowed("each >= 1")
        .means("the numbers n of mode diameters across L (d0 = L / n)");
    r.key("sample.discretisation.d_l")
        .is(KeyKind::list)
        .fallback("fixed")
        .allowed("`fixed`, `scaled`, or a list of them")
        .means("fixed: the largest diameter d_l times the coarsest d0, for every n; scaled: d_l times each d0");
    r.key("sample.lammps_data")
        .is(KeyKind::list)
        .fallback_is("required by lammps_data")
        .allowed("existing files")
        .means("lammps_data: a LAMMPS data file periodic on every axis, or a list of them; relative to the input "
               "file's directory");
    document_amorphous_relaxation(r, "relaxation", amorphous);
    r.describe_section("relaxation", "Read by kind amorphous only.");

    document_elastic(r);
    document_strength(r);

    r.key("output").is(KeyKind::section).fallback_is("optional").means("where and what to write");
    r.key("output.directory").is(KeyKind::text).fallback("out/patch").means("the output directory (-o replaces it)");
    r.key("output.plots")
        .is(KeyKind::boolean)
        .fallback("true")
        .means("draw the PNG plots with gnuplot (when installed)");
    r.key("output.progress_seconds")
        .is(KeyKind::quantity)
        .in(units::time)
        .fallback("10")
        .allowed("> 0")
        .means("wall-clock time between progress lines of a running case");
    r.key("threads")
        .is(KeyKind::integer)
        .fallback("0")
        .allowed(">= 0")
        .means("host threads; 0: OMP_NUM_THREADS, else tuned while stepping (--threads replaces it)");
    return r;
  }();
  return ref;
}

const ColumnTable& patch_cases_table() {
  static const ColumnTable t{
      "cases.csv",
      "One row per case, written when it ends (a case kept by --resume keeps its row); a column that does not "
      "apply to the case is empty. Stresses in Pa and lengths in m, or in the input's own units when it gives "
      "none (Table 4's material has none).",
      {
          {"case", "-", "case number, in run order", ""},
          {"test", "-", "elastic, tension or shear", ""},
          {"sample", "-", "hcp, the amorphous sample's label, or the data file", ""},
          {"c_axis", "-", "hcp: the stacking axis, x, y or z", ""},
          {"d0_over_dc", "-", "d0 over d_c", ""},
          {"d0", "m", "hcp: the particle diameter; lammps_data: the mean diameter; amorphous: the mode d0", ""},
          {"nu_target", "-", "the input Poisson's ratio nu", ""},
          {"s", "-", "the coarse-graining exponent s", ""},
          {"particles", "-", "particles of the sample, walls included", ""},
          {"deformable", "-", "particles between the walls", ""},
          {"Lx_over_d0", "-", "box length along x over d0", ""},
          {"Ly_over_d0", "-", "box length along y (the load axis) over d0", ""},
          {"Lz_over_d0", "-", "box length along z over d0", ""},
          {"dt", "s", "time step", ""},
          {"status", "-", "`ok`, or `failed: ` and why the case has no result", ""},
          {"steps", "-", "steps run", ""},
          {"wall_seconds", "s", "wall-clock time of the test", ""},
          {"eps_yy", "-",
           "elastic: strain of the bulk, the slope of the interior particles' displacements against their height",
           ""},
          {"sigma_xx", "Pa", "elastic: xx stress of the bulk (tension positive)", ""},
          {"sigma_yy", "Pa", "elastic: yy stress of the bulk", ""},
          {"sigma_zz", "Pa", "elastic: zz stress of the bulk", ""},
          {"C11", "Pa", "elastic: sigma_yy / eps_yy (stresses less their values before the load)", ""},
          {"C12", "Pa", "elastic: sigma_xx / eps_yy", ""},
          {"C13", "Pa", "elastic: sigma_zz / eps_yy", ""},
          {"E", "Pa", "elastic: Young's modulus of an isotropic solid with these C11 and C12", ""},
          {"nu", "-", "elastic: Poisson's ratio C12 / (C11 + C12)", ""},
          {"E_dev", "-", "elastic: E over the input E, minus 1", ""},
          {"nu_dev", "-", "elastic: nu minus the input nu", ""},
          {"nu_rel_dev", "-", "elastic: nu over the input nu, minus 1 (empty for an input nu of 0)", ""},
          {"eps_yy_walls", "-", "elastic: top-wall displacement over the height between the walls", ""},
          {"sigma_yy_part", "Pa", "elastic: yy stress of the whole deformable part", ""},
          {"C11_walls", "Pa", "elastic: C11 from the walls' strain and the whole part's stress", ""},
          {"C12_walls", "Pa", "elastic: C12 from the walls' strain and the whole part's stress", ""},
          {"E_walls", "Pa", "elastic: E from C11_walls and C12_walls", ""},
          {"nu_walls", "-", "elastic: nu from C11_walls and C12_walls", ""},
          {"strength", "Pa", "tension: the peak sigma_yy; shear: the peak sigma_xy", ""},
          {"target_strength", "Pa", "tension, shear: the input strength scaled by eq 20 for d0 (paper A)", ""},
          {"strength_over_target", "-", "tension, shear: strength over target_strength", ""},
          {"strain_at_peak", "-", "tension, shear: the strain at the peak", ""},
          {"outcome", "-",
           "tension, shear: `broke` (fell below fall_fraction of the peak), `peak held` (yield) or `max strain` "
           "(still rising: a lower bound)",
           ""},
          {"final_over_peak", "-", "tension, shear: the stress at the stop over the peak", ""},
          {"curve_file", "-", "tension, shear: the stress-strain CSV, relative to the output directory", ""},
          {"volume_fraction", "-", "the spheres' volumes over the box volume of the periodic sample", ""},
          {"system_size_over_dc", "-", "discretisation study: the system size L over d_c", ""},
          {"initial_overlap_over_r_min", "-", "deepest overlap at the start, over the smallest radius", ""},
          {"overlap_limit", "-", "the health check's limit used, in smallest radii", ""},
          {"sigma0_xx", "Pa", "elastic: xx stress of the bulk before the load (an amorphous sample's pre-stress)", ""},
          {"sigma0_yy", "Pa", "elastic: yy stress of the bulk before the load", ""},
      }};
  return t;
}

const ColumnTable& patch_curve_table() {
  static const ColumnTable t{
      "curves/case_<NNN>_<test>.csv",
      "The stress-strain curve of one tension or shear case (`<NNN>` its number, three digits), one row every "
      "`strength.sample_every` steps. Stresses of the deformable part, tension positive.",
      {
          {"step", "-", "time step", ""},
          {"strain", "-", "top-wall displacement along the load (y: tension, x: shear) over the height between the "
                          "walls",
           ""},
          {"eps_yy", "-", "top-wall displacement along y over the height between the walls", ""},
          {"sigma_xx", "Pa", "xx stress", ""},
          {"sigma_yy", "Pa", "yy stress", ""},
          {"sigma_zz", "Pa", "zz stress", ""},
          {"sigma_xy", "Pa", "xy stress", ""},
          {"sigma_xz", "Pa", "xz stress", ""},
          {"sigma_yz", "Pa", "yz stress", ""},
          {"kinetic_energy", "J", "kinetic energy of the deformable part", ""},
      }};
  return t;
}

std::vector<ColumnTable> patch_output_columns() { return {patch_cases_table(), patch_curve_table()}; }

}  // namespace debris
