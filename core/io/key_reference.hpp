#pragma once
// One description per input key, shared by the reader and the manual. Each executable builds a
// KeyReference of every key its reader accepts (type, unit, default, allowed range, meaning, the paper's
// equation); `--keys` prints it as the Markdown tables of the executable's manual, and a test keeps the
// manual's tables equal to it. With DEBRIS_KEY_AUDIT=1 in the environment (every test sets it),
// audit_keys() holds the reader to the reference: a key the reader asks for that is not described, or whose
// type, unit, default or choices differ from the description, ends the run with a std::logic_error. So a
// key added to a reader without its description fails the test suite.
//
// Output tables get the same treatment: a ColumnTable lists a file's columns with their units; the writer
// takes its header from it and `--columns` prints it for the manual.
#include <iosfwd>
#include <map>
#include <string>
#include <vector>

#include "core/units.hpp"

namespace debris {

class InputNode;

enum class KeyKind {
  quantity,  // a number with an optional unit ("73 GPa")
  vector,    // [x, y, z], each a quantity
  numbers,   // a list of quantities
  integer,   // a whole number
  boolean,   // true / false
  text,      // free text (a name, a file path)
  choice,    // one of a fixed list of words
  section,   // a map of further keys
  list,      // a list of entries (maps or values)
};

/// The description of one key. `path` is dotted, without list indices ("groups.motion" is the `motion` of
/// every entry of `groups`); a segment in angle brackets ("shapes.<name>.mesh_size") stands for any name
/// the user chooses. A section or list whose keys are those of a shared table (a region) names it in `table`.
struct KeyDoc {
  std::string path;
  KeyKind kind = KeyKind::section;
  units::Dimension dim = units::dimensionless;
  std::vector<std::string> choices;
  std::string table;  // shared table the keys below follow ("region"), or empty
  bool or_list = false;  // also takes a list in place of the one value (`fixed: true` or `fixed: [x, y]`;
                         // `poisson_ratio: 0.1` or a sweep `[0, 0.1]`)

  enum class Default { required, literal, described };
  Default default_kind = Default::required;
  std::string default_text;  // literal: as an input would write it ("0", "1 nm", "y"); described: prose

  std::string range;     // allowed values, as the reader checks them ("> 0", "[0, 0.25]"); empty: any
  std::string meaning;   // one or two sentences
  std::string equation;  // the paper's equation or table ("A eq 8", "B eq 2.4"); empty if none

  // Builders, so a description reads as one chained line.
  KeyDoc& is(KeyKind k) { kind = k; return *this; }
  KeyDoc& in(units::Dimension d) { dim = d; return *this; }
  KeyDoc& one_of(std::vector<std::string> c) { kind = KeyKind::choice; choices = std::move(c); return *this; }
  KeyDoc& follows(std::string shared_table) { table = std::move(shared_table); return *this; }
  KeyDoc& or_a_list() { or_list = true; return *this; }
  /// A default the reader uses as written here (checked against the reader by the audit).
  KeyDoc& fallback(std::string literal) { default_kind = Default::literal; default_text = std::move(literal); return *this; }
  /// A default that depends on other keys or the run, said in words (not checked).
  KeyDoc& fallback_is(std::string prose) { default_kind = Default::described; default_text = std::move(prose); return *this; }
  KeyDoc& allowed(std::string r) { range = std::move(r); return *this; }
  KeyDoc& means(std::string m) { meaning = std::move(m); return *this; }
  KeyDoc& eq(std::string e) { equation = std::move(e); return *this; }
};

class KeyReference {
 public:
  explicit KeyReference(std::string program) : program_(std::move(program)) {}

  const std::string& program() const { return program_; }

  /// Adds a key of the main table (or, with `table`, of a shared table such as "region") and returns its
  /// description for the builders. Adding a path twice is a std::logic_error.
  KeyDoc& key(const std::string& path, const std::string& table = "");
  /// A paragraph printed under a top-level section's heading (or a shared table's).
  void describe_section(const std::string& section, const std::string& text, const std::string& table = "");

  /// The description of a key path as the reader names it ("groups[2].region.box" is looked up as
  /// "groups.region.box", through the shared table of "groups.region"); nullptr when there is none.
  const KeyDoc* find(const std::string& path) const;

  /// The reference as Markdown: one table per top-level section, then each shared table.
  void print_markdown(std::ostream& out) const;

  const std::vector<KeyDoc>& entries(const std::string& table = "") const;

 private:
  const KeyDoc* find_in(const std::string& table, const std::vector<std::string>& segments, int depth) const;

  std::string program_;
  std::map<std::string, std::vector<KeyDoc>> tables_;  // "" is the main table
  std::map<std::string, std::string> section_text_;    // "table/section" -> paragraph
};

/// The SI unit a manual shows for a dimension: "Pa", "kg/m^3", "J/m^2", "m/s", "-" for none.
std::string si_unit(units::Dimension d);

/// With DEBRIS_KEY_AUDIT set (not "0"), checks every key the reader asked of `root` (and of the nodes read
/// from it) against `reference`: described, of the same kind, dimension and choices, with the same literal
/// default. Throws std::logic_error listing every difference. Without the variable it does nothing.
void audit_keys(const InputNode& root, const KeyReference& reference);
/// The same check, whatever the environment says (for the tests of the audit itself).
std::vector<std::string> key_audit_findings(const InputNode& root, const KeyReference& reference);

/// One column of an output table. A name in angle brackets ("<group>_fx") stands for one column per
/// group, wall or grain, named by the input.
struct ColumnDoc {
  std::string name;
  std::string unit;     // "m", "J", "-": in SI, or the input's own units when it gives none
  std::string meaning;
  std::string when;     // empty: always written; else only in runs with this condition ("3D", "per grain")
};

/// The columns of one output file, in order.
struct ColumnTable {
  std::string file;         // "thermo.csv"
  std::string description;  // when it is written, one row per what
  std::vector<ColumnDoc> columns;

  /// The header: each fixed name as it stands; a patterned name ("<group>_fx") once per entry of
  /// `names[pattern]` ({"group", {"top", "bottom"}} gives top_fx, bottom_fx), in the order of the entries.
  /// A pattern repeated over several columns is expanded entry by entry (top_fx, top_fy, bottom_fx, ...).
  /// A column with a `when` is written only when `conditions` holds it.
  std::vector<std::string> header(const std::map<std::string, std::vector<std::string>>& names = {},
                                  const std::vector<std::string>& conditions = {}) const;
};

/// The tables as Markdown, one heading per file.
void print_columns_markdown(std::ostream& out, const std::vector<ColumnTable>& tables);

}  // namespace debris
