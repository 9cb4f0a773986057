#include "core/io/node_trajectory_writer.hpp"

#include <cstdint>
#include <numeric>
#include <stdexcept>

#include "core/comm/communicator.hpp"
#include "core/error.hpp"
#include "core/io/hdf5_file.hpp"
#include "core/io/xdmf.hpp"
#include "core/pd_nodes.hpp"

namespace debris {

NodeFrameShare NodeFrameShare::all_of(const PdNodes& nodes) {
  NodeFrameShare all;
  all.which.resize(nodes.size());
  std::iota(all.which.begin(), all.which.end(), 0);
  all.rows.resize(nodes.size());
  std::iota(all.rows.begin(), all.rows.end(), std::int64_t{0});
  all.total = nodes.size();
  return all;
}

NodeTrajectoryWriter::NodeTrajectoryWriter(const std::string& dir, const std::string& stem, const PdNodes& nodes,
                                           const PdGrains& grains, const std::vector<std::string>& grain_names)
    : NodeTrajectoryWriter(dir, stem, nodes, NodeFrameShare::all_of(nodes), {},
                           std::vector<int>(grains.kind.begin(), grains.kind.end()), grain_names, false) {}

NodeTrajectoryWriter::NodeTrajectoryWriter(const std::string& dir, const std::string& stem, const PdNodes& nodes,
                                           const NodeFrameShare& share, const std::vector<int>& grain_ids,
                                           const std::vector<int>& grain_kinds,
                                           const std::vector<std::string>& grain_names, bool all_ranks)
    : h5_name_(stem + ".h5"),
      h5_path_(dir + "/" + stem + ".h5"),
      xmf_path_(dir + "/" + stem + ".xmf"),
      nodes_(share.total),
      all_ranks_(all_ranks) {
  xdmf::check_stem(stem);
  if (grain_names.size() != grain_kinds.size())
    throw std::invalid_argument("node trajectory: " + std::to_string(grain_names.size()) + " names for " +
                                std::to_string(grain_kinds.size()) + " grains");
  const std::size_t n = share.which.size();
  std::vector<std::int64_t> id(n);
  std::vector<std::int32_t> grain(n);
  std::vector<double> volume(n);
  for (std::size_t r = 0; r < n; ++r) {
    const auto i = static_cast<std::size_t>(share.which[r]);
    id[r] = nodes.id[i];
    const int g = nodes.grain[i];
    grain[r] = grain_ids.empty() ? g : grain_ids[static_cast<std::size_t>(g)];
    volume[r] = nodes.volume[i];
  }
  try {
    h5::File file(h5_path_, h5::File::Mode::create, xdmf::frames_file_options(all_ranks_));
    file.set_string_attribute("format",
                              "debris node trajectory 1: nodes/{id,grain,volume}, grains/{name,kind}, "
                              "frames/<k>/{position,velocity,force,damage,broken_fraction}");
    const h5::RowSelection one(share.rows, {share.total});
    file.write_rows<std::int64_t>("nodes/id", id, one);
    file.write_rows<std::int32_t>("nodes/grain", grain, one);
    file.write_rows<double>("nodes/volume", volume, one);
    file.write_strings("grains/name", grain_names);
    file.write("grains/kind", std::vector<std::int32_t>(grain_kinds.begin(), grain_kinds.end()));
    file.create_group("frames", {.reserved_name_bytes = xdmf::kFrameNameBytes});
    file.flush();
    file.close();
  } catch (const std::runtime_error& e) {
    throw output_error(h5_path_, e.what());
  }
  if (!all_ranks_ || comm::rank() == 0) write_xmf();
}

void NodeTrajectoryWriter::write_frame(long step, double time, const PdNodes& nodes,
                                       const std::vector<double>& broken_fraction) {
  if (nodes.size() != nodes_)
    throw std::invalid_argument("node trajectory " + h5_path_ + ": " + std::to_string(nodes.size()) +
                                " nodes, the file holds " + std::to_string(nodes_));
  write_frame(step, time, nodes, NodeFrameShare::all_of(nodes), broken_fraction);
}

void NodeTrajectoryWriter::write_frame(long step, double time, const PdNodes& nodes, const NodeFrameShare& share,
                                       const std::vector<double>& broken_fraction) {
  const std::size_t n = share.which.size();
  if (share.total != nodes_ || broken_fraction.size() != nodes.size())
    throw std::invalid_argument("node trajectory " + h5_path_ + ": a frame of " + std::to_string(share.total) +
                                " nodes with " + std::to_string(broken_fraction.size()) + " damage values for " +
                                std::to_string(nodes.size()) + " held, the file holds " + std::to_string(nodes_));
  std::vector<double> position(3 * n), velocity(3 * n), force(3 * n), damage(n), broken(n);
  for (std::size_t r = 0; r < n; ++r) {
    const auto i = static_cast<std::size_t>(share.which[r]);
    position[3 * r] = nodes.x[i], position[3 * r + 1] = nodes.y[i], position[3 * r + 2] = nodes.z[i];
    velocity[3 * r] = nodes.vx[i], velocity[3 * r + 1] = nodes.vy[i], velocity[3 * r + 2] = nodes.vz[i];
    force[3 * r] = nodes.fx[i], force[3 * r + 1] = nodes.fy[i], force[3 * r + 2] = nodes.fz[i];
    damage[r] = nodes.damage[i];
    broken[r] = broken_fraction[i];
  }
  const std::size_t k = frames_.size();
  try {
    // Open only inside this block; the frame is flushed before it is linked (trajectory_writer.cpp).
    h5::File file(h5_path_, h5::File::Mode::read_write, xdmf::frames_file_options(all_ranks_));
    {
      h5::Group g = file.create_unlinked_group({.small = true});
      const h5::RowSelection one(share.rows, {share.total}), three(share.rows, {share.total, 3});
      g.write_rows<double>("position", position, three);
      g.write_rows<double>("velocity", velocity, three);
      g.write_rows<double>("force", force, three);
      g.write_rows<double>("damage", damage, one);
      g.write_rows<double>("broken_fraction", broken, one);
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
  if (!all_ranks_ || comm::rank() == 0) write_xmf();  // only now is frame k complete on disk
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
