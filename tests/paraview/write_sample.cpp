// Writes a small known trajectory for the ParaView test: OUTPUT_DIR/sample.{h5,xmf} through
// TrajectoryWriter, and OUTPUT_DIR/expected.json with what ParaView must show (check_trajectory.py).
// Particles are stored out of id order and the last frame has more of them, as in a real run.
// Under mpirun (an MPI build) the ranks write the file together, each a share of every frame's particles
// (the parallel trajectory of a run cut among ranks); rank 0 writes expected.json.
#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <fstream>
#include <numeric>
#include <string>
#include <vector>

#include "core/comm/communicator.hpp"
#include "core/io/trajectory_writer.hpp"

namespace {

using debris::Particles;

/// Shortest text that reads back as the same double (valid JSON for finite values).
std::string num(double v) {
  char buf[32];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, res.ptr);
}

Particles frame(int k) {
  std::vector<std::int64_t> ids = {50, 3, 27, 8, 14};
  if (k == 2) ids.insert(ids.end(), {1, 99, 33});
  Particles p;
  for (std::int64_t id : ids) {
    const double d = static_cast<double>(id);
    // -d/3 needs all 17 digits, so a reader that loses precision shows up.
    const std::size_t i = p.add(id, 1 + static_cast<int>(id % 2), 0.5 * d + k, -d / 3.0, 0.125 * k, 0.1 + d / 1000.0);
    // Every component distinct per particle and frame, some needing all 17 digits.
    p.vx[i] = 1.0 + k, p.vy[i] = -d, p.vz[i] = d / 9.0;
    p.fx[i] = 1e-3 * d + k, p.fy[i] = -d / 11.0, p.fz[i] = -9.81 * d;
    p.group[i] = id < 10 ? 0 : -1;
    p.wx[i] = d / 7.0, p.wy[i] = -0.5, p.wz[i] = 1e-3 * k;
    p.ix[i] = static_cast<int>(id % 3) - 1, p.iy[i] = 0, p.iz[i] = k;
    p.label[i] = static_cast<int>(id % 4);  // 0 = unlabelled
  }
  p.label_names = {"bottom", "top", "junction"};
  return p;
}

const double kTimes[] = {0.0, 0.25, 0.5};

/// One frame as ParaView must show it: points in id order.
std::string expected_frame(const Particles& p) {
  std::vector<std::size_t> order(p.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&p](std::size_t a, std::size_t b) { return p.id[a] < p.id[b]; });
  std::string ids, pos, rad, label, omega, image, type, group, vel, force;
  for (std::size_t i : order) {
    const std::string sep = ids.empty() ? "" : ", ";
    ids += sep + std::to_string(p.id[i]);
    pos += sep + "[" + num(p.x[i]) + ", " + num(p.y[i]) + ", " + num(p.z[i]) + "]";
    type += sep + std::to_string(p.type[i]);
    group += sep + std::to_string(p.group[i]);
    vel += sep + "[" + num(p.vx[i]) + ", " + num(p.vy[i]) + ", " + num(p.vz[i]) + "]";
    force += sep + "[" + num(p.fx[i]) + ", " + num(p.fy[i]) + ", " + num(p.fz[i]) + "]";
    rad += sep + num(p.radius[i]);
    label += sep + std::to_string(p.label[i]);
    omega += sep + "[" + num(p.wx[i]) + ", " + num(p.wy[i]) + ", " + num(p.wz[i]) + "]";
    image += sep + "[" + std::to_string(p.ix[i]) + ", " + std::to_string(p.iy[i]) + ", " + std::to_string(p.iz[i]) + "]";
  }
  return "{\"points\": " + std::to_string(p.size()) + ", \"id\": [" + ids + "], \"position\": [" + pos +
         "], \"radius\": [" + rad + "], \"label\": [" + label + "], \"angular_velocity\": [" + omega +
         "], \"image\": [" + image + "], \"type\": [" + type + "], \"group\": [" + group + "], \"velocity\": [" +
         vel + "], \"force\": [" + force + "]}";
}

}  // namespace

// This rank's share of frame `p`: every size()-th particle in storage order, and the rows of their ids.
debris::FrameShare share_of(const Particles& p) {
  std::vector<std::int64_t> ids(p.id.begin(), p.id.end());
  std::sort(ids.begin(), ids.end());
  debris::FrameShare share;
  for (std::size_t i = static_cast<std::size_t>(debris::comm::rank()); i < p.size();
       i += static_cast<std::size_t>(debris::comm::size()))
    share.which.push_back(static_cast<int>(i));
  std::sort(share.which.begin(), share.which.end(), [&p](int a, int b) {
    return p.id[static_cast<std::size_t>(a)] < p.id[static_cast<std::size_t>(b)];
  });
  for (const int i : share.which)
    share.rows.push_back(std::lower_bound(ids.begin(), ids.end(), p.id[static_cast<std::size_t>(i)]) - ids.begin());
  share.total = p.size();
  return share;
}

int main(int argc, char** argv) {
  debris::comm::Session mpi(&argc, &argv);
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUTPUT_DIR\n", argv[0]);
    return 2;
  }
  const std::string dir = argv[1];
  try {
    const debris::Box box({-1, -40, -1}, {60, 1, 1}, {true, false, true});
    const bool ranks = debris::comm::size() > 1;
    debris::TrajectoryWriter w(dir, "sample", {"small_ids"}, ranks);
    for (int k = 0; k < 3; ++k) {
      const Particles p = frame(k);
      if (ranks) w.write_frame(100L * k, kTimes[k], box, p, share_of(p));
      else w.write_frame(100L * k, kTimes[k], box, p);
    }
    if (debris::comm::rank() != 0) return 0;
    std::ofstream json(dir + "/expected.json");
    json << "{\"times\": [" << num(kTimes[0]) << ", " << num(kTimes[1]) << ", " << num(kTimes[2]) << "],\n"
         << " \"first\": " << expected_frame(frame(0)) << ",\n"
         << " \"last\": " << expected_frame(frame(2)) << "}\n";
    if (!json.flush()) throw std::runtime_error("cannot write " + dir + "/expected.json");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "write_sample: %s\n", e.what());
    return 1;
  }
  return 0;
}
