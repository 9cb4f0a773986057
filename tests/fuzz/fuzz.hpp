#pragma once
// The fuzzer's targets: one per reader of outside data. A target takes the bytes of one input and hands them
// to the reader the executables use (text readers directly, file readers through a scratch file). It
// returns normally for an input the reader accepted and lets the reader's named error escape for one it
// rejected; `named_error` says which exceptions count as named errors. Anything else that escapes, a
// sanitizer report, a hang past the time limit or an allocation past the cap is a finding.
#include <exception>
#include <functional>
#include <string>
#include <vector>

namespace debris::fuzz {

/// Outcome of an input the reader handled.
enum class Outcome { accepted, rejected, skipped };

struct Target {
  std::string name;
  std::string about;
  /// Runs the reader on one input; returns accepted or skipped (see Target::skip_reason), or throws.
  std::function<Outcome(const std::string& input)> run;
  /// Whether `e` is one of the reader's documented errors (debris::InputError at least).
  std::function<bool(const std::exception& e)> named_error;
  /// File name endings of seed files, when seeds are found by walking directories ("yaml", "msh").
  std::vector<std::string> seed_endings;
  /// Seeds the target makes itself (the checkpoint targets' mutation programs), added to any given.
  std::function<std::vector<std::string>()> builtin_seeds;
  /// Why run() returned skipped, for the report.
  std::string skip_reason;
  /// Work done once before the first input, outside its time limit (the checkpoint targets' seed runs).
  std::function<void()> prepare;
};

/// Every target, in a fixed order. `scratch` is an empty directory the targets may write into.
std::vector<Target> all_targets(const std::string& scratch);

}  // namespace debris::fuzz
