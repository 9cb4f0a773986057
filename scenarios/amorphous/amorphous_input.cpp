#include "scenarios/amorphous/amorphous_input.hpp"

#include <algorithm>

#include "core/error.hpp"
#include "core/io/input.hpp"
#include "scenarios/amorphous/amorphous_keys.hpp"
#include "scenarios/common/dem/cohesive_material_input.hpp"

namespace debris {

namespace {

CohesiveMaterial read_material(const InputNode& root) {
  if (!root.has("material")) return table4_material();
  const InputNode m = root.child("material");
  const std::string preset = m.choice("preset", {"table4", "silica"}, "table4");
  return read_cohesive_material(m, preset == "silica" ? silica_material() : table4_material());
}

}  // namespace

AmorphousConfig read_amorphous_config(const std::string& text, const std::string& name) {
  const InputNode root = InputNode::load_string(text, name);
  AmorphousConfig cfg;
  AmorphousSpec& s = cfg.base;
  s.material = read_material(root);

  const InputNode sample = root.child("sample");
  s.d0 = sample.quantity("d0", units::dimensionless);
  read_amorphous_sample_keys(sample, s);
  if (root.has("relaxation")) read_amorphous_relaxation_keys(root.child("relaxation"), s);

  cfg.d0s = {s.d0};
  cfg.scalings = {s.material.scaling};
  if (root.has("sweep")) {
    const InputNode sw = root.child("sweep");
    if (sw.has("d0")) cfg.d0s = sw.numbers("d0", units::dimensionless);
    if (sw.has("scaling")) cfg.scalings = sw.numbers("scaling", units::dimensionless);
    if (cfg.d0s.empty()) throw input_error("sweep.d0", "[]", "give at least one d0 (units of d_c)");
    if (cfg.scalings.empty()) throw input_error("sweep.scaling", "[]", "give at least one s");
    std::sort(cfg.d0s.begin(), cfg.d0s.end());
  }

  if (root.has("output")) {
    const InputNode out = root.child("output");
    cfg.directory = out.string("directory", cfg.directory);
    cfg.thermo_every = out.integer("thermo_every", cfg.thermo_every);
    if (cfg.thermo_every < 1)
      throw input_error("output.thermo_every", std::to_string(cfg.thermo_every), "must be >= 1");
    cfg.save_samples = out.boolean("save_samples", cfg.save_samples);
    cfg.plot = out.boolean("plot", cfg.plot);
  }
  if (root.has("run")) {
    const InputNode run = root.child("run");
    cfg.threads = static_cast<int>(run.integer("threads", 0));
    if (cfg.threads < 0) throw input_error("run.threads", std::to_string(cfg.threads), "must be >= 0");
  }
  root.reject_unknown_keys();
  audit_keys(root, amorphous_keys());

  // Every sample of the sweep is checked before the first one runs, so a bad d0 fails now, not hours later.
  for (std::size_t k = 0; k < cfg.scalings.size(); ++k) {
    for (std::size_t j = 0; j < cfg.d0s.size(); ++j) {
      AmorphousSpec t = s;
      t.material.scaling = cfg.scalings[k];
      t.d0 = cfg.d0s[j];
      try {
        t.validate();
      } catch (const InputError& e) {
        if (cfg.d0s.size() == 1 && cfg.scalings.size() == 1) throw;
        throw InputError(std::string(e.what()) + " [sweep sample d0 = " + format_value(t.d0) +
                         " d_c, s = " + format_value(t.material.scaling) + "]");
      }
    }
  }
  return cfg;
}

}  // namespace debris
