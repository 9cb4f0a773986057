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

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_all(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
}

// A resumed table keeps only intact rows: a row of too few cells (a torn row an earlier restart kept), a
// cell that is not a number, a last row without its line break; known rows fill what is missing, and rows
// due after the last intact one that nothing rebuilds are named as lost.
TEST(ThermoCsv, ResumingKeepsOnlyIntactRows) {
  const std::string path = ::testing::TempDir() + "/debris_thermo_resume.csv";
  write_all(path, "step,a,b\n0,1,2\n10,1.5\n20,x,3\n30,4,5\n40,6,7\n50,8,9\n60,1,2.5");
  {
    ThermoResume r{60, 10, {}};
    r.known[10] = {10, 0.25, 0.5};
    r.known[60] = {60, 1, 2.5};
    ThermoCsv csv(path, {"step", "a", "b"}, r);
    EXPECT_EQ(csv.repair_note(),
              "debris_thermo_resume.csv was cut short or damaged before this restart: 3 rows cut short or "
              "unreadable are dropped; the rows of steps 10 and 60 are rewritten from the checkpoint; the row of "
              "step 20 is lost (neither intact in the file nor in the checkpoint).");
    csv.write_row({70, 3, 4});
  }
  EXPECT_EQ(read_all(path), "step,a,b\n0,1,2\n10,0.25,0.5\n30,4,5\n40,6,7\n50,8,9\n60,1,2.5\n70,3,4\n");

  // Cut back at a row's end: the rows due after it are lost, unless known.
  write_all(path, "step,a,b\n0,1,2\n10,3,4\n");
  EXPECT_EQ(ThermoCsv(path, {"step", "a", "b"}, ThermoResume{50, 10, {{50, {50, 1, 1}}}}).repair_note(),
            "debris_thermo_resume.csv was cut short or damaged before this restart: the row of step 50 is "
            "rewritten from the checkpoint; the rows of steps 20, 30 and 40 are lost (neither intact in the file "
            "nor in the checkpoint).");
  // Empty or cut inside the header: as if missing; a header that differs is refused.
  for (const char* text : {"", "step,"}) {
    write_all(path, text);
    EXPECT_NO_THROW(ThermoCsv(path, {"step", "a", "b"}, ThermoResume{50, 10, {}}));
    EXPECT_EQ(read_all(path), "step,a,b\n") << text;
  }
  write_all(path, "step,a,c\n0,1,2\n");
  EXPECT_THROW(ThermoCsv(path, {"step", "a", "b"}, ThermoResume{50, 10, {}}), InputError);
}

}  // namespace
}  // namespace debris
