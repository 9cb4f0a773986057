#pragma once
// debris_patch --resume: what an earlier run of the same input left in its output directory. Each row of
// cases.csv is a finished case (rows are written and flushed one per case); its numbers are read back at
// full precision (they were written with 17 digits) and a strength test's curve from its curves/ file, so
// that a resumed sweep runs only the missing cases and its plots hold every case, the same as one run would
// have drawn them. A sweep of hours (the full-size inputs) is then a series of chunks, not one sitting.
#include <map>
#include <string>
#include <vector>

#include "scenarios/patch/patch_report.hpp"

namespace debris {

struct FinishedCases {
  std::vector<std::string> rows;           // the kept lines of cases.csv, as written, in file order
  std::map<int, PatchCaseResult> results;  // by case index, each with its case and what the plots need
  std::string dropped;                     // why lines were not kept (a torn last line, a missing curve), or empty
};

/// Reads `dir`/cases.csv against this input's cases. No file: nothing finished. InputError naming "--resume"
/// for a table another version wrote (its columns differ) or a row that does not match the case of its
/// index (another input wrote it).
FinishedCases read_finished_cases(const std::string& dir, const std::vector<PatchCaseResult>& cases);

}  // namespace debris
