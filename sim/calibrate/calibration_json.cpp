#include "sim/calibrate/calibration_json.h"

#include <cstdio>

namespace incise::sim::calibrate {
namespace {

using nlohmann::json;

json constants(const Material& m) {
  return {{"E", m.youngs_modulus},
          {"nu", m.poisson_ratio},
          {"density", m.density},
          {"damping", m.damping}};
}

}  // namespace

json calibration_json(const CalibrationResult& result, Method method) {
  json out;
  const Scene& scene = result.calibrated;
  out["material"] = constants(scene.material);
  out["material"]["model"] = material_model_name(scene.material.model);
  if (scene.material.volume_stiffness > 0) {
    out["material"]["volume_stiffness"] = scene.material.volume_stiffness;
  }
  json materials = json::object();
  for (const auto& [label, m] : scene.materials_by_label) {
    if (label != 0) materials[std::to_string(label)] = constants(m);
  }
  if (!materials.empty()) out["materials"] = materials;
  if (result.parameters == ParameterKind::node_moduli) {
    json moduli = json::array();
    for (const CalibratedValue& v : result.values)
      moduli.push_back(v.value);
    out["node_moduli"] = moduli;
  }
  json c;
  c["method"] = method_name(method);
  c["parameters"] = result.parameters == ParameterKind::node_moduli ? "node" : "label";
  c["misfit"] = result.misfit;
  c["start_misfit"] = result.start_misfit;
  c["evaluations"] = result.search.evaluations;
  c["iterations"] = result.search.iterations;
  c["seconds"] = result.seconds;
  c["stopped"] = result.search.stopped;
  c["history"] = result.search.history;
  json values = json::array();
  for (const CalibratedValue& v : result.values) {
    values.push_back({{"name", v.name},
                      {"owner", v.owner},
                      {"start", v.start},
                      {"value", v.value},
                      {"spread", v.spread}});
  }
  c["values"] = values;
  json fits = json::array();
  for (const ContactFit& f : result.fits) {
    fits.push_back({{"contact", f.contact_id},
                    {"node", f.node},
                    {"distance", f.distance},
                    {"time", f.time},
                    {"force", f.force},
                    {"measured", f.measured},
                    {"start", f.start},
                    {"fitted", f.fitted}});
  }
  c["fits"] = fits;
  out["calibration"] = c;
  return out;
}

std::string progress_line(Method method, const Progress& progress) {
  char line[160];
  std::snprintf(line, sizeof line, "%s %d: misfit %.4g after %d simulations",
                method == Method::lm ? "iteration" : "generation", progress.iteration,
                progress.misfit, progress.evaluations);
  return line;
}

}  // namespace incise::sim::calibrate
