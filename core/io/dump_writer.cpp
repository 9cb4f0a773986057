#include "core/io/dump_writer.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <numeric>
#include <vector>

#include "core/error.hpp"
#include "core/io/text_format.hpp"

namespace debris {

const ColumnTable& dump_table() {
  static const ColumnTable t{
      "dump.lammpstrj",
      "LAMMPS `dump custom` text frames (OVITO opens them), every `output.dump_every` steps and at the first and "
      "the last step; one line per particle, sorted by id, after the frame's step, particle count and box bounds "
      "(`pp` periodic, `ff` not); the input's units.",
      {
          {"id", "-", "the particle's permanent id", ""},
          {"type", "-", "the particle's type", ""},
          {"x", "m", "position, wrapped into the box on periodic axes", ""},
          {"y", "m", "position", ""},
          {"z", "m", "position", ""},
          {"radius", "m", "radius", ""},
          {"vx", "m/s", "velocity", ""},
          {"vy", "m/s", "velocity", ""},
          {"vz", "m/s", "velocity", ""},
          {"fx", "N", "force: the pair forces plus damping and external loads", ""},
          {"fy", "N", "force", ""},
          {"fz", "N", "force", ""},
          {"omegax", "rad/s", "angular velocity", ""},
          {"omegay", "rad/s", "angular velocity", ""},
          {"omegaz", "rad/s", "angular velocity", ""},
          {"ix", "-", "periodic image count along x: the unwrapped x is x + ix L_x", ""},
          {"iy", "-", "periodic image count along y", ""},
          {"iz", "-", "periodic image count along z", ""},
          {"mol", "-", "the particle's label, the body it started in (0: unlabelled); OVITO's Molecule Identifier", ""},
          {"dissipated", "J",
           "energy dissipated at this particle since the start: half of each of its pairs' damping and sliding "
           "losses, and the global damping of its own motion (0 without the energy accounting)",
           ""},
          {"tangential_work", "J",
           "work the relative motion did against the tangential forces of its pairs since the start, half of each "
           "pair's",
           ""},
      }};
  return t;
}

DumpWriter::DumpWriter(const std::string& path) : path_(path), out_(path, std::ios::binary | std::ios::trunc) {
  if (!out_) throw output_error(path, std::string("cannot open for writing: ") + std::strerror(errno));
}

void DumpWriter::write_frame(long step, const Box& box, const Particles& p) {
  std::vector<std::size_t> order(p.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&p](std::size_t a, std::size_t b) { return p.id[a] < p.id[b]; });

  std::string text = "ITEM: TIMESTEP\n";
  append_number(text, step);
  text += "\nITEM: NUMBER OF ATOMS\n";
  append_number(text, static_cast<std::int64_t>(p.size()));
  text += "\nITEM: BOX BOUNDS";
  for (int a = 0; a < 3; ++a) text += box.periodic(a) ? " pp" : " ff";
  text += '\n';
  const Vec3 lo = box.lo(), hi = box.hi();
  for (const auto& [l, h] : {std::pair{lo.x, hi.x}, std::pair{lo.y, hi.y}, std::pair{lo.z, hi.z}}) {
    append_number(text, l);
    text += ' ';
    append_number(text, h);
    text += '\n';
  }
  text += "ITEM: ATOMS";
  for (const std::string& c : dump_table().header()) text += ' ' + c;
  text += '\n';
  for (std::size_t k : order) {
    append_number(text, p.id[k]);
    text += ' ';
    append_number(text, p.type[k]);
    for (double v : {p.x[k], p.y[k], p.z[k], p.radius[k], p.vx[k], p.vy[k], p.vz[k], p.fx[k], p.fy[k], p.fz[k],
                     p.wx[k], p.wy[k], p.wz[k]}) {
      text += ' ';
      append_number(text, v);
    }
    for (int v : {p.ix[k], p.iy[k], p.iz[k], p.label[k]}) {
      text += ' ';
      append_number(text, v);
    }
    for (double v : {particle_dissipated(p, k), p.tangential_work[k]}) {
      text += ' ';
      append_number(text, v);
    }
    text += '\n';
    if (text.size() >= (1u << 20)) {  // bounded memory for large frames
      out_.write(text.data(), static_cast<std::streamsize>(text.size()));
      text.clear();
    }
  }
  out_.write(text.data(), static_cast<std::streamsize>(text.size()));
  out_.flush();
  if (!out_) throw output_error(path_, "writing a frame failed (disk full?)");
}

}  // namespace debris
