#include "core/io/dump_writer.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <numeric>
#include <vector>

#include "core/error.hpp"

namespace debris {

namespace {

/// Full double precision, %.17g, whatever the locale.
void put(std::string& out, double v) {
  char buf[32];
  const auto res = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 17);
  out.append(buf, res.ptr);
}

template <class Int>
void put(std::string& out, Int v) {
  char buf[24];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, res.ptr);
}

}  // namespace

DumpWriter::DumpWriter(const std::string& path) : path_(path), out_(path, std::ios::binary | std::ios::trunc) {
  if (!out_) throw input_error("output", path, std::string("cannot open for writing: ") + std::strerror(errno));
}

void DumpWriter::write_frame(long step, const Box& box, const Particles& p) {
  std::vector<std::size_t> order(p.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&p](std::size_t a, std::size_t b) { return p.id[a] < p.id[b]; });

  std::string text = "ITEM: TIMESTEP\n";
  put(text, step);
  text += "\nITEM: NUMBER OF ATOMS\n";
  put(text, static_cast<std::int64_t>(p.size()));
  text += "\nITEM: BOX BOUNDS";
  for (int a = 0; a < 3; ++a) text += box.periodic(a) ? " pp" : " ff";
  text += '\n';
  const Vec3 lo = box.lo(), hi = box.hi();
  for (const auto& [l, h] : {std::pair{lo.x, hi.x}, std::pair{lo.y, hi.y}, std::pair{lo.z, hi.z}}) {
    put(text, l);
    text += ' ';
    put(text, h);
    text += '\n';
  }
  text += "ITEM: ATOMS id type x y z radius vx vy vz fx fy fz\n";
  for (std::size_t k : order) {
    put(text, p.id[k]);
    text += ' ';
    put(text, p.type[k]);
    for (double v : {p.x[k], p.y[k], p.z[k], p.radius[k], p.vx[k], p.vy[k], p.vz[k], p.fx[k], p.fy[k], p.fz[k]}) {
      text += ' ';
      put(text, v);
    }
    text += '\n';
    if (text.size() >= (1u << 20)) {  // bounded memory for large frames
      out_.write(text.data(), static_cast<std::streamsize>(text.size()));
      text.clear();
    }
  }
  out_.write(text.data(), static_cast<std::streamsize>(text.size()));
  out_.flush();
  if (!out_) throw input_error("output", path_, "writing a frame failed (disk full?)");
}

}  // namespace debris
