#pragma once
// The one exception type for bad input. Its message names the key, the value and what would be valid;
// executables catch it in main and exit non-zero with that message.
#include <sstream>
#include <stdexcept>
#include <string>

namespace debris {

class InputError : public std::runtime_error {
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

}  // namespace debris
