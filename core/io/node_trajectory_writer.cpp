#include "core/io/node_trajectory_writer.hpp"

#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "core/error.hpp"
#include "core/io/hdf5_file.hpp"
#include "core/pd_nodes.hpp"

namespace debris {

namespace {

// As in trajectory_writer.cpp: index leaves and the name heap of /frames sized up front, so that linking
// a frame rewrites them in place (what a kill between two writes cannot damage) in all but rare frames.
constexpr unsigned kFramesPerLeaf = 512;
constexpr std::size_t kFrameNameBytes = 8 * 8192;

/// Shortest text that reads back as the same double.
std::string text_of(double v) {
  char buf[32];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, res.ptr);
}

std::string xml_escaped(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

void attribute(std::string& x, const char* name, bool vector, const std::string& n, const char* number_type,
               int precision, const std::string& h5, const std::string& dataset) {
  x += std::string("        <Attribute Name=\"") + name + "\" AttributeType=\"" + (vector ? "Vector" : "Scalar") +
       "\" Center=\"Node\">\n";
  x += "          <DataItem Dimensions=\"" + (vector ? n + " 3" : n) + "\" NumberType=\"" + number_type +
       "\" Precision=\"" + std::to_string(precision) + "\" Format=\"HDF\">" + h5 + ":" + dataset + "</DataItem>\n";
  x += "        </Attribute>\n";
}

}  // namespace

NodeTrajectoryWriter::NodeTrajectoryWriter(const std::string& dir, const std::string& stem, const PdNodes& nodes,
                                           const PdGrains& grains, const std::vector<std::string>& grain_names)
    : h5_name_(stem + ".h5"),
      h5_path_(dir + "/" + stem + ".h5"),
      xmf_path_(dir + "/" + stem + ".xmf"),
      nodes_(nodes.size()) {
  // XDMF splits "file.h5:/path" at the colon, and the reference must stay relative to the .xmf.
  if (stem.empty() || stem.find_first_of(":/") != std::string::npos)
    throw input_error("output", stem, "a trajectory file stem must be non-empty and hold neither ':' nor '/'");
  if (grain_names.size() != grains.size())
    throw std::invalid_argument("node trajectory: " + std::to_string(grain_names.size()) + " names for " +
                                std::to_string(grains.size()) + " grains");
  try {
    h5::File file(h5_path_, h5::File::Mode::create, {.file_locking = false, .group_leaf_k = kFramesPerLeaf / 2});
    file.set_string_attribute("format",
                              "debris node trajectory 1: nodes/{id,grain,volume}, grains/{name,kind}, "
                              "frames/<k>/{position,velocity,force,damage,broken_fraction}");
    file.write("nodes/id", nodes.id);
    file.write("nodes/grain", nodes.grain);
    file.write("nodes/volume", nodes.volume);
    file.write_strings("grains/name", grain_names);
    file.write("grains/kind", grains.kind);
    file.create_group("frames", {.reserved_name_bytes = kFrameNameBytes});
    file.flush();
    file.close();
  } catch (const std::runtime_error& e) {
    throw input_error("output", h5_path_, e.what());
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
  {
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
  }
  frames_.push_back({step, time});
  write_xmf();  // only now is frame k complete on disk
}

void NodeTrajectoryWriter::write_xmf() const {
  const std::string h5 = xml_escaped(h5_name_);
  const std::string n = std::to_string(nodes_);
  std::string x =
      "<?xml version=\"1.0\" ?>\n"
      "<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
      "<Xdmf Version=\"2.0\">\n"
      "  <Domain>\n"
      "    <Grid Name=\"nodes\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (std::size_t k = 0; k < frames_.size(); ++k) {
    const std::string frame = "/frames/" + std::to_string(k) + "/";
    x += "      <Grid Name=\"step " + std::to_string(frames_[k].step) + "\" GridType=\"Uniform\">\n";
    x += "        <Time Value=\"" + text_of(frames_[k].time) + "\"/>\n";
    x += "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" + n + "\"/>\n";
    x += "        <Geometry GeometryType=\"XYZ\">\n";
    x += "          <DataItem Dimensions=\"" + n + " 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" + h5 +
         ":" + frame + "position</DataItem>\n";
    x += "        </Geometry>\n";
    attribute(x, "id", false, n, "Int", 8, h5, "/nodes/id");
    attribute(x, "grain", false, n, "Int", 4, h5, "/nodes/grain");
    attribute(x, "volume", false, n, "Float", 8, h5, "/nodes/volume");
    attribute(x, "damage", false, n, "Float", 8, h5, frame + "damage");
    attribute(x, "broken_fraction", false, n, "Float", 8, h5, frame + "broken_fraction");
    attribute(x, "velocity", true, n, "Float", 8, h5, frame + "velocity");
    attribute(x, "force", true, n, "Float", 8, h5, frame + "force");
    x += "      </Grid>\n";
  }
  x += "    </Grid>\n  </Domain>\n</Xdmf>\n";

  // Written beside and renamed over, so a reader (or a kill) never sees half a file.
  const std::string tmp = xmf_path_ + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw input_error("output", tmp, std::string("cannot open for writing: ") + std::strerror(errno));
    out.write(x.data(), static_cast<std::streamsize>(x.size()));
    out.close();
    if (!out) throw std::runtime_error("node trajectory: writing " + tmp + " failed (disk full?)");
  }
  if (std::rename(tmp.c_str(), xmf_path_.c_str()) != 0)
    throw std::runtime_error("node trajectory: cannot rename " + tmp + " to " + xmf_path_ + ": " +
                             std::strerror(errno));
}

}  // namespace debris
