#pragma once
// The amorphous samples of a debris_patch run: each is made once by the section 3.2 recipe
// (scenarios/common/dem/amorphous_sample.hpp) and saved as <directory>/<tag>.h5 and .data, so that the tests
// of one sample (elastic, tension, shear) and later runs of the same input share it. A saved file is used
// only when the recipe key stored in it (amorphous_spec_key) equals the case's: any change of material,
// size, seed or relaxation setting makes a new sample. A sample is always read back from its file, so a
// run gives the same results whether it made the sample or found it.
#include <map>
#include <ostream>
#include <string>

#include "scenarios/common/dem/amorphous_sample.hpp"

namespace debris {

class AmorphousSampleCache {
 public:
  /// `log` gets one line per sample made or loaded (and its relaxation summary).
  AmorphousSampleCache(std::string directory, std::ostream& log);

  /// The relaxed sample of `spec`. Throws PatchRunError when the relaxation failed (a stress threshold
  /// not met within the step limit, a box that would become too thin, a non-finite state): the message names
  /// the setting; a failed spec is not tried again in the same run.
  const AmorphousSampleFile& get(const AmorphousSpec& spec);
  /// "made in 12.3 s" or "loaded from <file>", for the sample's description.
  std::string source(const AmorphousSpec& spec) const;

  /// File stem (no extension) the sample of `spec` is saved under: d0, s, nu and a hash of the key.
  std::string stem(const AmorphousSpec& spec) const;

 private:
  struct Entry {
    bool ok = false;
    std::string error, source;
    AmorphousSampleFile file;
  };
  std::string directory_;
  std::ostream& log_;
  std::map<std::string, Entry> entries_;  // by amorphous_spec_key
};

}  // namespace debris
