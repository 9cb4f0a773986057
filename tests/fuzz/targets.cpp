// The fuzz targets: every reader of outside data, called as the executables call it.
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstring>
#include <typeinfo>
#include <filesystem>
#include <fstream>
#include <optional>

#include "core/error.hpp"
#include "core/io/gmsh_msh.hpp"
#include "core/io/hdf5_seal.hpp"
#include "core/io/grain_csv.hpp"
#include "core/io/input.hpp"
#include "core/io/lammps_data.hpp"
#include "core/rough/height_map_file.hpp"
#include "scenarios/amorphous/amorphous_input.hpp"
#include "scenarios/common/dem/dem_input.hpp"
#include "scenarios/common/dem/dem_simulation.hpp"
#include "scenarios/common/peridem/peridem_input.hpp"
#include "scenarios/common/peridem/peridem_simulation.hpp"
#include "scenarios/patch/patch_input.hpp"
#include "scenarios/restitution/restitution_input.hpp"
#include "tests/fuzz/fuzz.hpp"
#include "tests/fuzz/hdf5_mutation.hpp"

namespace debris::fuzz {

namespace {

namespace fs = std::filesystem;

const std::string kSource = DEBRIS_SOURCE_DIR;

bool is_input_error(const std::exception& e) { return dynamic_cast<const InputError*>(&e) != nullptr; }

// The restart loaders report a file that is not a checkpoint of theirs, or a damaged one, as InputError or as
// a std::runtime_error naming the file ("checkpoint <path>: ..." from the loaders, "HDF5: ..." from
// core/io/hdf5_file): the runner prints it and exits 1. Other exception types (std::out_of_range,
// std::length_error, std::bad_alloc) would mean the loader trusted the file.
bool is_checkpoint_error(const std::exception& e) {
  if (is_input_error(e)) return true;
  if (typeid(e) != typeid(std::runtime_error)) return false;
  const std::string what = e.what();
  return what.rfind("checkpoint ", 0) == 0 || what.rfind("HDF5: ", 0) == 0;
}

void write_file(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

// An input may rightly ask for a lattice larger than this machine holds (up to 2^31 sites): the fuzzer tests
// the reader, not the memory, so DEM inputs asking for more than 10^5 sites are skipped (counted as such).
bool lattice_too_large(const std::string& text) {
  try {
    const YAML::Node cells = YAML::Load(text)["particles"]["lattice"]["cells"];
    if (!cells.IsSequence()) return false;
    double sites = 4;
    for (const YAML::Node& c : cells) sites *= std::abs(c.as<double>());
    return sites > 1e5;
  } catch (const std::exception&) {
    return false;  // whatever the reader makes of it
  }
}

// The checkpoints the checkpoint targets mutate: small real runs, written once per fuzzer process.
const char* kDemSeedInput = R"(material: {youngs_modulus: 1, poisson_ratio: 0.15, tensile_strength: 0.2, shear_strength: 0.1,
  surface_energy: 1.5, restitution: 0.95, density: 1, scaling: 0}
particles:
  lattice: {kind: hcp, hcp_c_axis: y, spacing: 100, diameter: 100, cells: [4, 3, 2], size_spread: 0.04, displacement: 1}
box: {periodic: [true, false, true]}
groups:
  - {name: bottom, region: {y: [-inf, 100]}, motion: frozen}
  - {name: top, region: {y: [350, inf]}, motion: force, stress: [0.001, -0.01, 0]}
run: {steps: 40, time_step_fraction: 0.1, global_damping: 0.02}
)";

const std::string& dem_seed_checkpoint(const std::string& scratch) {
  static std::string path;
  if (path.empty()) {
    DemRunConfig cfg = read_dem_input_text(kDemSeedInput, "dem_seed.yaml", scratch);
    DemSimulation sim(cfg.box, std::move(cfg.particles), std::move(cfg.groups), cfg.settings);
    sim.run(40);
    path = scratch + "/dem_seed_checkpoint.h5";
    sim.write_checkpoint(path, kDemSeedInput);
    strip_seal(path);
  }
  return path;
}

std::string peridem_seed_input() {
  const std::string mesh = kSource + "/scenarios/peridem/data/two_particle_circ_example/mesh_cir_1_0.msh";
  return R"(dimension: 2
materials:
  M1: {density: 1200 kg/m^3, bulk_modulus: 0.0216 GPa, shear_modulus: 0.01296 GPa, fracture_energy: 50 J/m^2, horizon: 0.6 mm}
  M2: {density: 1200 kg/m^3, bulk_modulus: 0.0216 GPa, shear_modulus: 0.01296 GPa, fracture_energy: 0.5 J/m^2, horizon: 0.6 mm}
shapes:
  disc: {type: mesh_file, file: )" + mesh + R"(, reference_radius: 1 mm}
grains:
  - {name: bottom, shape: disc, material: M1, centre: [0, 1.2 mm, 0], fixed: true}
  - {name: top, shape: disc, material: M2, centre: [0.1 mm, 3.3 mm, 0], velocity: [0, -20 m/s, 0]}
contact: {restitution: 0.9, friction: 0.3, pairs: [{materials: [M1, M2], restitution: 0.8}]}
gravity: [0, -10 m/s^2, 0]
run: {time_step: 0.05 us, steps: 150, skin: 0.05 mm}
)";
}

const std::string& peridem_seed_checkpoint(const std::string& scratch) {
  static std::string path;
  if (path.empty()) {
    PeridemInputOptions o;
    o.output_directory = scratch;
    PeridemRunConfig cfg = read_peridem_input_text(peridem_seed_input(), "peridem_seed.yaml", scratch, o);
    PeridemSimulation sim(std::move(cfg.nodes), std::move(cfg.grains), cfg.materials, cfg.contact, cfg.settings);
    sim.set_grain_names(cfg.grain_names);
    sim.run(150);
    path = scratch + "/peridem_seed_checkpoint.h5";
    sim.write_checkpoint(path, peridem_seed_input());
    strip_seal(path);
  }
  return path;
}

// A few edit programs to start from (tests/fuzz/hdf5_mutation.cpp reads them): none, and short ones.
std::vector<std::string> program_seeds() {
  std::vector<std::string> out{std::string()};
  for (unsigned k = 0; k < 64; ++k) {
    std::string p;
    for (unsigned b = 0; b < 6; ++b) p += static_cast<char>((k * 37u + b * 101u + k * b * 13u) & 0xff);
    out.push_back(p);
  }
  return out;
}

}  // namespace

std::vector<Target> all_targets(const std::string& scratch) {
  std::vector<Target> t;
  const std::string file = scratch + "/input";

  t.push_back({"dem_input", "debris_dem YAML input (read_dem_input_text; LAMMPS data paths relative to scenarios/wear)",
               [](const std::string& in) {
                 if (lattice_too_large(in)) return Outcome::skipped;
                 read_dem_input_text(in, "fuzz.yaml", kSource + "/scenarios/wear");
                 return Outcome::accepted;
               },
               is_input_error, {"yaml"}, nullptr, "a lattice of more than 1e5 sites", nullptr});

  t.push_back({"peridem_input", "debris_peridem YAML input (read_peridem_input_text, system not built: no Gmsh run)",
               [scratch](const std::string& in) {
                 PeridemInputOptions o;
                 o.build_system = false;
                 o.output_directory = scratch + "/peridem_out";
                 read_peridem_input_text(in, "fuzz.yaml", kSource + "/scenarios/peridem", o);
                 return Outcome::accepted;
               },
               is_input_error, {"yaml"}, nullptr, "", nullptr});

  t.push_back({"patch_input", "debris_patch YAML input (read_patch_input_text)",
               [](const std::string& in) {
                 read_patch_input_text(in, "fuzz.yaml", kSource + "/scenarios/patch");
                 return Outcome::accepted;
               },
               is_input_error, {"yaml"}, nullptr, "", nullptr});

  t.push_back({"amorphous_input", "debris_amorphous YAML input (read_amorphous_config)",
               [](const std::string& in) {
                 read_amorphous_config(in, "fuzz.yaml");
                 return Outcome::accepted;
               },
               is_input_error, {"yaml"}, nullptr, "", nullptr});

  t.push_back({"restitution_input", "debris_restitution YAML input (read_restitution_input_text)",
               [scratch](const std::string& in) {
                 read_restitution_input_text(in, "fuzz.yaml", scratch + "/restitution_out");
                 return Outcome::accepted;
               },
               is_input_error, {"yaml"}, nullptr, "", nullptr});

  t.push_back({"lammps_data", "LAMMPS data file, atom_style sphere (read_lammps_data)",
               [file](const std::string& in) {
                 write_file(file, in);
                 const bool periodic = in.size() % 2 == 0;  // both ways, decided by the input
                 read_lammps_data(file, {periodic, false, periodic});
                 return Outcome::accepted;
               },
               is_input_error, {"data"}, nullptr, "", nullptr});

  t.push_back({"height_map", "measured height map, a text grid of heights (read_height_map)",
               [file](const std::string& in) {
                 write_file(file, in);
                 read_height_map(file, 1, 1e-9, 1e-9, 1e-9);
                 return Outcome::accepted;
               },
               is_input_error, {"txt"}, nullptr, "", nullptr});

  t.push_back({"gmsh_msh", "Gmsh MSH 2.2 / 4.1 ASCII mesh (read_gmsh_msh)",
               [file](const std::string& in) {
                 write_file(file, in);
                 read_gmsh_msh(file);
                 return Outcome::accepted;
               },
               is_input_error, {"msh"}, nullptr, "", nullptr});

  t.push_back({"grain_csv", "PeriDEM particle CSV (read_grain_csv)",
               [file](const std::string& in) {
                 write_file(file, in);
                 read_grain_csv(file);
                 return Outcome::accepted;
               },
               is_input_error, {"csv"}, nullptr, "", nullptr});

  t.push_back({"dem_checkpoint", "debris_dem checkpoint: a real one with datasets deleted, resized, retyped or set to awkward values",
               [scratch, file](const std::string& in) {
                 mutate_hdf5(dem_seed_checkpoint(scratch), file, in);
                 DemSimulation::from_checkpoint(file);
                 return Outcome::accepted;
               },
               is_checkpoint_error, {}, program_seeds, "", nullptr});
  t.back().prepare = [scratch] { dem_seed_checkpoint(scratch); };

  t.push_back({"peridem_checkpoint", "debris_peridem checkpoint: a real one with datasets deleted, resized, retyped or set to awkward values",
               [scratch, file](const std::string& in) {
                 mutate_hdf5(peridem_seed_checkpoint(scratch), file, in);
                 PeridemSimulation::from_checkpoint(file);
                 return Outcome::accepted;
               },
               is_checkpoint_error, {}, program_seeds, "", nullptr});
  t.back().prepare = [scratch] { peridem_seed_checkpoint(scratch); };

  t.push_back({"dem_checkpoint_bytes", "debris_dem checkpoint as raw bytes, sealed (the seal's reader) and unsealed (HDF5's own parser)",
               [file](const std::string& in) {
                 write_file(file, in);
                 DemSimulation::from_checkpoint(file);
                 return Outcome::accepted;
               },
               is_checkpoint_error, {"h5"},
               [scratch]() {
                 const std::string sealed = scratch + "/dem_seed_sealed.h5";
                 fs::copy_file(dem_seed_checkpoint(scratch), sealed, fs::copy_options::overwrite_existing);
                 h5::seal(sealed);
                 std::vector<std::string> s;
                 for (const std::string& p : {dem_seed_checkpoint(scratch), sealed}) {
                   std::ifstream f(p, std::ios::binary);
                   s.emplace_back(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
                 }
                 return s;
               },
               "", nullptr});
  t.back().prepare = [scratch] { dem_seed_checkpoint(scratch); };
  return t;
}

}  // namespace debris::fuzz
