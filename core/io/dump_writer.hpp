#pragma once
// Snapshots as LAMMPS `dump custom` text frames, the format OVITO opens directly:
//   ITEM: ATOMS id type x y z radius vx vy vz fx fy fz omegax omegay omegaz ix iy iz mol
// with LAMMPS's names, so OVITO maps them to its standard properties: omega* the angular velocity, ix iy iz
// the periodic image counts (OVITO's "Periodic Image", for unwrapped trajectories), mol the particle's label
// (Particles::label, the body it started in: 0 none, k = label_names[k-1]; OVITO's "Molecule Identifier",
// for colouring by body). New columns go at the end, so readers that count columns keep working.
// One file holds every frame of a run; each frame is flushed, so a killed run keeps what it wrote.
#include <fstream>
#include <string>

#include "core/box.hpp"
#include "core/io/key_reference.hpp"
#include "core/particles.hpp"

namespace debris {

/// The columns of a frame's ITEM: ATOMS lines; the writer takes its header from it.
const ColumnTable& dump_table();

class DumpWriter {
 public:
  /// Truncates `path`; InputError ("output") if it cannot be opened.
  explicit DumpWriter(const std::string& path);

  /// Appends one frame with the particles sorted by id (their order in memory changes when they are
  /// sorted by cell) and every value at full double precision.
  void write_frame(long step, const Box& box, const Particles& p);

 private:
  std::string path_;
  std::ofstream out_;
};

}  // namespace debris
