#pragma once
// A CSV table of run statistics (step, time, energies, ...), one row per call. Each row is flushed, so a
// run that is killed keeps every row it wrote and can be plotted while it runs.
#include <fstream>
#include <string>
#include <vector>

namespace debris {

class ThermoCsv {
 public:
  /// Truncates `path` and writes the header line; InputError ("output") if it cannot be opened.
  /// Column names may not contain ',', '"' or line breaks (std::invalid_argument).
  ThermoCsv(const std::string& path, std::vector<std::string> columns);

  /// Resumes a table after a restart: keeps the rows of an existing `path` whose first column (the step) is
  /// <= keep_up_to_step, drops later ones (written after the checkpoint by the run that stopped), then appends.
  /// A missing file starts afresh; a header that differs is an InputError.
  ThermoCsv(const std::string& path, std::vector<std::string> columns, long keep_up_to_step);

  /// One row at full double precision; std::logic_error if values.size() differs from the columns.
  void write_row(const std::vector<double>& values);

  const std::vector<std::string>& columns() const { return columns_; }
  /// Rows the resuming constructor dropped (past keep_up_to_step), and the last step they reached.
  long dropped_rows() const { return dropped_; }
  long dropped_to_step() const { return dropped_to_; }

 private:
  std::string path_;
  std::vector<std::string> columns_;
  std::ofstream out_;
  long dropped_ = 0, dropped_to_ = 0;
};

}  // namespace debris
