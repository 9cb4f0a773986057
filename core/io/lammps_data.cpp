#include "core/io/lammps_data.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <numbers>
#include <numeric>
#include <sstream>
#include <unordered_map>

#include "core/error.hpp"
#include "core/io/text_format.hpp"

namespace debris {

namespace {

// The same expression, in the same order, as Particles::set_mass_from_density, so that a particle whose
// mass came from a density gets that mass back bit for bit when its file is read.
double sphere_mass(double density, double r) { return density * 4.0 / 3.0 * std::numbers::pi * r * r * r; }

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

std::vector<std::string> split(const std::string& s) {
  std::istringstream in(s);
  std::vector<std::string> out;
  for (std::string t; in >> t;) out.push_back(t);
  return out;
}

/// Reads the file line by line and says where, in every error.
class DataFileReader {
 public:
  explicit DataFileReader(const std::string& path) : path_(path) {
    std::ifstream in(path);
    if (!in) throw input_error("data file", path, std::string("cannot be opened for reading: ") + std::strerror(errno));
    for (std::string line; std::getline(in, line);) lines_.push_back(line);
    if (in.bad()) throw input_error("data file", path, "cannot be read");
  }

  [[noreturn]] void fail(std::size_t line, const std::string& key, const std::string& value,
                         const std::string& what) const {
    throw input_error(key, value, what + " (" + path_ + " line " + std::to_string(line + 1) + ")");
  }

  double real(std::size_t line, const std::string& key, const std::string& token) const {
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(token.c_str(), &end);
    if (end == token.c_str() || *end != '\0') fail(line, key, token, "not a number");
    if (!std::isfinite(v) || errno == ERANGE) fail(line, key, token, "not a finite number in double range");
    return v;
  }

  template <class Int>
  Int whole(std::size_t line, const std::string& key, const std::string& token) const {
    Int v = 0;
    const auto [stop, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
    if (ec != std::errc() || stop != token.data() + token.size())
      fail(line, key, token, "not a whole number in range");
    return v;
  }

  std::size_t size() const { return lines_.size(); }
  const std::string& operator[](std::size_t i) const { return lines_[i]; }

 private:
  std::string path_;
  std::vector<std::string> lines_;
};

/// The line without its '#' comment, trimmed.
std::string content_of(const std::string& line) { return trim(line.substr(0, line.find('#'))); }

/// Section keywords start with a letter; data lines and header counts start with a number.
bool starts_section(const std::string& content) {
  return !content.empty() && std::isalpha(static_cast<unsigned char>(content[0]));
}

struct AtomRow {
  std::size_t line;
  std::int64_t id;
  int type;
  double diameter, density, x, y, z;
  int ix = 0, iy = 0, iz = 0;
};

struct VelocityRow {
  std::size_t line;
  std::int64_t id;
  double v[6];
};

AtomRow parse_atom(const DataFileReader& f, std::size_t line, const std::string& content, long atom_types) {
  const std::vector<std::string> t = split(content);
  if (t.size() != 7 && t.size() != 10)
    f.fail(line, "Atoms", content,
           "expected 7 or 10 columns (atom-ID atom-type diameter density x y z [ix iy iz]), found " +
               std::to_string(t.size()));
  AtomRow a{};
  a.line = line;
  a.id = f.whole<std::int64_t>(line, "atom-ID", t[0]);
  if (a.id < 1) f.fail(line, "atom-ID", t[0], "must be >= 1");
  a.type = f.whole<int>(line, "atom-type", t[1]);
  if (a.type < 1 || a.type > atom_types)
    f.fail(line, "atom-type", t[1], "must be in [1, " + std::to_string(atom_types) + "] (the header's atom types)");
  a.diameter = f.real(line, "diameter", t[2]);
  if (!(a.diameter > 0)) f.fail(line, "diameter", t[2], "must be > 0 (point particles are not supported)");
  a.density = f.real(line, "density", t[3]);
  if (!(a.density > 0)) f.fail(line, "density", t[3], "must be > 0");
  a.x = f.real(line, "x", t[4]);
  a.y = f.real(line, "y", t[5]);
  a.z = f.real(line, "z", t[6]);
  if (t.size() == 10) {
    a.ix = f.whole<int>(line, "ix", t[7]);
    a.iy = f.whole<int>(line, "iy", t[8]);
    a.iz = f.whole<int>(line, "iz", t[9]);
  }
  return a;
}

VelocityRow parse_velocity(const DataFileReader& f, std::size_t line, const std::string& content) {
  const std::vector<std::string> t = split(content);
  if (t.size() != 7)
    f.fail(line, "Velocities", content,
           "expected 7 columns (atom-ID vx vy vz wx wy wz), found " + std::to_string(t.size()));
  VelocityRow r{};
  r.line = line;
  r.id = f.whole<std::int64_t>(line, "atom-ID", t[0]);
  static const char* names[6] = {"vx", "vy", "vz", "wx", "wy", "wz"};
  for (int k = 0; k < 6; ++k) r.v[k] = f.real(line, names[k], t[static_cast<std::size_t>(k) + 1]);
  return r;
}

}  // namespace

LammpsData read_lammps_data(const std::string& path, std::array<bool, 3> periodic) {
  const DataFileReader f(path);

  // Header: counts and box bounds, up to the first section keyword. Line 0 is the title.
  long long atoms = -1;
  long atom_types = -1;
  std::size_t atoms_line = 0;
  double lo[3], hi[3];
  bool have_bounds[3] = {false, false, false};
  std::size_t i = 1;
  for (; i < f.size(); ++i) {
    const std::string content = content_of(f[i]);
    if (content.empty()) continue;
    if (starts_section(content)) break;
    const std::vector<std::string> t = split(content);
    if (t.size() == 2 && t[1] == "atoms") {
      atoms = f.whole<long long>(i, "atoms", t[0]);
      if (atoms < 0) f.fail(i, "atoms", t[0], "must be >= 0");
      atoms_line = i;
    } else if (t.size() == 3 && t[1] == "atom" && t[2] == "types") {
      atom_types = f.whole<long>(i, "atom types", t[0]);
      if (atom_types < 1) f.fail(i, "atom types", t[0], "must be >= 1");
    } else if (t.size() == 4 && (t[2] + " " + t[3] == "xlo xhi" || t[2] + " " + t[3] == "ylo yhi" ||
                                 t[2] + " " + t[3] == "zlo zhi")) {
      const int a = t[2][0] - 'x';
      const std::string key = t[2] + " " + t[3];
      lo[a] = f.real(i, key, t[0]);
      hi[a] = f.real(i, key, t[1]);
      if (!(hi[a] > lo[a])) f.fail(i, key, t[0] + " " + t[1], "hi must be larger than lo");
      have_bounds[a] = true;
    } else if (t.size() == 6 && t[3] == "xy" && t[4] == "xz" && t[5] == "yz") {
      for (int k = 0; k < 3; ++k)
        if (f.real(i, "xy xz yz", t[static_cast<std::size_t>(k)]) != 0.0)
          f.fail(i, "xy xz yz", t[0] + " " + t[1] + " " + t[2], "only orthogonal boxes are supported; tilts must be 0");
    }
    // Other header counts (bonds, ellipsoids, ...) have no meaning for atom_style sphere.
  }
  const std::size_t header_end = f.size() == 0 ? 0 : std::min(i, f.size() - 1);
  if (atoms < 0) f.fail(header_end, "atoms", "(absent)", "missing header line 'N atoms'");
  for (int a = 0; a < 3; ++a)
    if (!have_bounds[a]) {
      const std::string key = std::string(1, char('x' + a)) + "lo " + char('x' + a) + "hi";
      f.fail(header_end, key, "(absent)", "missing header line '" + key + "'");
    }
  if (atom_types < 0 && atoms > 0)
    f.fail(header_end, "atom types", "(absent)", "missing header line 'N atom types'");

  // Sections: each runs from its keyword to the next line that starts with a letter.
  std::vector<AtomRow> atom_rows;
  std::vector<VelocityRow> velocity_rows;
  std::size_t atoms_section = 0, velocities_section = 0;
  bool seen_atoms = false, seen_velocities = false;
  while (i < f.size()) {
    const std::size_t header = i;
    const std::string name = content_of(f[i]);
    const auto hash = f[i].find('#');
    const std::string hint = hash == std::string::npos ? "" : trim(f[i].substr(hash + 1));
    bool* seen = nullptr;
    if (name == "Atoms") {
      seen = &seen_atoms;
      atoms_section = header;
      // write_data names the atom style after '#'; columns of another style would be misread silently.
      if (!hint.empty() && split(hint)[0] != "sphere")
        f.fail(header, "Atoms", "# " + hint, "atom style must be sphere (atom-ID atom-type diameter density x y z)");
    } else if (name == "Velocities") {
      seen = &seen_velocities;
      velocities_section = header;
    }
    if (seen) {
      if (*seen) f.fail(header, name, "(section)", "section given twice");
      *seen = true;
    }
    for (++i; i < f.size(); ++i) {
      const std::string content = content_of(f[i]);
      if (content.empty()) continue;
      if (starts_section(content)) break;
      if (name == "Atoms") atom_rows.push_back(parse_atom(f, i, content, atom_types));
      if (name == "Velocities") velocity_rows.push_back(parse_velocity(f, i, content));
    }
  }

  if (static_cast<long long>(atom_rows.size()) != atoms)
    f.fail(seen_atoms ? atoms_section : atoms_line, "atoms", std::to_string(atoms),
           "the header says " + std::to_string(atoms) + " atoms but the Atoms section has " +
               std::to_string(atom_rows.size()) + " lines");
  if (seen_velocities && velocity_rows.size() != atom_rows.size())
    f.fail(velocities_section, "Velocities", std::to_string(velocity_rows.size()) + " lines",
           "must have one line per atom (" + std::to_string(atom_rows.size()) + ")");

  LammpsData data;
  data.box = Box({lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}, periodic);
  Particles& p = data.particles;
  std::unordered_map<std::int64_t, std::size_t> index_of;
  for (const AtomRow& a : atom_rows) {
    const auto [it, fresh] = index_of.emplace(a.id, p.size());
    if (!fresh)
      f.fail(a.line, "atom-ID", std::to_string(a.id),
             "appears twice (also line " + std::to_string(atom_rows[it->second].line + 1) + ")");
    const std::size_t k = p.add(a.id, a.type, a.x, a.y, a.z, a.diameter / 2);
    const double r = p.radius[k];
    p.mass[k] = sphere_mass(a.density, r);
    p.inertia[k] = 0.4 * p.mass[k] * r * r;
    p.ix[k] = a.ix;
    p.iy[k] = a.iy;
    p.iz[k] = a.iz;
    data.density.push_back(a.density);
  }
  // An image count means nothing on an axis that is not periodic: LAMMPS resets it to 0 with a warning,
  // and so does this reader (an unwrapped position x + ix L_x would otherwise be off by whole box lengths).
  for (int axis = 0; axis < 3; ++axis) {
    if (periodic[static_cast<std::size_t>(axis)]) continue;
    auto& image = axis == 0 ? p.ix : axis == 1 ? p.iy : p.iz;
    std::size_t reset = 0;
    for (int& c : image)
      if (c != 0) {
        c = 0;
        ++reset;
      }
    if (reset > 0)
      std::cerr << "warning: " << path << ": " << reset << " atom" << (reset == 1 ? " has" : "s have")
                << " a nonzero image flag on the non-periodic " << "xyz"[axis]
                << " axis; reset to 0, as LAMMPS does\n";
  }
  std::vector<bool> has_velocity(p.size(), false);
  for (const VelocityRow& v : velocity_rows) {
    const auto it = index_of.find(v.id);
    if (it == index_of.end()) f.fail(v.line, "atom-ID", std::to_string(v.id), "is not in the Atoms section");
    const std::size_t k = it->second;
    if (has_velocity[k]) f.fail(v.line, "atom-ID", std::to_string(v.id), "has two lines in the Velocities section");
    has_velocity[k] = true;
    p.vx[k] = v.v[0];
    p.vy[k] = v.v[1];
    p.vz[k] = v.v[2];
    p.wx[k] = v.v[3];
    p.wy[k] = v.v[4];
    p.wz[k] = v.v[5];
  }
  return data;
}

namespace {

/// The density that read_lammps_data turns back into exactly mass `m`, as short as possible: particles of
/// one material share a density, so `hint` (the last density used for this type) usually answers at once;
/// otherwise m / V is rounded to ever more digits ("2000", not "1999.9999999999998"), and as a last resort
/// stepped by ulps, keeping the density whose mass comes closest.
double density_for(double m, double r, double hint) {
  if (hint > 0 && sphere_mass(hint, r) == m) return hint;
  const double estimate = m / (4.0 / 3.0 * std::numbers::pi * r * r * r);
  char buf[40];
  for (int digits = 1; digits <= 17; ++digits) {
    const auto res = std::to_chars(buf, buf + sizeof buf - 1, estimate, std::chars_format::scientific, digits - 1);
    *res.ptr = '\0';
    const double rounded = std::strtod(buf, nullptr);
    if (sphere_mass(rounded, r) == m) return rounded;
  }
  double rho = estimate, best = estimate;
  for (int step = 0; step < 8; ++step) {
    const double back = sphere_mass(rho, r);
    if (back == m) return rho;
    if (std::abs(back - m) < std::abs(sphere_mass(best, r) - m)) best = rho;
    rho = std::nextafter(rho, back < m ? std::numeric_limits<double>::infinity() : 0.0);
  }
  return best;
}

}  // namespace

void write_lammps_data(const std::string& path, const Box& box, const Particles& p) {
  std::vector<std::size_t> order(p.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&p](std::size_t a, std::size_t b) { return p.id[a] < p.id[b]; });

  int atom_types = 1;
  for (std::size_t k : order) {
    const auto which = [&p, k] { return " (particle id " + std::to_string(p.id[k]) + ")"; };
    if (p.id[k] < 1) throw input_error("particle id", std::to_string(p.id[k]), "LAMMPS atom IDs must be >= 1");
    if (p.type[k] < 1)
      throw input_error("type", std::to_string(p.type[k]), "LAMMPS atom types must be >= 1" + which());
    if (!(p.radius[k] > 0)) throw input_error("radius", std::to_string(p.radius[k]), "must be > 0" + which());
    if (!(p.mass[k] > 0)) throw input_error("mass", std::to_string(p.mass[k]), "must be > 0" + which());
    atom_types = std::max(atom_types, p.type[k]);
  }

  const std::string tmp = path + ".tmp";
  std::ofstream file(tmp, std::ios::binary | std::ios::trunc);
  if (!file) throw output_error(path, "cannot open '" + tmp + "' for writing: " + std::strerror(errno));
  std::string out;
  // Lines are formatted into `out` and handed to the file a megabyte at a time.
  const auto drain = [&file, &out](std::size_t keep_below) {
    if (out.size() < keep_below) return;
    file.write(out.data(), static_cast<std::streamsize>(out.size()));
    out.clear();
  };

  out += "LAMMPS data file written by debris (atom_style sphere)\n\n";
  append_number(out, static_cast<std::int64_t>(p.size()));
  out += " atoms\n";
  append_number(out, atom_types);
  out += " atom types\n\n";
  const Vec3 lo = box.lo(), hi = box.hi();
  const double los[3] = {lo.x, lo.y, lo.z}, his[3] = {hi.x, hi.y, hi.z};
  for (int a = 0; a < 3; ++a) {
    append_number(out, los[a]);
    out += ' ';
    append_number(out, his[a]);
    out += std::string(" ") + char('x' + a) + "lo " + char('x' + a) + "hi\n";
  }
  out += "\nAtoms # sphere\n\n";
  std::vector<double> density_of_type(static_cast<std::size_t>(atom_types) + 1, 0.0);
  for (std::size_t k : order) {
    double& density = density_of_type[static_cast<std::size_t>(p.type[k])];
    density = density_for(p.mass[k], p.radius[k], density);
    append_number(out, p.id[k]);
    out += ' ';
    append_number(out, p.type[k]);
    for (double v : {2 * p.radius[k], density, p.x[k], p.y[k], p.z[k]}) {
      out += ' ';
      append_number(out, v);
    }
    for (int v : {p.ix[k], p.iy[k], p.iz[k]}) {
      out += ' ';
      append_number(out, v);
    }
    out += '\n';
    drain(1 << 20);
  }
  out += "\nVelocities\n\n";
  for (std::size_t k : order) {
    append_number(out, p.id[k]);
    for (double v : {p.vx[k], p.vy[k], p.vz[k], p.wx[k], p.wy[k], p.wz[k]}) {
      out += ' ';
      append_number(out, v);
    }
    out += '\n';
    drain(1 << 20);
  }
  drain(0);
  file.close();
  std::error_code ec;
  if (!file) {
    std::filesystem::remove(tmp, ec);
    throw output_error(path, "writing '" + tmp + "' failed (disk full?)");
  }
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw output_error(path, "cannot rename '" + tmp + "' onto it: " + ec.message());
}

}  // namespace debris
