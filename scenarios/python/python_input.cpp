#include "scenarios/python/python_input.hpp"

#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <cstdlib>

#include "core/io/input.hpp"

namespace debris {

namespace py = pybind11;

namespace {

YAML::Node node_of(const py::handle& v, const std::string& path) {
  if (v.is_none()) return YAML::Node(YAML::NodeType::Null);
  // bool before int: True is an int in Python.
  if (py::isinstance<py::bool_>(v)) return YAML::Node(v.cast<bool>() ? "true" : "false");
  if (py::isinstance<py::int_>(v)) return YAML::Node(py::str(v).cast<std::string>());
  if (py::isinstance<py::float_>(v)) return YAML::Node(py::repr(v).cast<std::string>());
  if (py::isinstance<py::str>(v)) return YAML::Node(v.cast<std::string>());
  if (py::isinstance<py::dict>(v)) {
    YAML::Node map(YAML::NodeType::Map);
    for (const auto& [key, value] : py::reinterpret_borrow<py::dict>(v)) {
      if (!py::isinstance<py::str>(key))
        throw py::type_error("input key " + py::repr(key).cast<std::string>() + (path.empty() ? "" : " under '" + path + "'") +
                             ": keys are strings");
      const std::string k = key.cast<std::string>();
      map[k] = node_of(value, path.empty() ? k : path + "." + k);
    }
    return map;
  }
  if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
    YAML::Node seq(YAML::NodeType::Sequence);
    std::size_t k = 0;
    for (const py::handle e : v) seq.push_back(node_of(e, path + "[" + std::to_string(k++) + "]"));
    return seq;
  }
  if (py::hasattr(v, "tolist")) return node_of(v.attr("tolist")(), path);  // numpy arrays and scalars
  throw py::type_error("input '" + path + "' = " + py::repr(v).cast<std::string>() + ": a " +
                       py::str(v.get_type().attr("__name__")).cast<std::string>() +
                       " has no YAML form (give a str, number, bool, list or dict)");
}

py::object scalar_of(const YAML::Node& n) {
  const std::string& t = n.Scalar();
  if (n.Tag() != "?") return py::str(t);  // quoted: a string whatever it says
  if (t == "true") return py::bool_(true);
  if (t == "false") return py::bool_(false);
  if (t.empty() || t == "~" || t == "null") return py::none();
  char* end = nullptr;
  errno = 0;
  const long long i = std::strtoll(t.c_str(), &end, 10);
  if (end && *end == '\0' && errno == 0) return py::int_(i);
  errno = 0;
  const double d = std::strtod(t.c_str(), &end);
  if (end && *end == '\0' && errno == 0) return py::float_(d);
  return py::str(t);
}

py::object python_of(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Map: {
      py::dict d;
      for (const auto& kv : n) d[py::str(kv.first.Scalar())] = python_of(kv.second);
      return d;
    }
    case YAML::NodeType::Sequence: {
      py::list l;
      for (const auto& e : n) l.append(python_of(e));
      return l;
    }
    case YAML::NodeType::Scalar: return scalar_of(n);
    default: return py::none();
  }
}

}  // namespace

py::object python_from_yaml_file(const std::string& path) {
  const std::string text = read_input_file(path);  // InputError naming the file when it cannot be read
  (void)InputNode::load_string(text, path);  // the executables' checks first: syntax, one document, aliases
  return python_of(YAML::Load(text));
}

std::string yaml_from_python(const py::handle& value) {
  if (!py::isinstance<py::dict>(value)) throw py::type_error("an input given as a value is a dict of its keys");
  YAML::Emitter out;
  out << node_of(value, "");
  if (!out.good()) throw py::value_error("the input cannot be written as YAML: " + out.GetLastError());
  return std::string(out.c_str()) + "\n";
}

}  // namespace debris
