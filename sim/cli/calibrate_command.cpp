#include "sim/cli/calibrate_command.h"

#include <charconv>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

#include "sim/calibrate/calibration_json.h"
#include "sim/cli/cli.h"
#include "sim/cli/scene_mesh.h"
#include "sim/io/scene_json.h"

namespace incise::sim {
namespace {

using namespace calibrate;

constexpr const char* kUsage =
    "usage: incise calibrate DATA.csv SCENE.json --method ga|cmaes|lm --out MATERIAL.json "
    "[--per label|node] [--budget N] [--seed S] [--population P] [--smoothing A]";

// A data file larger than this is not a probing experiment.
constexpr std::uintmax_t kMaxDataBytes = 64u << 20;

int usage_error(std::ostream& err, const std::string& problem) {
  err << "incise: " << problem << " (" << kUsage << ")\n";
  return kExitUsage;
}

std::optional<long long> parse_count(const std::string& text, long long low, long long high) {
  long long value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc{} || end != text.data() + text.size() || value < low || value > high) {
    return std::nullopt;
  }
  return value;
}

std::optional<std::string> read_text(const std::filesystem::path& file, std::string& problem) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(file, ec);
  if (ec) {
    problem = "cannot read it (" + ec.message() + ")";
    return std::nullopt;
  }
  if (size > kMaxDataBytes) {
    problem = "larger than 64 MiB";
    return std::nullopt;
  }
  std::ifstream stream(file, std::ios::binary);
  std::ostringstream text;
  text << stream.rdbuf();
  if (!stream) {
    problem = "cannot read it";
    return std::nullopt;
  }
  return text.str();
}

}  // namespace

int run_calibrate_command(const std::vector<std::string>& args, std::ostream& out,
                          std::ostream& err) {
  static const std::map<std::string, std::string, std::less<>> kOptions = {
      {"--method", "a method"},   {"--out", "a file name"}, {"--per", "label or node"},
      {"--budget", "a number"},   {"--seed", "a number"},   {"--population", "a number"},
      {"--smoothing", "a number"}};
  std::vector<std::string> files;
  std::map<std::string, std::string, std::less<>> options;
  for (std::size_t i = 1; i < args.size(); ++i) {
    const auto option = kOptions.find(args[i]);
    if (option != kOptions.end()) {
      if (i + 1 == args.size()) return usage_error(err, args[i] + " needs " + option->second);
      options[args[i]] = args[i + 1];
      ++i;
    } else if (!args[i].empty() && args[i][0] == '-') {
      return usage_error(err, "unknown option " + args[i]);
    } else {
      files.push_back(args[i]);
    }
  }
  if (files.size() != 2) return usage_error(err, "calibrate needs a data file and a scene file");
  if (!options.contains("--out")) return usage_error(err, "--out MATERIAL.json is required");
  if (!options.contains("--method")) return usage_error(err, "--method ga|cmaes|lm is required");

  CalibrationOptions calibration;
  const auto method = method_named(options["--method"]);
  if (!method) return usage_error(err, "--method must be ga, cmaes or lm");
  calibration.method = *method;
  if (options.contains("--per")) {
    if (options["--per"] == "node") {
      calibration.parameters = ParameterKind::node_moduli;
    } else if (options["--per"] != "label") {
      return usage_error(err, "--per must be label or node");
    }
  }
  if (options.contains("--budget")) {
    const auto budget = parse_count(options["--budget"], 1, 10'000'000);
    if (!budget) return usage_error(err, "--budget must be a whole number from 1 to 10000000");
    calibration.max_evaluations = static_cast<int>(*budget);
  }
  if (options.contains("--seed")) {
    const auto seed = parse_count(options["--seed"], 0, 1LL << 62);
    if (!seed) return usage_error(err, "--seed must be a whole number >= 0");
    calibration.seed = static_cast<std::uint64_t>(*seed);
  }
  if (options.contains("--population")) {
    const auto population = parse_count(options["--population"], 4, 10'000);
    if (!population) return usage_error(err, "--population must be a whole number from 4 to 10000");
    calibration.population = static_cast<int>(*population);
  }
  if (options.contains("--smoothing")) {
    const auto smoothing = parse_real(options["--smoothing"]);
    if (!smoothing || *smoothing < 0) return usage_error(err, "--smoothing must be a number >= 0");
    calibration.smoothing = *smoothing;
  }

  const std::string& data_file = files[0];
  const std::string& scene_file = files[1];
  std::string problem;
  const std::optional<std::string> text = read_text(data_file, problem);
  if (!text) {
    err << "incise: " << data_file << ": " << problem << "\n";
    return kExitUsage;
  }
  ProbeData data;
  try {
    data = parse_probe_csv(*text);
  } catch (const CalibrationError& error) {
    err << "incise: " << data_file << ": " << error.what() << "\n";
    return kExitUsage;
  }
  Scene scene;
  TetMesh mesh;
  try {
    scene = read_scene_file(scene_file);
    mesh = build_scene_mesh(scene, std::filesystem::path(scene_file).parent_path());
  } catch (const SceneError& error) {
    err << "incise: " << scene_file << ": " << error.what() << "\n";
    return kExitUsage;
  }
  calibration.progress = [&](const Progress& progress) {
    out << progress_line(calibration.method, progress) << "\n";
  };
  CalibrationResult result;
  try {
    result = calibrate::calibrate(scene, mesh, data, calibration);
  } catch (const CalibrationError& error) {
    err << "incise: " << data_file << " on " << scene_file << ": " << error.what() << "\n";
    return kExitUsage;
  }
  nlohmann::json json = calibration_json(result, calibration.method);
  json["calibration"]["data"] = data_file;
  json["calibration"]["scene"] = scene_file;
  std::ofstream stream(options["--out"]);
  stream << json.dump(2) << "\n";
  stream.close();
  if (!stream) {
    err << "incise: " << options["--out"] << ": cannot write the material\n";
    return kExitUsage;
  }
  char line[240];
  std::snprintf(
      line, sizeof line,
      "%s: %zu parameter%s by %s, misfit %.3g (scene's constants %.3g), %d "
      "simulations, %.1f s, stopped: %s",
      options["--out"].c_str(), result.values.size(), result.values.size() == 1 ? "" : "s",
      std::string(method_name(calibration.method)).c_str(), result.misfit, result.start_misfit,
      result.search.evaluations, result.seconds, result.search.stopped.c_str());
  out << line << "\n";
  for (const CalibratedValue& v : result.values) {
    if (result.values.size() > 8) break;  // per-node results are in the file
    const char* unit = v.name.starts_with("E") ? " Pa" : "";
    std::snprintf(line, sizeof line, "  %s = %.6g%s +- %.2g%s (was %.6g%s)", v.name.c_str(),
                  v.value, unit, v.spread, unit, v.start, unit);
    out << line << "\n";
  }
  return kExitOk;
}

}  // namespace incise::sim
