// LAMMPS data files (atom_style sphere): exact round trips, handwritten files, and errors with line numbers.
#include "core/io/lammps_data.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <string>

#include "core/error.hpp"
#include "tests/cli_helpers.hpp"

namespace debris {
namespace {

std::string temp_path(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "/debris_lammps_data_test";
  std::filesystem::create_directories(dir);
  return dir + "/" + name;
}

std::string write_file(const std::string& name, const std::string& text) {
  const std::string path = temp_path(name);
  std::ofstream(path) << text;
  return path;
}

std::string read_error(const std::string& path) {
  try {
    read_lammps_data(path, {true, true, false});
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError reading " << path;
  return "";
}

using test::contains;

/// Particles in shuffled id order with awkward values: every bit must survive the text file.
Particles awkward_particles(std::size_t n) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Particles p;
  for (std::size_t k = 0; k < n; ++k) {
    const std::int64_t id = static_cast<std::int64_t>((k * 7) % n) + 1;  // a permutation of 1..n
    const double r = 1e-9 * (1.0 + 0.3 * u(rng));
    const std::size_t i = p.add(id, 1 + static_cast<int>(k % 3), 5e-9 * u(rng), 5e-9 * u(rng), 1e-8 * u(rng), r);
    p.vx[i] = u(rng) / 3.0;
    p.vy[i] = -0.0;
    p.vz[i] = 1e-300 * u(rng);
    p.wx[i] = 1e9 * u(rng);
    p.wy[i] = u(rng);
    p.wz[i] = 0.1;
    p.ix[i] = static_cast<int>(k % 5) - 2;
    p.iy[i] = -7;
    p.iz[i] = 0;
  }
  // Masses as the material sets them: one density per type.
  const double densities[3] = {2200.0, 2650.5, 7.9e3 / 3.0};
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double r = p.radius[i];
    p.mass[i] = densities[p.type[i] - 1] * 4.0 / 3.0 * std::numbers::pi * r * r * r;
    p.inertia[i] = 0.4 * p.mass[i] * r * r;
  }
  return p;
}

TEST(LammpsDataRoundTrip, EveryBitSurvives) {
  const Particles p = awkward_particles(97);  // 97 is prime, so (k * 7) % 97 visits every id once
  const Box box({-5e-9, -5e-9, -1e-8}, {5e-9, 5e-9, 1.0 / 3.0 * 3e-8}, {true, true, false});
  const std::string path = temp_path("round_trip.data");
  write_lammps_data(path, box, p);
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));

  const LammpsData d = read_lammps_data(path, box.periodic());
  EXPECT_EQ(d.box.lo().x, box.lo().x);
  EXPECT_EQ(d.box.hi().z, box.hi().z);
  EXPECT_EQ(d.box.periodic(), box.periodic());
  ASSERT_EQ(d.particles.size(), p.size());
  ASSERT_EQ(d.density.size(), p.size());

  // The file is sorted by id; find each original particle by id.
  std::vector<std::size_t> by_id(p.size() + 1);
  for (std::size_t i = 0; i < p.size(); ++i) by_id[static_cast<std::size_t>(p.id[i])] = i;
  const Particles& q = d.particles;
  for (std::size_t j = 0; j < q.size(); ++j) {
    ASSERT_EQ(q.id[j], static_cast<std::int64_t>(j) + 1);
    const std::size_t i = by_id[static_cast<std::size_t>(q.id[j])];
    EXPECT_EQ(q.type[j], p.type[i]);
    EXPECT_EQ(q.group[j], -1);
    for (const auto& [a, b] : {std::pair{q.x[j], p.x[i]}, std::pair{q.y[j], p.y[i]}, std::pair{q.z[j], p.z[i]},
                               std::pair{q.radius[j], p.radius[i]}, std::pair{q.mass[j], p.mass[i]},
                               std::pair{q.inertia[j], p.inertia[i]}, std::pair{q.vx[j], p.vx[i]},
                               std::pair{q.vy[j], p.vy[i]}, std::pair{q.vz[j], p.vz[i]}, std::pair{q.wx[j], p.wx[i]},
                               std::pair{q.wy[j], p.wy[i]}, std::pair{q.wz[j], p.wz[i]}})
      EXPECT_EQ(std::bit_cast<std::uint64_t>(a), std::bit_cast<std::uint64_t>(b)) << "id " << q.id[j];
    EXPECT_EQ(q.ix[j], p.ix[i]);
    EXPECT_EQ(q.iy[j], p.iy[i]);
    EXPECT_EQ(q.iz[j], p.iz[i]);
  }
  // The file holds each material's own density, not m / V an ulp away from it.
  for (std::size_t j = 0; j < q.size(); ++j) {
    const double expected[3] = {2200.0, 2650.5, 7.9e3 / 3.0};
    EXPECT_EQ(d.density[j], expected[q.type[j] - 1]) << "id " << q.id[j];
  }
}

TEST(LammpsDataRoundTrip, ArbitraryMassesSurvive) {
  // A density has too few bits to hit every mass through the reader's m = rho * 4/3 pi r^3, so masses that
  // did not come from a density come back within two ulps (about two thirds of them exactly).
  Particles p;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.5, 2.0);
  for (int k = 0; k < 200; ++k) {
    p.add(k + 1, 1, 0, 0, 0, u(rng));
    p.mass.back() = u(rng) * 1e3;
  }
  const std::string path = temp_path("masses.data");
  write_lammps_data(path, Box({-1, -1, -1}, {1, 1, 1}, {false, false, false}), p);
  const LammpsData d = read_lammps_data(path, {false, false, false});
  int exact = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    EXPECT_LE(std::abs(d.particles.mass[i] - p.mass[i]), 2 * (std::nextafter(p.mass[i], 1e9) - p.mass[i]));
    exact += d.particles.mass[i] == p.mass[i];
  }
  EXPECT_GT(exact, 100);
}

TEST(LammpsDataRead, HandwrittenFileWithCommentsAndMasses) {
  const std::string path = write_file("hand.data", R"(# two spheres written by hand
  2 atoms   # count
  2 atom types
0 bonds

 0.0 10.0 xlo xhi
-5 5 ylo yhi
0 20 zlo zhi
0.0 0.0 0.0 xy xz yz

Masses

1 1.0
2 3.0

Atoms # sphere

7 2 2.0 3.0 1.0 2.0 3.0 1 0 -1
3 1 0.5 1000 4 5 6

Velocities

3 0.1 0.2 0.3 1 2 3
7 -1 -2 -3 0 0 0.5
)");
  const LammpsData d = read_lammps_data(path, {true, false, false});
  EXPECT_EQ(d.box.lo().x, 0.0);
  EXPECT_EQ(d.box.hi().x, 10.0);
  EXPECT_EQ(d.box.lo().y, -5.0);
  EXPECT_EQ(d.box.hi().z, 20.0);
  EXPECT_TRUE(d.box.periodic(0));
  EXPECT_FALSE(d.box.periodic(1));
  const Particles& p = d.particles;
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p.id[0], 7);  // file order
  EXPECT_EQ(p.type[0], 2);
  EXPECT_EQ(p.radius[0], 1.0);
  EXPECT_DOUBLE_EQ(p.mass[0], 3.0 * 4.0 / 3.0 * std::numbers::pi);
  EXPECT_DOUBLE_EQ(p.inertia[0], 0.4 * p.mass[0]);
  EXPECT_EQ(p.x[0], 1.0);
  EXPECT_EQ(p.z[0], 3.0);
  EXPECT_EQ(p.ix[0], 1);
  EXPECT_EQ(p.iz[0], 0);  // -1 in the file, on an axis that is not periodic: reset (as LAMMPS does)
  EXPECT_EQ(p.vx[0], -1.0);
  EXPECT_EQ(p.wz[0], 0.5);
  EXPECT_EQ(p.id[1], 3);
  EXPECT_EQ(p.radius[1], 0.25);
  EXPECT_DOUBLE_EQ(p.mass[1], 1000 * 4.0 / 3.0 * std::numbers::pi * 0.25 * 0.25 * 0.25);
  EXPECT_EQ(p.ix[1], 0);
  EXPECT_EQ(p.vy[1], 0.2);
  EXPECT_EQ(p.wy[1], 2.0);
  EXPECT_EQ(p.group[1], -1);
  ASSERT_EQ(d.density.size(), 2u);
  EXPECT_EQ(d.density[0], 3.0);
  EXPECT_EQ(d.density[1], 1000.0);
}

TEST(LammpsDataRead, NoVelocitiesMeansAtRest) {
  const std::string path = write_file("rest.data", "t\n1 atoms\n1 atom types\n0 1 xlo xhi\n0 1 ylo yhi\n"
                                                   "0 1 zlo zhi\nAtoms\n\n1 1 0.2 5 0.5 0.5 0.5\n");
  const LammpsData d = read_lammps_data(path, {false, false, false});
  ASSERT_EQ(d.particles.size(), 1u);
  EXPECT_EQ(d.particles.vx[0], 0.0);
  EXPECT_EQ(d.particles.wz[0], 0.0);
}

// Image flags on an axis that is not periodic mean nothing: reset to 0 with a warning naming the count and
// the axis, as LAMMPS does; on periodic axes they are kept.
TEST(LammpsDataRead, ImageFlagsOnNonPeriodicAxesAreResetWithAWarning) {
  const std::string path = write_file("images.data", "t\n3 atoms\n1 atom types\n0 10 xlo xhi\n0 10 ylo yhi\n"
                                                     "0 10 zlo zhi\nAtoms\n\n1 1 1 1 5 5 5 2 1 0\n"
                                                     "2 1 1 1 6 5 5 -1 3 0\n3 1 1 1 7 5 5 0 0 0\n");
  ::testing::internal::CaptureStderr();
  const LammpsData d = read_lammps_data(path, {true, false, false});
  const std::string warning = ::testing::internal::GetCapturedStderr();
  ASSERT_EQ(d.particles.size(), 3u);
  EXPECT_EQ(d.particles.ix, (std::vector<int>{2, -1, 0}));  // x is periodic: kept
  EXPECT_EQ(d.particles.iy, (std::vector<int>{0, 0, 0}));
  EXPECT_NE(warning.find("warning: " + path + ": 2 atoms have a nonzero image flag on the non-periodic y axis"),
            std::string::npos)
      << warning;
  EXPECT_EQ(warning.find(" x axis"), std::string::npos) << warning;
  EXPECT_EQ(warning.find(" z axis"), std::string::npos) << warning;
  // Periodic everywhere: nothing to say.
  ::testing::internal::CaptureStderr();
  const LammpsData all = read_lammps_data(path, {true, true, true});
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
  EXPECT_EQ(all.particles.iy, (std::vector<int>{1, 3, 0}));
}

/// A valid header around `atoms` (the Atoms section body) and optional extra sections.
std::string data_file(const std::string& atoms, const std::string& header_count = "2 atoms",
                      const std::string& extra = "") {
  return "title\n" + header_count +
         "\n1 atom types\n0 10 xlo xhi\n0 10 ylo yhi\n0 10 zlo zhi\n\nAtoms # sphere\n\n" + atoms + extra;
}

struct BadCase {
  const char* name;
  std::string text;
  const char* expect_line;
  const char* expect_text;
};

TEST(LammpsDataRead, BadFilesNameTheLine) {
  const std::string good_atom = "1 1 1.0 2.0 1 1 1\n";
  const std::vector<BadCase> cases = {
      {"columns", data_file(good_atom + "2 1 1.0 2.0 1 1\n"), "line 11", "found 6"},
      {"nonnumeric", data_file(good_atom + "2 1 1.0 2.0 1 x 1\n"), "line 11", "'y' = x"},
      {"diameter", data_file(good_atom + "2 1 -0.5 2.0 1 1 1\n"), "line 11", "'diameter' = -0.5"},
      {"zero_diameter", data_file("2 1 0 2.0 1 1 1\n" + good_atom), "line 10", "'diameter' = 0"},
      {"density", data_file(good_atom + "2 1 1.0 0 1 1 1\n"), "line 11", "'density' = 0"},
      {"duplicate", data_file(good_atom + "1 1 1.0 2.0 2 2 2\n"), "line 11", "also line 10"},
      {"type", data_file(good_atom + "2 3 1.0 2.0 1 1 1\n"), "line 11", "'atom-type' = 3"},
      {"count", data_file(good_atom, "2 atoms"), "line 8", "the header says 2 atoms"},
      {"count_more", data_file(good_atom + "2 1 1 2 1 1 1\n3 1 1 2 1 1 1\n"), "line 8", "has 3 lines"},
      {"style", "t\n1 atoms\n1 atom types\n0 1 xlo xhi\n0 1 ylo yhi\n0 1 zlo zhi\nAtoms # atomic\n\n1 1 0 0 0\n",
       "line 7", "atom style must be sphere"},
      {"tilt", "t\n0 atoms\n0 1 xlo xhi\n0 1 ylo yhi\n0 1 zlo zhi\n0.5 0 0 xy xz yz\n", "line 6", "orthogonal"},
      {"bounds", "t\n0 atoms\n0 1 xlo xhi\n2 1 ylo yhi\n0 1 zlo zhi\n", "line 4", "hi must be larger"},
      {"no_z", "t\n0 atoms\n0 1 xlo xhi\n0 1 ylo yhi\n", "line 4", "zlo zhi"},
      {"velocity_id",
       data_file(good_atom + "2 1 1 2 1 1 1\n", "2 atoms", "\nVelocities\n\n1 0 0 0 0 0 0\n9 0 0 0 0 0 0\n"), "line 16",
       "'atom-ID' = 9"},
      {"velocity_count", data_file(good_atom + "2 1 1 2 1 1 1\n", "2 atoms", "\nVelocities\n\n1 0 0 0 0 0 0\n"),
       "line 13", "one line per atom"},
      {"velocity_columns",
       data_file(good_atom + "2 1 1 2 1 1 1\n", "2 atoms", "\nVelocities\n\n1 0 0 0 0 0 0\n2 0 0 0\n"), "line 16",
       "found 4"},
  };
  for (const BadCase& c : cases) {
    const std::string path = write_file(std::string(c.name) + ".data", c.text);
    const std::string msg = read_error(path);
    EXPECT_TRUE(contains(msg, path + " " + c.expect_line)) << c.name << ": " << msg;
    EXPECT_TRUE(contains(msg, c.expect_text)) << c.name << ": " << msg;
  }
}

TEST(LammpsDataRead, MissingFileNamesThePath) {
  const std::string path = temp_path("does_not_exist.data");
  const std::string msg = read_error(path);
  EXPECT_TRUE(contains(msg, path)) << msg;
}

TEST(LammpsDataWrite, FileLooksLikeLammpsWritesIt) {
  Particles p;
  p.add(2, 1, 0.5, 0.25, 0.125, 0.5);
  p.add(1, 2, 1.5, 1.25, 1.125, 0.25);
  p.set_mass_from_density(2000.0);
  p.vx[0] = 3.0;
  p.wz[1] = -4.0;
  const std::string path = temp_path("layout.data");
  write_lammps_data(path, Box({0, 0, 0}, {2, 2, 2}, {true, true, true}), p);
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  ASSERT_EQ(lines.size(), 18u);
  EXPECT_EQ(lines[2], "2 atoms");
  EXPECT_EQ(lines[3], "2 atom types");
  EXPECT_EQ(lines[5], "0 2 xlo xhi");
  EXPECT_EQ(lines[9], "Atoms # sphere");
  EXPECT_EQ(lines[11], "1 2 0.5 2000 1.5 1.25 1.125 0 0 0");  // sorted by id: diameter 2r, density
  EXPECT_EQ(lines[12], "2 1 1 2000 0.5 0.25 0.125 0 0 0");
  EXPECT_EQ(lines[14], "Velocities");
  EXPECT_EQ(lines[16], "1 0 0 0 0 0 -4");
  EXPECT_EQ(lines[17], "2 3 0 0 0 0 0");
}

TEST(LammpsDataWrite, RefusesWhatLammpsCannotRead) {
  Particles p;
  p.add(0, 1, 0, 0, 0, 1.0);
  p.set_mass_from_density(1.0);
  const std::string path = temp_path("id0.data");
  EXPECT_THROW(write_lammps_data(path, Box({-1, -1, -1}, {1, 1, 1}, {false, false, false}), p), InputError);
  EXPECT_FALSE(std::filesystem::exists(path));
  EXPECT_THROW(write_lammps_data(temp_path("no_such_dir/x.data"), Box(), Particles()), OutputError);
}

}  // namespace
}  // namespace debris
