#include "scenarios/common/run/reference_flags.hpp"

#include <CLI/CLI.hpp>
#include <iostream>

namespace debris {

void add_reference_flags(CLI::App& app, ReferenceFlags& flags) {
  app.add_flag("--keys", flags.keys, "print every input key (type, unit, default, range, meaning) as Markdown and exit");
  app.add_flag("--columns", flags.columns, "print every output table's columns and units as Markdown and exit");
}

bool print_reference(const ReferenceFlags& flags, const KeyReference& keys, const std::vector<ColumnTable>& columns) {
  if (flags.keys) keys.print_markdown(std::cout);
  if (flags.columns) print_columns_markdown(std::cout, columns);
  return flags.keys || flags.columns;
}

}  // namespace debris
