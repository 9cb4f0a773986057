// Checkpoint and restart of a DEM run (HDF5). A checkpoint holds the whole state, not just what a user
// would call the state: the neighbour list as built (positions at the build included) and the contact
// history in its entry order, so that N steps + checkpoint + restart + N steps equals 2N steps bit for bit.
// The per-pair constant table and the thread buffers are derived data and are rebuilt. No random numbers
// are drawn while stepping (lattices draw theirs at set-up, from the seed in the input echo), so there is
// no generator state to save.
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <utility>

#include "core/error.hpp"
#include "core/io/hdf5_file.hpp"
#include "scenarios/common/dem_simulation.hpp"

namespace debris {

namespace {

// 2: groups/prescribed (per-axis velocity of force groups).
constexpr std::int64_t kFormatVersion = 2;

template <class T>
std::vector<T> as_vector(const h5::Array<T>& a) {
  return a.values;
}

void write_vec3s(h5::Location& g, const std::string& name, const std::vector<Vec3>& v) {
  std::vector<double> flat;
  for (const Vec3& x : v) flat.insert(flat.end(), {x.x, x.y, x.z});
  g.write(name, flat, v.size(), 3);
}

std::vector<Vec3> read_vec3s(const h5::Location& g, const std::string& name) {
  const auto a = g.read<double>(name);
  std::vector<Vec3> v(a.values.size() / 3);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = {a.values[3 * i], a.values[3 * i + 1], a.values[3 * i + 2]};
  return v;
}

}  // namespace

void DemSimulation::write_checkpoint(const std::string& path, const std::string& input_echo) const {
  // The device's state, copied back (offload builds).
  particles_to_host();
  pairs_to_host();
  const std::string tmp = path + ".tmp";
  {
    h5::File f(tmp, h5::File::Mode::create);
    f.set_attribute<std::int64_t>("format_version", kFormatVersion);
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
    }
    {
      h5::Group set = f.create_group("settings");
      const CohesiveMaterial& m = settings_.material;
      set.write("material", std::vector<double>{m.youngs_modulus, m.poisson_ratio, m.tensile_strength, m.shear_strength,
                                                m.surface_energy, m.restitution, m.density, m.scaling});
      set.write("options", std::vector<std::int32_t>{settings_.options.adhesive, settings_.options.tangential});
      set.write("time_step", std::vector<double>{settings_.time_step, settings_.time_step_fraction,
                                                 settings_.global_damping, settings_.skin});
      set.write("flags", std::vector<std::int32_t>{settings_.allow_unstable_time_step, settings_.sort_by_cell,
                                                   settings_.masses_from_density,
                                                   static_cast<std::int32_t>(settings_.pair_pass),
                                                   settings_.size_classes});
    }
    {
      h5::Group box = f.create_group("box");
      box.write("lo", std::vector<double>{box_.lo().x, box_.lo().y, box_.lo().z});
      box.write("hi", std::vector<double>{box_.hi().x, box_.hi().y, box_.hi().z});
      box.write("periodic", std::vector<std::int32_t>{box_.periodic(0), box_.periodic(1), box_.periodic(2)});
    }
    {
      h5::Group parts = f.create_group("particles");
      const_cast<Particles&>(p_).for_each_column([&](const char* name, auto& col) { parts.write(name, col); });
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
      h5::Group nl = f.create_group("neighbors");
      const NeighborList::Saved s = list_.save();
      nl.write_scalar<std::int32_t>("kind", static_cast<std::int32_t>(s.kind));
      nl.write_scalar<double>("skin", s.skin);
      nl.write("offset", s.offset);
      nl.write("index", s.index);
      nl.write("x0", s.x0);
      nl.write("y0", s.y0);
      nl.write("z0", s.z0);
      nl.write("len0", std::vector<double>{s.len0[0], s.len0[1], s.len0[2]});
    }
    {
      h5::Group hist = f.create_group("history");
      hist.write("hx", history_.hx);
      hist.write("hy", history_.hy);
      hist.write("hz", history_.hz);
    }
    f.close();
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw std::runtime_error("checkpoint: cannot rename " + tmp + " to " + path + ": " + ec.message());
}

DemSimulation DemSimulation::from_checkpoint(const std::string& path, std::string* input_echo) {
  if (!std::filesystem::exists(path)) throw input_error("restart", path, "no such checkpoint file");
  h5::File f(path, h5::File::Mode::read_only);
  if (f.attribute<std::int64_t>("format_version") != kFormatVersion)
    throw input_error("restart", path, "written by an incompatible version of debris");
  if (input_echo) *input_echo = f.read_string("input");

  DemSimulation sim{Restored{}};
  const h5::Group set = f.open_group("settings");
  const auto mat = set.read<double>("material").values;
  CohesiveMaterial& m = sim.settings_.material;
  m = CohesiveMaterial{mat[0], mat[1], mat[2], mat[3], mat[4], mat[5], mat[6], mat[7]};
  const auto opt = set.read<std::int32_t>("options").values;
  sim.settings_.options = CohesiveOptions{opt[0], opt[1]};
  const auto ts = set.read<double>("time_step").values;
  sim.settings_.time_step = ts[0];
  sim.settings_.time_step_fraction = ts[1];
  sim.settings_.global_damping = ts[2];
  sim.settings_.skin = ts[3];
  const auto flags = set.read<std::int32_t>("flags").values;
  sim.settings_.allow_unstable_time_step = flags[0] != 0;
  sim.settings_.sort_by_cell = flags[1] != 0;
  sim.settings_.masses_from_density = flags[2] != 0;
  sim.settings_.pair_pass = static_cast<PairPass>(flags[3]);
  // Checkpoints from before size classes have four flags: they continue with the default.
  if (flags.size() > 4) sim.settings_.size_classes = flags[4];
  sim.list_.set_max_size_classes(sim.settings_.size_classes);

  const h5::Group state = f.open_group("state");
  sim.step_ = state.read_scalar<std::int64_t>("step");
  sim.time_ = state.read_scalar<double>("time");
  sim.dt_ = state.read_scalar<double>("dt");
  sim.damping_ = state.read_scalar<double>("damping");
  sim.skin_ = state.read_scalar<double>("skin");
  sim.max_cutoff_ = state.read_scalar<double>("max_cutoff");
  sim.pass_ = static_cast<PairPass>(state.read_scalar<std::int32_t>("pair_pass"));

  const h5::Group box = f.open_group("box");
  const auto lo = box.read<double>("lo").values, hi = box.read<double>("hi").values;
  const auto per = box.read<std::int32_t>("periodic").values;
  sim.box_ = Box({lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}, {per[0] != 0, per[1] != 0, per[2] != 0});

  const h5::Group parts = f.open_group("particles");
  sim.p_.for_each_column([&](const char* name, auto& col) {
    using T = typename std::decay_t<decltype(col)>::value_type;
    if (std::string(name) == "label" && !parts.has(name)) return;  // written before labels existed: all 0
    if constexpr (std::is_same_v<T, int>) {
      const auto v = parts.read<std::int32_t>(name).values;
      col.assign(v.begin(), v.end());
    } else {
      const auto v = parts.read<T>(name).values;
      col.assign(v.begin(), v.end());
    }
  });
  if (sim.p_.label.size() != sim.p_.id.size()) sim.p_.label.assign(sim.p_.id.size(), 0);
  if (f.has("labels")) {
    const h5::Group labels = f.open_group("labels");
    if (labels.attribute<std::int64_t>("size") > 0) sim.p_.label_names = labels.read_strings("name");
  }

  const h5::Group groups = f.open_group("groups");
  const auto ng = groups.attribute<std::int64_t>("size");
  if (ng > 0) {
    const auto names = groups.read_strings("name");
    const auto motion = groups.read<std::int32_t>("motion").values;
    const auto prescribed = groups.read<std::int32_t>("prescribed").values;
    const auto count = groups.read<std::int64_t>("count").values;
    const auto mass = groups.read<double>("mass").values;
    const auto velocity = read_vec3s(groups, "velocity"), force = read_vec3s(groups, "external_force");
    const auto reaction = read_vec3s(groups, "reaction"), displacement = read_vec3s(groups, "displacement");
    for (std::size_t g = 0; g < names.size(); ++g) {
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
  s.kind = static_cast<NeighborKind>(nl.read_scalar<std::int32_t>("kind"));
  s.skin = nl.read_scalar<double>("skin");
  s.offset = nl.read<std::int32_t>("offset").values;
  s.index = nl.read<std::int32_t>("index").values;
  s.x0 = nl.read<double>("x0").values;
  s.y0 = nl.read<double>("y0").values;
  s.z0 = nl.read<double>("z0").values;
  const auto len0 = nl.read<double>("len0").values;
  for (int a = 0; a < 3; ++a) s.len0[a] = len0[static_cast<std::size_t>(a)];
  sim.list_.restore(std::move(s));

  const h5::Group hist = f.open_group("history");
  for (auto [name, column] : {std::pair{"hx", &sim.history_.hx}, std::pair{"hy", &sim.history_.hy},
                              std::pair{"hz", &sim.history_.hz}}) {
    const auto v = hist.read<double>(name).values;
    column->assign(v.begin(), v.end());
  }
  if (sim.history_.hx.size() != static_cast<std::size_t>(sim.list_.entries()))
    throw std::runtime_error("checkpoint " + path + ": history and neighbour list disagree");

  // Derived data, recomputed exactly as the original run computed it.
  sim.coef_ = CohesiveCoefficients::from(sim.settings_.material);
  sim.limits_ = stability_limits(sim.coef_, sim.p_);
  // Everything read goes to the device (the list did in restore()).
  if constexpr (exec::offload_build()) {
    to_device(sim.p_);
    sim.history_.to_device();
  }
  sim.host_edited_ = false;
  if (sim.pass_ == PairPass::half) sim.index_half_pass();
  return sim;
}

}  // namespace debris
