#pragma once
// debris_patch's reference: every key its input reader accepts (patch_input.cpp, with the material block and
// the amorphous sample recipe's keys it shares with debris_amorphous) and the columns of the tables it
// writes. `debris_patch --keys` and `--columns` print them; scenarios/patch/README.md holds the same tables.
#include <vector>

#include "core/io/key_reference.hpp"

namespace debris {

const KeyReference& patch_keys();
std::vector<ColumnTable> patch_output_columns();

/// cases.csv: one row per case.
const ColumnTable& patch_cases_table();
/// curves/case_<NNN>_<test>.csv: the stress-strain curve of one strength test.
const ColumnTable& patch_curve_table();

}  // namespace debris
