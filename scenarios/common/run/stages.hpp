#pragma once
// Staged runs: an input may split its run into stages (settle, then load; slide, then unload), each with
// a length and the changes made at its start. This file reads the part every executable shares, the
// names and lengths; what a stage changes (a group's motion, a wall's velocity, the damping) is read by the
// executable's own input reader from the same node. The layout:
//
//   stages:
//     - name: settle
//       steps: 20000            # or duration: 0.06 s (rounded to whole steps of the run's time step)
//       global_damping: 0.5     # ... changes, read by the executable
//     - name: slide
//       duration: 10 ns
//
// Stage k starts at step S_k, the sum of the lengths before it (S_0 = 0), and its changes are applied
// when the run is at step S_k, after that step's output and checkpoint and before the next step. A
// checkpoint therefore always holds the state before the changes of the stage starting at its step, and a
// restart from it applies them exactly as the uninterrupted run did: staged runs restart bit for bit
// anywhere, stage boundaries included, because every setting a stage can change is in the checkpoint.
#include <string>
#include <vector>

namespace debris {

class InputNode;
class KeyReference;

/// A stage as the input gives it: a name, and its length in steps or as a duration (one of the two).
struct StageLength {
  std::string name;
  std::string key;        // "stages[2]", for messages
  long steps = -1;        // given as steps (>= 1), or -1
  double duration = -1;   // given as a duration in s (> 0), or -1
};

/// Reads the names and lengths of root.stages (an empty list when absent), leaving the other keys of each
/// stage to the caller (`nodes` receives each stage's node). InputError for a missing or non-positive
/// length, both steps and duration, or a repeated name.
std::vector<StageLength> read_stage_lengths(const InputNode& root, std::vector<InputNode>* nodes);

/// Describes `stages` and the keys read_stage_lengths() reads (name, steps, duration); the executable
/// describes what else a stage may change.
void document_stage_lengths(KeyReference& ref);

/// The stages on the step axis.
struct StagePlan {
  std::vector<std::string> names;
  std::vector<long> start;  // first step of each stage
  long end = 0;             // the step after the last stage's last one (the run's total)

  bool empty() const { return start.empty(); }
  /// Index of the stage that contains `step` (the last one whose start is <= step), or -1 without stages.
  int stage_at(long step) const;
  /// Index of the stage starting exactly at `step`, or -1.
  int stage_starting_at(long step) const;
};

/// Converts durations to steps of `dt` (rounded to the nearest, InputError if that is 0 steps or more than
/// 1e15) and lays the stages end to end.
StagePlan resolve_stages(const std::vector<StageLength>& stages, double dt);

}  // namespace debris
