#include "core/io/trajectory_writer.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <numeric>
#include <stdexcept>

#include "core/error.hpp"
#include "core/io/hdf5_file.hpp"

namespace debris {

namespace {

// Linking a frame rewrites the index of /frames in place, which a kill between two writes cannot damage;
// splitting a full index leaf or moving a full heap of names can (a kill mid-way leaves pointers past the
// end of file that the superblock records). Sizing both up front makes those events rare: a leaf split every 256 frames after the first 512,
// a heap move after 8192 frames (names take 8 bytes each). The price is ~85 KiB rewritten per frame.
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
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

/// One <DataItem> that points into the .h5; `dims` is "N" or "N 3".
void data_item(std::string& x, const std::string& dims, const char* number_type, int precision,
               const std::string& h5_name, std::size_t frame, const char* dataset) {
  x += "          <DataItem Dimensions=\"" + dims + "\" NumberType=\"" + number_type + "\" Precision=\"" +
       std::to_string(precision) + "\" Format=\"HDF\">" + h5_name + ":/frames/" + std::to_string(frame) + "/" +
       dataset + "</DataItem>\n";
}

}  // namespace

TrajectoryWriter::TrajectoryWriter(const std::string& dir, const std::string& stem, std::vector<std::string> group_names)
    : h5_name_(stem + ".h5"),
      h5_path_(dir + "/" + stem + ".h5"),
      xmf_path_(dir + "/" + stem + ".xmf"),
      group_names_(std::move(group_names)) {
  // XDMF splits "file.h5:/path" at the colon, and the reference must stay relative to the .xmf.
  if (stem.empty() || stem.find_first_of(":/") != std::string::npos) {
    throw input_error("output", stem, "a trajectory file stem must be non-empty and hold neither ':' nor '/'");
  }
  try {
    h5::File file(h5_path_, h5::File::Mode::create, {.file_locking = false, .group_leaf_k = kFramesPerLeaf / 2});
    file.set_string_attribute("format", "debris trajectory 1: frames/<k>/{position,id,type,radius,velocity,force,group}");
    file.write_strings("group_names", group_names_);
    file.create_group("frames", {.reserved_name_bytes = kFrameNameBytes});
    file.flush();
    file.close();
  } catch (const std::runtime_error& e) {
    throw input_error("output", h5_path_, e.what());
  }
  write_xmf();
}

void TrajectoryWriter::write_frame(long step, double time, const Box& box, const Particles& p) {
  const std::size_t n = p.size();
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&p](std::size_t a, std::size_t b) { return p.id[a] < p.id[b]; });

  std::vector<double> position(3 * n), velocity(3 * n), force(3 * n), radius(n);
  std::vector<std::int64_t> id(n);
  std::vector<std::int32_t> type(n), group(n);
  const int groups = static_cast<int>(group_names_.size());
  for (std::size_t r = 0; r < n; ++r) {
    const std::size_t i = order[r];
    position[3 * r] = p.x[i], position[3 * r + 1] = p.y[i], position[3 * r + 2] = p.z[i];
    velocity[3 * r] = p.vx[i], velocity[3 * r + 1] = p.vy[i], velocity[3 * r + 2] = p.vz[i];
    force[3 * r] = p.fx[i], force[3 * r + 1] = p.fy[i], force[3 * r + 2] = p.fz[i];
    radius[r] = p.radius[i];
    id[r] = p.id[i];
    type[r] = p.type[i];
    group[r] = p.group[i];
    if (group[r] < -1 || group[r] >= groups) {
      throw std::invalid_argument("trajectory " + h5_path_ + ": particle " + std::to_string(id[r]) + " is in group " +
                                  std::to_string(group[r]) + ", but only " + std::to_string(groups) + " are named");
    }
  }

  const std::size_t k = frames_.size();
  {
    // The file is open only inside this block: a kill between frames finds it closed and complete.
    // Within the block, a two-step commit: the frame is built as a group linked nowhere and flushed, so
    // its data and the new end of file are on disk before anything the file already held is touched;
    // only then does linking it as /frames/<k> rewrite the index of /frames, and close() flushes that.
    h5::File file(h5_path_, h5::File::Mode::read_write, {.file_locking = false});
    {
      h5::Group g = file.create_unlinked_group({.small = true});
      g.write("position", position, n, 3);
      g.write("id", id);
      g.write("type", type);
      g.write("radius", radius);
      g.write("velocity", velocity, n, 3);
      g.write("force", force, n, 3);
      g.write("group", group);
      const Vec3 lo = box.lo(), hi = box.hi();
      g.set_attribute("step", static_cast<std::int64_t>(step));
      g.set_attribute("time", time);
      g.set_attribute("box_lo", std::vector<double>{lo.x, lo.y, lo.z});
      g.set_attribute("box_hi", std::vector<double>{hi.x, hi.y, hi.z});
      g.set_attribute("periodic", std::vector<std::int32_t>{box.periodic(0), box.periodic(1), box.periodic(2)});
      file.flush();
      file.link(g, "frames/" + std::to_string(k));
    }
    file.close();
  }
  frames_.push_back({step, time, n});
  write_xmf();  // only now is frame k complete on disk
}

void TrajectoryWriter::write_xmf() const {
  const std::string h5 = xml_escaped(h5_name_);
  std::string x =
      "<?xml version=\"1.0\" ?>\n"
      "<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
      "<Xdmf Version=\"2.0\">\n"
      "  <Domain>\n"
      "    <Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (std::size_t k = 0; k < frames_.size(); ++k) {
    const Frame& f = frames_[k];
    const std::string n = std::to_string(f.particles);
    x += "      <Grid Name=\"step " + std::to_string(f.step) + "\" GridType=\"Uniform\">\n";
    x += "        <Time Value=\"" + text_of(f.time) + "\"/>\n";
    x += "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" + n + "\"/>\n";
    x += "        <Geometry GeometryType=\"XYZ\">\n";
    data_item(x, n + " 3", "Float", 8, h5, k, "position");
    x += "        </Geometry>\n";
    struct Field {
      const char* name;
      bool vector;
      const char* number_type;
      int precision;
    };
    for (const Field& a : {Field{"id", false, "Int", 8}, Field{"type", false, "Int", 4}, Field{"radius", false, "Float", 8},
                           Field{"group", false, "Int", 4}, Field{"velocity", true, "Float", 8},
                           Field{"force", true, "Float", 8}}) {
      x += std::string("        <Attribute Name=\"") + a.name + "\" AttributeType=\"" + (a.vector ? "Vector" : "Scalar") +
           "\" Center=\"Node\">\n";
      data_item(x, a.vector ? n + " 3" : n, a.number_type, a.precision, h5, k, a.name);
      x += "        </Attribute>\n";
    }
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
    if (!out) throw std::runtime_error("trajectory: writing " + tmp + " failed (disk full?)");
  }
  if (std::rename(tmp.c_str(), xmf_path_.c_str()) != 0) {
    throw std::runtime_error("trajectory: cannot rename " + tmp + " to " + xmf_path_ + ": " + std::strerror(errno));
  }
}

}  // namespace debris
