#include "scenarios/common/dem/dem_keys.hpp"

#include "core/io/dump_writer.hpp"
#include "core/region.hpp"
#include "scenarios/common/dem/cohesive_material_input.hpp"
#include "scenarios/common/dem/run_pictures.hpp"
#include "scenarios/common/dem/surface_census.hpp"
#include "scenarios/common/dem/wear_analysis.hpp"
#include "scenarios/common/run/stages.hpp"

namespace debris {

namespace {

// particles: a lattice or a LAMMPS data file (dem_input.cpp, read_lattice and read_system).
void document_particles(KeyReference& r) {
  r.describe_section("particles",
                     "Exactly one of `lattice` (built in place) or `lammps_data` (read from a file). The particles "
                     "are then wrapped into the box on its periodic axes, carved by `remove`, labelled by `labels` "
                     "and grouped by `groups`, in that order.");
  r.key("particles").is(KeyKind::section).allowed("exactly one of `lattice`, `lammps_data`")
      .means("where the particles come from");
  r.key("particles.lattice").is(KeyKind::section).fallback_is("give `lattice` or `lammps_data`")
      .means("a crystal of equal spheres (or spread diameters) built in place; the box is its period");
  r.key("particles.lattice.kind").one_of({"fcc", "hcp"})
      .means("face-centred cubic or hexagonal close-packed; both unit cells hold 4 particles");
  r.key("particles.lattice.spacing").is(KeyKind::quantity).in(units::length).allowed("> 0")
      .means("the nearest-neighbour distance a");
  r.key("particles.lattice.diameter").is(KeyKind::quantity).in(units::length).fallback_is("`spacing`")
      .allowed("> 0").means("the mean particle diameter");
  r.key("particles.lattice.size_spread").is(KeyKind::quantity).in(units::dimensionless).fallback("0")
      .allowed("[0, 1)").means("the diameters' relative spread: d = diameter (1 + size_spread U(-1, 1))");
  r.key("particles.lattice.displacement").is(KeyKind::quantity).in(units::length).fallback("0").allowed(">= 0")
      .means("a random shift of every coordinate: displacement U(-1, 1)");
  r.key("particles.lattice.cells").is(KeyKind::numbers).in(units::dimensionless)
      .allowed("[nx, ny, nz], whole numbers in [1, 1e6]; 4 nx ny nz particles, within memory and int indices")
      .means("repetitions of the orthogonal 4-particle unit cell along x, y, z");
  r.key("particles.lattice.origin").is(KeyKind::vector).in(units::length).fallback("[0, 0, 0]").allowed("finite")
      .means("the low corner of the lattice and of its box");
  r.key("particles.lattice.seed").is(KeyKind::integer).fallback("1")
      .means("the seed of the random diameters and shifts (std::mt19937_64): a seed gives the same particles");
  r.key("particles.lattice.hcp_c_axis").one_of({"x", "y", "z"}).fallback("y")
      .means("HCP's stacking (c) axis; with y the close-packed planes are x-z planes");
  r.key("particles.lammps_data").is(KeyKind::text).fallback_is("give `lattice` or `lammps_data`")
      .means("a LAMMPS data file, atom_style sphere (id type diameter density x y z [ix iy iz], optional "
             "Velocities), relative to the input file; its particles are unlabelled and its bounds are the box");
  r.key("particles.replicate").is(KeyKind::numbers).fallback("[1, 1, 1]")
      .allowed("three whole numbers, 1 to 1000")
      .means("tiles the particles n_x x n_y x n_z times, each copy shifted by whole box lengths, and grows the "
             "box to match (before `box.lo`/`box.hi`, carving, labels and groups): a sample relaxed in a "
             "periodic box continues across every seam with the neighbours it had across its periodic faces; "
             "copy c's ids are id + c (max id + 1)");
  r.key("particles.masses_from_file").is(KeyKind::boolean).fallback("false")
      .means("with `lammps_data`: true keeps the file's densities (masses); false gives every particle "
             "`material.density`");
}

void document_box(KeyReference& r) {
  r.key("box").is(KeyKind::section).fallback_is("not periodic, the lattice's or the data file's bounds")
      .means("the simulation box (orthogonal)");
  r.key("box.periodic").is(KeyKind::list).fallback("[false, false, false]")
      .allowed("[x, y, z], each true or false (yes, no)").means("which axes are periodic");
  r.key("box.lo").is(KeyKind::vector).in(units::length).fallback_is("the lattice's or the data file's low corner")
      .means("the box's low corner");
  r.key("box.hi").is(KeyKind::vector).in(units::length).fallback_is("the lattice's or the data file's high corner")
      .means("the box's high corner");
}

void document_carving(KeyReference& r) {
  r.key("remove").is(KeyKind::list).follows("region").fallback_is("nothing removed")
      .allowed("one region or a list; each removes at least one particle and leaves at least one")
      .means("regions whose particles are deleted, each in turn, before labels and groups are assigned");
  r.describe_section("labels",
                     "Labels name the body each particle starts in (the dump's `mol`, the trajectory's `label`); "
                     "entry k gives label k, 0 is unlabelled. They are assigned in order, a later entry overriding "
                     "an earlier one, and follow each particle through checkpoints.");
  r.key("labels").is(KeyKind::list).fallback_is("none: every particle 0")
      .allowed("each label holds at least one particle").means("the labels, in order");
  r.key("labels.name").is(KeyKind::text).allowed("non-empty, unique").means("the label's name");
  r.key("labels.region").is(KeyKind::section).follows("region").means("the particles the label paints");
}

// The motion keys of a group, in `groups` and in a stage's `groups` (read_group_motion).
void document_group_motion(KeyReference& r, const std::string& at, bool in_stage) {
  r.key(at + ".motion").one_of({"free", "frozen", "velocity", "force"}).fallback("free")
      .means("free: moved by its forces, as every particle; frozen: held at rest; velocity: a rigid translation "
             "at `velocity`; force: a rigid translation under `force` or `stress`, axis by axis (no rotation)");
  r.key(at + ".velocity").is(KeyKind::vector).in(units::velocity)
      .fallback_is("required with `motion: velocity`; with `force`, every axis free")
      .allowed("velocity: three velocities; force: each a velocity (that axis prescribed) or `free` (left to the load)")
      .means("the group's velocity");
  r.key(at + ".force").is(KeyKind::vector).in(units::force)
      .fallback_is("with `motion: force`, give `force` or `stress`").allowed("0 on the axes `velocity` prescribes")
      .means("the external force on the whole group");
  r.key(at + ".stress").is(KeyKind::vector).in(units::pressure)
      .fallback_is("with `motion: force`, give `force` or `stress`").allowed("0 on the axes `velocity` prescribes")
      .means("a traction: the force is it times the box's area normal to `area_normal`");
  r.key(at + ".area_normal").one_of({"x", "y", "z"}).fallback_is("the axis of `stress`'s largest component")
      .means("the axis normal to the area that turns `stress` into a force");
  KeyDoc& v0 = r.key(at + ".initial_velocity").is(KeyKind::vector).in(units::velocity)
                   .allowed("0 (or the prescribed value) on the axes `velocity` prescribes");
  if (in_stage)
    v0.fallback_is("the group's velocity as it was").means("with `motion: force`: the new velocity of the load-driven axes");
  else
    v0.fallback("[0, 0, 0]").means("with `motion: force`: the starting velocity of the load-driven axes");
}

void document_groups(KeyReference& r) {
  r.describe_section("groups",
                     "Groups are named sets of particles that move together (walls) or are measured together: "
                     "thermo.csv has each group's reaction and displacement. A particle belongs to at most one "
                     "group. Members are chosen by `region`, `types` and `ids`; each one given narrows them down.");
  r.key("groups").is(KeyKind::list).fallback_is("none").means("the groups, in order");
  r.key("groups.name").is(KeyKind::text).allowed("non-empty, unique, without `,`, `\"` or line breaks")
      .means("the group's name, which heads its thermo.csv columns");
  r.key("groups.region").is(KeyKind::section).follows("region")
      .fallback_is("any place; give at least one of `region`, `types`, `ids`")
      .means("the members' place");
  r.key("groups.types").is(KeyKind::list).fallback_is("any type").allowed("whole numbers")
      .means("the members' particle types");
  r.key("groups.ids").is(KeyKind::list).fallback_is("any id").allowed("whole numbers").means("the members' ids");
  document_group_motion(r, "groups", false);
}

void document_stage_changes(KeyReference& r) {
  r.key("stages.global_damping").is(KeyKind::quantity).in(units::dimensionless).fallback_is("unchanged")
      .allowed(">= 0, below m_min / (c_c dt)").means("`run.global_damping` from this stage on").eq("A eq 21");
  r.key("stages.adhesive").is(KeyKind::boolean).fallback_is("unchanged").means("`run.adhesive` from this stage on");
  r.key("stages.tangential").is(KeyKind::boolean).fallback_is("unchanged")
      .means("`run.tangential` from this stage on");
  r.key("stages.groups").is(KeyKind::list).fallback_is("none")
      .means("groups whose motion changes at the stage's start: each entry gives a group's whole motion, as in "
             "`groups` (its members stay)");
  r.key("stages.groups.name").is(KeyKind::text).allowed("a group of `groups`, once per stage")
      .means("the group to change");
  document_group_motion(r, "stages.groups", true);
  r.key("stages.groups.set_velocity").is(KeyKind::vector).in(units::velocity).fallback_is("none")
      .allowed("a free group's only")
      .means("every member's velocity at the stage's start (LAMMPS's `velocity group set`); spins untouched");
}

void document_run(KeyReference& r) {
  r.describe_section("run",
                     "At `--restart` the checkpoint gives `time_step`, `time_step_fraction`, "
                     "`allow_unstable_time_step`, `global_damping`, `skin`, `adhesive` and `tangential` (and the "
                     "whole system); `steps`, `overlap_limit` and `threads` are read from the input.");
  r.key("run").is(KeyKind::section).means("the run's length, time step, damping and checks");
  r.key("run.steps").is(KeyKind::integer).fallback_is("required without `stages`; with them, their sum")
      .allowed(">= 0; with stages, at most their sum")
      .means("the step the run ends at, counted from step 0 (a restart goes on to it); with stages it may stop "
             "the run early");
  r.key("run.time_step").is(KeyKind::quantity).in(units::time).fallback_is("`time_step_fraction` of dt_c")
      .allowed("> 0, at most dt_c (unless `allow_unstable_time_step`); not with `time_step_fraction`")
      .means("the time step dt").eq("A eq 6");
  r.key("run.time_step_fraction").is(KeyKind::quantity).in(units::dimensionless).fallback("0.1")
      .allowed("> 0, at most 1 (unless `allow_unstable_time_step`)")
      .means("the time step as a fraction of the critical time step dt_c of the smallest particle").eq("A eq 6");
  r.key("run.allow_unstable_time_step").is(KeyKind::boolean).fallback("false")
      .means("true: accept a time step above dt_c");
  r.key("run.global_damping").is(KeyKind::quantity).in(units::dimensionless).fallback("0")
      .allowed(">= 0, below m_min / (c_c dt)")
      .means("viscous damping of the free particles' translation, F -= c v, with c this fraction of the critical "
             "damping c_c")
      .eq("A eq 21");
  r.key("run.skin").is(KeyKind::quantity).in(units::length)
      .fallback_is("0: 0.2 r_min, or 0.25 r_mean when r_max >= 2 r_min").allowed(">= 0")
      .means("the Verlet skin of the neighbour list (rebuilt when a particle has moved half of it)");
  r.key("run.adhesive").is(KeyKind::boolean).fallback("true")
      .means("false: repulsion only, no normal force in tension (relaxation phase 1)").eq("A eq 3");
  r.key("run.tangential").is(KeyKind::boolean).fallback("true")
      .means("false: no tangential force (relaxation phase 2)").eq("A eqs 4-5");
  r.key("run.overlap_limit").is(KeyKind::quantity).in(units::dimensionless).fallback("0.5")
      .allowed("> 0, or `auto`")
      .means("health check: an overlap deeper than this many smallest radii stops the run (exit 3); `auto`: the "
             "deepest overlap at the start plus one (a restart keeps the limit it continues)");
  r.key("run.threads").is(KeyKind::integer).fallback("0").allowed(">= 0")
      .means("host threads; 0: OMP_NUM_THREADS, else tuned while stepping; `--threads` overrides it");
}

void document_output(KeyReference& r) {
  r.key("output").is(KeyKind::section).fallback_is("every default below").means("what is written, and where");
  r.key("output.directory").is(KeyKind::text).fallback("out")
      .means("the output directory, relative to the working directory (input files are read relative to the input file), created when missing; `-o` overrides it");
  r.key("output.thermo_every").is(KeyKind::integer).fallback("100").allowed(">= 1")
      .means("steps between thermo.csv rows, terminal lines and health checks");
  r.key("output.dump_every").is(KeyKind::integer).fallback("0").allowed(">= 0")
      .means("steps between LAMMPS dump frames; 0: the first and the last step only");
  r.key("output.trajectory_every").is(KeyKind::integer).fallback("0").allowed(">= 0")
      .means("steps between HDF5 + XDMF trajectory frames; 0: as `dump_every`");
  r.key("output.checkpoint_every").is(KeyKind::integer).fallback("0").allowed(">= 0")
      .means("steps between checkpoints; 0: at the end only (a checkpoint is also written where a stage starts)");
  r.key("output.progress_seconds").is(KeyKind::quantity).in(units::time).fallback("10 s").allowed("> 0")
      .means("the progress line (steps/s, time left) comes at most this often");
  r.key("output.pictures").is(KeyKind::boolean).fallback("false")
      .means("true: side_view.png and tangential_force.png at the end, drawn by gnuplot");
  r.key("output.energy").is(KeyKind::boolean).fallback("true")
      .means("the energy accounting: work done by each drive and energy dissipated by each mechanism, in "
             "thermo.csv, the dump and the closing balance; false saves its cost (a restart keeps the setting of "
             "the run it continues)");
}

}  // namespace

const KeyReference& dem_keys() {
  static const KeyReference ref = [] {
    KeyReference r("debris_dem");
    document_cohesive_material(r, "material", nullptr);
    document_particles(r);
    document_box(r);
    document_carving(r);
    document_groups(r);
    document_stage_lengths(r);
    document_stage_changes(r);
    document_run(r);
    document_wear_settings(r);
    document_surface_settings(r);
    document_output(r);
    document_regions(r);
    return r;
  }();
  return ref;
}

const ColumnTable& dem_thermo_table() {
  static const ColumnTable t{
      "thermo.csv",
      "One row every `output.thermo_every` steps (and at the last step); SI, or the input's own units when it "
      "gives none.",
      {
          {"step", "-", "time step number, counted from the start of the run", ""},
          {"time", "s", "simulated time", ""},
          {"kinetic_energy", "J", "translational plus rotational kinetic energy of all particles", ""},
          {"elastic_energy", "J",
           "energy of the pair springs: the potential of the normal force (paper A eq 3), zero for separated "
           "pairs and so negative in the cohesive well, plus the tangential springs' energy",
           ""},
          {"max_overlap", "m", "largest interpenetration of an interacting pair (0 when none overlaps)", ""},
          {"interacting_pairs", "-", "pairs within their interaction distance delta_f", ""},
          {"<group>_fx", "N",
           "x component of the group's reaction: the sum of the pair forces (springs and damping) on its members, "
           "external loads left out (a wall pressed down onto the sample reads a positive fy)",
           ""},
          {"<group>_fy", "N", "y component of the group's reaction", ""},
          {"<group>_fz", "N", "z component of the group's reaction", ""},
          {"<group>_dx", "m", "x displacement of the group's centre of mass since the start of the run", ""},
          {"<group>_dy", "m", "y displacement of the group's centre of mass", ""},
          {"<group>_dz", "m", "z displacement of the group's centre of mass", ""},
          {"<group>_work", "J",
           "work the group's drive did on the system since the start: what set its members' velocities other than "
           "their own forces (a frozen wall's does none; a wall moved at a velocity or under a load does); 0 for "
           "a free group",
           "energy"},
          {"work_in", "J", "work done on the system since the start: every group's drive plus `work_stages`",
           "energy"},
          {"work_stages", "J",
           "work the stages' changes did at once: velocities they set, the pair law they switched (the energy "
           "content after the change minus before)",
           "energy"},
          {"dissipated_normal", "J", "energy taken by the normal damping of eq 2, c_N v_N^2, since the start",
           "energy"},
          {"dissipated_tangential", "J", "energy taken by the tangential damping of eq 2, c_T |v_T|^2, since the start",
           "energy"},
          {"dissipated_sliding", "J",
           "energy taken where the tangential spring slid (eq 4: F'_mT times the slip) or was let go (a pair "
           "leaving range keeps none of its spring energy), since the start",
           "energy"},
          {"dissipated_global", "J", "energy taken by the global damping (`run.global_damping`, stages) since the start",
           "energy"},
          {"tangential_work", "J",
           "work the pairs' relative motion did against their tangential forces (springs and damping), since the "
           "start: the frictional work of the wear laws",
           "energy"},
          {"energy_residual", "J",
           "work_in - (kinetic_energy - its start) - (elastic_energy - its start) - the four dissipated columns: "
           "the integrator's error (README: energy balance)",
           "energy"},
      }};
  return t;
}

std::vector<ColumnTable> dem_output_columns() {
  return {dem_thermo_table(),
          WearAnalysis::table(),
          SurfaceCensus::table(),
          SurfaceCensus::histogram_table(),
          SurfaceCensus::debris_table(),
          dump_table(),
          side_view_table()};
}

}  // namespace debris
