#include "core/io/gmsh_msh.hpp"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <string_view>
#include <unordered_map>

#include "core/error.hpp"

namespace debris {

namespace {

/// What Gmsh's element types are (the table of the MSH format reference): dimension and node count.
struct ElementType {
  int dim;
  int nodes;
  const char* name;
};

const ElementType* element_type(long type) {
  static const std::map<long, ElementType> table = {
      {1, {1, 2, "2-node line"}},
      {2, {2, 3, "3-node triangle"}},
      {3, {2, 4, "4-node quadrangle"}},
      {4, {3, 4, "4-node tetrahedron"}},
      {5, {3, 8, "8-node hexahedron"}},
      {6, {3, 6, "6-node prism"}},
      {7, {3, 5, "5-node pyramid"}},
      {8, {1, 3, "3-node second-order line"}},
      {9, {2, 6, "6-node second-order triangle"}},
      {10, {2, 9, "9-node second-order quadrangle"}},
      {11, {3, 10, "10-node second-order tetrahedron"}},
      {12, {3, 27, "27-node second-order hexahedron"}},
      {13, {3, 18, "18-node second-order prism"}},
      {14, {3, 14, "14-node second-order pyramid"}},
      {15, {0, 1, "1-node point"}},
      {16, {2, 8, "8-node second-order quadrangle"}},
      {17, {3, 20, "20-node second-order hexahedron"}},
      {18, {3, 15, "15-node second-order prism"}},
      {19, {3, 13, "13-node second-order pyramid"}},
      {20, {2, 9, "9-node third-order triangle"}},
      {21, {2, 10, "10-node third-order triangle"}},
      {22, {2, 12, "12-node fourth-order triangle"}},
      {23, {2, 15, "15-node fourth-order triangle"}},
      {24, {2, 15, "15-node fifth-order triangle"}},
      {25, {2, 21, "21-node fifth-order triangle"}},
      {26, {1, 4, "4-node third-order line"}},
      {27, {1, 5, "5-node fourth-order line"}},
      {28, {1, 6, "6-node fifth-order line"}},
      {29, {3, 20, "20-node third-order tetrahedron"}},
      {30, {3, 35, "35-node fourth-order tetrahedron"}},
      {31, {3, 56, "56-node fifth-order tetrahedron"}},
      {92, {3, 64, "64-node third-order hexahedron"}},
      {93, {3, 125, "125-node fourth-order hexahedron"}},
  };
  const auto it = table.find(type);
  return it == table.end() ? nullptr : &it->second;
}

constexpr long kTriangle = 2, kTetrahedron = 4;

std::vector<std::string_view> split(std::string_view s) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (true) {
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t')) ++i;
    if (i >= s.size()) break;
    const std::size_t b = i;
    while (i < s.size() && s[i] != ' ' && s[i] != '\t') ++i;
    out.push_back(s.substr(b, i - b));
  }
  return out;
}

/// The file as lines, with a cursor that skips blank lines and says where, in every error.
class MshLines {
 public:
  explicit MshLines(const std::string& path) : path_(path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw input_error("mesh file", path, std::string("cannot be opened for reading: ") + std::strerror(errno));
    for (std::string line; std::getline(in, line);) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      lines_.push_back(std::move(line));
    }
    if (in.bad()) throw input_error("mesh file", path, "cannot be read");
  }

  [[noreturn]] void fail(std::size_t line, const std::string& key, std::string_view value,
                         const std::string& what) const {
    throw input_error(key, "'" + std::string(value) + "'",
                      what + " (" + path_ + " line " + std::to_string(line + 1) + ")");
  }

  bool at_end() {
    skip_blank();
    return pos_ >= lines_.size();
  }

  /// The next non-blank line (its index in `line`), or an error naming the section that was cut short.
  std::string_view next(const std::string& where, std::size_t& line) {
    skip_blank();
    if (pos_ >= lines_.size())
      fail(lines_.empty() ? 0 : lines_.size() - 1, "mesh file", path_, "unexpected end of file in " + where);
    line = pos_;
    return lines_[pos_++];
  }

  /// The next non-blank line split into tokens; `count` > 0 demands exactly that many.
  std::vector<std::string_view> tokens(const std::string& where, std::size_t& line, std::size_t count,
                                       const std::string& layout) {
    std::vector<std::string_view> t = split(next(where, line));
    if (count > 0 && t.size() != count)
      fail(line, where, lines_[line],
           "expected " + std::to_string(count) + " values (" + layout + "), found " + std::to_string(t.size()));
    return t;
  }

  void expect(const std::string& keyword, const std::string& where) {
    std::size_t line = 0;
    const std::string_view s = trim(next(where, line));
    if (s != keyword) fail(line, where, s, "expected '" + keyword + "'");
  }

  /// Skips a section we do not read, up to and including its $End line.
  void skip_section(const std::string& name, std::size_t start) {
    const std::string end = "$End" + name;
    while (pos_ < lines_.size()) {
      if (trim(lines_[pos_++]) == end) return;
    }
    fail(start, "mesh file", path_, "section $" + name + " has no " + end);
  }

  double real(std::size_t line, const std::string& key, std::string_view token) const {
    double v = 0;
    const auto [stop, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
    if (ec != std::errc() || stop != token.data() + token.size()) fail(line, key, token, "not a number");
    if (!std::isfinite(v)) fail(line, key, token, "not a finite number");
    return v;
  }

  long long whole(std::size_t line, const std::string& key, std::string_view token, long long min) const {
    long long v = 0;
    const auto [stop, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
    if (ec != std::errc() || stop != token.data() + token.size()) fail(line, key, token, "not a whole number");
    if (v < min) fail(line, key, token, "must be >= " + std::to_string(min));
    return v;
  }

  static std::string_view trim(std::string_view s) {
    const auto b = s.find_first_not_of(" \t");
    if (b == std::string_view::npos) return {};
    return s.substr(b, s.find_last_not_of(" \t") - b + 1);
  }

  const std::string& path() const { return path_; }

 private:
  void skip_blank() {
    while (pos_ < lines_.size() && trim(lines_[pos_]).empty()) ++pos_;
  }

  std::string path_;
  std::vector<std::string> lines_;
  std::size_t pos_ = 0;
};

/// What the element sections found besides the simplices we keep, to report or reject at the end.
struct ElementCensus {
  long long other_count[4] = {0, 0, 0, 0};  // unsupported elements, by dimension
  long other_type[4] = {0, 0, 0, 0};        // one such type per dimension, for the message
  std::size_t other_line[4] = {0, 0, 0, 0};
};

class MshParser {
 public:
  explicit MshParser(const std::string& path) : f_(path) {}

  SimplexMesh parse() {
    read_format();
    bool have_nodes = false, have_elements = false;
    std::size_t last_line = 0;
    while (!f_.at_end()) {
      std::size_t line = 0;
      const std::string_view s = MshLines::trim(f_.next("the file", line));
      last_line = line;
      if (s.empty() || s[0] != '$') f_.fail(line, "mesh file", s, "expected a section keyword such as $Nodes");
      const std::string name(s.substr(1));
      if (name == "Nodes") {
        if (have_nodes) f_.fail(line, "mesh file", s, "a second $Nodes section");
        version4_ ? read_nodes_41() : read_nodes_22();
        have_nodes = true;
      } else if (name == "Elements") {
        if (!have_nodes) f_.fail(line, "mesh file", s, "$Elements before $Nodes");
        if (have_elements) f_.fail(line, "mesh file", s, "a second $Elements section");
        version4_ ? read_elements_41() : read_elements_22();
        have_elements = true;
      } else if (name == "MeshFormat") {
        f_.fail(line, "mesh file", s, "a second $MeshFormat section");
      } else {
        f_.skip_section(name, line);  // $PhysicalNames, $Entities, $Periodic, $NodeData, ...
      }
    }
    if (!have_nodes) f_.fail(last_line, "mesh file", f_.path(), "no $Nodes section");
    if (!have_elements) f_.fail(last_line, "mesh file", f_.path(), "no $Elements section");
    return finish(last_line);
  }

 private:
  void read_format() {
    std::size_t line = 0;
    const std::string_view first = MshLines::trim(f_.next("$MeshFormat", line));
    if (first != "$MeshFormat") f_.fail(line, "mesh file", first, "a Gmsh MSH file starts with $MeshFormat");
    const auto t = f_.tokens("$MeshFormat", line, 3, "version file-type data-size");
    if (t[0] == "2.2") {
      version4_ = false;
    } else if (t[0] == "4.1") {
      version4_ = true;
    } else {
      f_.fail(line, "$MeshFormat version", t[0],
              "supported MSH versions are 2.2 and 4.1 (gmsh -format msh22 or msh41)");
    }
    if (t[1] != "0")
      f_.fail(line, "$MeshFormat file-type", t[1],
              "only ASCII MSH files (file-type 0) are supported; write the mesh without -bin");
    f_.expect("$EndMeshFormat", "$MeshFormat");
  }

  void add_node(std::size_t line, long long tag, double x, double y, double z) {
    if (!tag_to_index_.emplace(tag, static_cast<int>(mesh_.nodes.size())).second)
      f_.fail(line, "$Nodes node tag", std::to_string(tag), "duplicate node tag");
    mesh_.node_tag.push_back(tag);
    mesh_.nodes.push_back({x, y, z});
  }

  long long node_count(std::size_t line, std::string_view token) {
    const long long n = f_.whole(line, "$Nodes count", token, 0);
    if (n > std::numeric_limits<int>::max()) f_.fail(line, "$Nodes count", token, "more nodes than an int indexes");
    return n;
  }

  void read_nodes_22() {
    std::size_t line = 0;
    const auto head = f_.tokens("$Nodes", line, 1, "number-of-nodes");
    const long long n = node_count(line, head[0]);
    for (long long k = 0; k < n; ++k) {
      const auto t = f_.tokens("$Nodes", line, 4, "node-number x y z");
      const long long tag = f_.whole(line, "$Nodes node tag", t[0], 1);
      add_node(line, tag, f_.real(line, "$Nodes x", t[1]), f_.real(line, "$Nodes y", t[2]),
               f_.real(line, "$Nodes z", t[3]));
    }
    f_.expect("$EndNodes", "$Nodes (more node lines than its count " + std::to_string(n) + "?)");
  }

  void read_nodes_41() {
    std::size_t line = 0;
    const auto head = f_.tokens("$Nodes", line, 4, "numEntityBlocks numNodes minNodeTag maxNodeTag");
    const long long blocks = f_.whole(line, "$Nodes numEntityBlocks", head[0], 0);
    const long long n = node_count(line, head[1]);
    const std::size_t head_line = line;
    std::vector<long long> tags;
    for (long long b = 0; b < blocks; ++b) {
      const auto bt = f_.tokens("$Nodes", line, 4, "entityDim entityTag parametric numNodesInBlock");
      const long long dim = f_.whole(line, "$Nodes entityDim", bt[0], 0);
      if (dim > 3) f_.fail(line, "$Nodes entityDim", bt[0], "must be 0, 1, 2 or 3");
      const long long parametric = f_.whole(line, "$Nodes parametric", bt[2], 0);
      if (parametric > 1) f_.fail(line, "$Nodes parametric", bt[2], "must be 0 or 1");
      const long long in_block = f_.whole(line, "$Nodes numNodesInBlock", bt[3], 0);
      if (static_cast<long long>(mesh_.nodes.size()) + in_block > n)
        f_.fail(line, "$Nodes numNodesInBlock", bt[3],
                "more nodes in the blocks than the header's " + std::to_string(n));
      tags.clear();
      for (long long k = 0; k < in_block; ++k) {
        const auto t = f_.tokens("$Nodes", line, 1, "nodeTag");
        tags.push_back(f_.whole(line, "$Nodes node tag", t[0], 1));
      }
      // A parametric node carries its parametric coordinates (u; u v; u v w) after x y z.
      const std::size_t columns = 3 + static_cast<std::size_t>(parametric * dim);
      for (const long long tag : tags) {
        const auto t = f_.tokens("$Nodes", line, columns, parametric ? "x y z and parametric coordinates" : "x y z");
        add_node(line, tag, f_.real(line, "$Nodes x", t[0]), f_.real(line, "$Nodes y", t[1]),
                 f_.real(line, "$Nodes z", t[2]));
      }
    }
    if (static_cast<long long>(mesh_.nodes.size()) != n)
      f_.fail(head_line, "$Nodes numNodes", head[1],
              "the blocks hold " + std::to_string(mesh_.nodes.size()) + " nodes, not the header's count");
    f_.expect("$EndNodes", "$Nodes");
  }

  int node_index(std::size_t line, std::string_view token) {
    const long long tag = f_.whole(line, "element node tag", token, 1);
    const auto it = tag_to_index_.find(tag);
    if (it == tag_to_index_.end()) f_.fail(line, "element node tag", token, "no node with this tag in $Nodes");
    return it->second;
  }

  /// One element: keeps triangles and tetrahedra, counts the others by dimension.
  void add_element(std::size_t line, long type, const ElementType& et, const std::string_view* node_tokens) {
    int v[4];
    for (int k = 0; k < et.nodes; ++k) {
      const int index = node_index(line, node_tokens[k]);
      if (k < 4) v[k] = index;
    }
    if (type == kTriangle) {
      mesh_.triangles.push_back({v[0], v[1], v[2]});
    } else if (type == kTetrahedron) {
      mesh_.tetrahedra.push_back({v[0], v[1], v[2], v[3]});
    } else {
      if (census_.other_count[et.dim]++ == 0) {
        census_.other_type[et.dim] = type;
        census_.other_line[et.dim] = line;
      }
    }
  }

  const ElementType& known_type(std::size_t line, std::string_view token, long& type) {
    type = static_cast<long>(f_.whole(line, "element type", token, 1));
    const ElementType* et = element_type(type);
    if (!et) f_.fail(line, "element type", token, "not a Gmsh element type this reader knows");
    return *et;
  }

  void read_elements_22() {
    std::size_t line = 0;
    const auto head = f_.tokens("$Elements", line, 1, "number-of-elements");
    const long long n = f_.whole(line, "$Elements count", head[0], 0);
    for (long long k = 0; k < n; ++k) {
      const auto t = f_.tokens("$Elements", line, 0, "");
      if (t.size() < 3)
        f_.fail(line, "$Elements", t.empty() ? "" : t[0], "expected elm-number elm-type number-of-tags <tags> <nodes>");
      f_.whole(line, "element number", t[0], 1);
      long type = 0;
      const ElementType& et = known_type(line, t[1], type);
      const long long tags = f_.whole(line, "element number-of-tags", t[2], 0);
      const std::size_t expected = 3 + static_cast<std::size_t>(tags) + static_cast<std::size_t>(et.nodes);
      if (t.size() != expected)
        f_.fail(line, "$Elements", t[0],
                "a " + std::string(et.name) + " with " + std::to_string(tags) + " tags needs " +
                    std::to_string(expected) + " values, found " + std::to_string(t.size()));
      add_element(line, type, et, t.data() + 3 + tags);
    }
    f_.expect("$EndElements", "$Elements (more element lines than its count " + std::to_string(n) + "?)");
  }

  void read_elements_41() {
    std::size_t line = 0;
    const auto head = f_.tokens("$Elements", line, 4, "numEntityBlocks numElements minElementTag maxElementTag");
    const long long blocks = f_.whole(line, "$Elements numEntityBlocks", head[0], 0);
    const long long n = f_.whole(line, "$Elements numElements", head[1], 0);
    const std::size_t head_line = line;
    long long seen = 0;
    for (long long b = 0; b < blocks; ++b) {
      const auto bt = f_.tokens("$Elements", line, 4, "entityDim entityTag elementType numElementsInBlock");
      long type = 0;
      const ElementType& et = known_type(line, bt[2], type);
      const long long in_block = f_.whole(line, "$Elements numElementsInBlock", bt[3], 0);
      seen += in_block;
      if (seen > n)
        f_.fail(line, "$Elements numElementsInBlock", bt[3],
                "more elements in the blocks than the header's " + std::to_string(n));
      const std::size_t columns = 1 + static_cast<std::size_t>(et.nodes);
      for (long long k = 0; k < in_block; ++k) {
        const auto t = f_.tokens("$Elements", line, columns, "elementTag and the " + std::string(et.name) + "'s nodes");
        f_.whole(line, "element tag", t[0], 1);
        add_element(line, type, et, t.data() + 1);
      }
    }
    if (seen != n)
      f_.fail(head_line, "$Elements numElements", head[1],
              "the blocks hold " + std::to_string(seen) + " elements, not the header's count");
    f_.expect("$EndElements", "$Elements");
  }

  SimplexMesh finish(std::size_t last_line) {
    int dim = 0;
    if (!mesh_.tetrahedra.empty()) {
      dim = 3;
    } else if (!mesh_.triangles.empty()) {
      dim = 2;
    }
    for (int d = 3; d > dim; --d)
      if (census_.other_count[d] > 0) dim = d;  // e.g. hexahedra next to boundary triangles: a 3D mesh
    if (dim < 2)
      f_.fail(last_line, "mesh file", f_.path(),
              "no 3-node triangles (type 2) or 4-node tetrahedra (type 4): nothing to take nodal volumes from");
    if (census_.other_count[dim] > 0) {
      const ElementType* et = element_type(census_.other_type[dim]);
      f_.fail(census_.other_line[dim], "element type", std::to_string(census_.other_type[dim]),
              std::to_string(census_.other_count[dim]) + " element(s) of type " + et->name + " in a " +
                  std::to_string(dim) + "D mesh: only linear " + (dim == 2 ? "triangles" : "tetrahedra") +
                  " are supported (mesh with Mesh.ElementOrder = 1 and no recombination)");
    }
    mesh_.dimension = dim;
    if (dim == 3) mesh_.triangles.clear();  // the boundary faces of the tetrahedra
    return std::move(mesh_);
  }

  MshLines f_;
  bool version4_ = false;
  SimplexMesh mesh_;
  std::unordered_map<long long, int> tag_to_index_;
  ElementCensus census_;
};

}  // namespace

SimplexMesh read_gmsh_msh(const std::string& path) { return MshParser(path).parse(); }

}  // namespace debris
