#pragma once
// debris_dem's reference: every key its input reader accepts (dem_input.cpp and the sections it shares:
// material, regions, stages, the wear analysis) and the columns of every table it writes. `debris_dem --keys`
// and `--columns` print them; scenarios/dem/README.md holds the same tables.
#include <vector>

#include "core/io/key_reference.hpp"

namespace debris {

const KeyReference& dem_keys();
std::vector<ColumnTable> dem_output_columns();

/// thermo.csv: one row every output.thermo_every steps; `<group>` columns once per group.
const ColumnTable& dem_thermo_table();

}  // namespace debris
