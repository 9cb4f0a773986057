#include "scenarios/calibrate/calibrate_keys.hpp"

#include "scenarios/calibrate/calibration.hpp"
#include "scenarios/common/dem/cohesive_material_input.hpp"

namespace debris {

const KeyReference& calibrate_keys() {
  static const KeyReference ref = [] {
    KeyReference r("debris_calibrate");
    const CalibrationSpec d;  // what the reader starts from
    const std::vector<CohesiveMaterialPreset>& presets = cohesive_material_presets();
    document_cohesive_material(r, "target", presets, false);
    r.describe_section(
        "target",
        "youngs_modulus, poisson_ratio, tensile_strength and shear_strength are what the calibrated sample must "
        "measure; surface_energy, restitution, density and scaling are the user's and are kept (gamma / E too, "
        "unless the surface energy is the input that moves the tension). A target shear_strength must be > 0 "
        "here.");
    const auto per_preset = [&](double CohesiveMaterial::*field) {
      std::string text;
      for (const CohesiveMaterialPreset& p : presets)
        text += (text.empty() ? "" : "; ") + p.name + ": " + shortest_text(p.values.*field);
      return text;
    };
    r.key("target.poisson_ratio")
        .is(KeyKind::quantity)
        .in(units::dimensionless)
        .fallback_is(per_preset(&CohesiveMaterial::poisson_ratio))
        .allowed("[0, 0.25)")
        .means("the Poisson's ratio nu the sample must measure; its input stops at 0.25, where A_T vanishes")
        .eq("A eqs 15-16");
    r.key("target.scaling")
        .is(KeyKind::quantity)
        .in(units::dimensionless)
        .fallback_is(per_preset(&CohesiveMaterial::scaling))
        .allowed("[0, 1]")
        .means("coarse-graining exponent s, kept: 0 keeps the strength, 0.5 the surface energy")
        .eq("A eqs 10, 20");

    r.key("sample").is(KeyKind::section).means(
        "the amorphous sample every step relaxes and tests (paper A section 3.2), made with the step's inputs");
    r.key("sample.d0")
        .is(KeyKind::quantity)
        .in(units::length)
        .allowed("> 0, >= the target's d_min")
        .means("the mode diameter d0, a length in the material's units (\"3 nm\" for silica, 90 for Table 4)")
        .eq("A eq 19");
    document_amorphous_sample(r, "sample", d.sample);
    r.key("sample.wall_thickness")
        .is(KeyKind::quantity)
        .in(units::dimensionless)
        .fallback(shortest_text(d.wall_thickness))
        .allowed("> 0")
        .means("thickness of each wall of the patch tests, in mean diameters");
    document_amorphous_relaxation(r, "relaxation", d.sample);

    r.key("calibration").is(KeyKind::section).fallback_is("optional").means("how far and how closely to calibrate");
    r.key("calibration.max_runs")
        .is(KeyKind::integer)
        .fallback(std::to_string(d.max_runs))
        .allowed(">= 3")
        .means("patch runs in all (a step runs up to three: elastic, tension, shear)");
    r.key("calibration.tolerance_E")
        .is(KeyKind::quantity)
        .in(units::dimensionless)
        .fallback(shortest_text(d.tolerance_E))
        .allowed("> 0")
        .means("relative error allowed on E");
    r.key("calibration.tolerance_nu")
        .is(KeyKind::quantity)
        .in(units::dimensionless)
        .fallback(shortest_text(d.tolerance_nu))
        .allowed("> 0")
        .means("absolute error allowed on nu");
    r.key("calibration.tolerance_strength")
        .is(KeyKind::quantity)
        .in(units::dimensionless)
        .fallback(shortest_text(d.tolerance_strength))
        .allowed("> 0")
        .means("relative error allowed on the tensile and the shear strength");
    r.key("calibration.elastic_load")
        .is(KeyKind::quantity)
        .in(units::dimensionless)
        .fallback(shortest_text(d.elastic_load))
        .allowed("> 0")
        .means("the elastic test's compressive stress over the inputs' E (paper A section 3: 0.01)");
    r.key("calibration.spread_seeds")
        .is(KeyKind::numbers)
        .in(units::dimensionless)
        .fallback("[2, 3]")
        .allowed("whole numbers >= 1")
        .means("seeds of further samples the calibrated inputs are measured on (spread.csv)");

    r.key("output").is(KeyKind::section).fallback_is("optional").means("where to write");
    r.key("output.directory")
        .is(KeyKind::text)
        .fallback("out/calibrate")
        .means("the output directory (created; -o replaces it)");
    r.key("run").is(KeyKind::section).fallback_is("optional").means("how to run");
    r.key("run.threads")
        .is(KeyKind::integer)
        .fallback("1")
        .allowed(">= 0")
        .means("host threads; 0: OpenMP's default (--threads replaces it)");
    return r;
  }();
  return ref;
}

namespace {

/// The columns after the first: the inputs of a row, its measures, their errors against the targets.
std::vector<ColumnDoc> measure_columns(const std::string& runs, const std::string& what) {
  return {
      {"runs", "-", runs, ""},
      {"collapsed", "-", "1 when the sample collapsed (no measures: the measured columns are 0), else 0", ""},
      {"E_in", "Pa", "input Young's modulus", ""},
      {"nu_in", "-", "input Poisson's ratio", ""},
      {"tensile_strength_in", "Pa", "input tensile strength", ""},
      {"shear_strength_in", "Pa", "input shear strength", ""},
      {"surface_energy_in", "J/m^2", "input surface energy", ""},
      {"E", "Pa", "Young's modulus " + what, ""},
      {"nu", "-", "Poisson's ratio " + what, ""},
      {"tensile_strength", "Pa", "tensile strength " + what, ""},
      {"shear_strength", "Pa", "shear strength " + what, ""},
      {"error_E", "-", "E over the target, minus 1", ""},
      {"error_nu", "-", "nu minus the target", ""},
      {"error_tensile", "-", "tensile strength over the target, minus 1", ""},
      {"error_shear", "-", "shear strength over the target, minus 1", ""},
      {"relaxed_fraction", "-", "volume fraction of the relaxed sample", ""},
      {"seconds", "s", "wall-clock time of the relaxation (when one ran) and the tests", ""},
  };
}

}  // namespace

const ColumnTable& calibration_table() {
  static const ColumnTable t = [] {
    ColumnTable c{"calibration.csv",
                  "One row per calibration step that made or collapsed a sample, written as it ends (a step whose "
                  "sample did not relax has none). SI, or the input's own units when it gives none.",
                  {{"step", "-", "the step's number, from 1", ""}}};
    for (ColumnDoc& d : measure_columns("patch runs so far, this step's included", "the sample measured"))
      c.columns.push_back(std::move(d));
    return c;
  }();
  return t;
}

const ColumnTable& spread_table() {
  static const ColumnTable t = [] {
    ColumnTable c{"spread.csv",
                  "The calibrated inputs on other samples: a row for the calibration's own seed (what the inputs "
                  "measure, or should measure where no run confirmed them), then one per calibration.spread_seeds. "
                  "SI, or the input's own units when it gives none.",
                  {{"seed", "-", "the sample's seed", ""}}};
    for (ColumnDoc& d : measure_columns("0 (not a calibration step)", "the sample of this seed measured"))
      c.columns.push_back(std::move(d));
    return c;
  }();
  return t;
}

std::vector<ColumnTable> calibrate_output_columns() { return {calibration_table(), spread_table()}; }

}  // namespace debris
