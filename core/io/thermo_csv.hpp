#pragma once
// A CSV table of run statistics (step, time, energies, ...), one row per call. Each row is flushed, so a
// run that is killed keeps every row it wrote and can be plotted while it runs.
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace debris {

/// How a table continues after a restart from a checkpoint at some step.
struct ThermoResume {
  /// Rows after this step were written past the checkpoint by the run that stopped: they are dropped.
  long keep_up_to_step = 0;
  /// Rows are due at the multiples of `every` (0: unknown). A file that ends early (cut back by a crash
  /// before it was synced) misses those after its last intact row: they are named as lost.
  long every = 0;
  /// Rows the caller can rebuild from the checkpoint, by step: they take the place of rows of the file that
  /// are missing or not intact.
  std::map<long, std::vector<double>> known;
};

class ThermoCsv {
 public:
  /// Truncates `path` and writes the header line; InputError ("output") if it cannot be opened.
  /// Column names may not contain ',', '"' or line breaks (std::invalid_argument).
  ThermoCsv(const std::string& path, std::vector<std::string> columns);

  /// Resumes a table after a restart: keeps the intact rows of an existing `path` up to
  /// resume.keep_up_to_step, drops later ones, puts resume.known where the file has no intact row, then
  /// appends. A row is intact when it ends in a line break and holds one number per column: a crash can cut
  /// the last row short, and such a row is never kept. A missing or empty file (or one cut inside its
  /// header) starts afresh; a header that differs is an InputError.
  ThermoCsv(const std::string& path, std::vector<std::string> columns, const ThermoResume& resume);
  ThermoCsv(const std::string& path, std::vector<std::string> columns, long keep_up_to_step);

  /// One row at full double precision; std::logic_error if values.size() differs from the columns.
  void write_row(const std::vector<double>& values);

  const std::vector<std::string>& columns() const { return columns_; }
  /// Rows the resuming constructor dropped (past keep_up_to_step), and the last step they reached.
  long dropped_rows() const { return dropped_; }
  long dropped_to_step() const { return dropped_to_; }
  /// What the resuming constructor repaired, as a line for the terminal ("thermo.csv: ..."); empty when the
  /// file was sound.
  const std::string& repair_note() const { return note_; }

 private:
  std::string path_;
  std::vector<std::string> columns_;
  std::ofstream out_;
  long dropped_ = 0, dropped_to_ = 0;
  std::string note_;
};

}  // namespace debris
