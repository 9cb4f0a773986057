#pragma once
// The debris_amorphous input file: the material, the sample recipe (scenarios/common/dem/amorphous_sample.hpp),
// an optional sweep over d0 and s, output and run settings. Read apart from the run so that every sample of
// a sweep is checked before the first one runs, and so that the fuzzer (tests/fuzz) can reach the reader.
#include <string>
#include <vector>

#include "scenarios/common/dem/amorphous_sample.hpp"

namespace debris {

struct AmorphousConfig {
  AmorphousSpec base;
  std::vector<double> d0s, scalings;  // the sweep (one value each without a sweep)
  std::string directory = "out/amorphous";
  long thermo_every = 1000;  // progress line and relax_<tag>.csv row
  bool save_samples = true;
  bool plot = true;
  int threads = 0;
};

/// Reads and checks the whole input from its text; `name` stands for the file in messages. InputError
/// naming the key and the value for anything missing, malformed, out of range or unknown, and for any
/// sample of the sweep that could not be made.
AmorphousConfig read_amorphous_config(const std::string& text, const std::string& name);

}  // namespace debris
