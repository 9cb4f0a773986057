#pragma once
// A Python dict with the keys of an input file, as the YAML text the executables read: the module hands
// that text to the same readers, so a dict and a file with the same keys make the same run, and the text is
// what a checkpoint keeps (a restart in the executable reads it back). Units stay strings ("73 GPa"), as in
// the files; floats are written as Python's repr, the shortest text that reads back to the same double.
#include <pybind11/pybind11.h>

#include <string>

namespace debris {

/// YAML text of `value` (a dict, list, tuple, str, int, float, bool, None, or anything with tolist(), such
/// as a numpy array). TypeError naming the key path for anything else.
std::string yaml_from_python(const pybind11::handle& value);

/// An input file as a dict (the other way): plain scalars that read as an int, a float, true/false or null
/// become those, anything else (a quantity with its unit, a quoted string) stays a str, so the dict written
/// back is the same input. InputError for a file that cannot be read or parsed (the readers' messages).
pybind11::object python_from_yaml_file(const std::string& path);

}  // namespace debris
