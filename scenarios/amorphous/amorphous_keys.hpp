#pragma once
// debris_amorphous's reference: every key its input reader accepts (amorphous_input.cpp, with the material
// block and the sample recipe's keys it shares with debris_patch and debris_calibrate) and the columns of the
// tables it writes. `debris_amorphous --keys` and `--columns` print them; scenarios/amorphous/README.md
// holds the same tables.
#include <vector>

#include "core/io/key_reference.hpp"

namespace debris {

const KeyReference& amorphous_keys();
std::vector<ColumnTable> amorphous_output_columns();

/// relax_<tag>.csv: the relaxation of one sample, one row per progress line.
const ColumnTable& amorphous_relax_table();
/// summary.csv: one row per sample.
const ColumnTable& amorphous_summary_table();

}  // namespace debris
