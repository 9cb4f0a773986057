#pragma once
// A measured height map from a text file, as AFM software exports one: a grid of heights, one row per line,
// values separated by spaces, tabs or commas (a run of them is one separator); '#' starts a comment; blank
// lines are skipped. The grid spacing is given by the caller (the input's keys), with the heights' length unit.
// Rows run along axis a, columns along b (one column: a profile, whose spacing_b is not used). The heights are
// kept as measured (in SI: times height_unit), mean included. Ragged rows, a value that is not a number, NaN
// or inf, an empty or missing file: an InputError naming the file, the line and the value.
#include <string>

#include "core/rough/height_field.hpp"

namespace debris {

HeightField read_height_map(const std::string& path, int normal_axis, double spacing_a, double spacing_b,
                            double height_unit);

}  // namespace debris
