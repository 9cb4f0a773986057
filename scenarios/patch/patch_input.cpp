#include "scenarios/patch/patch_input.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "core/io/input.hpp"
#include "core/io/lammps_data.hpp"

namespace debris {

namespace {

// A key that holds one value or a list of them (a sweep).
std::vector<double> one_or_list(const InputNode& n, const std::string& key, units::Dimension dim, double fallback) {
  if (!n.has(key)) return {fallback};
  if (n.child(key).is_sequence()) {
    std::vector<double> v = n.numbers(key, dim);
    if (v.empty()) throw input_error(n.path().empty() ? key : n.path() + "." + key, "[]", "give at least one value");
    return v;
  }
  return {n.quantity(key, dim)};
}

std::vector<InputNode> scalars(const InputNode& n, const std::string& key) {
  if (n.child(key).is_sequence()) {
    std::vector<InputNode> v = n.list(key);
    if (v.empty()) throw input_error(n.path().empty() ? key : n.path() + "." + key, "[]", "give at least one value");
    return v;
  }
  return {n.child(key)};
}

std::string one_of(const InputNode& n, const std::vector<std::string>& allowed) {
  const std::string t = n.text();
  for (const std::string& a : allowed)
    if (t == a) return t;
  std::string list;
  for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
  throw input_error(n.path(), t, "must be one of: " + list);
}

double pick(const InputNode& n, const std::string& key, double fallback) {
  return n.quantity(key, units::dimensionless, fallback);
}

long pick_integer(const InputNode& n, const std::string& key, long fallback) { return n.integer(key, fallback); }

}  // namespace

std::string PatchCase::sample_label() const {
  if (lattice) return std::string("hcp c=") + "xyz"[hcp.c_axis];
  return std::filesystem::path(data_file).filename().string();
}

PatchConfig read_patch_input_text(const std::string& text, const std::string& name, const std::string& base) {
  const InputNode root = InputNode::load_string(text, name);
  PatchConfig cfg;

  // Tests.
  std::vector<PatchTest> tests;
  for (const InputNode& t : scalars(root, "test")) {
    const std::string s = one_of(t, {"elastic", "tension", "shear"});
    tests.push_back(s == "elastic" ? PatchTest::elastic : (s == "tension" ? PatchTest::tension : PatchTest::shear));
  }

  // Material: Table 4 unless told otherwise; poisson_ratio and scaling may be sweeps.
  CohesiveMaterial base_material = table4_material(0.0);
  std::vector<double> nus{base_material.poisson_ratio}, scalings{0.0};
  if (root.has("material")) {
    const InputNode m = root.child("material");
    base_material.youngs_modulus = m.quantity("youngs_modulus", units::pressure, base_material.youngs_modulus);
    base_material.tensile_strength = m.quantity("tensile_strength", units::pressure, base_material.tensile_strength);
    base_material.shear_strength = m.quantity("shear_strength", units::pressure, base_material.shear_strength);
    base_material.surface_energy = m.quantity("surface_energy", units::surface_energy, base_material.surface_energy);
    base_material.restitution = m.quantity("restitution", units::dimensionless, base_material.restitution);
    base_material.density = m.quantity("density", units::density, base_material.density);
    nus = one_or_list(m, "poisson_ratio", units::dimensionless, base_material.poisson_ratio);
    scalings = one_or_list(m, "scaling", units::dimensionless, 0.0);
  }
  for (double nu : nus)
    for (double s : scalings) {
      CohesiveMaterial m = base_material;
      m.poisson_ratio = nu;
      m.scaling = s;
      m.validate("material");
    }
  const double d_c = base_material.critical_diameter();

  // Samples: HCP lattices (orientations x diameters) or LAMMPS data files.
  struct SampleChoice {
    bool lattice;
    HcpSampleSpec hcp;
    double d0_over_dc;
    std::string file;
    double wall;
  };
  std::vector<int> axes;
  std::vector<double> d0s;
  std::vector<std::string> files;
  const InputNode sample = root.child("sample");
  const bool lattice = sample.choice("kind", {"hcp", "lammps_data"}, "hcp") == "hcp";
  HcpSampleSpec spec;
  spec.wall_thickness = sample.quantity("wall_thickness", units::dimensionless, spec.wall_thickness);
  if (lattice) {
    spec.length = sample.quantity("length", units::dimensionless, spec.length);
    spec.thickness = sample.quantity("thickness", units::dimensionless, spec.thickness);
    if (sample.has("c_axis")) {
      for (const InputNode& a : scalars(sample, "c_axis")) {
        const std::string ax = one_of(a, {"x", "y", "z"});
        axes.push_back(ax == "x" ? 0 : (ax == "y" ? 1 : 2));
      }
    } else {
      axes.push_back(1);
    }
    if (!sample.has("d0"))
      throw input_error("sample.d0", "missing",
                        "give the particle diameter in units of d_c (eq 18), or a list of them");
    d0s = one_or_list(sample, "d0", units::dimensionless, 0.0);
    for (double d : d0s)
      if (!(std::isfinite(d) && d > 0))
        throw input_error("sample.d0", format_value(d), "must be > 0 (a diameter in units of d_c)");
  } else {
    if (!sample.has("lammps_data"))
      throw input_error("sample.lammps_data", "missing", "kind lammps_data needs a data file (or a list of them)");
    for (const InputNode& f : scalars(sample, "lammps_data")) {
      std::filesystem::path p = f.text();
      if (p.is_relative() && !base.empty()) p = std::filesystem::path(base) / p;
      if (!std::filesystem::exists(p)) throw input_error(f.path(), f.text(), "no such file");
      files.push_back(p.string());
    }
  }

  // Test settings.
  if (root.has("elastic")) {
    const InputNode e = root.child("elastic");
    ElasticSettings& es = cfg.elastic;
    es.stress = e.quantity("stress", units::pressure, es.stress);
    es.time_step_fraction = pick(e, "time_step_fraction", es.time_step_fraction);
    es.damping = pick(e, "damping", es.damping);
    es.sample_every = pick_integer(e, "sample_every", es.sample_every);
    es.window = pick_integer(e, "window", es.window);
    es.tolerance = pick(e, "tolerance", es.tolerance);
    es.max_steps = pick_integer(e, "max_steps", es.max_steps);
    es.max_strain = pick(e, "max_strain", es.max_strain);
    es.interior_margin = pick(e, "interior_margin", es.interior_margin);
  }
  validate(cfg.elastic);
  if (root.has("strength")) {
    const InputNode e = root.child("strength");
    StrengthSettings& ss = cfg.strength;
    ss.strain_rate = pick(e, "strain_rate", ss.strain_rate);
    ss.time_step_fraction = pick(e, "time_step_fraction", ss.time_step_fraction);
    ss.damping = pick(e, "damping", ss.damping);
    ss.sample_every = pick_integer(e, "sample_every", ss.sample_every);
    ss.fall_fraction = pick(e, "fall_fraction", ss.fall_fraction);
    ss.fall_strain = pick(e, "fall_strain", ss.fall_strain);
    ss.hold_strain = pick(e, "hold_strain", ss.hold_strain);
    ss.max_strain = pick(e, "max_strain", ss.max_strain);
    ss.shear_fixed_height = e.choice("shear_top", {"fixed_height", "normal_stress"}, "fixed_height") == "fixed_height";
    ss.shear_normal_stress = e.quantity("shear_normal_stress", units::pressure, ss.shear_normal_stress);
  }
  validate(cfg.strength);

  if (root.has("output")) {
    const InputNode o = root.child("output");
    cfg.output_directory = o.string("directory", cfg.output_directory);
    cfg.plots = o.boolean("plots", cfg.plots);
    cfg.progress_seconds = o.quantity("progress_seconds", units::time, cfg.progress_seconds);
    if (!(cfg.progress_seconds > 0))
      throw input_error("output.progress_seconds", format_value(cfg.progress_seconds), "must be > 0");
  }
  cfg.threads = static_cast<int>(root.integer("threads", 0));
  if (cfg.threads < 0) throw input_error("threads", std::to_string(cfg.threads), "must be >= 0");
  root.reject_unknown_keys();

  // Expand the sweeps: test, sample, nu, s, d0 (innermost), so that each strength-vs-d0 curve is one block.
  std::vector<SampleChoice> samples;
  if (lattice) {
    for (int a : axes) {
      HcpSampleSpec h = spec;
      h.c_axis = a;
      samples.push_back({true, h, 0.0, {}, spec.wall_thickness});
    }
  } else {
    for (const std::string& f : files) samples.push_back({false, spec, 0.0, f, spec.wall_thickness});
  }
  for (PatchTest t : tests)
    for (const SampleChoice& sc : samples)
      for (double nu : nus)
        for (double s : scalings) {
          const std::vector<double> sizes = sc.lattice ? d0s : std::vector<double>{0.0};
          for (double d : sizes) {
            PatchCase c;
            c.index = static_cast<int>(cfg.cases.size()) + 1;
            c.test = t;
            c.material = base_material;
            c.material.poisson_ratio = nu;
            c.material.scaling = s;
            c.lattice = sc.lattice;
            c.hcp = sc.hcp;
            c.hcp.d0 = d * d_c;
            c.d0_over_dc = d;
            c.data_file = sc.file;
            c.wall_thickness = sc.wall;
            cfg.cases.push_back(c);
          }
        }
  return cfg;
}

PatchConfig read_patch_input(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw input_error("input file", path, "no such file");
  std::stringstream ss;
  ss << in.rdbuf();
  return read_patch_input_text(ss.str(), path, std::filesystem::path(path).parent_path().string());
}

PatchSample make_case_sample(const PatchCase& c) {
  if (c.lattice) return make_hcp_sample(c.hcp, c.material);
  LammpsData data = read_lammps_data(c.data_file, {true, true, true});
  return make_walled_sample(data.box, std::move(data.particles), c.wall_thickness, c.material, "sample.lammps_data",
                            "sample from " + c.data_file);
}

}  // namespace debris
