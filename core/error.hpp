#pragma once
// The exception types an executable's main maps to its exit status, one meaning each across all of them:
//   0 done; 2 bad input (InputError: a key and its value, a corrupt or foreign checkpoint, a system too
//   large for the machine), nothing written; 3 the run could not finish (OutputError: an output that
//   cannot be written, a full disk; a failed health check; out of memory), the last good results kept;
//   1 anything else (a bug).
#include <sstream>
#include <stdexcept>
#include <string>

namespace debris {

constexpr int kExitInput = 2;       // bad input: nothing was written
constexpr int kExitUnfinished = 3;  // the run could not finish (output not writable, non-finite state, ...)

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// An output file or directory that cannot be created or written (full disk, a file where a directory
/// should be, a file size limit): the run cannot finish, whatever its input.
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A run that cannot go on, met alike by every rank of a run cut among MPI ranks (a decision they take
/// together): each rank stops with exit 3, naming the last good checkpoint, and none ends the job for the
/// others. (A grain grown too large for the ranks: the run continues from the checkpoint on fewer.)
class RunStop : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A number as an error message shows it: 12 significant digits, enough to tell values apart.
inline std::string format_value(double v) {
  std::ostringstream os;
  os.precision(12);
  os << v;
  return os.str();
}

/// "key 'material.poisson_ratio' = 0.3: must be in (-1, 0.25] ..."
inline InputError input_error(const std::string& key, const std::string& value, const std::string& what) {
  return InputError("input error: '" + key + "' = " + value + ": " + what);
}

/// "output error: 'out/run/thermo.csv': writing a row failed (disk full?)"
inline OutputError output_error(const std::string& path, const std::string& what) {
  return OutputError("output error: '" + path + "': " + what);
}

}  // namespace debris
