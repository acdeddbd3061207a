#include "sim/cli/plan_command.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "sim/cli/cli.h"
#include "sim/plan/penetration_planner.h"
#include "sim/surgery/scene_file.h"

namespace incise::sim {
namespace {

using nlohmann::json;
using namespace surgery;

constexpr const char* kUsage =
    "usage: incise plan SCENE.json --from X,Y,Z --to X,Y,Z [--degree N] [--probe-radius R] "
    "[--bound B] --out PATH.json";

int usage_error(std::ostream& err, const std::string& problem) {
  err << "incise: " << problem << " (" << kUsage << ")\n";
  return kExitUsage;
}

// "x,y,z" in metres, all finite.
std::optional<Vec3> parse_point(const std::string& text) {
  Vec3 p;
  std::size_t start = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const auto comma = axis < 2 ? text.find(',', start) : text.size();
    if (comma == std::string::npos) return std::nullopt;
    const auto value = parse_real(text.substr(start, comma - start));
    if (!value) return std::nullopt;
    p[axis] = *value;
    start = comma + 1;
  }
  return p;
}

json vec3_json(const Vec3& v) {
  return json::array({v.x(), v.y(), v.z()});
}

// Young's modulus of a tissue of the scene, by the anatomy and the tissue's name.
Real youngs_modulus(const SurgicalSceneFile& file, const std::string& tissue) {
  if (file.anatomy == Anatomy::liver) return file.liver.liver.youngs_modulus;
  return tissue == "ligament" ? file.knee.ligament.youngs_modulus
                              : file.knee.meniscus.youngs_modulus;
}

// The scene's tissues, one obstacle per named tissue (labels of one name together; protected when
// the scene protects one of its labels, as the liver's gallbladder bed), and its bones,
// protected.
std::vector<plan::Obstacle> scene_obstacles(const SurgicalSceneFile& file,
                                            const SurgicalSceneSetup& setup, Real spacing) {
  const TetMesh& mesh = setup.spec.tissue;
  std::map<std::string, std::vector<int>> tets_of;  // tissue name -> its tets
  std::set<std::string> protect;
  const auto& protected_labels = setup.spec.damage.protected_labels;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const int label = mesh.labels.size() ? mesh.labels[t] : 0;
    const auto name = setup.tissue_names.contains(label) ? setup.tissue_names.at(label)
                                                         : "tissue " + std::to_string(label);
    if (std::find(protected_labels.begin(), protected_labels.end(), label) !=
        protected_labels.end()) {
      protect.insert(name);
    }
    tets_of[name].push_back(t);
  }
  Real softest = std::numeric_limits<Real>::infinity(), stiffest = 0;
  for (const auto& [name, _] : tets_of) {
    softest = std::min(softest, youngs_modulus(file, name));
    stiffest = std::max(stiffest, youngs_modulus(file, name));
  }
  std::vector<plan::Obstacle> obstacles;
  for (const auto& [name, tets] : tets_of) {
    plan::Obstacle o;
    o.name = name;
    Tets own(static_cast<Eigen::Index>(tets.size()), 4);
    for (std::size_t i = 0; i < tets.size(); ++i)
      own.row(static_cast<Eigen::Index>(i)) = mesh.tets.row(tets[i]);
    // The mesh's cells are larger than the probe: its volume sampled at the probe's size.
    o.points = plan::volume_points(mesh.rest, own, spacing);
    o.stiffness = youngs_modulus(file, name) / softest;
    o.protect = protect.contains(name);
    obstacles.push_back(std::move(o));
  }
  for (const auto& bone : setup.spec.bones) {
    plan::Obstacle o;
    o.name = bone.name;
    o.points = bone.vertices;
    o.depth = VecX::Zero(bone.vertices.rows());  // a surface: its vertices are on it
    o.stiffness = 1000 * stiffest / softest;
    o.protect = true;
    obstacles.push_back(std::move(o));
  }
  return obstacles;
}

}  // namespace

int run_plan_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  const CommandArgs parsed = parse_command_args(
      args, {"--out", "--from", "--to", "--degree", "--probe-radius", "--bound"});
  if (!parsed.problem.empty()) return usage_error(err, parsed.problem);
  const auto option = [&](const char* name) -> std::optional<std::string> {
    const auto it = parsed.options.find(name);
    if (it == parsed.options.end()) return std::nullopt;
    return it->second;
  };
  if (!parsed.file) return usage_error(err, "plan needs a scene file");
  const auto out_file = option("--out");
  if (!out_file) return usage_error(err, "plan needs --out PATH.json");
  std::optional<Vec3> from, to;
  if (const auto text = option("--from")) from = parse_point(*text);
  if (const auto text = option("--to")) to = parse_point(*text);
  if (!from) return usage_error(err, "--from needs a point x,y,z in metres");
  if (!to) return usage_error(err, "--to needs a point x,y,z in metres");
  if ((*to - *from).norm() == 0) return usage_error(err, "--from and --to are the same point");
  plan::PlanOptions options;
  if (const auto text = option("--degree")) {
    const auto degree = parse_real(*text);
    if (!degree || *degree != std::floor(*degree) || *degree < 2 || *degree > 7) {
      return usage_error(err, "--degree needs a whole number from 2 to 7");
    }
    options.degree = static_cast<int>(*degree);
  }
  if (const auto text = option("--probe-radius")) {
    const auto radius = parse_real(*text);
    if (!radius || *radius <= 0 || *radius > 0.05) {
      return usage_error(err, "--probe-radius needs metres in (0, 0.05]");
    }
    options.probe_radius = *radius;
  }
  if (const auto text = option("--bound")) {
    const auto bound = parse_real(*text);
    if (!bound || *bound < 0 || *bound > 0.05) {
      return usage_error(err, "--bound needs metres in [0, 0.05]");
    }
    options.penetration_bound = *bound;
  }

  SurgicalSceneFile file;
  SurgicalSceneSetup setup;
  try {
    std::ifstream in(*parsed.file);
    if (!in) throw SceneError("", "cannot read the file");
    std::stringstream text;
    text << in.rdbuf();
    const auto root = json::parse(text.str(), nullptr, false);
    if (root.is_discarded()) throw SceneError("", "malformed JSON");
    file = parse_surgical_scene_file(root);
    setup = build_surgical_scene(file);
  } catch (const SceneError& error) {
    err << "incise: " << *parsed.file << ": " << error.what() << "\n";
    return kExitUsage;
  }
  // Points a probe radius apart (but not under a millimetre: a tissue's volume in at most a few
  // hundred thousand points).
  const auto obstacles = scene_obstacles(file, setup, std::max<Real>(options.probe_radius, 0.001));
  const auto start = std::chrono::steady_clock::now();
  const auto path = plan::plan_path(*from, *to, obstacles, options);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  json result;
  result["scene"] = setup.name;
  result["from"] = vec3_json(*from);
  result["to"] = vec3_json(*to);
  result["degree"] = options.degree;
  result["probe_radius"] = options.probe_radius;
  result["penetration_bound"] = options.penetration_bound;
  result["coefficients"] = json::array();
  for (const auto& c : path.bend)
    result["coefficients"].push_back(vec3_json(c));
  result["path"] = json::array();
  for (const auto& p : path.polyline(65))
    result["path"].push_back(vec3_json(p));
  result["straight_cost"] = path.straight_cost;
  result["cost"] = path.cost;
  result["iterations"] = path.iterations;
  result["max_penetration"] = path.max_penetration;
  result["deepest_obstacle"] = path.deepest_obstacle;
  result["max_protected_penetration"] = path.max_protected_penetration;
  result["within_bound"] = path.within_bound;
  result["problem"] = path.problem;
  result["obstacles"] = json::array();
  for (const auto& o : obstacles) {
    result["obstacles"].push_back({{"name", o.name},
                                   {"points", o.points.rows()},
                                   {"stiffness", o.stiffness},
                                   {"protected", o.protect}});
  }
  std::ofstream stream(*out_file);
  stream << result.dump(2) << "\n";
  stream.close();
  if (!stream) {
    err << "incise: " << *out_file << ": cannot write the path\n";
    return kExitUsage;
  }
  char line[200];
  std::snprintf(line, sizeof line,
                "%s: degree %d, cost %.3g (straight line %.3g), deepest %.2f mm into %s, %.2f s",
                setup.name.c_str(), options.degree, path.cost, path.straight_cost,
                path.max_penetration * 1000,
                path.deepest_obstacle.empty() ? "nothing" : path.deepest_obstacle.c_str(), seconds);
  out << line << "\n";
  if (!path.within_bound) err << "incise: " << path.problem << "\n";
  return kExitOk;
}

}  // namespace incise::sim
