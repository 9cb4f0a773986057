// The thermo CSV: a header line, then one full-precision row per call, readable while the run goes on.
#include "core/io/thermo_csv.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
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

std::vector<double> cells(const std::string& line) {
  std::istringstream in(line);
  std::vector<double> out;
  for (std::string c; std::getline(in, c, ',');) out.push_back(std::strtod(c.c_str(), nullptr));
  return out;
}

TEST(ThermoCsv, HeaderAndRowsReadBack) {
  const std::string path = ::testing::TempDir() + "/debris_thermo_test.csv";
  ThermoCsv csv(path, {"step", "time", "kinetic_energy", "bonds"});
  EXPECT_EQ(read_lines(path), std::vector<std::string>{"step,time,kinetic_energy,bonds"});  // header at once
  const std::vector<double> row0 = {0, 0, 1.0 / 3.0, 1200};
  const std::vector<double> row1 = {100, 2e-12, 6.02214076e23 / 7.0, 1187};
  csv.write_row(row0);
  EXPECT_EQ(read_lines(path).size(), 2u);  // flushed: visible before the writer goes away
  csv.write_row(row1);

  const std::vector<std::string> lines = read_lines(path);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0], "step,time,kinetic_energy,bonds");
  EXPECT_EQ(lines[1].substr(0, 4), "0,0,");
  EXPECT_EQ(cells(lines[1]), row0);
  EXPECT_EQ(cells(lines[2]), row1);  // every bit, at 17 significant digits
}

TEST(ThermoCsv, WrongRowSizeIsALogicError) {
  ThermoCsv csv(::testing::TempDir() + "/debris_thermo_size.csv", {"a", "b"});
  EXPECT_THROW(csv.write_row({1.0}), std::logic_error);
  EXPECT_THROW(csv.write_row({1.0, 2.0, 3.0}), std::logic_error);
  EXPECT_NO_THROW(csv.write_row({1.0, 2.0}));
}

TEST(ThermoCsv, BadColumnsAndPaths) {
  EXPECT_THROW(ThermoCsv(::testing::TempDir() + "/debris_thermo_bad.csv", {"a,b"}), std::invalid_argument);
  EXPECT_THROW(ThermoCsv(::testing::TempDir() + "/debris_thermo_bad.csv", {}), std::invalid_argument);
  EXPECT_THROW(ThermoCsv(::testing::TempDir() + "/no_such_dir_for_debris/t.csv", {"a"}), OutputError);
}

}  // namespace
}  // namespace debris
