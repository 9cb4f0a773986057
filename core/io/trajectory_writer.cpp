#include "core/io/trajectory_writer.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <span>
#include <stdexcept>

#include "core/comm/communicator.hpp"
#include "core/error.hpp"
#include "core/io/hdf5_file.hpp"
#include "core/io/xdmf.hpp"

namespace debris {

TrajectoryWriter::TrajectoryWriter(const std::string& dir, const std::string& stem, std::vector<std::string> group_names,
                                   bool all_ranks)
    : h5_name_(stem + ".h5"),
      h5_path_(dir + "/" + stem + ".h5"),
      xmf_path_(dir + "/" + stem + ".xmf"),
      group_names_(std::move(group_names)),
      all_ranks_(all_ranks) {
  xdmf::check_stem(stem);
  try {
    h5::File file(h5_path_, h5::File::Mode::create, xdmf::frames_file_options(all_ranks_));
    file.set_string_attribute("format", "debris trajectory 1: frames/<k>/{position,id,type,radius,velocity,force,group,angular_velocity,image,label,label_names}");
    file.write_strings("group_names", group_names_);
    file.create_group("frames", {.reserved_name_bytes = xdmf::kFrameNameBytes});
    file.flush();
    file.close();
  } catch (const std::runtime_error& e) {
    throw output_error(h5_path_, e.what());
  }
  if (!all_ranks_ || comm::rank() == 0) write_xmf();
}

FrameShare FrameShare::all_of(const Particles& p) {
  FrameShare all;
  all.which.resize(p.size());
  std::iota(all.which.begin(), all.which.end(), 0);
  std::sort(all.which.begin(), all.which.end(), [&p](int a, int b) {
    return p.id[static_cast<std::size_t>(a)] < p.id[static_cast<std::size_t>(b)];
  });
  all.rows.resize(p.size());
  std::iota(all.rows.begin(), all.rows.end(), std::int64_t{0});
  all.total = p.size();
  return all;
}

void TrajectoryWriter::write_frame(long step, double time, const Box& box, const Particles& p) {
  write_frame(step, time, box, p, FrameShare::all_of(p));
}

void TrajectoryWriter::write_frame(long step, double time, const Box& box, const Particles& p, const FrameShare& share) {
  const std::size_t n = share.which.size();
  std::vector<double> position(3 * n), velocity(3 * n), force(3 * n), omega(3 * n), radius(n);
  std::vector<double> dissipated(n), tangential_work(n);
  std::vector<std::int64_t> id(n);
  std::vector<std::int32_t> type(n), group(n), image(3 * n), label(n);
  const int groups = static_cast<int>(group_names_.size());
  std::string unnamed;  // the first particle in a group without a name
  for (std::size_t r = 0; r < n; ++r) {
    const auto i = static_cast<std::size_t>(share.which[r]);
    position[3 * r] = p.x[i], position[3 * r + 1] = p.y[i], position[3 * r + 2] = p.z[i];
    velocity[3 * r] = p.vx[i], velocity[3 * r + 1] = p.vy[i], velocity[3 * r + 2] = p.vz[i];
    force[3 * r] = p.fx[i], force[3 * r + 1] = p.fy[i], force[3 * r + 2] = p.fz[i];
    omega[3 * r] = p.wx[i], omega[3 * r + 1] = p.wy[i], omega[3 * r + 2] = p.wz[i];
    image[3 * r] = p.ix[i], image[3 * r + 1] = p.iy[i], image[3 * r + 2] = p.iz[i];
    label[r] = p.label[i];
    radius[r] = p.radius[i];
    dissipated[r] = particle_dissipated(p, i);
    tangential_work[r] = p.tangential_work[i];
    id[r] = p.id[i];
    type[r] = p.type[i];
    group[r] = p.group[i];
    if ((group[r] < -1 || group[r] >= groups) && unnamed.empty())
      unnamed = "trajectory " + h5_path_ + ": particle " + std::to_string(id[r]) + " is in group " +
                std::to_string(group[r]) + ", but only " + std::to_string(groups) + " are named";
  }
  // Every rank stops alike (before any collective call) when one holds such a particle.
  if (all_ranks_) unnamed = comm::first_message(unnamed);
  if (!unnamed.empty()) throw std::invalid_argument(unnamed);

  const std::size_t k = frames_.size();
  try {
    // The file is open only inside this block: a kill between frames finds it closed and complete.
    // Within the block, a two-step commit: the frame is built as a group linked nowhere and flushed, so
    // its data and the new end of file are on disk before anything the file already held is touched;
    // only then does linking it as /frames/<k> rewrite the index of /frames, and close() flushes that.
    h5::File file(h5_path_, h5::File::Mode::read_write, xdmf::frames_file_options(all_ranks_));
    {
      h5::Group g = file.create_unlinked_group({.small = true});
      const h5::RowSelection one(share.rows, {share.total}), three(share.rows, {share.total, 3});
      g.write_rows<double>("position", position, three);
      g.write_rows<std::int64_t>("id", id, one);
      g.write_rows<std::int32_t>("type", type, one);
      g.write_rows<double>("radius", radius, one);
      g.write_rows<double>("velocity", velocity, three);
      g.write_rows<double>("force", force, three);
      g.write_rows<std::int32_t>("group", group, one);
      g.write_rows<double>("angular_velocity", omega, three);
      g.write_rows<std::int32_t>("image", image, three);
      g.write_rows<std::int32_t>("label", label, one);
      g.write_rows<double>("dissipated", dissipated, one);
      g.write_rows<double>("tangential_work", tangential_work, one);
      // The legend of `label`, per frame: it travels with the particles (Particles::label_names).
      g.write_strings("label_names", p.label_names);
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
  } catch (const std::runtime_error& e) {  // HDF5 cannot write: a full disk, a file size limit
    throw output_error(h5_path_, e.what());
  }
  frames_.push_back({step, time, share.total});
  if (!all_ranks_ || comm::rank() == 0) write_xmf();  // only now is frame k complete on disk
}

void TrajectoryWriter::write_xmf() const {
  const std::string h5 = xdmf::escaped(h5_name_);
  std::string x = xdmf::begin("particles");
  for (std::size_t k = 0; k < frames_.size(); ++k) {
    const Frame& f = frames_[k];
    const std::string n = std::to_string(f.particles), frame = h5 + ":/frames/" + std::to_string(k) + "/";
    xdmf::begin_frame(x, f.step, f.time, n, frame + "position");
    struct Field {
      const char* name;
      bool vector;
      const char* number_type;
      int precision;
    };
    for (const Field& a : {Field{"id", false, "Int", 8}, Field{"type", false, "Int", 4}, Field{"radius", false, "Float", 8},
                           Field{"group", false, "Int", 4}, Field{"label", false, "Int", 4},
                           Field{"dissipated", false, "Float", 8}, Field{"tangential_work", false, "Float", 8},
                           Field{"velocity", true, "Float", 8}, Field{"force", true, "Float", 8},
                           Field{"angular_velocity", true, "Float", 8}, Field{"image", true, "Int", 4}})
      xdmf::attribute(x, a.name, a.vector, n, a.number_type, a.precision, frame + a.name);
    xdmf::end_frame(x);
  }
  xdmf::end(x);
  xdmf::replace_file(xmf_path_, x, "trajectory");
}

}  // namespace debris
