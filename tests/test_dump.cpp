// LAMMPS `dump custom` frames as OVITO reads them: header items, bounds tags, rows sorted by id, exact values.
#include "core/io/dump_writer.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.hpp"

namespace debris {
namespace {

std::vector<std::string> read_lines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

std::vector<double> numbers_of(const std::string& line) {
  std::istringstream in(line);
  std::vector<double> out;
  for (std::string t; in >> t;) out.push_back(std::strtod(t.c_str(), nullptr));
  return out;
}

/// Three particles stored out of id order, with values that need all 17 digits.
Particles sample() {
  Particles p;
  p.add(30, 2, 0.1, 0.2, 0.3, 1.0 / 3.0);
  p.add(4, 1, -1.0 / 7.0, 2.5, 1e-9, 0.5);
  p.add(17, 1, 3.0, 2.0 / 3.0, -0.0, 0.25);
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.vx[i] = 0.1 * static_cast<double>(i + 1);
    p.vy[i] = -1e-300;
    p.vz[i] = 7.0;
    p.fx[i] = 1.0 / 9.0;
    p.fy[i] = -2.0 * static_cast<double>(i);
    p.fz[i] = 6.02214076e23;
    p.wx[i] = -1.0 / 11.0 * static_cast<double>(i + 1);
    p.wy[i] = 2.5e12;
    p.wz[i] = -0.0;
    p.ix[i] = static_cast<int>(i) - 1;
    p.iy[i] = 0;
    p.iz[i] = 1000 * static_cast<int>(i);
    p.label[i] = static_cast<int>(2 - i);  // 0 (unlabelled) for the last one
    p.dissipated_normal[i] = 1.0 / 3.0 * static_cast<double>(i);  // the dump's dissipated adds the four
    p.dissipated_sliding[i] = 1e-20;
    p.tangential_work[i] = -2.0 / 7.0;
  }
  p.label_names = {"bottom", "top"};
  return p;
}

TEST(DumpWriter, TwoFramesParseBackExactly) {
  const std::string path = ::testing::TempDir() + "/debris_dump_test.lammpstrj";
  Particles p = sample();
  const Box box({-1, 0, -2.5}, {1, 1.0 / 3.0, 2.5}, {true, false, true});
  {
    DumpWriter dump(path);
    dump.write_frame(0, box, p);
    p.x[0] = 0.7;  // particle id 30 moves between the frames
    dump.write_frame(1000, box, p);
  }
  const std::vector<std::string> lines = read_lines(path);
  const std::size_t frame_lines = 9 + p.size();
  ASSERT_EQ(lines.size(), 2 * frame_lines);

  const std::vector<std::size_t> order = {1, 2, 0};  // memory index of ids 4, 17, 30
  for (int f = 0; f < 2; ++f) {
    const std::size_t o = static_cast<std::size_t>(f) * frame_lines;
    EXPECT_EQ(lines[o + 0], "ITEM: TIMESTEP");
    EXPECT_EQ(lines[o + 1], f == 0 ? "0" : "1000");
    EXPECT_EQ(lines[o + 2], "ITEM: NUMBER OF ATOMS");
    EXPECT_EQ(lines[o + 3], "3");
    EXPECT_EQ(lines[o + 4], "ITEM: BOX BOUNDS pp ff pp");
    EXPECT_EQ(numbers_of(lines[o + 5]), (std::vector<double>{-1, 1}));
    EXPECT_EQ(numbers_of(lines[o + 6]), (std::vector<double>{0, 1.0 / 3.0}));
    EXPECT_EQ(numbers_of(lines[o + 7]), (std::vector<double>{-2.5, 2.5}));
    EXPECT_EQ(lines[o + 8], "ITEM: ATOMS id type x y z radius vx vy vz fx fy fz omegax omegay omegaz ix iy iz mol dissipated tangential_work");
    for (std::size_t row = 0; row < p.size(); ++row) {
      const std::size_t i = order[row];
      const std::vector<double> v = numbers_of(lines[o + 9 + row]);
      ASSERT_EQ(v.size(), 21u);
      const double x = (f == 0 && i == 0) ? 0.1 : p.x[i];
      const std::vector<double> expected = {static_cast<double>(p.id[i]), static_cast<double>(p.type[i]),
                                            x, p.y[i], p.z[i], p.radius[i], p.vx[i], p.vy[i], p.vz[i],
                                            p.fx[i], p.fy[i], p.fz[i], p.wx[i], p.wy[i], p.wz[i],
                                            static_cast<double>(p.ix[i]), static_cast<double>(p.iy[i]),
                                            static_cast<double>(p.iz[i]), static_cast<double>(p.label[i]),
                                            particle_dissipated(p, i), p.tangential_work[i]};
      EXPECT_EQ(v, expected) << "frame " << f << " row " << row;
    }
  }
  EXPECT_EQ(lines[9].substr(0, 4), "4 1 ");  // ids and types are written as integers
  EXPECT_TRUE(lines[9].find(" 0 0 1000 1 ") != std::string::npos) << lines[9];  // so are ix iy iz mol (id 4)
}

TEST(DumpWriter, ReopeningTruncates) {
  const std::string path = ::testing::TempDir() + "/debris_dump_truncate.lammpstrj";
  const Box box({0, 0, 0}, {1, 1, 1}, {false, false, false});
  DumpWriter(path).write_frame(1, box, sample());
  DumpWriter second(path);
  second.write_frame(2, box, Particles());
  const std::vector<std::string> lines = read_lines(path);
  ASSERT_EQ(lines.size(), 9u);
  EXPECT_EQ(lines[1], "2");
  EXPECT_EQ(lines[3], "0");
  EXPECT_EQ(lines[4], "ITEM: BOX BOUNDS ff ff ff");
}

TEST(DumpWriter, UnwritablePathIsAnOutputErrorNamingIt) {
  const std::string path = ::testing::TempDir() + "/no_such_dir_for_debris/x.lammpstrj";
  try {
    DumpWriter dump(path);
    FAIL() << "opened " << path;
  } catch (const OutputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("output error"), std::string::npos) << msg;
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
  }
}

}  // namespace
}  // namespace debris
