#pragma once
// `--keys` and `--columns` for every executable: the input key reference and the output columns, printed
// as the Markdown tables of the executable's manual (scenarios/*/README.md, kept equal by
// tests/scripts/check_manuals.py).
#include <functional>
#include <vector>

#include "core/io/key_reference.hpp"

namespace CLI {
class App;
}

namespace debris {

struct ReferenceFlags {
  bool keys = false;
  bool columns = false;
};

/// Adds the two flags to `app`.
void add_reference_flags(CLI::App& app, ReferenceFlags& flags);

/// Prints what the flags ask for to std::cout; true when something was printed (the program then exits 0
/// without running).
bool print_reference(const ReferenceFlags& flags, const KeyReference& keys, const std::vector<ColumnTable>& columns);

}  // namespace debris
