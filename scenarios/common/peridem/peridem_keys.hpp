#pragma once
// debris_peridem's reference: every key its input reader accepts (peridem_input.cpp and the sections it
// shares: stages) and the columns of every table it writes. `debris_peridem --keys` and `--columns` print
// them; scenarios/peridem/README.md holds the same tables.
#include <vector>

#include "core/io/key_reference.hpp"

namespace debris {

const KeyReference& peridem_keys();
std::vector<ColumnTable> peridem_output_columns();

/// thermo.csv: `<wall>` columns once per wall, `<grain>` columns once per grain in runs with few grains
/// ("per grain"); z components only in 3D runs.
const ColumnTable& peridem_thermo_table();

}  // namespace debris
