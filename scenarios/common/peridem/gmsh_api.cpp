#include "scenarios/common/peridem/gmsh_api.hpp"

#include <algorithm>
#include <fstream>
#include <mutex>
#include <numeric>
#include <vector>

#include "core/error.hpp"

#if DEBRIS_HAVE_GMSH_API
#include <gmsh.h>
#endif

namespace debris {

#if DEBRIS_HAVE_GMSH_API

namespace {

std::mutex& gmsh_lock() {
  static std::mutex m;
  return m;
}

/// Gmsh stays initialised between uses, except after an error: Gmsh 4.8 keeps counting it, and a later
/// mesh generation in the same Gmsh session then stops before it starts (an empty mesh, seen in the tests), so
/// a failure finalises Gmsh and the next use starts it afresh. Under gmsh_lock().
bool gmsh_initialised = false;

void initialise() {
  if (gmsh_initialised) return;
  gmsh::initialize(0, nullptr, /*readConfigFiles=*/false);
  gmsh::option::setNumber("General.Terminal", 0);
  gmsh_initialised = true;
}

void finalise() {
  gmsh::finalize();
  gmsh_initialised = false;
}

/// Gmsh's last messages, for an error: its errors and warnings, or else the last few lines it logged.
std::string gmsh_messages() {
  std::vector<std::string> log;
  gmsh::logger::get(log);
  std::vector<std::string> serious;
  for (const std::string& line : log)
    if (line.rfind("Error", 0) == 0 || line.rfind("Warning", 0) == 0) serious.push_back(line);
  const std::vector<std::string>& shown = serious.empty() ? log : serious;
  std::string out;
  for (std::size_t k = shown.size() > 12 ? shown.size() - 12 : 0; k < shown.size(); ++k) out += shown[k] + "\n";
  return out.empty() ? "(Gmsh logged nothing)\n" : out;
}

}  // namespace

bool gmsh_api_available() { return true; }

std::string gmsh_version() { return GMSH_API_VERSION; }

void with_gmsh(const std::string& key, const std::string& value, const std::function<void()>& work) {
  const std::lock_guard<std::mutex> hold(gmsh_lock());
  initialise();
  gmsh::clear();
  gmsh::logger::start();
  std::string failure;
  try {
    work();
  } catch (const InputError&) {
    finalise();
    throw;
  } catch (const std::exception& e) {
    failure = e.what();
  } catch (const std::string& e) {  // Gmsh 4.8 throws its last error message as a string
    failure = e;
  } catch (...) {
    failure = "an unknown exception";
  }
  if (failure.empty()) {
    gmsh::logger::stop();
    gmsh::clear();
    return;
  }
  const std::string messages = gmsh_messages();
  finalise();
  throw input_error(key, value, "Gmsh failed (" + failure + "):\n" + messages);
}

namespace {

/// The current model's mesh as a SimplexMesh: nodes in tag order, the linear simplices of the highest
/// dimension present.
SimplexMesh model_mesh(const std::string& path) {
  std::vector<std::size_t> tags;
  std::vector<double> coord, parametric;
  gmsh::model::mesh::getNodes(tags, coord, parametric, -1, -1, false, false);
  std::vector<int> types;
  std::vector<std::vector<std::size_t>> element_tags, element_nodes;
  gmsh::model::mesh::getElements(types, element_tags, element_nodes, -1, -1);

  SimplexMesh m;
  struct Type {
    int type, dim, nodes;
    std::string name;
  };
  std::vector<Type> props;
  for (const int t : types) {
    Type p{t, 0, 0, ""};
    int order = 0, primary = 0;
    std::vector<double> local;
    gmsh::model::mesh::getElementProperties(t, p.name, p.dim, order, p.nodes, local, primary);
    props.push_back(p);
    m.dimension = std::max(m.dimension, p.dim);
  }
  if (m.dimension < 2)
    throw input_error("mesh file", path, "Gmsh read no triangles or tetrahedra from it (a mesh of dimension " +
                                             std::to_string(m.dimension) + ")");

  std::vector<std::size_t> order(tags.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return tags[a] < tags[b]; });
  std::vector<int> index_of_tag(tags.empty() ? 0 : *std::max_element(tags.begin(), tags.end()) + 1, -1);
  for (const std::size_t k : order) {
    index_of_tag[tags[k]] = static_cast<int>(m.nodes.size());
    m.nodes.push_back({coord[3 * k], coord[3 * k + 1], coord[3 * k + 2]});
    m.node_tag.push_back(static_cast<std::int64_t>(tags[k]));
  }
  auto index = [&](std::size_t tag) {
    if (tag >= index_of_tag.size() || index_of_tag[tag] < 0)
      throw input_error("mesh file", path, "an element names node " + std::to_string(tag) + ", which Gmsh did not read");
    return index_of_tag[tag];
  };
  const int simplex = m.dimension == 2 ? 2 : 4;  // Gmsh's 3-node triangle and 4-node tetrahedron
  for (std::size_t b = 0; b < props.size(); ++b) {
    if (props[b].dim != m.dimension) continue;
    if (props[b].type != simplex)
      throw input_error("mesh file", path,
                        "holds " + props[b].name + " elements: only linear " +
                            (m.dimension == 2 ? "triangles" : "tetrahedra") + " make a " +
                            std::to_string(m.dimension) + "D grain");
    const std::vector<std::size_t>& n = element_nodes[b];
    for (std::size_t e = 0; e + props[b].nodes <= n.size(); e += static_cast<std::size_t>(props[b].nodes)) {
      if (m.dimension == 2)
        m.triangles.push_back({index(n[e]), index(n[e + 1]), index(n[e + 2])});
      else
        m.tetrahedra.push_back({index(n[e]), index(n[e + 1]), index(n[e + 2]), index(n[e + 3])});
    }
  }
  return m;
}

}  // namespace

#else  // without Gmsh's API

bool gmsh_api_available() { return false; }

std::string gmsh_version() { return "none"; }

void with_gmsh(const std::string& key, const std::string& value, const std::function<void()>&) {
  throw input_error(key, value, gmsh_api_missing());
}

#endif

std::string gmsh_api_missing() {
  return "a shape is meshed by Gmsh's C++ API, and this debris was built without it: install it (Debian: "
         "apt-get install libgmsh-dev, or cmake/install-debian-deps.sh), configure and build again; or mesh "
         "the shape with Gmsh yourself and give the MSH file (type: mesh_file)";
}

namespace {

/// ASCII MSH 2.2 or 4.1, the two formats debris's own reader knows, judged from the $MeshFormat line; a
/// file that cannot be opened, or is not MSH at all (no $MeshFormat), also goes to that reader, for its
/// error, unless Gmsh may read it as another format (its name does not end in .msh).
bool own_reader_format(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return true;  // its "cannot be opened" error (Gmsh would read an empty model, without one)
  std::string first, version, file_type;
  std::getline(in, first);
  if (!first.empty() && first.back() == '\r') first.pop_back();
  if (first != "$MeshFormat") return path.size() >= 4 && path.compare(path.size() - 4, 4, ".msh") == 0;
  in >> version >> file_type;
  return (version == "2.2" || version == "4.1") && file_type == "0";
}

}  // namespace

SimplexMesh read_mesh_file(const std::string& path) {
  if (!gmsh_api_available() || own_reader_format(path)) return read_gmsh_msh(path);
#if DEBRIS_HAVE_GMSH_API
  SimplexMesh m;
  with_gmsh("mesh file", path, [&] {
    gmsh::open(path);
    m = model_mesh(path);
  });
  return m;
#else
  return read_gmsh_msh(path);
#endif
}

}  // namespace debris
