#include "scenarios/restitution/two_particle_drop.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "core/error.hpp"
#include "scenarios/common/peridem/grain_placement.hpp"
#include "scenarios/common/peridem/gmsh_api.hpp"
#include "scenarios/common/peridem/shape_mesh.hpp"
#include "scenarios/common/peridem/peridem_simulation.hpp"

namespace debris {

namespace {

constexpr double kPi = 3.14159265358979323846;

void check_positive(double v, const char* key) {
  if (!(v > 0) || !std::isfinite(v)) throw input_error(key, format_value(v), "must be > 0");
}

// A circle of radius `radius`: Gmsh's mesh at `mesh_size`, or the given MSH file's mesh (about its origin,
// R_ref its largest node distance from the origin, so that placing it scales it to `radius`).
ReferenceGrain circle_grain(const std::string& file, double radius, double mesh_size, const GmshRun& gmsh, int material,
                            const std::string& what) {
  if (file.empty())
    return make_reference_grain(mesh_shape(ShapeSpec::make_circle(radius, mesh_size), gmsh), radius, material, what);
  SimplexMesh mesh = read_mesh_file(file);
  double r_ref = 0.0;
  for (const Vec3& v : mesh.nodes) r_ref = std::max(r_ref, norm(v));
  return make_reference_grain(std::move(mesh), r_ref, material, what + " (" + file + ")");
}

}  // namespace

TwoParticleDropResult run_two_particle_drop(const TwoParticleDrop& spec) {
  check_positive(spec.bottom_radius, "bottom_radius");
  check_positive(spec.top_radius, "top_radius");
  check_positive(spec.mesh_size, "mesh_size");
  check_positive(spec.drop_height, "drop_height");
  check_positive(spec.gravity, "gravity");
  check_positive(spec.time_step, "time_step");
  check_positive(spec.start_gap, "start_gap");
  if (spec.max_steps <= 0) throw input_error("max_steps", std::to_string(spec.max_steps), "must be > 0");
  const auto t0 = std::chrono::steady_clock::now();

  // Two circle meshes made by Gmsh at the same characteristic length (the paper meshes both radii at h),
  // bottom grain 0 (material 0), top grain 1 (material 1) turned by pi/2 as in the authors' particle list.
  GmshRun gmsh;
  gmsh.directory = spec.mesh_directory.empty() ? std::string("pd_meshes") : spec.mesh_directory;
  const ReferenceGrain bottom_ref =
      circle_grain(spec.bottom_mesh_file, spec.bottom_radius, spec.mesh_size, gmsh, 0, "bottom grain");
  const ReferenceGrain top_ref =
      circle_grain(spec.top_mesh_file, spec.top_radius, spec.mesh_size, gmsh, 1, "top grain");

  const double gap0 = spec.full_drop ? spec.drop_height : std::min(spec.start_gap, spec.drop_height);
  PdNodes nodes;
  PdGrains grains;
  GrainRecord bottom{0, 0.0, 0.0, 0.0, spec.bottom_radius, 0.0};
  GrainRecord top{1, 0.0, spec.bottom_radius + spec.top_radius + gap0, 0.0, spec.top_radius, 0.5 * kPi};
  const int gb = place_grain(bottom_ref, bottom, nodes, grains);
  const int gt = place_grain(top_ref, top, nodes, grains);
  for (int i = grains.node_begin[gb]; i < grains.node_end[gb]; ++i) nodes.fixed[i] = 1 | 2 | 4;
  for (int i = grains.node_begin[gt]; i < grains.node_end[gt]; ++i) nodes.fixed[i] = 4;  // plane motion

  PdContactSettings contact;
  contact.contact_radius_factor = spec.contact_radius_factor;
  contact.restitution = spec.restitution;
  contact.damping_factor = spec.damping_factor;
  contact.damping_onset_factor = spec.damping_onset_factor;
  PeridemSettings settings;
  settings.time_step = spec.time_step;
  settings.gravity = Vec3{0.0, -spec.gravity, 0.0};
  settings.damping = spec.damping;
  settings.damping_centre_node = spec.damping_centre_node;
  settings.allow_unstable_time_step = spec.allow_unstable_time_step;
  PeridemSimulation sim(nodes, grains, {spec.bottom_material, spec.top_material}, {contact}, settings);
  if (!(spec.initial_speed >= 0)) throw input_error("initial_speed", format_value(spec.initial_speed), "must be >= 0");
  const double v0 = std::sqrt(spec.initial_speed * spec.initial_speed + 2.0 * spec.gravity * (spec.drop_height - gap0));
  sim.set_grain_velocity(gt, Vec3{0.0, -v0, 0.0});

  // Reads go through the const accessors: they bring back what changed and do not count as edits (offload
  // builds: the grain centres and, while the grains touch, the nodes come back every step).
  const PeridemSimulation& view = sim;
  sim.refresh_grain_centres();
  const double centre_gap0 = view.grains().cy[gt] - view.grains().cy[gb];
  auto gap = [&] { return gap0 + (view.grains().cy[gt] - view.grains().cy[gb]) - centre_gap0; };

  TwoParticleDropResult r;
  r.nodes = static_cast<long>(sim.node_count());
  r.mesh_h = sim.mesh_size();
  bool touched = false;
  long first_touch = -1, last_touch = -1, free_rising = 0;
  double max_gap_after = 0.0;
  const double g = spec.gravity, dt = spec.time_step;
  for (long s = 0; s < spec.max_steps; ++s) {
    sim.step();
    sim.refresh_grain_centres();
    const long touching = sim.touching_pairs();
    if (touching > 0) {
      // Damage peaks during the impact (eq 14 measures the current stretch): track its maximum per grain.
      sim.refresh_damage();
      for (int i = view.grains().node_begin[gb]; i < view.grains().node_end[gb]; ++i)
        r.bottom_max_damage = std::max(r.bottom_max_damage, view.nodes().damage[i]);
      for (int i = view.grains().node_begin[gt]; i < view.grains().node_end[gt]; ++i)
        r.top_max_damage = std::max(r.top_max_damage, view.nodes().damage[i]);
      if (!touched) first_touch = sim.step_count();
      touched = true;
      last_touch = sim.step_count();
      free_rising = 0;
      continue;
    }
    if (!touched) continue;
    // The stored velocity is half a step behind the positions (eq 32 in velocity form): the centre's
    // velocity at this step's time is v^{n-1/2} + dt/2 (-g) while the grain is free.
    const double v = view.grains().cvy[gt] - 0.5 * dt * g;
    const double h = gap();
    // Free and rising for 100 steps (a node pushed back into its grain can leave R_c for a few steps while
    // the grains still press together, so one free step does not end the contact): from here the centre
    // of mass rises ballistically.
    if (v > 0) ++free_rising;
    if (free_rising >= 100) {
      if (!spec.full_drop) {
        r.rebound_height = h + v * v / (2.0 * g);
        r.steps = sim.step_count();
        break;
      }
      max_gap_after = std::max(max_gap_after, h);
      if (v < 0) {  // past the top of the rebound
        r.rebound_height = max_gap_after;
        r.steps = sim.step_count();
        break;
      }
      continue;
    }
    if (v <= 0 && free_rising == 0 && s > 0 && sim.step_count() - last_touch > 1000) {
      r.rebound_height = std::max(h, 0.0);  // no rebound at all (stuck together)
      r.steps = sim.step_count();
      break;
    }
  }
  if (r.steps == 0)
    throw input_error("max_steps", std::to_string(spec.max_steps),
                      touched ? "steps were not enough for the top grain to leave the bottom one"
                              : "steps were not enough for the grains to touch");
  const std::string health = sim.health_check();
  if (!health.empty()) throw RunStop(health);  // exit 3: a run that cannot finish, not a bug
  // Eq 37 (with an initial speed, the height it would have fallen from at rest: H0 + v0^2 / 2g).
  r.restitution_coefficient =
      std::sqrt(r.rebound_height / (spec.drop_height + spec.initial_speed * spec.initial_speed / (2.0 * spec.gravity)));
  // Energy can only be lost: a rebound above the drop height means the run was unstable (possible only with
  // allow_unstable_time_step), and its numbers mean nothing.
  if (!(r.restitution_coefficient < 1.02))
    throw RunStop("the top grain rebounded with C_R = " + format_value(r.restitution_coefficient) +
                             " > 1: the contact gained energy, so the time step " + format_value(spec.time_step) +
                             " s is unstable for these grains (stable estimate " + format_value(sim.stable_time_step()) +
                             " s)");
  r.contact_time = static_cast<double>(last_touch - first_touch + 1) * dt;
  const PeridemDiagnostics d = sim.diagnostics();
  r.broken_bonds = d.broken_bonds;
  r.max_damage = std::max({d.max_damage, r.bottom_max_damage, r.top_max_damage});
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace debris
