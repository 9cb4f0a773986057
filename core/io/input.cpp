#include "core/io/input.hpp"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <sstream>

#include "core/error.hpp"

namespace debris {

/// Shared by every copy of every node of one file: what the run asked for and what it read.
struct InputNode::Tracking {
  std::string source;                                     // file name, for messages
  std::set<std::string> read;                             // key paths consumed by a getter
  std::map<std::string, std::vector<std::string>> known;  // node path -> keys asked for, in order
  bool any_unit = false;                                  // a quantity read with a unit ("73 GPa")
  std::vector<std::string> plain;                         // "path = text" of dimensional quantities without one
  std::vector<InputNode::Asked> asked;                    // what the getters asked, for the key audit
  std::map<std::string, std::vector<std::size_t>> asked_at;  // path -> its entries in `asked`
};

namespace {

using NodePtr = std::shared_ptr<const YAML::Node>;

std::string join(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

std::string element_path(const std::string& path, std::size_t i) {
  return path + "[" + std::to_string(i) + "]";
}

/// The value as the user wrote it, short enough for a one-line message.
std::string show(const YAML::Node& node) {
  if (!node.IsDefined() || node.IsNull()) return "(no value)";
  if (node.IsScalar()) return node.Scalar();
  YAML::Emitter out;
  out.SetMapFormat(YAML::Flow);
  out.SetSeqFormat(YAML::Flow);
  out << node;
  std::string text = out.c_str();
  if (text.size() > 80) text = text.substr(0, 77) + "...";
  return text;
}

std::string kind(const YAML::Node& node) {
  if (node.IsMap()) return "a map";
  if (node.IsSequence()) return "a sequence";
  if (node.IsScalar()) return "a single value";
  return "empty";
}

/// " (in.yaml line 12)", or nothing for a node that did not come from the parser or for a text without a
/// name (one whose lines the user never saw, such as the Python module's dict made into YAML).
std::string where(const std::string& source, const YAML::Node& node) {
  const YAML::Mark mark = node.Mark();
  if (source.empty() || mark.is_null() || mark.line < 0) return "";
  return " (" + source + " line " + std::to_string(mark.line + 1) + ")";
}

/// input_error() with the place in the file appended.
InputError fail(const std::string& path, const std::string& value, const std::string& what,
                const std::string& location) {
  return InputError(input_error(path, value, what).what() + location);
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

std::string list_of(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out.empty() ? "(none)" : out;
}

/// Edits (insert, delete, replace, swap two neighbours) that turn a into b: the usual typos count one each.
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i)
    for (std::size_t j = 1; j <= b.size(); ++j) {
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

/// Nodes in the tree below `node`, itself included, with every alias expanded: what a walk of the tree
/// (check_keys, the getters, an error message that prints a value) visits. An alias (*a) is the very node of
/// its anchor (&a) in yaml-cpp, with the anchor's place in the file, so each distinct map or sequence is
/// counted once and its count reused: the cost follows the text's size, however far nested aliases multiply.
double expanded_nodes(const YAML::Node& node, std::map<std::pair<int, int>, double>& seen) {
  if (!node.IsMap() && !node.IsSequence()) return 1.0;
  const YAML::Mark mark = node.Mark();
  const std::pair<int, int> key{mark.pos, static_cast<int>(node.Type())};
  if (!mark.is_null())
    if (const auto it = seen.find(key); it != seen.end()) return it->second;
  double n = 1.0;
  if (node.IsMap())
    for (const auto& entry : node) n += 1.0 + expanded_nodes(entry.second, seen);
  else
    for (const auto& element : node) n += expanded_nodes(element, seen);
  if (!mark.is_null()) seen[key] = n;
  return n;
}

/// yaml-cpp keeps repeated keys and answers with the first; a repeated key is almost always a mistake.
void check_keys(const YAML::Node& node, const std::string& path, const std::string& source) {
  if (node.IsMap()) {
    std::set<std::string> seen;
    for (const auto& entry : node) {
      if (!entry.first.IsScalar())
        throw fail(path.empty() ? source : path, show(entry.first), "keys must be plain names",
                   where(source, entry.first));
      const std::string key = entry.first.Scalar();
      if (!seen.insert(key).second)
        throw fail(join(path, key), show(entry.second), "key given twice; keep only one",
                   where(source, entry.first));
      check_keys(entry.second, join(path, key), source);
    }
  } else if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i) check_keys(node[i], element_path(path, i), source);
  }
}

// Walks the documents of `yaml` without building them and returns how many there are. yaml-cpp 0.7 (Debian
// 12) loops for ever, one null document per turn, on some malformed text such as a lone ',' (yaml-cpp bug
// 1040, fixed upstream in 2024): the parser reports a document and consumes nothing. Such a document starts where
// the previous one did; it is reported as the syntax error it is instead of being read again.
class DocumentCounter final : public YAML::EventHandler {
 public:
  void OnDocumentStart(const YAML::Mark& mark) override {
    if (count_ > 0 && mark.pos == start_.pos)
      throw YAML::ParserException(mark, "unexpected token (the parser cannot go past it)");
    start_ = mark;
    ++count_;
  }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark&, YAML::anchor_t) override {}
  void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t, const std::string&) override {}
  void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {}
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {}
  void OnMapEnd() override {}
  std::size_t count() const { return count_; }

 private:
  std::size_t count_ = 0;
  YAML::Mark start_;
};

std::size_t count_documents(const std::string& yaml) {
  std::istringstream in(yaml);
  YAML::Parser parser(in);
  DocumentCounter counter;
  while (parser.HandleNextDocument(counter)) {
  }
  return counter.count();
}

}  // namespace

// ---- loading ----------------------------------------------------------------------------------------

InputNode InputNode::load_string(const std::string& yaml, const std::string& name) {
  std::vector<YAML::Node> documents;
  try {
    const std::size_t count = count_documents(yaml);  // first, so that LoadAll cannot loop
    if (count > 1)
      throw input_error("input file", name, "holds " + std::to_string(count) + " YAML documents ('---'); expected one");
    documents = YAML::LoadAll(yaml);
  } catch (const YAML::Exception& e) {
    const std::string location =
        e.mark.is_null() ? std::string()
                         : " at line " + std::to_string(e.mark.line + 1) + ", column " +
                               std::to_string(e.mark.column + 1);
    throw input_error("input file", name, "YAML syntax error" + location + ": " + e.msg);
  }
  YAML::Node root = documents.empty() ? YAML::Node(YAML::NodeType::Map) : documents.front();
  if (root.IsNull()) root = YAML::Node(YAML::NodeType::Map);  // an empty file: every key takes its default
  if (!root.IsMap())
    throw input_error("input file", name,
                      "the top level is " + kind(root) + "; expected a map of keys such as 'material:'");
  {
    // A "billion laughs" input (nested aliases, each repeating the one before ten times) is a few lines of
    // text but a tree of 10^9 nodes: refused before anything walks it.
    std::map<std::pair<int, int>, double> seen;
    const double nodes = expanded_nodes(root, seen);
    if (nodes > static_cast<double>(kMaxInputNodes))
      throw input_error("input file", name,
                        "expands to " + format_value(nodes) + " YAML nodes (aliases '*name' included), more than the " +
                            std::to_string(kMaxInputNodes) + " an input may hold; are aliases nested in aliases?");
  }
  check_keys(root, "", name);
  auto tracking = std::make_shared<Tracking>();
  tracking->source = name;
  return InputNode(std::make_shared<const YAML::Node>(root), "", tracking);
}

std::string read_input_file(const std::string& path) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (status.type() == std::filesystem::file_type::not_found) throw input_error("input file", path, "no such file");
  if (ec) throw input_error("input file", path, "cannot be accessed: " + ec.message());
  if (std::filesystem::is_directory(status)) throw input_error("input file", path, "is a directory, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw input_error("input file", path, "cannot be opened for reading");
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad()) throw input_error("input file", path, "cannot be read");
  return text;
}

InputNode InputNode::load_file(const std::string& path) { return load_string(read_input_file(path), path); }

InputNode::InputNode(NodePtr node, std::string path, std::shared_ptr<Tracking> tracking)
    : node_(std::move(node)), path_(std::move(path)), tracking_(std::move(tracking)) {}

// ---- structure --------------------------------------------------------------------------------------

struct InputNode::Value {
  YAML::Node node;
  std::string path;      // "material.density"
  std::string location;  // " (run.yaml line 12)": the line of the key, which a null value lacks
};

bool InputNode::is_map() const { return node_->IsMap(); }
bool InputNode::is_sequence() const { return node_->IsSequence(); }
bool InputNode::is_scalar() const { return node_->IsScalar(); }

std::shared_ptr<const InputNode::Value> InputNode::find(const std::string& key) const {
  auto& known = tracking_->known[path_];
  if (std::find(known.begin(), known.end(), key) == known.end()) known.push_back(key);
  if (!node_->IsMap())
    throw fail(path_.empty() ? tracking_->source : path_, show(*node_),
               "is " + kind(*node_) + "; expected a map with the key '" + key + "'", where(tracking_->source, *node_));
  for (const auto& entry : *node_) {
    if (entry.first.Scalar() != key) continue;
    const std::string path = join(path_, key);
    tracking_->read.insert(path);
    return std::make_shared<const Value>(Value{entry.second, path, where(tracking_->source, entry.first)});
  }
  return nullptr;
}

std::shared_ptr<const InputNode::Value> InputNode::require(const std::string& key, const std::string& expected) const {
  auto value = find(key);
  if (!value) {
    const std::string location = where(tracking_->source, *node_);
    throw fail(join(path_, key), "(absent)", "missing key; expected " + expected,
               path_.empty() || location.empty() ? "" : " (in the section at " + location.substr(2));
  }
  return value;
}

InputNode::Value InputNode::self() const { return Value{*node_, path_, where(tracking_->source, *node_)}; }

bool InputNode::has(const std::string& key) const {
  note(key, KeyKind::section);  // presence only
  auto& known = tracking_->known[path_];
  if (std::find(known.begin(), known.end(), key) == known.end()) known.push_back(key);
  if (!node_->IsMap()) return false;
  for (const auto& entry : *node_)
    if (entry.first.Scalar() == key) return true;
  return false;
}

std::vector<std::string> InputNode::keys() const {
  std::vector<std::string> out;
  if (node_->IsMap())
    for (const auto& entry : *node_) out.push_back(entry.first.Scalar());
  return out;
}

InputNode InputNode::child(const std::string& key) const {
  note(key, KeyKind::section);
  const auto value = require(key, "a section '" + key + ":'");
  return InputNode(std::make_shared<const YAML::Node>(value->node), value->path, tracking_);
}

std::vector<InputNode> InputNode::list(const std::string& key) const {
  note(key, KeyKind::list);
  const auto value = require(key, "a list");
  const YAML::Node& seq = value->node;
  if (!seq.IsSequence())
    throw fail(value->path, show(seq), "is " + kind(seq) + "; expected a list such as [a, b]", value->location);
  std::vector<InputNode> out;
  for (std::size_t i = 0; i < seq.size(); ++i)
    out.push_back(InputNode(std::make_shared<const YAML::Node>(seq[i]), element_path(value->path, i), tracking_));
  return out;
}

// ---- what the getters asked, for the key audit ----------------------------------------------------------

namespace {

std::string canonical(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}
std::string canonical(Vec3 v) { return canonical(v.x) + ", " + canonical(v.y) + ", " + canonical(v.z); }
std::string canonical(long v) { return std::to_string(v); }
std::string canonical(bool v) { return v ? "true" : "false"; }

}  // namespace

void InputNode::note(const std::string& key, KeyKind kind, units::Dimension dim, const std::string* fallback,
                     const std::vector<std::string>* choices) const {
  Asked a;
  a.path = join(path_, key);
  a.kind = kind;
  a.dim = dim;
  // has(), child() and list() say only that the key may be there; a getter says what it holds.
  a.presence_only = kind == KeyKind::section && fallback == nullptr && choices == nullptr && dim == units::dimensionless;
  if (fallback) a.has_fallback = true, a.fallback = *fallback;
  if (choices) a.choices = *choices;
  auto& at = tracking_->asked_at[a.path];
  for (const std::size_t k : at) {
    const Asked& b = tracking_->asked[k];
    if (b.kind == a.kind && b.dim == a.dim && b.presence_only == a.presence_only && b.has_fallback == a.has_fallback &&
        b.fallback == a.fallback && b.choices == a.choices)
      return;
  }
  at.push_back(tracking_->asked.size());
  tracking_->asked.push_back(std::move(a));
}

std::vector<InputNode::Asked> InputNode::asked() const { return tracking_->asked; }

// ---- values -----------------------------------------------------------------------------------------
// Each converter takes the node, its key path and its place in the file, so that its errors name all three.

namespace {

/// The scalar text of a value, or an error saying what was expected instead.
std::string scalar_text(const YAML::Node& node, const std::string& path, const std::string& location,
                        const std::string& expected) {
  if (!node.IsScalar()) throw fail(path, show(node), "is " + kind(node) + "; expected " + expected, location);
  return node.Scalar();
}

double to_quantity(const YAML::Node& node, const std::string& path, const std::string& location,
                   units::Dimension dim) {
  const std::string text = scalar_text(node, path, location, "a single value in " + units::to_string(dim));
  try {
    return units::parse(text, dim, path);
  } catch (const InputError& e) {
    throw InputError(e.what() + location);
  }
}

Vec3 to_vec3(const YAML::Node& node, const std::string& path, const std::string& location,
             const std::string& source, units::Dimension dim) {
  if (!node.IsSequence() || node.size() != 3)
    throw fail(path, show(node),
               "expected three values [x, y, z] in " + units::to_string(dim) +
                   ", such as [1, 2, 3] or ['1 nm', '2 nm', '3 nm']",
               location);
  double xyz[3];
  for (std::size_t i = 0; i < 3; ++i) {
    const std::string at = node[i].IsNull() ? location : where(source, node[i]);
    xyz[i] = to_quantity(node[i], element_path(path, i), at, dim);
  }
  return {xyz[0], xyz[1], xyz[2]};
}

long to_integer(const YAML::Node& node, const std::string& path, const std::string& location) {
  const std::string text = trim(scalar_text(node, path, location, "a whole number such as 42"));
  const char* begin = text.data();
  const char* end = text.data() + text.size();
  if (begin != end && *begin == '+') ++begin;  // from_chars refuses an explicit '+'
  long value = 0;
  const auto [stop, ec] = std::from_chars(begin, end, value);
  if (ec == std::errc::result_out_of_range) throw fail(path, text, "out of the range of a whole number", location);
  if (ec == std::errc() && stop == end && begin != end) return value;
  // Exponent notation of a whole number ("1e9", "2.5e3"): taken when exact; "1.5" and "1e-3" are not whole.
  if (text.find_first_of("eE") != std::string::npos) {
    double d = 0;
    const auto [dstop, dec] = std::from_chars(begin, end, d);
    if (dec == std::errc() && dstop == end && std::isfinite(d) && d == std::floor(d)) {
      if (std::fabs(d) > 9.0e18) throw fail(path, text, "out of the range of a whole number", location);
      return static_cast<long>(d);
    }
  }
  throw fail(path, text, "expected a whole number such as 42 (or 1e9)", location);
}

bool to_boolean(const YAML::Node& node, const std::string& path, const std::string& location) {
  std::string text = trim(scalar_text(node, path, location, "true or false"));
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  if (text == "true" || text == "yes" || text == "on") return true;
  if (text == "false" || text == "no" || text == "off") return false;
  throw fail(path, node.Scalar(), "expected true or false", location);
}

std::string to_choice(const YAML::Node& node, const std::string& path, const std::string& location,
                      const std::vector<std::string>& allowed) {
  const std::string expected = "one of: " + list_of(allowed);
  const std::string text = scalar_text(node, path, location, expected);
  if (std::find(allowed.begin(), allowed.end(), text) == allowed.end())
    throw fail(path, text, "must be " + expected, location);
  return text;
}

}  // namespace

void InputNode::observe(const YAML::Node& node, const std::string& path, units::Dimension dim) const {
  if (dim == units::dimensionless) return;
  const std::string suffix = "_seconds";  // a key that names its unit (output.progress_seconds)
  if (path.size() >= suffix.size() && path.compare(path.size() - suffix.size(), suffix.size(), suffix) == 0) return;
  if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i) observe(node[i], element_path(path, i), dim);
    return;
  }
  if (!node.IsScalar()) return;
  const std::string text = trim(node.Scalar());
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  const bool plain = !text.empty() && end == text.c_str() + text.size();
  if (plain && value == 0.0) return;  // zero in any unit
  if (!plain) {
    tracking_->any_unit = tracking_->any_unit || text.find_first_of("0123456789") != std::string::npos;
    return;
  }
  const std::string entry = path + " = " + text;
  if (std::find(tracking_->plain.begin(), tracking_->plain.end(), entry) == tracking_->plain.end())
    tracking_->plain.push_back(entry);
}

std::vector<std::string> InputNode::plain_beside_units() const {
  return tracking_->any_unit ? tracking_->plain : std::vector<std::string>{};
}

double InputNode::quantity(const std::string& key, units::Dimension dim) const {
  note(key, KeyKind::quantity, dim);
  const auto v = require(key, "a value in " + units::to_string(dim));
  const double q = to_quantity(v->node, v->path, v->location, dim);
  observe(v->node, v->path, dim);
  return q;
}

double InputNode::quantity(const std::string& key, units::Dimension dim, double fallback) const {
  const std::string f = canonical(fallback);
  note(key, KeyKind::quantity, dim, &f);
  const auto v = find(key);
  if (!v) return fallback;
  const double q = to_quantity(v->node, v->path, v->location, dim);
  observe(v->node, v->path, dim);
  return q;
}

double InputNode::quantity(units::Dimension dim) const {
  const Value v = self();
  const double q = to_quantity(v.node, v.path, v.location, dim);
  observe(v.node, v.path, dim);
  return q;
}

Vec3 InputNode::vec3(const std::string& key, units::Dimension dim) const {
  note(key, KeyKind::vector, dim);
  const auto v = require(key, "[x, y, z] in " + units::to_string(dim));
  const Vec3 q = to_vec3(v->node, v->path, v->location, tracking_->source, dim);
  observe(v->node, v->path, dim);
  return q;
}

Vec3 InputNode::vec3(const std::string& key, units::Dimension dim, Vec3 fallback) const {
  const std::string f = canonical(fallback);
  note(key, KeyKind::vector, dim, &f);
  const auto v = find(key);
  if (!v) return fallback;
  const Vec3 q = to_vec3(v->node, v->path, v->location, tracking_->source, dim);
  observe(v->node, v->path, dim);
  return q;
}

long InputNode::integer(const std::string& key) const {
  note(key, KeyKind::integer);
  const auto v = require(key, "a whole number");
  return to_integer(v->node, v->path, v->location);
}

long InputNode::integer() const {
  const Value v = self();
  return to_integer(v.node, v.path, v.location);
}

long InputNode::integer(const std::string& key, long fallback) const {
  const std::string f = canonical(fallback);
  note(key, KeyKind::integer, units::dimensionless, &f);
  const auto v = find(key);
  return v ? to_integer(v->node, v->path, v->location) : fallback;
}

bool InputNode::boolean(const std::string& key) const {
  note(key, KeyKind::boolean);
  const auto v = require(key, "true or false");
  return to_boolean(v->node, v->path, v->location);
}

bool InputNode::boolean(const std::string& key, bool fallback) const {
  const std::string f = canonical(fallback);
  note(key, KeyKind::boolean, units::dimensionless, &f);
  const auto v = find(key);
  return v ? to_boolean(v->node, v->path, v->location) : fallback;
}

std::string InputNode::string(const std::string& key) const {
  note(key, KeyKind::text);
  const auto v = require(key, "a text value");
  return scalar_text(v->node, v->path, v->location, "a text value");
}

std::string InputNode::string(const std::string& key, const std::string& fallback) const {
  note(key, KeyKind::text, units::dimensionless, &fallback);
  const auto v = find(key);
  return v ? scalar_text(v->node, v->path, v->location, "a text value") : fallback;
}

std::string InputNode::text() const {
  const Value v = self();
  return scalar_text(v.node, v.path, v.location, "a text value");
}

std::string InputNode::choice(const std::string& key, const std::vector<std::string>& allowed) const {
  note(key, KeyKind::choice, units::dimensionless, nullptr, &allowed);
  const auto v = require(key, "one of: " + list_of(allowed));
  return to_choice(v->node, v->path, v->location, allowed);
}

std::string InputNode::choice(const std::string& key, const std::vector<std::string>& allowed,
                              const std::string& fallback) const {
  note(key, KeyKind::choice, units::dimensionless, &fallback, &allowed);
  const auto v = find(key);
  return v ? to_choice(v->node, v->path, v->location, allowed) : fallback;
}

std::vector<double> InputNode::numbers(const std::string& key, units::Dimension dim) const {
  note(key, KeyKind::numbers, dim);
  const auto v = require(key, "a list of values in " + units::to_string(dim));
  if (!v->node.IsSequence())
    throw fail(v->path, show(v->node),
               "is " + kind(v->node) + "; expected a list of values in " + units::to_string(dim) + " such as [1, 2, 3]",
               v->location);
  std::vector<double> out;
  for (std::size_t i = 0; i < v->node.size(); ++i) {
    const YAML::Node element = v->node[i];
    const std::string at = element.IsNull() ? v->location : where(tracking_->source, element);
    out.push_back(to_quantity(element, element_path(v->path, i), at, dim));
  }
  observe(v->node, v->path, dim);
  return out;
}

// ---- unknown keys -----------------------------------------------------------------------------------

namespace {

using KnownKeys = std::map<std::string, std::vector<std::string>>;

void check_read(const YAML::Node& node, const std::string& path, const std::string& source,
                const std::set<std::string>& read, const KnownKeys& known_keys) {
  if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i)
      check_read(node[i], element_path(path, i), source, read, known_keys);
    return;
  }
  if (!node.IsMap()) return;
  for (const auto& entry : node) {
    const std::string key = entry.first.Scalar();
    const std::string key_path = join(path, key);
    if (read.count(key_path) == 0) {
      const auto known_it = known_keys.find(path);
      const std::vector<std::string> known =
          known_it == known_keys.end() ? std::vector<std::string>{} : known_it->second;
      std::string what = "unknown key";
      // A one- or two-letter slip is the usual cause; name the key that was probably meant.
      for (const auto& k : known)
        if (edit_distance(k, key) <= (k.size() <= 4 ? 1u : 2u)) {
          what += "; did you mean '" + k + "'?";
          break;
        }
      what += "; known keys here: " + list_of(known);
      throw fail(key_path, show(entry.second), what, where(source, entry.first));
    }
    check_read(entry.second, key_path, source, read, known_keys);
  }
}

}  // namespace

namespace {

void mark_read(const YAML::Node& node, const std::string& path, std::set<std::string>& read) {
  if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i) mark_read(node[i], element_path(path, i), read);
    return;
  }
  if (!node.IsMap()) return;
  for (const auto& entry : node) {
    const std::string key_path = join(path, entry.first.Scalar());
    read.insert(key_path);
    mark_read(entry.second, key_path, read);
  }
}

}  // namespace

void InputNode::skip(const std::string& key) const {
  note(key, KeyKind::section);
  const std::shared_ptr<const Value> v = find(key);
  if (v) mark_read(v->node, v->path, tracking_->read);
}

std::string InputNode::yaml_of(const std::string& key) const {
  if (!node_->IsMap()) return {};
  for (const auto& entry : *node_) {
    if (entry.first.Scalar() != key) continue;
    YAML::Emitter out;
    out.SetMapFormat(YAML::Flow);
    out.SetSeqFormat(YAML::Flow);
    out << entry.second;
    return out.c_str();
  }
  return {};
}

std::vector<std::string> differing_keys(const InputNode& given, const InputNode& kept,
                                        const std::vector<std::string>& keys) {
  // The text of `path` in `n` ("" when absent), walking maps without recording any read.
  auto text = [](const InputNode& n, const std::string& path) {
    const auto dot = path.find('.');
    if (dot == std::string::npos) return n.yaml_of(path);
    const std::string parent = path.substr(0, dot);
    if (!n.has(parent)) return std::string();
    const InputNode inner = InputNode::load_string(n.yaml_of(parent), "");
    return inner.is_map() ? inner.yaml_of(path.substr(dot + 1)) : std::string();
  };
  std::vector<std::string> out;
  for (const std::string& k : keys)
    if (text(given, k) != text(kept, k)) out.push_back(k);
  return out;
}

void InputNode::reject_unknown_keys() const {
  check_read(*node_, path_, tracking_->source, tracking_->read, tracking_->known);
}

}  // namespace debris
