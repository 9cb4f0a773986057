#pragma once
// debris_calibrate's reference: every key its input reader accepts (main.cpp's read_config, with the material
// block and the amorphous sample recipe's keys it shares with debris_amorphous and debris_patch) and the
// columns of the tables it writes. `debris_calibrate --keys` and `--columns` print them;
// scenarios/calibrate/README.md holds the same tables.
#include <vector>

#include "core/io/key_reference.hpp"

namespace debris {

const KeyReference& calibrate_keys();
std::vector<ColumnTable> calibrate_output_columns();

/// calibration.csv: one row per calibration step that made or collapsed a sample.
const ColumnTable& calibration_table();
/// spread.csv: the calibrated inputs on the calibration's seed and on calibration.spread_seeds.
const ColumnTable& spread_table();

}  // namespace debris
