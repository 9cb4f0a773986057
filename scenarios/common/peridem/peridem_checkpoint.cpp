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
// Offload builds: the writer brings the state back from the device first (state_to_host), the reader sends
// everything it read and derived to the device before it rebuilds the contact list there.
//
// The file is sealed with checksums and everything read is checked before it is used
// (scenarios/common/run/checkpoint_file.hpp): a damaged or foreign file is an input error naming it.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "core/comm/communicator.hpp"
#include "core/comm/grain_migration.hpp"
#include "core/comm/pack.hpp"
#include "core/error.hpp"
#include "core/exec.hpp"
#include "core/io/hdf5_file.hpp"
#include "kernels/peridem/pd_bond_passes.hpp"
#include "scenarios/common/run/checkpoint_file.hpp"
#include "scenarios/common/peridem/peridem_simulation.hpp"

namespace debris {

namespace {

// 2: sealed with checksums. Unsealed files (format 1) are refused (checkpoint_file.hpp).
constexpr std::int64_t kFormatVersion = 2;
constexpr std::int64_t kOldestFormat = 2;  // the first sealed format

constexpr int kMaterialFields = 6;  // density, K, G, G_c, horizon, dimension
constexpr int kContactFields = 6;   // radius factor, restitution, C, mu, stiffness factor, damping onset

InputError corrupt(const std::string& path, const std::string& what) { return unsound_checkpoint(path, what); }

bool all_finite(const std::vector<double>& v) {
  return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}

}  // namespace

void PeridemSimulation::write_checkpoint(const std::string& path, const std::string& input_echo) const {
  state_to_host();
  if (distributed_) return write_distributed_checkpoint(path, input_echo);
  write_checkpoint_of(path, input_echo, nodes_, grains_, bonds_, positions_at_build(), broken_total_);
}

PeridemSimulation::Positions PeridemSimulation::positions_at_build() const {
  return {std::vector<double>(list_.x_at_build().begin(), list_.x_at_build().end()),
          std::vector<double>(list_.y_at_build().begin(), list_.y_at_build().end()),
          std::vector<double>(list_.z_at_build().begin(), list_.z_at_build().end())};
}

void PeridemSimulation::write_distributed_checkpoint(const std::string& path, const std::string& input_echo) const {
  // The whole system on rank 0, as one process holds it: every rank's own nodes with their grains (a wall's
  // pieces merged) and bond rows, and the positions of its own nodes at the list's last build.
  PdNodes nodes;
  PdGrains grains;
  BondList bonds;
  // (Read only: the store's references are not const.)
  const comm::GrainStore mine{const_cast<PdNodes&>(nodes_), const_cast<PdGrains&>(grains_), const_cast<BondList&>(bonds_)};
  comm::gather_to_root(mine, halo_.owned_nodes(), {nodes, grains, bonds});
  std::vector<char> built;
  for (std::size_t i = 0; i < nodes_.size(); ++i)
    if (owns_node(i)) {
      comm::pack_value(nodes_.id[i], built);
      for (const auto* c : {&list_.x_at_build(), &list_.y_at_build(), &list_.z_at_build()}) comm::pack_value((*c)[i], built);
    }
  const std::vector<std::vector<char>> parts = comm::gather_to_root(built);
  std::int64_t broken = broken_total_;  // each rank's count of the bonds it broke
  comm::allreduce_sum(&broken, 1);
  if (comm::rank() != 0) return;  // rank 0 writes the file
  Positions at_build;
  for (auto& c : at_build) c.assign(nodes.size(), 0.0);
  for (const std::vector<char>& part : parts) {
    comm::Unpacker u(part);
    while (!u.done()) {
      const auto id = u.value<std::int64_t>();
      const auto w = static_cast<std::size_t>(std::lower_bound(nodes.id.begin(), nodes.id.end(), id) - nodes.id.begin());
      for (auto& c : at_build) c[w] = u.value<double>();
    }
  }
  // The centres one process holds at this step (a piece of a wall had its own): from the gathered nodes.
  PdContactWork work;
  pd_grain_centres(nodes, grains, work);
  write_checkpoint_of(path, input_echo, nodes, grains, bonds, at_build, broken);
}

void PeridemSimulation::write_checkpoint_of(const std::string& path, const std::string& input_echo, const PdNodes& nodes,
                                            const PdGrains& grains, const BondList& bonds,
                                            const Positions& at_build, long broken_total) const {
  write_checkpoint_file(path, [&](const std::string& tmp) {
    h5::File f(tmp, h5::File::Mode::create);
    f.set_attribute<std::int64_t>("format_version", kFormatVersion);
    f.set_string_attribute("format", "debris PeriDEM checkpoint " + std::to_string(kFormatVersion));
    f.write_string("input", input_echo);
    // Each section in its own scope: HDF5 keeps a file open while anything opened from it lives.
    {
      h5::Group state = f.create_group("state");
      state.write_scalar<std::int64_t>("step", step_);
      state.write_scalar<double>("time", time_);
      state.write_scalar<std::int64_t>("broken_bonds", broken_total);
      state.write_scalar<std::int64_t>("contact_rebuilds", rebuilds_);
      state.write_scalar<double>("mesh_size", mesh_size_);
      state.write_scalar<double>("stable_time_step", stable_dt_);
      state.write_scalar<double>("skin", skin_);
      state.write("placed_box", std::vector<double>{placed_lo_.x, placed_lo_.y, placed_lo_.z, placed_hi_.x,
                                                    placed_hi_.y, placed_hi_.z});
    }
    {
      h5::Group set = f.create_group("settings");
      set.write_scalar<double>("time_step", settings_.time_step);
      set.write_scalar<std::int32_t>("allow_unstable_time_step", settings_.allow_unstable_time_step ? 1 : 0);
      set.write("gravity", std::vector<double>{settings_.gravity.x, settings_.gravity.y, settings_.gravity.z});
      set.write_scalar<std::int32_t>("damping", static_cast<std::int32_t>(settings_.damping));
      set.write_scalar<double>("skin", settings_.skin);
      set.write_scalar<double>("global_damping", settings_.global_damping);
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
      h5::Group columns = f.create_group("nodes");
      nodes.for_each_column([&](const char* name, const auto& col) { columns.write(name, col); });
    }
    {
      h5::Group g = f.create_group("grains");
      g.write("node_begin", grains.node_begin);
      g.write("node_end", grains.node_end);
      g.write("kind", grains.kind);
      g.write("material", grains.material);
      g.write("volume", grains.volume);
      g.write("cx", grains.cx);
      g.write("cy", grains.cy);
      g.write("cz", grains.cz);
      g.write("cvx", grains.cvx);
      g.write("cvy", grains.cvy);
      g.write("cvz", grains.cvz);
      g.write("wall_vx", grains.wall_vx);
      g.write("wall_vy", grains.wall_vy);
      g.write("wall_vz", grains.wall_vz);
      g.write_strings("name", grain_names_);
    }
    {
      h5::Group b = f.create_group("bonds");
      b.write("offset", bonds.offset);
      std::vector<std::int64_t> broken;
      std::vector<std::int32_t> partner;
      for (std::size_t k = 0; k < bonds.entries(); ++k)
        if (bonds.broken[k]) {
          broken.push_back(static_cast<std::int64_t>(k));
          partner.push_back(bonds.partner[k]);
        }
      b.write_scalar<std::int64_t>("entries", static_cast<std::int64_t>(bonds.entries()));
      b.write("broken_entry", broken);
      b.write("broken_partner", partner);
    }
    {
      h5::Group l = f.create_group("contact_list");
      l.write("x_at_build", at_build[0]);
      l.write("y_at_build", at_build[1]);
      l.write("z_at_build", at_build[2]);
    }
    f.close();
  });
}

PeridemSimulation PeridemSimulation::from_checkpoint(const std::string& path, std::string* input_echo) {
  return read_checkpoint_file(path, "debris_peridem", [&] {
    h5::File f(path, h5::File::Mode::read_only);
    if (!f.has_attribute("format_version") || !f.has("bonds") || !f.has_attribute("format") ||
        f.string_attribute("format").rfind("debris PeriDEM checkpoint", 0) != 0)
      throw input_error("restart", path, "is not a debris_peridem checkpoint");
    const auto version = f.attribute<std::int64_t>("format_version");
    if (version < kOldestFormat || version > kFormatVersion)
      throw input_error("restart", path,
                        "has checkpoint format " + std::to_string(version) + "; this debris_peridem reads formats " +
                            std::to_string(kOldestFormat) + " to " + std::to_string(kFormatVersion));
    return restore(f, input_echo);
  });
}

PeridemSimulation PeridemSimulation::restore(const h5::File& f, std::string* input_echo) {
  const std::string& path = f.file_path();
  if (input_echo) *input_echo = f.read_string("input");

  PeridemSimulation sim{Restored{}};
  {
    const h5::Group set = f.open_group("settings");
    sim.settings_.time_step = set.read_scalar<double>("time_step");
    sim.settings_.allow_unstable_time_step = set.read_scalar<std::int32_t>("allow_unstable_time_step") != 0;
    const auto g = set.read<double>("gravity").values;
    if (g.size() != 3) throw corrupt(path, "settings/gravity is not 3 values");
    sim.settings_.gravity = {g[0], g[1], g[2]};
    const auto damping = set.read_scalar<std::int32_t>("damping");
    if (damping != static_cast<int>(PdDamping::node_pairs) && damping != static_cast<int>(PdDamping::grain_centres))
      throw corrupt(path, "settings/damping is no known damping");
    sim.settings_.damping = static_cast<PdDamping>(damping);
    sim.settings_.skin = set.read_scalar<double>("skin");
    // Absent from format-2 files written before stages could damp: no damping.
    sim.settings_.global_damping = set.has("global_damping") ? set.read_scalar<double>("global_damping") : 0.0;
    if (!(sim.settings_.global_damping >= 0)) throw corrupt(path, "settings/global_damping is negative or not a number");
    if (!std::isfinite(sim.settings_.time_step) || !all_finite(g) || !std::isfinite(sim.settings_.skin))
      throw corrupt(path, "settings/ holds a non-finite time step, gravity or skin");
    const auto mats = set.read<double>("materials").values;
    if (mats.empty() || mats.size() % kMaterialFields != 0) throw corrupt(path, "settings/materials has a bad shape");
    if (!all_finite(mats)) throw corrupt(path, "settings/materials holds a non-finite value");
    for (std::size_t k = 0; k < mats.size(); k += kMaterialFields) {
      PdMaterial m;
      m.density = mats[k];
      m.bulk_modulus = mats[k + 1];
      m.shear_modulus = mats[k + 2];
      m.fracture_energy = mats[k + 3];
      m.horizon = mats[k + 4];
      if (mats[k + 5] != 2.0 && mats[k + 5] != 3.0)
        throw corrupt(path, "settings/materials gives a dimension not 2 or 3");
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
    if (!all_finite(contact)) throw corrupt(path, "settings/contact holds a non-finite value");
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
    const std::size_t nm = sim.materials_.size();
    if (sim.contact_settings_.size() != 1 && sim.contact_settings_.size() != nm * nm)
      throw corrupt(path, "settings/contact holds " + std::to_string(sim.contact_settings_.size()) + " settings for " +
                              std::to_string(nm) + " materials");
  }
  bool placed_box_read = false;
  {
    const h5::Group state = f.open_group("state");
    sim.step_ = state.read_scalar<std::int64_t>("step");
    sim.time_ = state.read_scalar<double>("time");
    sim.broken_total_ = state.read_scalar<std::int64_t>("broken_bonds");
    sim.rebuilds_ = state.read_scalar<std::int64_t>("contact_rebuilds");
    sim.mesh_size_ = state.read_scalar<double>("mesh_size");
    sim.stable_dt_ = state.read_scalar<double>("stable_time_step");
    sim.skin_ = state.read_scalar<double>("skin");
    // Absent from checkpoints written before runs were cut among ranks: the box of the nodes as they are.
    if (state.has("placed_box")) {
      const auto b = state.read<double>("placed_box").values;
      if (b.size() != 6 || !all_finite(b) || b[0] > b[3] || b[1] > b[4] || b[2] > b[5])
        throw corrupt(path, "state/placed_box is not a box");
      sim.placed_lo_ = {b[0], b[1], b[2]};
      sim.placed_hi_ = {b[3], b[4], b[5]};
      placed_box_read = true;
    }
    if (sim.step_ < 0 || !std::isfinite(sim.time_) || sim.broken_total_ < 0 || sim.rebuilds_ < 0 ||
        !std::isfinite(sim.mesh_size_) || !(sim.mesh_size_ > 0) || !std::isfinite(sim.stable_dt_) ||
        !(sim.stable_dt_ > 0) || !std::isfinite(sim.skin_) || sim.skin_ < 0)
      throw corrupt(path, "state/ holds an impossible step, time, count, mesh size, stable time step or skin");
  }
  {
    const h5::Group nodes = f.open_group("nodes");
    // Assigned element-wise: the columns are device-resident vectors in offload builds.
    sim.nodes_.for_each_column([&](const char* name, auto& col) {
      using T = typename std::decay_t<decltype(col)>::value_type;
      if constexpr (std::is_same_v<T, int>) {
        const auto v = nodes.read<std::int32_t>(name).values;
        col.assign(v.begin(), v.end());
      } else {
        const auto v = nodes.read<T>(name).values;
        col.assign(v.begin(), v.end());
      }
    });
    const std::size_t n = sim.nodes_.size();
    sim.nodes_.for_each_column([&](const char* name, auto& col) {
      if (col.size() != n) throw corrupt(path, std::string("nodes/") + name + " has another length than nodes/id");
    });
    if (n == 0) throw corrupt(path, "it holds no nodes");
    std::vector<std::int64_t> ids(sim.nodes_.id.begin(), sim.nodes_.id.end());
    std::sort(ids.begin(), ids.end());
    if (std::adjacent_find(ids.begin(), ids.end()) != ids.end()) throw corrupt(path, "nodes/id holds a repeated id");
    for (std::size_t i = 0; i < n; ++i)
      if (!(sim.nodes_.volume[i] > 0) || !std::isfinite(sim.nodes_.volume[i]) || !(sim.nodes_.mass[i] > 0) ||
          !std::isfinite(sim.nodes_.mass[i]) || sim.nodes_.fixed[i] < 0 || sim.nodes_.fixed[i] > 7)
        throw corrupt(path, "node id " + std::to_string(sim.nodes_.id[i]) +
                                " has a volume or mass that is not positive, or an unknown fixed mask");
  }
  if (!placed_box_read) sim.set_placed_box();
  {
    const h5::Group g = f.open_group("grains");
    PdGrains& gr = sim.grains_;
    for (auto [name, col] : {std::pair{"node_begin", &gr.node_begin},
                             {"node_end", &gr.node_end},
                             {"kind", &gr.kind},
                             {"material", &gr.material}}) {
      const auto v = g.read<std::int32_t>(name).values;
      col->assign(v.begin(), v.end());
    }
    for (auto [name, col] : {std::pair{"volume", &gr.volume},
                             {"cx", &gr.cx},
                             {"cy", &gr.cy},
                             {"cz", &gr.cz},
                             {"cvx", &gr.cvx},
                             {"cvy", &gr.cvy},
                             {"cvz", &gr.cvz},
                             {"wall_vx", &gr.wall_vx},
                             {"wall_vy", &gr.wall_vy},
                             {"wall_vz", &gr.wall_vz}}) {
      const auto v = g.read<double>(name).values;
      col->assign(v.begin(), v.end());
    }
    sim.grain_names_ = g.read_strings("name");
    const std::size_t ng = gr.node_begin.size();
    gr.id.resize(ng);
    for (std::size_t k = 0; k < ng; ++k) gr.id[k] = static_cast<int>(k);
    // Every array read (a damaged file may shorten any one of them).
    for (const std::size_t s : {gr.node_end.size(), gr.kind.size(), gr.material.size(), gr.volume.size(), gr.cx.size(),
                                gr.cy.size(), gr.cz.size(), gr.cvx.size(), gr.cvy.size(), gr.cvz.size(),
                                gr.wall_vx.size(), gr.wall_vy.size(), gr.wall_vz.size(), sim.grain_names_.size()})
      if (s != ng) throw corrupt(path, "the grain arrays have different lengths");
    if (ng == 0) throw corrupt(path, "it holds no grains");
    // The grains own consecutive ranges of nodes that cover them all, and each node names its grain.
    for (std::size_t k = 0; k < ng; ++k) {
      if (gr.material[k] < 0 || static_cast<std::size_t>(gr.material[k]) >= sim.materials_.size() ||
          gr.node_begin[k] != (k == 0 ? 0 : gr.node_end[k - 1]) || gr.node_end[k] < gr.node_begin[k] ||
          static_cast<std::size_t>(gr.node_end[k]) > sim.nodes_.size() ||
          (gr.kind[k] != static_cast<int>(PdGrainKind::particle) && gr.kind[k] != static_cast<int>(PdGrainKind::wall)))
        throw corrupt(path, "grain " + std::to_string(k) + " does not fit the nodes, materials or grain kinds");
      for (int i = gr.node_begin[k]; i < gr.node_end[k]; ++i)
        if (sim.nodes_.grain[static_cast<std::size_t>(i)] != static_cast<int>(k))
          throw corrupt(path, "node id " + std::to_string(sim.nodes_.id[static_cast<std::size_t>(i)]) +
                                  " names grain " + std::to_string(sim.nodes_.grain[static_cast<std::size_t>(i)]) +
                                  " but lies in the nodes of grain " + std::to_string(k));
    }
    if (static_cast<std::size_t>(gr.node_end[ng - 1]) != sim.nodes_.size())
      throw corrupt(path, "the grains do not cover all the nodes");
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
    if (!(sim.bonds_.offset == b.read<std::int32_t>("offset").values) ||
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
    const auto x = l.read<double>("x_at_build").values;
    const auto y = l.read<double>("y_at_build").values;
    const auto z = l.read<double>("z_at_build").values;
    const std::size_t n = sim.nodes_.size();
    if (x.size() != n || y.size() != n || z.size() != n)
      throw corrupt(path, "contact_list positions do not match the nodes");
    // Everything read and derived goes to the device (offload builds), then the list is rebuilt there.
    to_device(sim.nodes_);
    to_device(sim.grains_);
    to_device(sim.bonds_);
    exec::to_device(sim.lps_);
    // The bond weights are derived, not saved: the pass that made them (m_i again too, the same bits as saved).
    pd_weighted_volume_pass(sim.lps_, sim.grains_, sim.bonds_, sim.nodes_);
    exec::to_host(sim.nodes_.weighted_volume);
    exec::to_host(sim.bonds_.weight);
    sim.nodes_edited_ = sim.grains_edited_ = false;
    PdNodes at_build = sim.nodes_;
    at_build.x.assign(x.begin(), x.end());
    at_build.y.assign(y.begin(), y.end());
    at_build.z.assign(z.begin(), z.end());
    to_device(at_build);
    sim.list_.build(at_build, sim.grains_, sim.bonds_, sim.table_.max_contact_radius(), sim.skin_);
    sim.device_changed(pairs_changed);  // the list's build positions are on the device only
    // The centre damping's slot forces of the step that wrote the checkpoint (the wall reactions read them),
    // from the same positions and velocities: the same bits.
    if (sim.settings_.damping == PdDamping::grain_centres) {
      pd_grain_centres(sim.nodes_, sim.grains_, sim.work_);
      pd_centre_slot_forces(sim.table_, sim.nodes_, sim.grains_, sim.list_, sim.work_);
      sim.device_changed(grains_changed);
    }
  }
  return sim;
}

}  // namespace debris
