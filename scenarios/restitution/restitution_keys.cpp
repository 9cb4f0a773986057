#include "scenarios/restitution/restitution_keys.hpp"

#include <string>

#include "core/units.hpp"
#include "scenarios/common/peridem/peridem_keys.hpp"

namespace debris {

namespace {
namespace u = units;

/// A setting given at the top level for every case, which a case may change for itself.
const char* const kCaseSettings[] = {"contact_radius_factor", "damping_factor", "damping_onset_factor"};
}  // namespace

const KeyReference& restitution_keys() {
  static const KeyReference ref = [] {
    KeyReference r("debris_restitution");
    r.key("dimension").is(KeyKind::integer).fallback("2").allowed("2").means("plane strain: only 2D is run");
    r.key("materials").is(KeyKind::section).allowed("at least the materials the cases name")
        .means("the materials, by name").eq("B Table 1");
    document_pd_material(r, "materials.<name>");

    r.key("mesh_size").is(KeyKind::quantity).in(u::length).fallback("0.2 mm").allowed("> 0")
        .means("Gmsh's characteristic length for the circle meshes");
    r.key("drop_height").is(KeyKind::quantity).in(u::length).fallback("1 mm").allowed("> 0")
        .means("H0: the gap the top grain falls from, at rest").eq("B eq 37, Fig 5");
    r.key("gravity").is(KeyKind::quantity).in(u::acceleration).fallback("10").allowed("> 0")
        .means("g, pointing down (-y)");
    document_pd_contact_setting(r, "damping_factor", "damping_factor").fallback("100");
    document_pd_contact_setting(r, "contact_radius_factor", "contact_radius_factor").fallback("0.95");
    document_pd_contact_setting(r, "damping_onset_factor", "damping_onset_factor").fallback("1");
    r.key("start_gap").is(KeyKind::quantity).in(u::length).fallback("0.2 mm").allowed("> 0 (capped at drop_height)")
        .means("H_s: the gap a shortened run starts from, with the speed of the fall from H0");
    r.key("full_drop").is(KeyKind::boolean).fallback("false")
        .means("run the whole fall from H0 at rest and the whole rise instead (checks the shortcut)");
    r.key("allow_unstable_time_step").is(KeyKind::boolean).fallback("false")
        .means("run a time step above the stable estimate (the bonds' largest frequency and one contact spring)");
    r.key("max_steps").is(KeyKind::integer).fallback("5000000").allowed("> 0")
        .means("the most steps a case may take: a rebound not over by then is an error");
    document_pd_contact_setting(r, "damping", "damping").fallback("grain_centres");
    r.key("damping_centre").one_of({"mean", "centre_node"}).fallback("mean")
        .means("the centre and velocity of a grain in the centre damping: the volume-weighted means of its nodes, "
               "or its centre node (the node nearest its centroid at set-up), as the authors' code")
        .eq("B eqs 26-29");
    r.key("circle_meshes").is(KeyKind::list).fallback_is("none: Gmsh meshes each circle at `mesh_size`")
        .means("mesh files to use for the circles of a given radius (the meshes the authors' code ran on)");
    r.key("circle_meshes.radius").is(KeyKind::quantity).in(u::length).allowed("> 0")
        .means("the radius of the grains this mesh serves (equal to 1e-9 relative)");
    r.key("circle_meshes.file").is(KeyKind::text).allowed("an existing file")
        .means("a Gmsh MSH file of a circle about the origin, relative to the input file; scaled to the grain by "
               "its farthest node");

    r.describe_section("cases", "The drops, run in order; every case is read before the first one runs.");
    r.key("cases").is(KeyKind::list).allowed("at least one").means("the cases to run");
    r.key("cases.name").is(KeyKind::text).means("the case's name (Table 2 and 3 rows repeat names)");
    r.key("cases.radii").is(KeyKind::numbers).in(u::length).allowed("two, > 0: [bottom, top]")
        .means("the radii (R1, R2) of the bottom and the top grain").eq("B Tables 2-3");
    r.key("cases.materials").is(KeyKind::list).allowed("two names under `materials`: [bottom, top]")
        .means("the materials of the bottom and the top grain").eq("B Tables 2-3");
    document_pd_contact_setting(r, "cases.restitution", "restitution");
    r.key("cases.time_step").is(KeyKind::quantity).in(u::time)
        .allowed("> 0; at most the stable estimate unless `allow_unstable_time_step`").means("the time step dt")
        .eq("B eq 32");
    r.key("cases.initial_speed").is(KeyKind::quantity).in(u::velocity).fallback("0").allowed(">= 0")
        .means("v0: the top grain's downward speed at H0 (the fracture runs); C_R is then measured against "
               "H0 + v0^2 / 2g");
    r.key("cases.mesh_size").is(KeyKind::quantity).in(u::length).fallback_is("the top-level `mesh_size`").allowed("> 0")
        .means("the case's own mesh size (a mesh study)");
    r.key("cases.horizon").is(KeyKind::quantity).in(u::length).fallback_is("the materials' horizons")
        .allowed("> 0").means("the horizon of both grains (a mesh study refines it with the mesh)").eq("B Table 4");
    for (const char* setting : kCaseSettings)
      document_pd_contact_setting(r, std::string("cases.") + setting, setting)
          .fallback_is(std::string("the top-level `") + setting + "`");
    r.key("cases.start_gap").is(KeyKind::quantity).in(u::length).fallback_is("the top-level `start_gap`").allowed("> 0")
        .means("the case's own H_s");
    r.key("cases.damping_centre").one_of({"mean", "centre_node"}).fallback_is("the top-level `damping_centre`")
        .means("the case's own damping centre");
    r.key("cases.meshes").is(KeyKind::list).fallback_is("from `circle_meshes`, else Gmsh's")
        .allowed("two existing files: [bottom, top]")
        .means("Gmsh MSH files of the two grains, relative to the input file");
    r.key("cases.paper").is(KeyKind::quantity).in(u::dimensionless).fallback("-1").allowed("negative: none")
        .means("the paper's C_R, written beside debris's").eq("B Tables 2-3");
    return r;
  }();
  return ref;
}

const ColumnTable& restitution_table() {
  static const ColumnTable t{
      "restitution.csv",
      "One row per case, in the input's order, written as each case ends; SI units.",
      {
          {"case", "-", "the case's name, in double quotes", ""},
          {"bottom_radius_m", "m", "R1: the bottom (fixed) grain's radius", ""},
          {"top_radius_m", "m", "R2: the top grain's radius", ""},
          {"materials", "-", "the materials, bottom/top", ""},
          {"restitution_parameter", "-", "epsilon_n of the contact damping (paper B eqs 23, 28)", ""},
          {"time_step_s", "s", "the time step", ""},
          {"initial_speed_m_s", "m/s", "v0, the top grain's downward speed at H0", ""},
          {"paper_C_R", "-", "the paper's C_R; empty when the case gives none", ""},
          {"debris_C_R", "-", "C_R = sqrt(H1 / H0) as measured (paper B eq 37; H0 + v0^2 / 2g with an initial speed)",
           ""},
          {"difference", "-", "debris_C_R - paper_C_R; empty without paper_C_R", ""},
          {"rebound_height_m", "m", "H1: the top grain's highest gap after the contact", ""},
          {"contact_time_s", "s", "from the first to the last step with a touching node pair", ""},
          {"steps", "-", "steps run", ""},
          {"nodes", "-", "nodes of the two grains", ""},
          {"broken_bonds", "-", "bonds broken by the impact", ""},
          {"bottom_max_damage", "-", "largest damage Z of the bottom grain's nodes during the contact (paper B eq 14)",
           ""},
          {"top_max_damage", "-", "the same for the top grain", ""},
          {"wall_seconds", "s", "wall-clock time of the case", ""},
          {"mesh_h_m", "m", "h: the smallest node spacing of the two meshes (paper B eq 35)", ""},
          {"horizon_m", "m", "the top grain's horizon", ""},
      }};
  return t;
}

std::vector<ColumnTable> restitution_output_columns() { return {restitution_table()}; }

}  // namespace debris
