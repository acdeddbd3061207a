#include "sim/cli/surgery_command.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>

#include <nlohmann/json.hpp>

#include "sim/cli/cli.h"
#include "sim/surgery/scene_file.h"
#include "sim/surgery/tool_script.h"
#include "sim/surgery/track_sampling.h"

namespace incise::sim {
namespace {

using nlohmann::json;
using namespace surgery;
using Clock = std::chrono::steady_clock;

constexpr const char* kUsage =
    "usage: incise surgery SCENE.json --script SCRIPT.json --out RESULT.json";

int usage_error(std::ostream& err, const std::string& problem) {
  err << "incise: " << problem << " (" << kUsage << ")\n";
  return kExitUsage;
}

Real seconds_since(Clock::time_point start) {
  return std::chrono::duration<Real>(Clock::now() - start).count();
}

json vec3_json(const Vec3& v) {
  return json::array({v.x(), v.y(), v.z()});
}

// What a run did, for RESULT.json.
struct SurgeryRun {
  std::int64_t steps = 0;
  Real wall_seconds = 0;
  bool finite = true;
  std::vector<SceneEvent> events;
};

// Steps the scene for the script's duration: step n takes the script's inputs at its end time
// (n + 1) dt, so the last step reaches the last keyframe. Stops at a non-finite state.
SurgeryRun run_script(SurgicalScene& scene, const ToolScript& script, Real dt) {
  SurgeryRun run;
  // The 1e-9 keeps a duration that is a whole number of steps from gaining one by rounding.
  const auto steps = static_cast<std::int64_t>(std::ceil(script.duration / dt - 1e-9));
  std::vector<ToolInput> inputs;
  const Clock::time_point start = Clock::now();
  for (std::int64_t n = 0; n < steps; ++n) {
    sample_script(script, static_cast<Real>(n + 1) * dt, inputs);
    scene.step(inputs);
    ++run.steps;
    if (!scene.state_finite()) {
      run.finite = false;
      break;
    }
  }
  run.wall_seconds = seconds_since(start);
  run.events = scene.take_events();
  return run;
}

json result_json(const SurgicalSceneSetup& setup, const SurgicalScene& scene,
                 const ToolScript& script, const SurgeryRun& run) {
  const Real dt = setup.spec.dt;
  json result;
  result["scene"] = setup.name;
  result["dt"] = dt;
  result["duration"] = script.duration;
  result["mass_scale"] = setup.mass_scale;
  result["steps"] = run.steps;
  result["nodes"] = scene.tissue().mesh().num_nodes();
  result["tets"] = scene.tissue().mesh().num_tets();
  result["wall_seconds"] = run.wall_seconds;
  // Simulated time over wall time (the steps run, also when a run stopped early): at least 1
  // keeps up with a station's clock.
  result["real_time_ratio"] = run.wall_seconds > 0 ? run.steps * dt / run.wall_seconds : 0.0;
  result["steps_per_second"] =
      run.wall_seconds > 0 ? static_cast<Real>(run.steps) / run.wall_seconds : 0.0;
  result["finite"] = run.finite;
  result["status"] = run.finite ? std::string("completed")
                                : "non-finite state at step " + std::to_string(run.steps) +
                                      " (t = " + std::to_string(scene.time()) + " s)";
  result["cuts_refused"] = scene.cuts_refused();
  result["mass_scaled_nodes"] = scene.tissue().mass_scaled_nodes();
  result["max_mass_scale"] = scene.tissue().max_mass_scale();
  json events = json::array();
  for (const SceneEvent& e : run.events) {
    events.push_back(
        {{"kind", std::string(to_string(e.kind))},
         {"tool", e.tool},
         {"tool_kind",
          e.tool >= 0 ? json(std::string(to_string(setup.spec.tools[std::size_t(e.tool)].kind)))
                      : json(nullptr)},
         {"time", e.time},
         {"detail", e.detail}});
  }
  result["events"] = std::move(events);
  json damage = json::array();
  for (const tools::MetricRow& row : tools::metric_rows(scene.damage())) {
    damage.push_back(
        {{"name", std::string(row.name)}, {"unit", std::string(row.unit)}, {"value", row.value}});
  }
  result["damage"] = std::move(damage);
  int devices = 0;
  for (const ToolSpec& t : setup.spec.tools)
    devices = std::max(devices, t.device + 1);
  json models = json::array();
  for (int d = 0; d < devices; ++d) {
    const tools::LocalForceModel m = scene.force_model(d);
    json stiffness = json::array();
    for (int r = 0; r < 3; ++r)
      stiffness.push_back(vec3_json(m.stiffness.row(r).transpose()));
    models.push_back({{"device", d},
                      {"reference_position", vec3_json(m.reference_position)},
                      {"force", vec3_json(m.force)},
                      {"stiffness", std::move(stiffness)}});
  }
  result["force_models"] = std::move(models);
  return result;
}

}  // namespace

int run_surgery_command(const std::vector<std::string>& args, std::ostream& out,
                        std::ostream& err) {
  const CommandArgs parsed = parse_command_args(args, {"--out", "--script"});
  if (!parsed.problem.empty()) return usage_error(err, parsed.problem);
  const std::optional<std::string>& scene_file = parsed.file;
  std::optional<std::string> script_file, result_file;
  if (parsed.options.contains("--script")) script_file = parsed.options.at("--script");
  if (parsed.options.contains("--out")) result_file = parsed.options.at("--out");
  if (!scene_file) return usage_error(err, "surgery needs a scene file");
  if (!script_file) return usage_error(err, "surgery needs --script SCRIPT.json");
  if (!result_file) return usage_error(err, "surgery needs --out RESULT.json");

  const Clock::time_point setup_start = Clock::now();
  SurgicalSceneSetup setup;
  ToolScript script;
  try {
    setup = read_surgical_scene(*scene_file);
  } catch (const SceneError& error) {
    err << "incise: " << *scene_file << ": " << error.what() << "\n";
    return kExitUsage;
  }
  try {
    script = read_tool_script(*script_file, setup);
  } catch (const SceneError& error) {
    err << "incise: " << *script_file << ": " << error.what() << "\n";
    return kExitUsage;
  }
  const Real dt = setup.spec.dt;
  SurgicalScene scene(setup.spec);  // a copy: RESULT.json names the tools of setup.spec
  const Real setup_seconds = seconds_since(setup_start);
  const SurgeryRun run = run_script(scene, script, dt);

  json result = result_json(setup, scene, script, run);
  result["scene_file"] = *scene_file;
  result["script_file"] = *script_file;
  result["setup_seconds"] = setup_seconds;
  std::ofstream stream(*result_file);
  stream << result.dump(2) << "\n";
  stream.close();
  if (!stream) {
    err << "incise: " << *result_file << ": cannot write the result\n";
    return kExitUsage;
  }
  char line[160];
  std::snprintf(line, sizeof line, "%s: %lld steps of %.3g s in %.2f s (%.0f steps/s), %zu events",
                setup.name.c_str(), static_cast<long long>(run.steps), dt, run.wall_seconds,
                result["steps_per_second"].get<Real>(), run.events.size());
  out << line << "\n";
  if (!run.finite) {
    err << "incise: " << *scene_file << ": " << result["status"].get<std::string>() << "\n";
    return kExitFailed;
  }
  return kExitOk;
}

}  // namespace incise::sim
