// Checkpoint and restart of a DEM run (HDF5). A checkpoint holds the whole state, not just what a user
// would call the state: the neighbour list as built (positions at the build included) and the contact
// history in its entry order, so that N steps + checkpoint + restart + N steps equals 2N steps bit for bit.
// The per-pair constant table and the thread buffers are derived data and are rebuilt. No random numbers
// are drawn while stepping (lattices draw theirs at set-up, from the seed in the input echo), so there is
// no generator state to save.
//
// The file is sealed with checksums and everything read is checked before it is used
// (scenarios/common/run/checkpoint_file.hpp): a damaged or foreign file is an input error naming it.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <utility>

#include "core/comm/communicator.hpp"
#include "core/error.hpp"
#include "core/io/hdf5_file.hpp"
#include "scenarios/common/run/checkpoint_file.hpp"
#include "scenarios/common/dem/dem_simulation.hpp"

namespace debris {

namespace {

// 2: groups/prescribed (per-axis velocity of force groups). 3: sealed with checksums, a "format" attribute.
// Unsealed files (format 2 and older) are refused (checkpoint_file.hpp).
constexpr std::int64_t kFormatVersion = 3;
constexpr std::int64_t kOldestFormat = 3;  // the first sealed format
constexpr const char* kFormatName = "debris DEM checkpoint";

template <class T>
std::vector<T> as_vector(const h5::Array<T>& a) {
  return a.values;
}

void write_vec3s(h5::Location& g, const std::string& name, const std::vector<Vec3>& v) {
  std::vector<double> flat;
  for (const Vec3& x : v) flat.insert(flat.end(), {x.x, x.y, x.z});
  g.write(name, flat, v.size(), 3);
}

std::vector<Vec3> read_vec3s(const h5::Location& g, const std::string& name, std::size_t count) {
  const auto a = g.read<double>(name);
  check_checkpoint(a.values.size() == 3 * count, g.file_path(),
                   g.object_path() + "/" + name + " holds " + std::to_string(a.values.size()) + " values, not " +
                       std::to_string(3 * count));
  std::vector<Vec3> v(a.values.size() / 3);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = {a.values[3 * i], a.values[3 * i + 1], a.values[3 * i + 2]};
  return v;
}

/// A dataset that must hold exactly `count` values.
template <class T>
std::vector<T> read_sized(const h5::Location& g, const std::string& name, std::size_t count) {
  std::vector<T> v = g.read<T>(name).values;
  check_checkpoint(
      v.size() == count, g.file_path(),
      g.object_path() + "/" + name + " holds " + std::to_string(v.size()) + " values, not " + std::to_string(count));
  return v;
}

// Rows and list entries are int32 in the file (as in memory).
// (write_checkpoint_file turns it into the OutputError naming the checkpoint.)
void check_checkpoint_size(std::int64_t particles, std::int64_t entries) {
  if (particles >= INT32_MAX || entries >= INT32_MAX)
    throw std::runtime_error("a checkpoint holds fewer than 2^31 particles and list entries; this one would have " +
                             std::to_string(particles) + " and " + std::to_string(entries));
}

bool all_finite(const std::vector<double>& v) {
  return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}

}  // namespace

void DemSimulation::write_checkpoint(const std::string& path, const std::string& input_echo,
                                     const std::function<void(h5::File&)>& extra) const {
  // The device's state, copied back (offload builds).
  particles_to_host();
  pairs_to_host();
  const NeighborList::Saved s = list_.save();
  const bool root = !distributed_ || comm::rank() == 0;
  write_checkpoint_file(path, distributed_, [&](const std::string& tmp) {
    // First what is per particle and per list entry: cut among ranks, each rank writes its own rows of the
    // one file (collective); alone, the rows are all the rows.
    const WholeRows w = whole_rows(s);
    check_checkpoint_size(w.particles, w.entries);
    {
      h5::File f(tmp, h5::File::Mode::create, {.all_ranks = distributed_});
      std::vector<std::int64_t> rows;
      for (const int i : w.owned) rows.push_back(w.row[static_cast<std::size_t>(i)]);
      const auto n = static_cast<std::size_t>(w.particles), entries = static_cast<std::size_t>(w.entries);
      const h5::RowSelection particle_rows(rows, {n});
      {
        h5::Group parts = f.create_group("particles");
        p_.for_each_column([&](const char* name, const auto& col) {
          using T = typename std::decay_t<decltype(col)>::value_type;
          std::vector<T> mine;
          for (const int i : w.owned) mine.push_back(col[static_cast<std::size_t>(i)]);
          parts.write_rows<T>(name, mine, particle_rows);
        });
      }
      // The list as built (rows and partners as rows of the whole system) and each entry's contact history.
      std::vector<std::int64_t> offset_rows = rows, entry_rows;
      std::vector<std::int32_t> offset, index;
      std::vector<double> x0, y0, z0, hx, hy, hz;
      for (std::size_t k = 0; k < w.owned.size(); ++k) {
        const auto i = static_cast<std::size_t>(w.owned[k]);
        offset.push_back(static_cast<std::int32_t>(w.first_entry[k]));
        x0.push_back(s.x0[i]);
        y0.push_back(s.y0[i]);
        z0.push_back(s.z0[i]);
        for (int e = s.offset[i]; e < s.offset[i + 1]; ++e) {
          const auto ue = static_cast<std::size_t>(e);
          entry_rows.push_back(w.first_entry[k] + (e - s.offset[i]));
          index.push_back(static_cast<std::int32_t>(w.row[static_cast<std::size_t>(s.index[ue])]));
          hx.push_back(history_.hx[ue]);
          hy.push_back(history_.hy[ue]);
          hz.push_back(history_.hz[ue]);
        }
      }
      if (root) {  // the end of the last row
        offset_rows.push_back(w.particles);
        offset.push_back(static_cast<std::int32_t>(w.entries));
      }
      const h5::RowSelection entry_selection(entry_rows, {entries});
      {
        h5::Group nl = f.create_group("neighbors");
        nl.write_rows<std::int32_t>("offset", offset, offset_rows, {n + 1});
        nl.write_rows<std::int32_t>("index", index, entry_selection);
        nl.write_rows<double>("x0", x0, particle_rows);
        nl.write_rows<double>("y0", y0, particle_rows);
        nl.write_rows<double>("z0", z0, particle_rows);
      }
      {
        h5::Group hist = f.create_group("history");
        hist.write_rows<double>("hx", hx, entry_selection);
        hist.write_rows<double>("hy", hy, entry_selection);
        hist.write_rows<double>("hz", hz, entry_selection);
      }
      f.close();
    }
    if (!root) return;
    // Then what the whole system has once (every rank holds the same): one process adds it.
    h5::File f(tmp, h5::File::Mode::read_write);
    f.set_attribute<std::int64_t>("format_version", kFormatVersion);
    f.set_string_attribute("format", std::string(kFormatName) + " " + std::to_string(kFormatVersion));
    f.write_string("input", input_echo);
    // Each section in its own scope: HDF5 keeps a file open while anything opened from it lives.
    {
      h5::Group state = f.create_group("state");
      state.write_scalar<std::int64_t>("step", step_);
      state.write_scalar<double>("time", time_);
      state.write_scalar<double>("dt", dt_);
      state.write_scalar<double>("damping", damping_);
      state.write_scalar<double>("skin", skin_);
      state.write_scalar<double>("max_cutoff", max_cutoff_);
      state.write_scalar<std::int32_t>("pair_pass", static_cast<std::int32_t>(pass_));
      // The energy balance's start and the stages' work (the per-particle sums are particle columns).
      state.write("energy", std::vector<double>{settings_.energy_accounting ? 1.0 : 0.0, kinetic0_, elastic0_,
                                                stage_work_});
    }
    {
      h5::Group set = f.create_group("settings");
      const CohesiveMaterial& m = settings_.material;
      set.write("material", std::vector<double>{m.youngs_modulus, m.poisson_ratio, m.tensile_strength, m.shear_strength,
                                                m.surface_energy, m.restitution, m.density, m.scaling});
      set.write("options", std::vector<std::int32_t>{settings_.options.adhesive, settings_.options.tangential});
      set.write("time_step", std::vector<double>{settings_.time_step, settings_.time_step_fraction,
                                                 settings_.global_damping, settings_.skin});
      set.write("flags", std::vector<std::int32_t>{
                             settings_.allow_unstable_time_step, settings_.sort_by_cell, settings_.masses_from_density,
                             static_cast<std::int32_t>(settings_.pair_pass), settings_.size_classes});
    }
    {
      h5::Group box = f.create_group("box");
      box.write("lo", std::vector<double>{box_.lo().x, box_.lo().y, box_.lo().z});
      box.write("hi", std::vector<double>{box_.hi().x, box_.hi().y, box_.hi().z});
      box.write("periodic", std::vector<std::int32_t>{box_.periodic(0), box_.periodic(1), box_.periodic(2)});
    }
    {
      // The legend of the particles' label column (label k is name k-1).
      h5::Group labels = f.create_group("labels");
      labels.set_attribute<std::int64_t>("size", static_cast<std::int64_t>(p_.label_names.size()));
      if (!p_.label_names.empty()) labels.write_strings("name", p_.label_names);
    }
    {
      h5::Group groups = f.create_group("groups");
      std::vector<std::string> names;
      std::vector<std::int32_t> motion, prescribed;
      std::vector<std::int64_t> count;
      std::vector<double> mass;
      std::vector<Vec3> velocity, force, reaction, displacement;
      for (const Group& g : groups_.list) {
        names.push_back(g.name);
        motion.push_back(static_cast<std::int32_t>(g.motion));
        for (bool b : g.prescribed) prescribed.push_back(b ? 1 : 0);
        count.push_back(g.count);
        mass.push_back(g.mass);
        velocity.push_back(g.velocity);
        force.push_back(g.external_force);
        reaction.push_back(g.reaction);
        displacement.push_back(g.displacement);
      }
      groups.set_attribute<std::int64_t>("size", static_cast<std::int64_t>(names.size()));
      if (!names.empty()) {
        groups.write_strings("name", names);
        groups.write("motion", motion);
        groups.write("prescribed", prescribed, names.size(), 3);
        groups.write("count", count);
        groups.write("mass", mass);
        write_vec3s(groups, "velocity", velocity);
        write_vec3s(groups, "external_force", force);
        write_vec3s(groups, "reaction", reaction);
        write_vec3s(groups, "displacement", displacement);
      }
    }
    {
      h5::Group nl = f.open_group("neighbors");
      nl.write_scalar<std::int32_t>("kind", static_cast<std::int32_t>(s.kind));
      nl.write_scalar<double>("skin", s.skin);
      nl.write("len0", std::vector<double>{s.len0[0], s.len0[1], s.len0[2]});
    }
    if (extra) extra(f);
    f.close();
  });
}

DemSimulation DemSimulation::from_checkpoint(const std::string& path, std::string* input_echo,
                                             const std::function<void(const h5::File&)>& extra, RestartRanks ranks) {
  return read_checkpoint_file(path, "debris_dem", [&] {
    h5::File f(path, h5::File::Mode::read_only);
    check_checkpoint(f.has_attribute("format_version"), path, "it is not a debris_dem checkpoint (no format_version)");
    const auto version = f.attribute<std::int64_t>("format_version");
    if (f.has_attribute("format")) {
      const std::string format = f.string_attribute("format");
      if (format.rfind(kFormatName, 0) != 0)
        throw input_error("restart", path, "is a '" + format + "' file, not a debris_dem checkpoint");
    }
    if (version < kOldestFormat || version > kFormatVersion)
      throw input_error("restart", path,
                        "written by an incompatible version of debris: checkpoint format " + std::to_string(version) +
                            "; this debris_dem reads formats " + std::to_string(kOldestFormat) + " to " +
                            std::to_string(kFormatVersion));
    check_checkpoint(f.has("particles"), path, "it is not a debris_dem checkpoint (no particles)");
    DemSimulation sim = restore(f, input_echo);
    if (extra) extra(f);
    if (ranks.distribute && comm::size() > 1) sim.distribute_restored(ranks.rank_grid);
    return sim;
  });
}

DemSimulation DemSimulation::restore(const h5::File& f, std::string* input_echo) {
  const std::string& path = f.file_path();
  auto check = [&](bool ok, const std::string& what) { check_checkpoint(ok, path, what); };
  if (input_echo) *input_echo = f.read_string("input");

  DemSimulation sim{Restored{}};
  const h5::Group set = f.open_group("settings");
  const auto mat = read_sized<double>(set, "material", 8);
  check(all_finite(mat), "settings/material holds a non-finite value");
  CohesiveMaterial& m = sim.settings_.material;
  m = CohesiveMaterial{mat[0], mat[1], mat[2], mat[3], mat[4], mat[5], mat[6], mat[7]};
  const auto opt = read_sized<std::int32_t>(set, "options", 2);
  check((opt[0] == 0 || opt[0] == 1) && (opt[1] == 0 || opt[1] == 1), "settings/options are not 0 or 1");
  sim.settings_.options = CohesiveOptions{opt[0], opt[1]};
  const auto ts = read_sized<double>(set, "time_step", 4);
  sim.settings_.time_step = ts[0];
  sim.settings_.time_step_fraction = ts[1];
  sim.settings_.global_damping = ts[2];
  sim.settings_.skin = ts[3];
  const auto flags = set.read<std::int32_t>("flags").values;
  // Checkpoints from before size classes have four flags: they continue with the default.
  check(flags.size() == 4 || flags.size() == 5, "settings/flags holds " + std::to_string(flags.size()) + " values");
  check(flags[3] >= 0 && flags[3] <= static_cast<int>(PairPass::half), "settings/flags names no pair pass");
  sim.settings_.allow_unstable_time_step = flags[0] != 0;
  sim.settings_.sort_by_cell = flags[1] != 0;
  sim.settings_.masses_from_density = flags[2] != 0;
  sim.settings_.pair_pass = static_cast<PairPass>(flags[3]);
  if (flags.size() > 4) {
    check(flags[4] >= 1 && flags[4] <= SizeClasses::kMax, "settings/flags gives an impossible number of size classes");
    sim.settings_.size_classes = flags[4];
  }
  sim.list_.set_max_size_classes(sim.settings_.size_classes);

  const h5::Group state = f.open_group("state");
  sim.step_ = state.read_scalar<std::int64_t>("step");
  sim.time_ = state.read_scalar<double>("time");
  sim.dt_ = state.read_scalar<double>("dt");
  sim.damping_ = state.read_scalar<double>("damping");
  sim.skin_ = state.read_scalar<double>("skin");
  sim.max_cutoff_ = state.read_scalar<double>("max_cutoff");
  const auto pass = state.read_scalar<std::int32_t>("pair_pass");
  check(sim.step_ >= 0 && std::isfinite(sim.time_) && std::isfinite(sim.dt_) && sim.dt_ > 0 &&
            std::isfinite(sim.damping_) && std::isfinite(sim.skin_) && sim.skin_ >= 0 &&
            std::isfinite(sim.max_cutoff_) && sim.max_cutoff_ > 0,
        "state/ holds an impossible step, time, time step, damping, skin or cutoff");
  check(pass == static_cast<int>(PairPass::full) || pass == static_cast<int>(PairPass::half),
        "state/pair_pass is neither the full nor the half pass");
  sim.pass_ = static_cast<PairPass>(pass);
  // Checkpoints from before the energy accounting: it starts at the restart, from zero.
  const bool energy_known = state.has("energy");
  if (energy_known) {
    const auto e = read_sized<double>(state, "energy", 4);
    check((e[0] == 0.0 || e[0] == 1.0) && std::isfinite(e[1]) && std::isfinite(e[2]) && std::isfinite(e[3]),
          "state/energy holds no energy balance (a flag and three finite energies)");
    sim.settings_.energy_accounting = e[0] != 0.0;
    sim.kinetic0_ = e[1];
    sim.elastic0_ = e[2];
    sim.stage_work_ = e[3];
  }

  const h5::Group box = f.open_group("box");
  const auto lo = read_sized<double>(box, "lo", 3), hi = read_sized<double>(box, "hi", 3);
  const auto per = read_sized<std::int32_t>(box, "periodic", 3);
  for (std::size_t a = 0; a < 3; ++a)
    check(std::isfinite(lo[a]) && std::isfinite(hi[a]) && lo[a] < hi[a] && (per[a] == 0 || per[a] == 1),
          "box/ is not a box (lo < hi, periodic 0 or 1)");
  sim.box_ = Box({lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}, {per[0] != 0, per[1] != 0, per[2] != 0});

  const h5::Group parts = f.open_group("particles");
  sim.p_.for_each_column([&](const char* name, auto& col) {
    using T = typename std::decay_t<decltype(col)>::value_type;
    if (std::string(name) == "label" && !parts.has(name)) return;  // written before labels existed: all 0
    // Written before the energy accounting: its columns start at 0.
    if (!energy_known && !parts.has(name) && std::string(name) != "id" && std::string(name) != "x") return;
    if constexpr (std::is_same_v<T, int>) {
      const auto v = parts.read<std::int32_t>(name).values;
      col.assign(v.begin(), v.end());
    } else {
      const auto v = parts.read<T>(name).values;
      col.assign(v.begin(), v.end());
    }
  });
  const std::size_t n = sim.p_.id.size();
  if (sim.p_.label.empty()) sim.p_.label.assign(n, 0);
  sim.p_.for_each_column([&](const char*, auto& col) {
    if (col.empty()) col.assign(n, 0);
  });
  check(n > 0, "it holds no particles");
  sim.p_.for_each_column([&](const char* name, auto& col) {
    check(col.size() == n, std::string("particles/") + name + " holds " + std::to_string(col.size()) + " values for " +
                               std::to_string(n) + " particles");
  });
  if (f.has("labels")) {
    const h5::Group labels = f.open_group("labels");
    const auto size = labels.attribute<std::int64_t>("size");
    check(size >= 0 && size <= static_cast<std::int64_t>(n), "labels/ has an impossible size");
    if (size > 0) sim.p_.label_names = labels.read_strings("name");
    check(sim.p_.label_names.size() == static_cast<std::size_t>(size), "labels/name does not hold labels/size names");
  }
  const auto ng = f.open_group("groups").attribute<std::int64_t>("size");
  check(ng >= 0 && ng <= static_cast<std::int64_t>(n), "groups/ has an impossible size");
  {
    std::vector<std::int64_t> ids(sim.p_.id.begin(), sim.p_.id.end());
    std::sort(ids.begin(), ids.end());
    check(std::adjacent_find(ids.begin(), ids.end()) == ids.end(), "particles/id holds a repeated id");
    const auto labels = static_cast<int>(sim.p_.label_names.size());
    for (std::size_t i = 0; i < n; ++i) {
      const std::string which = "particle id " + std::to_string(sim.p_.id[i]);
      check(sim.p_.group[i] >= -1 && sim.p_.group[i] < ng,
            which + " is in group " + std::to_string(sim.p_.group[i]) + " of " + std::to_string(ng));
      check(sim.p_.label[i] >= 0 && sim.p_.label[i] <= labels,
            which + " has label " + std::to_string(sim.p_.label[i]) + " of " + std::to_string(labels));
      check(sim.p_.type[i] >= 1, which + " has type " + std::to_string(sim.p_.type[i]));
      check(std::isfinite(sim.p_.radius[i]) && sim.p_.radius[i] > 0 && std::isfinite(sim.p_.mass[i]) &&
                sim.p_.mass[i] > 0 && std::isfinite(sim.p_.inertia[i]) && sim.p_.inertia[i] > 0,
            which + " has a radius, mass or inertia that is not positive");
    }
  }

  const h5::Group groups = f.open_group("groups");
  if (ng > 0) {
    const auto g_n = static_cast<std::size_t>(ng);
    const auto names = groups.read_strings("name");
    check(names.size() == g_n, "groups/name does not hold groups/size names");
    const auto motion = read_sized<std::int32_t>(groups, "motion", g_n);
    const auto prescribed = read_sized<std::int32_t>(groups, "prescribed", 3 * g_n);
    const auto count = read_sized<std::int64_t>(groups, "count", g_n);
    const auto mass = read_sized<double>(groups, "mass", g_n);
    const auto velocity = read_vec3s(groups, "velocity", g_n), force = read_vec3s(groups, "external_force", g_n);
    const auto reaction = read_vec3s(groups, "reaction", g_n), displacement = read_vec3s(groups, "displacement", g_n);
    std::vector<std::int64_t> members(g_n, 0);
    for (int g : sim.p_.group)
      if (g >= 0) ++members[static_cast<std::size_t>(g)];
    for (std::size_t g = 0; g < g_n; ++g) {
      check(motion[g] >= static_cast<int>(GroupMotion::free) && motion[g] <= static_cast<int>(GroupMotion::force),
            "groups/motion of group '" + names[g] + "' is no known motion");
      check(count[g] == members[g], "groups/count of group '" + names[g] + "' is " + std::to_string(count[g]) +
                                        ", but " + std::to_string(members[g]) + " particles are in it");
      Group gr{names[g], static_cast<GroupMotion>(motion[g]), velocity[g], force[g]};
      for (std::size_t a = 0; a < 3; ++a) gr.prescribed[a] = prescribed[3 * g + a] != 0;
      gr.count = count[g];
      gr.mass = mass[g];
      gr.reaction = reaction[g];
      gr.displacement = displacement[g];
      sim.groups_.add(gr);
    }
  }

  const h5::Group nl = f.open_group("neighbors");
  NeighborList::Saved s;
  const auto kind = nl.read_scalar<std::int32_t>("kind");
  check(kind == static_cast<int>(NeighborKind::full) || kind == static_cast<int>(NeighborKind::half),
        "neighbors/kind is neither a full nor a half list");
  s.kind = static_cast<NeighborKind>(kind);
  s.skin = nl.read_scalar<double>("skin");
  s.offset = read_sized<std::int32_t>(nl, "offset", n + 1);
  s.index = nl.read<std::int32_t>("index").values;
  s.x0 = read_sized<double>(nl, "x0", n);
  s.y0 = read_sized<double>(nl, "y0", n);
  s.z0 = read_sized<double>(nl, "z0", n);
  const auto len0 = read_sized<double>(nl, "len0", 3);
  for (int a = 0; a < 3; ++a) s.len0[a] = len0[static_cast<std::size_t>(a)];
  check(s.offset.front() == 0 && static_cast<std::size_t>(s.offset.back()) == s.index.size(),
        "neighbors/offset does not span neighbors/index");
  for (std::size_t i = 0; i < n; ++i) {
    check(s.offset[i] <= s.offset[i + 1] && static_cast<std::size_t>(s.offset[i + 1]) <= s.index.size(),
          "neighbors/offset decreases at row " + std::to_string(i) + " or runs past neighbors/index");
    for (int k = s.offset[i]; k < s.offset[i + 1]; ++k) {
      const int j = s.index[static_cast<std::size_t>(k)];
      check(j >= 0 && static_cast<std::size_t>(j) < n && static_cast<std::size_t>(j) != i,
            "neighbors/index entry " + std::to_string(k) + " names no other particle");
    }
  }
  const std::size_t entries = s.index.size();
  sim.list_.restore(std::move(s));

  const h5::Group hist = f.open_group("history");
  // Assigned element-wise: the history columns are device-resident vectors in offload builds.
  for (auto [name, column] : {std::pair{"hx", &sim.history_.hx}, std::pair{"hy", &sim.history_.hy},
                              std::pair{"hz", &sim.history_.hz}}) {
    const auto v = read_sized<double>(hist, name, entries);
    column->assign(v.begin(), v.end());
  }

  // Derived data, recomputed exactly as the original run computed it.
  sim.coef_ = CohesiveCoefficients::from(sim.settings_.material);
  sim.limits_ = stability_limits(sim.coef_, sim.p_);
  sim.limit_radius_ = sim.p_.radius[static_cast<std::size_t>(sim.limits_.particle)];
  sim.limit_mass_ = sim.p_.mass[static_cast<std::size_t>(sim.limits_.particle)];
  // Everything read goes to the device (the list did in restore()).
  if constexpr (exec::offload_build()) {
    to_device(sim.p_);
    sim.history_.to_device();
  }
  sim.host_edited_ = false;
  if (sim.pass_ == PairPass::half) sim.index_half_pass();
  if (!energy_known && sim.settings_.energy_accounting) {  // the balance counts from the restart
    sim.kinetic0_ = sim.totals().kinetic_energy;
    sim.elastic0_ = sim.diagnostics().elastic_energy;
  }
  return sim;
}

}  // namespace debris
