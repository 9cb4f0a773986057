#pragma once
// debris_restitution's reference: every key its input reader accepts (restitution_input.cpp; the material
// block is debris_peridem's, document_pd_material) and the columns of restitution.csv. `debris_restitution
// --keys` and `--columns` print them; scenarios/restitution/README.md holds the same tables.
#include <vector>

#include "core/io/key_reference.hpp"

namespace debris {

const KeyReference& restitution_keys();

/// restitution.csv: one row per case; the writer takes its header from it.
const ColumnTable& restitution_table();

std::vector<ColumnTable> restitution_output_columns();

}  // namespace debris
