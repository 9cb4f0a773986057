#include "core/io/thermo_csv.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <charconv>
#include <cstring>
#include <stdexcept>

#include "core/error.hpp"
#include "core/io/text_format.hpp"

namespace debris {

ThermoCsv::ThermoCsv(const std::string& path, std::vector<std::string> columns)
    : path_(path), columns_(std::move(columns)) {
  if (columns_.empty()) throw std::invalid_argument("ThermoCsv '" + path + "': no columns");
  std::string header;
  for (const auto& c : columns_) {
    // Names are written unquoted, so anything that would need CSV quoting is refused.
    if (c.empty() || c.find_first_of(",\"\r\n") != std::string::npos)
      throw std::invalid_argument("ThermoCsv '" + path + "': bad column name '" + c + "'");
    header += (header.empty() ? "" : ",") + c;
  }
  out_.open(path, std::ios::binary | std::ios::trunc);
  if (!out_) throw output_error(path, std::string("cannot open for writing: ") + std::strerror(errno));
  out_ << header << '\n' << std::flush;
  if (!out_) throw output_error(path, "writing the header failed (disk full?)");
}

ThermoCsv::ThermoCsv(const std::string& path, std::vector<std::string> columns, long keep_up_to_step)
    : path_(path), columns_(std::move(columns)) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {  // nothing to resume
    *this = ThermoCsv(path, columns_);
    return;
  }
  std::string header, line, kept;
  std::getline(in, header);
  std::string expected;
  for (const auto& c : columns_) expected += (expected.empty() ? "" : ",") + c;
  if (header != expected)
    throw input_error("output", path, "cannot resume: its columns differ from this run's (" + expected + ")");
  kept = header + '\n';
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    const double step = std::strtod(line.c_str(), nullptr);
    if (step <= static_cast<double>(keep_up_to_step)) {
      kept += line + '\n';
    } else {
      ++dropped_;
      dropped_to_ = std::max(dropped_to_, static_cast<long>(step));
    }
  }
  in.close();
  // Rewritten through a temporary file, so a crash here keeps the old table.
  const std::string tmp = path + ".tmp";
  {
    std::ofstream t(tmp, std::ios::binary | std::ios::trunc);
    t << kept;
    if (!t) throw output_error(tmp, "cannot write (disk full?)");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    throw output_error(path, std::string("cannot replace: ") + std::strerror(errno));
  out_.open(path, std::ios::binary | std::ios::app);
  if (!out_) throw output_error(path, std::string("cannot open for appending: ") + std::strerror(errno));
}

void ThermoCsv::write_row(const std::vector<double>& values) {
  if (values.size() != columns_.size())
    throw std::logic_error("ThermoCsv '" + path_ + "': row has " + std::to_string(values.size()) +
                           " values for " + std::to_string(columns_.size()) + " columns");
  std::string line;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i > 0) line += ',';
    append_number(line, values[i]);
  }
  line += '\n';
  out_.write(line.data(), static_cast<std::streamsize>(line.size()));
  out_.flush();
  if (!out_) throw output_error(path_, "writing a row failed (disk full?)");
}

}  // namespace debris
