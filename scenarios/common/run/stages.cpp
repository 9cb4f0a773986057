#include "scenarios/common/run/stages.hpp"

#include <cmath>

#include "core/error.hpp"
#include "core/io/input.hpp"
#include "core/io/key_reference.hpp"

namespace debris {

std::vector<StageLength> read_stage_lengths(const InputNode& root, std::vector<InputNode>* nodes) {
  std::vector<StageLength> out;
  if (!root.has("stages")) return out;
  const std::vector<InputNode> list = root.list("stages");
  if (list.empty()) throw input_error("stages", "[]", "give at least one stage, or leave 'stages' out");
  for (const InputNode& s : list) {
    if (!s.is_map()) throw input_error(s.path(), s.text(), "a stage is a map with a name and steps or duration");
    StageLength st;
    st.key = s.path();
    st.name = s.string("name", "stage" + std::to_string(out.size()));
    for (const StageLength& o : out)
      if (o.name == st.name) throw input_error(s.path() + ".name", st.name, "stage names must be unique");
    const bool has_steps = s.has("steps"), has_duration = s.has("duration");
    if (has_steps == has_duration)
      throw input_error(s.path() + ".steps", has_steps ? "given with duration" : "(absent)",
                        "give exactly one of steps (a number of steps) or duration (a time) per stage");
    if (has_steps) {
      st.steps = s.integer("steps");
      if (st.steps < 1) throw input_error(s.path() + ".steps", std::to_string(st.steps), "must be >= 1");
    } else {
      st.duration = s.quantity("duration", units::time);
      if (!(st.duration > 0) || !std::isfinite(st.duration))
        throw input_error(s.path() + ".duration", format_value(st.duration), "must be > 0");
    }
    out.push_back(st);
    if (nodes) nodes->push_back(s);
  }
  return out;
}

void document_stage_lengths(KeyReference& ref) {
  ref.describe_section("stages",
                       "A run may be split into stages (settle, then load; slide, then unload). Stage k starts at "
                       "the sum of the lengths before it; its changes apply at that step, after its output and "
                       "checkpoint, so a restart anywhere repeats the run bit for bit.");
  ref.key("stages").is(KeyKind::list).fallback_is("none: one stage of `run.steps`").allowed("at least one entry")
      .means("the stages, in order");
  ref.key("stages.name").is(KeyKind::text).fallback_is("`stage<k>` (k counted from 0)").allowed("unique")
      .means("the stage's name, printed when it starts");
  ref.key("stages.steps").is(KeyKind::integer).fallback_is("give steps or duration").allowed(">= 1")
      .means("the stage's length in steps");
  ref.key("stages.duration").is(KeyKind::quantity).in(units::time).fallback_is("give steps or duration")
      .allowed("> 0").means("the stage's length as a time, rounded to whole steps of `run.time_step`");
}

int StagePlan::stage_at(long step) const {
  int k = -1;
  for (std::size_t i = 0; i < start.size(); ++i)
    if (start[i] <= step) k = static_cast<int>(i);
  return k;
}

int StagePlan::stage_starting_at(long step) const {
  for (std::size_t i = 0; i < start.size(); ++i)
    if (start[i] == step) return static_cast<int>(i);
  return -1;
}

StagePlan resolve_stages(const std::vector<StageLength>& stages, double dt) {
  StagePlan plan;
  long at = 0;
  for (const StageLength& s : stages) {
    long n = s.steps;
    if (n < 0) {
      const double steps = std::round(s.duration / dt);
      if (!(steps >= 1))
        throw input_error(s.key + ".duration", format_value(s.duration),
                          "is less than half a time step (dt = " + format_value(dt) + " s)");
      if (steps > 1e15) throw input_error(s.key + ".duration", format_value(s.duration), "is more than 1e15 time steps");
      n = static_cast<long>(steps);
    }
    plan.names.push_back(s.name);
    plan.start.push_back(at);
    at += n;
  }
  plan.end = at;
  return plan;
}

}  // namespace debris
