// Checkpoint and restart of a PeriDEM run (HDF5). What N steps + checkpoint + restart + N steps needs to
// equal 2N steps bit for bit:
//  - every node column (positions, half-step velocities, this step's forces: the next kick uses them), every
//    grain array (centres, wall velocities), the step, the time as accumulated, the broken-bond count;
//  - the bonds: rebuilt from the reference positions (BondList::build is deterministic), their row offsets
//    checked against the saved ones, and the broken flags set from the saved list of broken entries;
//  - the contact list: rebuilt from the node positions at its last build, so its rows and slots, the order
//    of every force sum, and the moment of its next rebuild are those of the run that wrote it. Bonds that
//    broke after the build were added to the list in place, which gives exactly the list a build at those
//    positions with the current broken flags gives (rows ascending, core/pd_contact_list.hpp);
//  - the integrator's first-step flag is step == 0; the stable step and h (eq 35) are saved, not
//    recomputed (the stable step's power iteration is the slow part of a start).
// The LPS constants and the contact table are derived from the saved materials, contact settings and h,
// as the constructor derives them.
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "core/error.hpp"
#include "core/io/hdf5_file.hpp"
#include "scenarios/common/peridem_simulation.hpp"

namespace debris {

namespace {

constexpr std::int64_t kFormatVersion = 1;

constexpr int kMaterialFields = 6;  // density, K, G, G_c, horizon, dimension
constexpr int kContactFields = 6;   // radius factor, restitution, C, mu, stiffness factor, damping onset

std::runtime_error corrupt(const std::string& path, const std::string& what) {
  return std::runtime_error("checkpoint " + path + ": " + what);
}

}  // namespace

void PeridemSimulation::write_checkpoint(const std::string& path, const std::string& input_echo) const {
  const std::string tmp = path + ".tmp";
  {
    h5::File f(tmp, h5::File::Mode::create);
    f.set_attribute<std::int64_t>("format_version", kFormatVersion);
    f.set_string_attribute("format", "debris PeriDEM checkpoint 1");
    f.write_string("input", input_echo);
    // Each section in its own scope: HDF5 keeps a file open while anything opened from it lives.
    {
      h5::Group state = f.create_group("state");
      state.write_scalar<std::int64_t>("step", step_);
      state.write_scalar<double>("time", time_);
      state.write_scalar<std::int64_t>("broken_bonds", broken_total_);
      state.write_scalar<std::int64_t>("contact_rebuilds", rebuilds_);
      state.write_scalar<double>("mesh_size", mesh_size_);
      state.write_scalar<double>("stable_time_step", stable_dt_);
      state.write_scalar<double>("skin", skin_);
    }
    {
      h5::Group set = f.create_group("settings");
      set.write_scalar<double>("time_step", settings_.time_step);
      set.write_scalar<std::int32_t>("allow_unstable_time_step", settings_.allow_unstable_time_step ? 1 : 0);
      set.write("gravity", std::vector<double>{settings_.gravity.x, settings_.gravity.y, settings_.gravity.z});
      set.write_scalar<std::int32_t>("damping", static_cast<std::int32_t>(settings_.damping));
      set.write_scalar<double>("skin", settings_.skin);
      std::vector<double> mats;
      for (const PdMaterial& m : materials_)
        mats.insert(mats.end(), {m.density, m.bulk_modulus, m.shear_modulus, m.fracture_energy, m.horizon,
                                 static_cast<double>(m.dimension)});
      set.write("materials", mats, materials_.size(), kMaterialFields);
      std::vector<std::int32_t> compression;
      for (const PdMaterial& m : materials_) compression.push_back(m.break_in_compression);
      set.write("materials_break_in_compression", compression);
      std::vector<double> contact;
      for (const PdContactSettings& c : contact_settings_)
        contact.insert(contact.end(), {c.contact_radius_factor, c.restitution, c.damping_factor, c.friction,
                                       c.stiffness_factor, c.damping_onset_factor});
      set.write("contact", contact, contact_settings_.size(), kContactFields);
    }
    {
      h5::Group nodes = f.create_group("nodes");
      const_cast<PdNodes&>(nodes_).for_each_column([&](const char* name, auto& col) { nodes.write(name, col); });
    }
    {
      h5::Group g = f.create_group("grains");
      g.write("node_begin", grains_.node_begin);
      g.write("node_end", grains_.node_end);
      g.write("kind", grains_.kind);
      g.write("material", grains_.material);
      g.write("volume", grains_.volume);
      g.write("cx", grains_.cx);
      g.write("cy", grains_.cy);
      g.write("cz", grains_.cz);
      g.write("cvx", grains_.cvx);
      g.write("cvy", grains_.cvy);
      g.write("cvz", grains_.cvz);
      g.write("wall_vx", grains_.wall_vx);
      g.write("wall_vy", grains_.wall_vy);
      g.write("wall_vz", grains_.wall_vz);
      g.write_strings("name", grain_names_);
    }
    {
      h5::Group b = f.create_group("bonds");
      b.write("offset", bonds_.offset);
      std::vector<std::int64_t> broken;
      std::vector<std::int32_t> partner;
      for (std::size_t k = 0; k < bonds_.entries(); ++k)
        if (bonds_.broken[k]) {
          broken.push_back(static_cast<std::int64_t>(k));
          partner.push_back(bonds_.partner[k]);
        }
      b.write_scalar<std::int64_t>("entries", static_cast<std::int64_t>(bonds_.entries()));
      b.write("broken_entry", broken);
      b.write("broken_partner", partner);
    }
    {
      h5::Group l = f.create_group("contact_list");
      l.write("x_at_build", list_x_);
      l.write("y_at_build", list_y_);
      l.write("z_at_build", list_z_);
    }
    f.close();
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw std::runtime_error("checkpoint: cannot rename " + tmp + " to " + path + ": " + ec.message());
}

PeridemSimulation PeridemSimulation::from_checkpoint(const std::string& path, std::string* input_echo) {
  if (!std::filesystem::exists(path)) throw input_error("restart", path, "no such checkpoint file");
  h5::File f(path, h5::File::Mode::read_only);
  if (!f.has_attribute("format_version") || !f.has("bonds"))
    throw input_error("restart", path, "is not a debris_peridem checkpoint");
  if (f.attribute<std::int64_t>("format_version") != kFormatVersion)
    throw input_error("restart", path, "written by an incompatible version of debris");
  if (input_echo) *input_echo = f.read_string("input");

  PeridemSimulation sim{Restored{}};
  {
    const h5::Group set = f.open_group("settings");
    sim.settings_.time_step = set.read_scalar<double>("time_step");
    sim.settings_.allow_unstable_time_step = set.read_scalar<std::int32_t>("allow_unstable_time_step") != 0;
    const auto g = set.read<double>("gravity").values;
    if (g.size() != 3) throw corrupt(path, "settings/gravity is not 3 values");
    sim.settings_.gravity = {g[0], g[1], g[2]};
    sim.settings_.damping = static_cast<PdDamping>(set.read_scalar<std::int32_t>("damping"));
    sim.settings_.skin = set.read_scalar<double>("skin");
    const auto mats = set.read<double>("materials").values;
    if (mats.empty() || mats.size() % kMaterialFields != 0) throw corrupt(path, "settings/materials has a bad shape");
    for (std::size_t k = 0; k < mats.size(); k += kMaterialFields) {
      PdMaterial m;
      m.density = mats[k];
      m.bulk_modulus = mats[k + 1];
      m.shear_modulus = mats[k + 2];
      m.fracture_energy = mats[k + 3];
      m.horizon = mats[k + 4];
      m.dimension = static_cast<int>(mats[k + 5]);
      sim.materials_.push_back(m);
    }
    // Absent from checkpoints written before the setting existed: bonds broke in tension only then.
    if (set.has("materials_break_in_compression")) {
      const auto compression = set.read<std::int32_t>("materials_break_in_compression").values;
      if (compression.size() != sim.materials_.size())
        throw corrupt(path, "settings/materials_break_in_compression does not match the materials");
      for (std::size_t k = 0; k < compression.size(); ++k) sim.materials_[k].break_in_compression = compression[k] != 0;
    }
    const auto contact = set.read<double>("contact").values;
    if (contact.empty() || contact.size() % kContactFields != 0)
      throw corrupt(path, "settings/contact has a bad shape");
    for (std::size_t k = 0; k < contact.size(); k += kContactFields) {
      PdContactSettings c;
      c.contact_radius_factor = contact[k];
      c.restitution = contact[k + 1];
      c.damping_factor = contact[k + 2];
      c.friction = contact[k + 3];
      c.stiffness_factor = contact[k + 4];
      c.damping_onset_factor = contact[k + 5];
      sim.contact_settings_.push_back(c);
    }
  }
  {
    const h5::Group state = f.open_group("state");
    sim.step_ = state.read_scalar<std::int64_t>("step");
    sim.time_ = state.read_scalar<double>("time");
    sim.broken_total_ = state.read_scalar<std::int64_t>("broken_bonds");
    sim.rebuilds_ = state.read_scalar<std::int64_t>("contact_rebuilds");
    sim.mesh_size_ = state.read_scalar<double>("mesh_size");
    sim.stable_dt_ = state.read_scalar<double>("stable_time_step");
    sim.skin_ = state.read_scalar<double>("skin");
  }
  {
    const h5::Group nodes = f.open_group("nodes");
    sim.nodes_.for_each_column([&](const char* name, auto& col) {
      using T = typename std::decay_t<decltype(col)>::value_type;
      if constexpr (std::is_same_v<T, int>)
        col = nodes.read<std::int32_t>(name).values;
      else
        col = nodes.read<T>(name).values;
    });
    const std::size_t n = sim.nodes_.size();
    sim.nodes_.for_each_column([&](const char* name, auto& col) {
      if (col.size() != n) throw corrupt(path, std::string("nodes/") + name + " has another length than nodes/id");
    });
  }
  {
    const h5::Group g = f.open_group("grains");
    PdGrains& gr = sim.grains_;
    gr.node_begin = g.read<std::int32_t>("node_begin").values;
    gr.node_end = g.read<std::int32_t>("node_end").values;
    gr.kind = g.read<std::int32_t>("kind").values;
    gr.material = g.read<std::int32_t>("material").values;
    for (auto [name, col] : {std::pair{"volume", &gr.volume},
                             {"cx", &gr.cx},
                             {"cy", &gr.cy},
                             {"cz", &gr.cz},
                             {"cvx", &gr.cvx},
                             {"cvy", &gr.cvy},
                             {"cvz", &gr.cvz},
                             {"wall_vx", &gr.wall_vx},
                             {"wall_vy", &gr.wall_vy},
                             {"wall_vz", &gr.wall_vz}})
      *col = g.read<double>(name).values;
    sim.grain_names_ = g.read_strings("name");
    const std::size_t ng = gr.node_begin.size();
    for (const std::size_t s : {gr.node_end.size(), gr.kind.size(), gr.material.size(), gr.volume.size(), gr.cx.size(),
                                gr.wall_vz.size(), sim.grain_names_.size()})
      if (s != ng) throw corrupt(path, "the grain arrays have different lengths");
    for (std::size_t k = 0; k < ng; ++k)
      if (gr.material[k] < 0 || static_cast<std::size_t>(gr.material[k]) >= sim.materials_.size() ||
          gr.node_begin[k] < 0 || gr.node_end[k] < gr.node_begin[k] ||
          static_cast<std::size_t>(gr.node_end[k]) > sim.nodes_.size())
        throw corrupt(path, "grain " + std::to_string(k) + " does not fit the nodes or materials");
  }

  // Derived data, as the constructor derives it.
  for (std::size_t m = 0; m < sim.materials_.size(); ++m) {
    const std::string prefix = "materials[" + std::to_string(m) + "]";
    sim.lps_.push_back(PdLpsConstants::from(sim.materials_[m], prefix.c_str()));
  }
  sim.table_ = sim.contact_settings_.size() == 1
                   ? pd_contact_table(sim.materials_, sim.contact_settings_.front(), sim.mesh_size_)
                   : pd_contact_table(sim.materials_, sim.contact_settings_, sim.mesh_size_);
  std::vector<double> horizon(sim.grains_.size());
  for (std::size_t g = 0; g < sim.grains_.size(); ++g)
    horizon[g] = sim.materials_[static_cast<std::size_t>(sim.grains_.material[g])].horizon;
  sim.bonds_ = BondList::build(sim.nodes_, sim.grains_, horizon);
  {
    const h5::Group b = f.open_group("bonds");
    if (b.read<std::int32_t>("offset").values != sim.bonds_.offset ||
        b.read_scalar<std::int64_t>("entries") != static_cast<std::int64_t>(sim.bonds_.entries()))
      throw corrupt(path, "the bonds rebuilt from the reference positions differ from the saved ones");
    const auto broken = b.read<std::int64_t>("broken_entry").values;
    const auto partner = b.read<std::int32_t>("broken_partner").values;
    if (broken.size() != partner.size()) throw corrupt(path, "bonds/broken_entry and broken_partner differ in length");
    for (std::size_t k = 0; k < broken.size(); ++k) {
      const auto e = broken[k];
      if (e < 0 || static_cast<std::size_t>(e) >= sim.bonds_.entries() ||
          sim.bonds_.partner[static_cast<std::size_t>(e)] != partner[k])
        throw corrupt(path, "broken bond entry " + std::to_string(e) + " does not match the rebuilt bonds");
      sim.bonds_.broken[static_cast<std::size_t>(e)] = 1;
    }
  }
  {
    const h5::Group l = f.open_group("contact_list");
    sim.list_x_ = l.read<double>("x_at_build").values;
    sim.list_y_ = l.read<double>("y_at_build").values;
    sim.list_z_ = l.read<double>("z_at_build").values;
    const std::size_t n = sim.nodes_.size();
    if (sim.list_x_.size() != n || sim.list_y_.size() != n || sim.list_z_.size() != n)
      throw corrupt(path, "contact_list positions do not match the nodes");
    PdNodes at_build = sim.nodes_;
    at_build.x = sim.list_x_;
    at_build.y = sim.list_y_;
    at_build.z = sim.list_z_;
    sim.list_.build(at_build, sim.grains_, sim.bonds_, sim.table_.max_contact_radius(), sim.skin_);
  }
  return sim;
}

}  // namespace debris
