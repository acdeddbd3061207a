#include "sim/scene/scene_validation.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstddef>

#include "sim/solve/stable_time_step.h"

namespace incise::sim {
namespace {

constexpr const char* kAxisNames[3] = {"x", "y", "z"};

std::string element(const std::string& path, std::size_t index) {
  return path + "[" + std::to_string(index) + "]";
}

void require_finite(const std::string& path, Real value) {
  if (!std::isfinite(value))
    throw SceneError(path, "must be finite (got " + format_number(value) + ")");
}

void require_positive(const std::string& path, Real value) {
  require_finite(path, value);
  if (!(value > 0)) throw SceneError(path, "must be positive (got " + format_number(value) + ")");
}

void require_finite(const std::string& path, const Vec3& value) {
  for (int a = 0; a < 3; ++a)
    require_finite(element(path, static_cast<std::size_t>(a)), value(a));
}

void validate_selection(const std::string& path, const Selection& selection) {
  const std::string box_path = path + ".box";
  require_finite(element(box_path, 0), Vec3(selection.box.min()));
  require_finite(element(box_path, 1), Vec3(selection.box.max()));
  for (int a = 0; a < 3; ++a) {
    if (selection.box.min()(a) > selection.box.max()(a)) {
      throw SceneError(box_path, std::string("min corner exceeds max corner in ") + kAxisNames[a] +
                                     " (" + format_number(selection.box.min()(a)) + " > " +
                                     format_number(selection.box.max()(a)) + ")");
    }
  }
}

void validate_view(const ViewSpec& view) {
  require_finite("view.eye", view.eye);
  require_finite("view.target", view.target);
  require_finite("view.up", view.up);
  require_finite("view.fov_y_deg", view.fov_y_deg);
  const Vec3 forward = view.target - view.eye;
  if (!(forward.norm() > 0)) throw SceneError("view.target", "must differ from view.eye");
  // A camera basis needs an up direction with a component across the line of sight.
  if (!(forward.normalized().cross(view.up).norm() > 1e-6 * view.up.norm())) {
    throw SceneError("view.up", "must not be zero or parallel to target - eye");
  }
  if (!(view.fov_y_deg > 0 && view.fov_y_deg < 180)) {
    throw SceneError("view.fov_y_deg",
                     "must be in (0, 180) (got " + format_number(view.fov_y_deg) + ")");
  }
}

}  // namespace

std::string format_number(Real value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

namespace {

void validate_material(const std::string& path, const Material& material) {
  require_positive(path + ".E", material.youngs_modulus);
  require_positive(path + ".density", material.density);
  if (!(material.poisson_ratio > -1 && material.poisson_ratio < 0.5)) {
    throw SceneError(path + ".nu",
                     "must be in (-1, 0.5) (got " + format_number(material.poisson_ratio) + ")");
  }
  if (!(material.damping >= 0 && material.damping <= 1)) {
    throw SceneError(path + ".damping",
                     "must be in [0, 1] (got " + format_number(material.damping) + ")");
  }
  if (!(material.volume_stiffness >= 0) || !std::isfinite(material.volume_stiffness)) {
    throw SceneError(path + ".volume_stiffness",
                     "must not be negative (got " + format_number(material.volume_stiffness) + ")");
  }
}

void validate_mesh(const MeshSpec& mesh) {
  switch (mesh.source) {
    case MeshSource::box: {
      const BoxMeshSpec& box = mesh.box;
      for (int a = 0; a < 3; ++a) {
        require_positive(element("mesh.box.size", static_cast<std::size_t>(a)), box.size(a));
        if (box.cells(a) < 1) {
          throw SceneError(element("mesh.box.cells", static_cast<std::size_t>(a)),
                           "must be at least 1 (got " + std::to_string(box.cells(a)) + ")");
        }
      }
      const std::int64_t cells = std::int64_t{box.cells.x()} * box.cells.y() * box.cells.z();
      if (cells > kMaxBoxCells) {
        throw SceneError("mesh.box.cells", "at most " + std::to_string(kMaxBoxCells) +
                                               " cells in all (got " + std::to_string(cells) + ")");
      }
      return;
    }
    case MeshSource::file:
      if (mesh.file.empty()) throw SceneError("mesh.file", "must not be empty");
      return;
    case MeshSource::segmentation: {
      const SegmentationSpec& g = mesh.segmentation;
      if (g.file.empty()) throw SceneError("mesh.segmentation.file", "must not be empty");
      if (g.tissues.empty())
        throw SceneError("mesh.segmentation.labels", "must name at least one tissue");
      require_positive("mesh.segmentation.cell_size", g.cell_size);
      return;
    }
    case MeshSource::generate: {
      const GenerateSpec& g = mesh.generate;
      if (g.shape != "sphere" && g.shape != "ellipsoid" && g.shape != "liver") {
        throw SceneError("mesh.generate.shape",
                         "unknown shape \"" + g.shape + "\" (expected: sphere, ellipsoid, liver)");
      }
      require_finite("mesh.generate.centre", g.centre);
      for (int a = 0; a < 3; ++a)
        require_positive(element("mesh.generate.radii", static_cast<std::size_t>(a)), g.radii(a));
      require_positive("mesh.generate.cell_size", g.cell_size);
      // The same guard as kMaxBoxCells: about (radius / cell_size)^3 tets.
      if (g.radii.maxCoeff() / g.cell_size > 200) {
        throw SceneError("mesh.generate.cell_size",
                         "is too small for the shape (at most 1/200 of "
                         "its largest radius)");
      }
      return;
    }
  }
}

const char* integrator_name(Integrator integrator) {
  switch (integrator) {
    case Integrator::symplectic_euler:
      return "symplectic_euler";
    case Integrator::central_difference:
      return "central_difference";
    case Integrator::adaptive_explicit:
      return "adaptive_explicit";
    case Integrator::implicit_euler:
      return "implicit_euler";
    case Integrator::static_equilibrium:
      break;
  }
  return "static";
}

// Called after everything else is valid (the wave speed needs valid materials).
void validate_adaptivity(const Scene& scene) {
  const AdaptivitySpec& a = *scene.adaptivity;
  if (a.l_min != 0 && a.dt_min != 0) {
    throw SceneError("adaptivity", "has both \"l_min\" and \"dt_min\" (give one)");
  }
  if (a.dt_min != 0) {
    require_positive("adaptivity.dt_min", a.dt_min);
  } else {
    require_positive("adaptivity.l_min", a.l_min);
  }
  require_positive("adaptivity.fine_size", a.fine_size);
  require_finite("adaptivity.quality", a.quality);
  if (!(a.quality > 1)) {
    throw SceneError("adaptivity.quality",
                     "must be above 1 (got " + format_number(a.quality) + ")");
  }
  if (a.every < 1) {
    throw SceneError("adaptivity.every",
                     "must be at least 1 (got " + std::to_string(a.every) + ")");
  }
  if (!a.strain && !a.curvature) {
    throw SceneError("adaptivity", "needs at least one criterion: \"strain\" or \"curvature\"");
  }
  if (a.strain) {
    require_positive("adaptivity.strain.off", a.strain_off);
    require_finite("adaptivity.strain.on", a.strain_on);
    if (!(a.strain_off < a.strain_on)) {
      throw SceneError("adaptivity.strain", "off must be below on (got off " +
                                                format_number(a.strain_off) + ", on " +
                                                format_number(a.strain_on) + ")");
    }
  }
  if (a.curvature) {
    require_positive("adaptivity.curvature.off_degrees", a.bend_off_degrees);
    if (!(a.bend_on_degrees <= 180)) {
      throw SceneError("adaptivity.curvature.on_degrees",
                       "must be at most 180 (got " + format_number(a.bend_on_degrees) + ")");
    }
    if (!(a.bend_off_degrees < a.bend_on_degrees)) {
      throw SceneError("adaptivity.curvature", "off_degrees must be below on_degrees (got off " +
                                                   format_number(a.bend_off_degrees) + ", on " +
                                                   format_number(a.bend_on_degrees) + ")");
    }
  }
  if (a.keep_margin) {
    require_finite("adaptivity.keep_margin", *a.keep_margin);
    if (!(*a.keep_margin >= 0)) {
      throw SceneError("adaptivity.keep_margin",
                       "must not be negative (got " + format_number(*a.keep_margin) + ")");
    }
  }
  if (scene.solver.integrator != Integrator::symplectic_euler) {
    throw SceneError("adaptivity",
                     std::string("needs solver.integrator \"symplectic_euler\" (got \"") +
                         integrator_name(scene.solver.integrator) + "\")");
  }
  // The remesher holds a vertex by its rest point (every new vertex in a clamp is clamped too);
  // it has no per-axis or moving constraints.
  for (std::size_t c = 0; c < scene.constraints.size(); ++c) {
    const Constraint& constraint = scene.constraints[c];
    const bool all_axes = constraint.axes[0] && constraint.axes[1] && constraint.axes[2];
    if (!all_axes || constraint.displacement != Vec3::Zero()) {
      throw SceneError(
          element("constraints", c),
          std::string("with adaptivity a constraint must be \"fix\": \"xyz\" (this "
                      "one ") +
              (constraint.displacement != Vec3::Zero() ? "displaces" : "frees an axis") + ")");
    }
  }
  // The floor's promise: no element refinement creates needs a step below dt_min, so the run's
  // step must not exceed it (l_min = dt_min c / safety, stable_time_step.h).
  const Real c = fastest_wave_speed(scene);
  const Real dt_min = a.dt_min != 0 ? a.dt_min : kExplicitSafety * a.l_min / c;
  if (scene.solver.dt > dt_min) {
    const std::string key = a.dt_min != 0 ? "adaptivity.dt_min" : "adaptivity.l_min";
    throw SceneError(key, "refined tets are stable down to dt_min = " + format_number(dt_min) +
                              " s only, below solver.dt = " + format_number(scene.solver.dt) +
                              " s (give a larger " + (a.dt_min != 0 ? "dt_min" : "l_min") +
                              " or a smaller dt)");
  }
}

}  // namespace

void validate_scene(const Scene& scene) {
  validate_mesh(scene.mesh);
  validate_material("material", scene.material);
  for (const auto& [label, material] : scene.materials_by_label)
    validate_material("materials." + std::to_string(label), material);
  if (!(scene.solver.tolerance > 0 && scene.solver.tolerance < 1)) {
    throw SceneError("solver.tolerance",
                     "must be in (0, 1) (got " + format_number(scene.solver.tolerance) + ")");
  }

  for (std::size_t c = 0; c < scene.constraints.size(); ++c) {
    const Constraint& constraint = scene.constraints[c];
    const std::string path = element("constraints", c);
    validate_selection(path + ".where", constraint.where);
    require_finite(path + ".displace", constraint.displacement);
    if (!constraint.axes[0] && !constraint.axes[1] && !constraint.axes[2]) {
      throw SceneError(path, "constrains no axis");
    }
  }
  for (std::size_t l = 0; l < scene.loads.size(); ++l) {
    const std::string path = element("loads", l);
    validate_selection(path + ".where", scene.loads[l].where);
    require_finite(path + ".force", scene.loads[l].force);
  }
  require_finite("gravity", scene.gravity);

  if (scene.tool) {
    require_positive("tool.radius", scene.tool->radius);
    require_positive("tool.stiffness", scene.tool->stiffness);
    require_finite("tool.damping", scene.tool->damping);
    if (!(scene.tool->damping >= 0)) {
      throw SceneError("tool.damping",
                       "must not be negative (got " + format_number(scene.tool->damping) + ")");
    }
  }
  if (scene.view) validate_view(*scene.view);

  require_positive("solver.dt", scene.solver.dt);
  if (scene.solver.steps < 1) {
    throw SceneError("solver.steps",
                     "must be at least 1 (got " + std::to_string(scene.solver.steps) + ")");
  }
  if (scene.adaptivity) validate_adaptivity(scene);
}

Real fastest_wave_speed(const Scene& scene) {
  Real c = p_wave_speed(scene.material.youngs_modulus, scene.material.poisson_ratio,
                        scene.material.density);
  for (const auto& [label, m] : scene.materials_by_label)
    c = std::max(c, p_wave_speed(m.youngs_modulus, m.poisson_ratio, m.density));
  return c;
}

}  // namespace incise::sim
