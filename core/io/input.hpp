#pragma once
// The YAML input file as a tree of nodes that know their dotted key path ("groups[1].motion"), so every
// error names where it is. Getters convert on the spot (quantities with units go to SI) and remember what
// was read; reject_unknown_keys() then reports anything the run never asked for, which is how a typo such
// as "youngs_modulu" fails loudly instead of silently falling back to a default.
#include <memory>
#include <string>
#include <vector>

#include "core/io/key_reference.hpp"
#include "core/units.hpp"
#include "core/vec3.hpp"

namespace YAML {
class Node;
}

namespace debris {

/// The whole text of an input file; InputError ("input file") naming the path when it is missing, a
/// directory, or unreadable.
std::string read_input_file(const std::string& path);

/// The most nodes an input file's tree may hold with its YAML aliases expanded (maps, sequences, keys and
/// values each count one). Real inputs hold hundreds; nested aliases can make a few lines hold billions.
constexpr long kMaxInputNodes = 1'000'000;

class InputNode {
 public:
  /// InputError naming the path if the file is missing or unreadable, or the line and column of a syntax error.
  static InputNode load_file(const std::string& path);
  /// `name` stands in for the file name in error messages; an empty one gives no line numbers (a text the
  /// user never saw as lines: the key paths alone say where).
  static InputNode load_string(const std::string& yaml, const std::string& name = "<string>");

  /// Dotted key path of this node: "" for the root, "material", "groups[1].motion".
  const std::string& path() const { return path_; }

  bool is_map() const;
  bool is_sequence() const;
  bool is_scalar() const;

  /// Whether this map has `key`; does not count as reading it.
  bool has(const std::string& key) const;
  /// The keys of this map in file order; does not count as reading them.
  std::vector<std::string> keys() const;

  /// The node under `key`; InputError "missing key" if absent.
  InputNode child(const std::string& key) const;
  /// The elements of the sequence under `key` (maps or scalars), with paths "key[i]".
  std::vector<InputNode> list(const std::string& key) const;

  /// A number with an optional unit, in SI ("73 GPa" -> 7.3e10); a plain number is taken as given.
  double quantity(const std::string& key, units::Dimension dim) const;
  double quantity(const std::string& key, units::Dimension dim, double fallback) const;
  /// This scalar node itself as a quantity (for the elements handed out by list()).
  double quantity(units::Dimension dim) const;

  /// A sequence of three quantities: [1, 2, 3] or ["1 nm", "2 nm", "3 nm"].
  Vec3 vec3(const std::string& key, units::Dimension dim) const;
  Vec3 vec3(const std::string& key, units::Dimension dim, Vec3 fallback) const;

  /// A whole number, also in exponent notation when exact ("1e9", "2.5e3"); "1.5", "1e-3" and "abc" are errors.
  long integer(const std::string& key) const;
  long integer(const std::string& key, long fallback) const;
  /// This scalar node itself as a whole number (for the elements handed out by list()).
  long integer() const;

  /// true/false (also yes/no, on/off).
  bool boolean(const std::string& key) const;
  bool boolean(const std::string& key, bool fallback) const;

  std::string string(const std::string& key) const;
  std::string string(const std::string& key, const std::string& fallback) const;
  /// This scalar node itself as text (for the elements handed out by list()).
  std::string text() const;

  /// A string that must be one of `allowed`; the error lists them.
  std::string choice(const std::string& key, const std::vector<std::string>& allowed) const;
  std::string choice(const std::string& key, const std::vector<std::string>& allowed,
                     const std::string& fallback) const;

  /// A sequence of quantities, each converted to SI.
  std::vector<double> numbers(const std::string& key, units::Dimension dim) const;

  /// Throws InputError for the first key of this map, and recursively of every map or sequence read from
  /// it, that no getter ever read: "'material.youngs_modulu' = 1: unknown key; known keys here: ...".
  /// Copies of a node share what has been read, so the check can run on the root at the end of setup.
  void reject_unknown_keys() const;

  /// Counts the whole subtree under `key` as read, unchecked (the parts of an input that a restart takes
  /// from its checkpoint instead); nothing when absent.
  void skip(const std::string& key) const;
  /// The node under `key` as YAML text ("" when absent), to compare two inputs; does not count as reading.
  std::string yaml_of(const std::string& key) const;

  /// When some quantity read so far carried a unit, the dimensional ones read as plain numbers ("path =
  /// text"), which are taken as they stand (SI, or the run's own coherent units); else empty. A file that
  /// mixes the two may hold a forgotten unit, so the executables print them as a note.
  std::vector<std::string> plain_beside_units() const;

  /// What a reader asked of one key, for the key audit (key_reference.hpp): the getter's kind, unit,
  /// default (canonical text: "%.17g" numbers, "true"/"false") and choices. A presence test (has()) alone
  /// leaves presence_only set.
  struct Asked {
    std::string path;  // with list indices, as errors name it
    KeyKind kind = KeyKind::section;
    units::Dimension dim = units::dimensionless;
    bool presence_only = true;
    bool has_fallback = false;
    std::string fallback;
    std::vector<std::string> choices;
  };
  /// Every key asked of this file's tree so far, in the order first asked.
  std::vector<Asked> asked() const;

 private:
  struct Tracking;
  struct Value;  // a node found under a key, with its path and its place in the file
  InputNode(std::shared_ptr<const YAML::Node> node, std::string path, std::shared_ptr<Tracking> tracking);

  /// The value under `key`, or null when absent; records `key` as known here and, if present, as read.
  std::shared_ptr<const Value> find(const std::string& key) const;
  /// As find(), but a missing key is an InputError that says what was `expected`.
  std::shared_ptr<const Value> require(const std::string& key, const std::string& expected) const;
  /// This node itself as a Value, for the getters that read a list element directly.
  Value self() const;
  /// Records whether a quantity (or each element of a list of them) was written with a unit.
  void observe(const YAML::Node& node, const std::string& path, units::Dimension dim) const;
  /// Records what a getter asked of `key` (the key audit's evidence).
  void note(const std::string& key, KeyKind kind, units::Dimension dim = units::dimensionless,
            const std::string* fallback = nullptr, const std::vector<std::string>* choices = nullptr) const;

  std::shared_ptr<const YAML::Node> node_;
  std::string path_;
  std::shared_ptr<Tracking> tracking_;
};

/// Of `keys` ("material", or "run.time_step" one level down), those whose YAML text differs between
/// `given` and `kept` (absent on one side counts as differing): what a restart's -i changes in the parts a
/// checkpoint fixes. Reads nothing (no key counts as read).
std::vector<std::string> differing_keys(const InputNode& given, const InputNode& kept,
                                        const std::vector<std::string>& keys);

}  // namespace debris
