#include "core/io/node_trajectory_writer.hpp"

#include <cstdint>
#include <stdexcept>

#include "core/error.hpp"
#include "core/io/hdf5_file.hpp"
#include "core/io/xdmf.hpp"
#include "core/pd_nodes.hpp"

namespace debris {

NodeTrajectoryWriter::NodeTrajectoryWriter(const std::string& dir, const std::string& stem, const PdNodes& nodes,
                                           const PdGrains& grains, const std::vector<std::string>& grain_names)
    : h5_name_(stem + ".h5"),
      h5_path_(dir + "/" + stem + ".h5"),
      xmf_path_(dir + "/" + stem + ".xmf"),
      nodes_(nodes.size()) {
  xdmf::check_stem(stem);
  if (grain_names.size() != grains.size())
    throw std::invalid_argument("node trajectory: " + std::to_string(grain_names.size()) + " names for " +
                                std::to_string(grains.size()) + " grains");
  try {
    h5::File file(h5_path_, h5::File::Mode::create, {.file_locking = false, .group_leaf_k = xdmf::kFramesPerLeaf / 2});
    file.set_string_attribute("format",
                              "debris node trajectory 1: nodes/{id,grain,volume}, grains/{name,kind}, "
                              "frames/<k>/{position,velocity,force,damage,broken_fraction}");
    file.write("nodes/id", nodes.id);
    file.write("nodes/grain", nodes.grain);
    file.write("nodes/volume", nodes.volume);
    file.write_strings("grains/name", grain_names);
    file.write("grains/kind", grains.kind);
    file.create_group("frames", {.reserved_name_bytes = xdmf::kFrameNameBytes});
    file.flush();
    file.close();
  } catch (const std::runtime_error& e) {
    throw output_error(h5_path_, e.what());
  }
  write_xmf();
}

void NodeTrajectoryWriter::write_frame(long step, double time, const PdNodes& nodes,
                                       const std::vector<double>& broken_fraction) {
  const std::size_t n = nodes.size();
  if (n != nodes_ || broken_fraction.size() != n)
    throw std::invalid_argument("node trajectory " + h5_path_ + ": " + std::to_string(n) + " nodes and " +
                                std::to_string(broken_fraction.size()) + " damage values, the file holds " +
                                std::to_string(nodes_));
  std::vector<double> position(3 * n), velocity(3 * n), force(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    position[3 * i] = nodes.x[i], position[3 * i + 1] = nodes.y[i], position[3 * i + 2] = nodes.z[i];
    velocity[3 * i] = nodes.vx[i], velocity[3 * i + 1] = nodes.vy[i], velocity[3 * i + 2] = nodes.vz[i];
    force[3 * i] = nodes.fx[i], force[3 * i + 1] = nodes.fy[i], force[3 * i + 2] = nodes.fz[i];
  }
  const std::size_t k = frames_.size();
  try {
    // Open only inside this block; the frame is flushed before it is linked (trajectory_writer.cpp).
    h5::File file(h5_path_, h5::File::Mode::read_write, {.file_locking = false});
    {
      h5::Group g = file.create_unlinked_group({.small = true});
      g.write("position", position, n, 3);
      g.write("velocity", velocity, n, 3);
      g.write("force", force, n, 3);
      g.write("damage", nodes.damage);
      g.write("broken_fraction", broken_fraction);
      g.set_attribute("step", static_cast<std::int64_t>(step));
      g.set_attribute("time", time);
      file.flush();
      file.link(g, "frames/" + std::to_string(k));
    }
    file.close();
  } catch (const std::runtime_error& e) {  // HDF5 cannot write: a full disk, a file size limit
    throw output_error(h5_path_, e.what());
  }
  frames_.push_back({step, time});
  write_xmf();  // only now is frame k complete on disk
}

void NodeTrajectoryWriter::write_xmf() const {
  const std::string h5 = xdmf::escaped(h5_name_);
  const std::string n = std::to_string(nodes_);
  std::string x = xdmf::begin("nodes");
  for (std::size_t k = 0; k < frames_.size(); ++k) {
    const std::string frame = h5 + ":/frames/" + std::to_string(k) + "/";
    xdmf::begin_frame(x, frames_[k].step, frames_[k].time, n, frame + "position");
    xdmf::attribute(x, "id", false, n, "Int", 8, h5 + ":/nodes/id");
    xdmf::attribute(x, "grain", false, n, "Int", 4, h5 + ":/nodes/grain");
    xdmf::attribute(x, "volume", false, n, "Float", 8, h5 + ":/nodes/volume");
    xdmf::attribute(x, "damage", false, n, "Float", 8, frame + "damage");
    xdmf::attribute(x, "broken_fraction", false, n, "Float", 8, frame + "broken_fraction");
    xdmf::attribute(x, "velocity", true, n, "Float", 8, frame + "velocity");
    xdmf::attribute(x, "force", true, n, "Float", 8, frame + "force");
    xdmf::end_frame(x);
  }
  xdmf::end(x);
  xdmf::replace_file(xmf_path_, x, "node trajectory");
}

}  // namespace debris
