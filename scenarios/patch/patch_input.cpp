#include "scenarios/patch/patch_input.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "core/error.hpp"
#include "core/io/input.hpp"
#include "scenarios/common/dem/cohesive_material_input.hpp"
#include "core/io/lammps_data.hpp"
#include "scenarios/patch/amorphous_cache.hpp"
#include "scenarios/patch/patch_keys.hpp"

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

// Raises the box width of an amorphous spec to what the engine's neighbour list needs, with 6% to spare
// for phase 2, whose box shrank by up to 4.6% per axis in the samples measured (scenarios/amorphous/README.md).
// Returns a note saying so, or an empty string.
std::string raise_width(AmorphousSpec& a) {
  const double w_min = 1.06 * a.min_periodic_length() / a.d0_absolute();
  if (a.width >= w_min) return {};
  const double from = a.width;
  a.width = std::ceil(100.0 * w_min) / 100.0;
  return "W raised from " + format_value(from) + " to " + format_value(a.width) +
         " d0: the neighbour list needs 2 (cutoff + skin) of the largest particles, plus 6% for phase 2";
}

// overlap_limit: a number of smallest radii, or auto (0).
double overlap_limit_key(const InputNode& n) {
  if (!n.has("overlap_limit")) return 0.0;
  if (n.child("overlap_limit").text() == "auto") return 0.0;
  const double v = n.quantity("overlap_limit", units::dimensionless);
  if (!(std::isfinite(v) && v > 0))
    throw input_error(
        n.child("overlap_limit").path(), format_value(v),
        "must be > 0 (in smallest radii of the sample) or auto (the deepest initial overlap + an allowance)");
  return v;
}

}  // namespace

std::string PatchCase::sample_label() const {
  if (amorphous) return amorphous_label;
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
    base_material = read_cohesive_material(m, base_material, {.poisson_and_scaling = false});
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

  // Samples: HCP lattices (orientations x diameters), LAMMPS data files, or amorphous samples (diameters,
  // or the system sizes x divisions x d_l choices of the discretisation study).
  struct SampleChoice {
    bool lattice;
    HcpSampleSpec hcp;
    double d0_over_dc;
    std::string file;
    double wall;
    // amorphous: one case per entry of `sizes` (d0 / d_c, L / d0, d_l_fixed / d_c or 0)
    std::string label;
    double system_size = 0;
    std::vector<std::array<double, 3>> sizes;
  };
  std::vector<int> axes;
  std::vector<double> d0s;
  std::vector<std::string> files;
  const InputNode sample = root.child("sample");
  const std::string kind = sample.choice("kind", {"hcp", "lammps_data", "amorphous"}, "hcp");
  const bool lattice = kind == "hcp", amorphous = kind == "amorphous";
  HcpSampleSpec spec;
  spec.wall_thickness = sample.quantity("wall_thickness", units::dimensionless, spec.wall_thickness);
  AmorphousSpec aspec;
  aspec.length = 25;  // the lattice tests' L
  aspec.width = 3;    // the paper's W, raised per case to the engine's minimum
  std::vector<SampleChoice> amorphous_choices;
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
  } else if (amorphous) {
    read_amorphous_sample_keys(sample, aspec);
    if (root.has("relaxation")) read_amorphous_relaxation_keys(root.child("relaxation"), aspec);
    cfg.cache_directory = sample.string("cache", "");
    if (sample.has("discretisation")) {
      // Appendix A.4: systems of fixed size L (units of d_c) cut into d0 = L / n, with d_l = d_l (units of
      // d0) times the coarsest d0 for every n (fixed; the paper: 1.25 L / 25 = 0.05 L) or times each d0.
      for (const char* k : {"d0", "length", "d_l_fixed"})
        if (sample.has(k))
          throw input_error(std::string("sample.") + k, sample.child(k).text(),
                            "is set by sample.discretisation (d0 = size / divisions); leave it out");
      const InputNode dz = sample.child("discretisation");
      const std::vector<double> sizes = one_or_list(dz, "size", units::dimensionless, 0.0);
      const std::vector<double> divisions = one_or_list(dz, "divisions", units::dimensionless, 0.0);
      std::vector<std::string> modes;
      if (dz.has("d_l"))
        for (const InputNode& m : scalars(dz, "d_l")) modes.push_back(one_of(m, {"fixed", "scaled"}));
      else
        modes = {"fixed"};
      for (double L : sizes)
        if (!(std::isfinite(L) && L > 0))
          throw input_error("sample.discretisation.size", format_value(L), "must be > 0 (L in units of d_c)");
      for (double n : divisions)
        if (!(std::isfinite(n) && n >= 1))
          throw input_error("sample.discretisation.divisions", format_value(n), "must be >= 1 (L / d0)");
      const double n_min = *std::min_element(divisions.begin(), divisions.end());
      for (double L : sizes)
        for (const std::string& m : modes) {
          SampleChoice sc{false, spec, 0.0, {}, spec.wall_thickness, {}, L, {}};
          const double fixed = m == "fixed" ? aspec.d_l * L / n_min : 0.0;
          sc.label = "amorphous L=" + format_value(L) + " d_c, d_l " +
                     (m == "fixed" ? "fixed " + format_value(fixed) + " d_c" : "= " + format_value(aspec.d_l) + " d0");
          for (double n : divisions) sc.sizes.push_back({L / n, n, fixed});
          amorphous_choices.push_back(sc);
        }
    } else {
      if (!sample.has("d0"))
        throw input_error("sample.d0", "missing", "give the mode diameter in units of d_c (eq 18), or a list of them");
      SampleChoice sc{
          false, spec, 0.0, {}, spec.wall_thickness, aspec.d_l_fixed > 0 ? "amorphous, d_l fixed" : "amorphous", 0, {}};
      for (double d : one_or_list(sample, "d0", units::dimensionless, 0.0)) {
        if (!(std::isfinite(d) && d > 0))
          throw input_error("sample.d0", format_value(d), "must be > 0 (a diameter in units of d_c)");
        sc.sizes.push_back({d, aspec.length, aspec.d_l_fixed});
      }
      amorphous_choices.push_back(sc);
    }
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
    es.overlap_limit = overlap_limit_key(e);
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
    ss.overlap_limit = overlap_limit_key(e);
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
  audit_keys(root, patch_keys());

  // Expand the sweeps: test, sample, nu, s, d0 (innermost), so that each strength-vs-d0 curve is one block.
  std::vector<SampleChoice> samples;
  if (lattice) {
    for (int a : axes) {
      HcpSampleSpec h = spec;
      h.c_axis = a;
      samples.push_back({true, h, 0.0, {}, spec.wall_thickness, {}, 0, {}});
    }
  } else if (amorphous) {
    samples = amorphous_choices;
  } else {
    for (const std::string& f : files) samples.push_back({false, spec, 0.0, f, spec.wall_thickness, {}, 0, {}});
  }
  for (PatchTest t : tests)
    for (const SampleChoice& sc : samples)
      for (double nu : nus)
        for (double s : scalings) {
          const std::size_t count = sc.lattice ? d0s.size() : (amorphous ? sc.sizes.size() : 1);
          for (std::size_t k = 0; k < count; ++k) {
            PatchCase c;
            c.index = static_cast<int>(cfg.cases.size()) + 1;
            c.test = t;
            c.material = base_material;
            c.material.poisson_ratio = nu;
            c.material.scaling = s;
            c.lattice = sc.lattice;
            c.hcp = sc.hcp;
            c.data_file = sc.file;
            c.wall_thickness = sc.wall;
            if (sc.lattice) {
              c.hcp.d0 = d0s[k] * d_c;
              c.d0_over_dc = d0s[k];
            }
            if (amorphous) {
              c.amorphous = true;
              c.amorphous_label = sc.label;
              c.system_size = sc.system_size;
              c.d0_over_dc = sc.sizes[k][0];
              AmorphousSpec& a = c.amorphous_spec;
              a = aspec;
              a.material = c.material;
              a.d0 = sc.sizes[k][0];
              a.length = sc.sizes[k][1];
              // A fixed d_l equal to d_l d0 (the coarsest samples of the study) is the same sample as the
              // scaled one: given the same way, it is made once.
              if (sc.sizes[k][2] > 0 && std::abs(sc.sizes[k][2] - a.d_l * a.d0) > 1e-12 * sc.sizes[k][2])
                a.d_l_fixed = sc.sizes[k][2];
              try {
                if (!(a.d0 * d_c >= a.material.minimum_diameter())) a.validate();  // d0 below d_min: its message
                c.width_note = raise_width(a);
                a.validate();
              } catch (const InputError& e) {
                throw InputError(std::string(e.what()) + " [case " + std::to_string(c.index) +
                                 ": amorphous sample d0 = " + format_value(a.d0) + " d_c, s = " + format_value(s) +
                                 ", nu = " + format_value(nu) + "]");
              }
            }
            cfg.cases.push_back(c);
          }
        }
  return cfg;
}

PatchConfig read_patch_input(const std::string& path) {
  return read_patch_input_text(read_input_file(path), path, std::filesystem::path(path).parent_path().string());
}

PatchSample make_case_sample(const PatchCase& c, AmorphousSampleCache* cache) {
  if (c.amorphous) {
    if (!cache) throw std::invalid_argument("make_case_sample: an amorphous case needs the sample cache");
    const AmorphousSampleFile& f = cache->get(c.amorphous_spec);
    std::string what = "amorphous sample (section 3.2 recipe), d0 = " + format_value(c.d0_over_dc) + " d_c, d in [" +
                       format_value(c.amorphous_spec.d_s_absolute()) + ", " +
                       format_value(c.amorphous_spec.d_l_absolute()) + "], relaxed volume fraction " +
                       format_value(f.relaxed_fraction) + ", " + cache->source(c.amorphous_spec);
    if (!c.width_note.empty()) what += " (" + c.width_note + ")";
    PatchSample s = make_walled_sample(f.box, f.particles, c.wall_thickness, c.material, "sample", what);
    s.volume_fraction = f.relaxed_fraction;
    return s;
  }
  if (c.lattice) return make_hcp_sample(c.hcp, c.material);
  LammpsData data = read_lammps_data(c.data_file, {true, true, true});
  return make_walled_sample(data.box, std::move(data.particles), c.wall_thickness, c.material, "sample.lammps_data",
                            "sample from " + c.data_file);
}

void check_case_sample(const PatchCase& c) {
  if (c.amorphous) {
    insert_random_spheres(c.amorphous_spec);  // validates, and throws for a volume fraction it cannot reach
    return;
  }
  make_case_sample(c);
}

}  // namespace debris
