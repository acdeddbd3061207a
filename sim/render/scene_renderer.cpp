#include "sim/render/scene_renderer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "sim/render/gl_api.h"
#include "sim/render/primitives.h"

namespace incise::render {
namespace {

// One triangle that covers the viewport, from gl_VertexID alone; height is 0 at the bottom edge
// and 1 at the top, so that pixel row y (0 = top) of an H-row image gets
// mix(bottom, top, 1 - (y + 0.5) / H). It lies on the far plane (depth 1, the cleared value) and
// is drawn last with GL_LEQUAL, so it fills only the pixels nothing else covered: llvmpipe then
// shades each pixel about once, not twice where the floor fills the view.
constexpr const char* backdrop_vertex_source = R"(#version 330 core
out float height;
void main() {
  vec2 corner = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
  height = 0.5 * (corner.y + 1.0);
  gl_Position = vec4(corner, 1.0, 1.0);
}
)";

constexpr const char* backdrop_fragment_source = R"(#version 330 core
in float height;
uniform vec3 top_colour;
uniform vec3 bottom_colour;
out vec4 colour;
void main() {
  colour = vec4(mix(bottom_colour, top_colour, height), 1.0);
}
)";

constexpr const char* lit_vertex_source = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
uniform mat4 model;
uniform mat3 normal_matrix;
uniform mat4 view_projection;
out vec3 world_position;
out vec3 world_normal;
void main() {
  vec4 world = model * vec4(position, 1.0);
  world_position = world.xyz;
  world_normal = normal_matrix * normal;
  gl_Position = view_projection * world;
}
)";

// The formula documented on SceneStyle. The triangle's own normal, from the screen-space
// derivatives of the position, tells which side the camera sees; testing the interpolated
// normal against the view direction instead would flip it wrongly near silhouettes.
constexpr const char* lit_fragment_source = R"(#version 330 core
in vec3 world_position;
in vec3 world_normal;
uniform vec3 eye;
uniform vec3 to_light;
uniform float ambient;
uniform float diffuse;
uniform vec3 albedo;
uniform float specular;
uniform float shininess;
out vec4 colour;
void main() {
  vec3 v = normalize(eye - world_position);
  vec3 face = cross(dFdx(world_position), dFdy(world_position));
  if (dot(face, v) < 0.0) face = -face;
  vec3 n = normalize(world_normal);
  if (dot(n, face) < 0.0) n = -n;
  float lambert = max(dot(n, to_light), 0.0);
  float highlight = 0.0;
  if (lambert > 0.0) highlight = pow(max(dot(n, normalize(to_light + v)), 0.0), shininess);
  colour = vec4(clamp(albedo * (ambient + diffuse * lambert) + specular * highlight, 0.0, 1.0),
                1.0);
}
)";

// Tessellation of the tool: fine enough that its outline looks round at a few hundred pixels
// across, cheap next to the tissue.
constexpr int sphere_slices = 32;
constexpr int sphere_stacks = 16;
constexpr int cylinder_slices = 24;

void upload(GlMesh& mesh, const ShapeMesh& shape) {
  mesh.set_vertices(shape.vertices);
  mesh.set_indices(shape.indices);
}

// Two unit vectors completing unit vector w to a right-handed orthonormal basis (u, v, w).
void complete_basis(const Eigen::Vector3d& w, Eigen::Vector3d& u, Eigen::Vector3d& v) {
  const Eigen::Vector3d helper =
      std::abs(w.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  u = helper.cross(w).normalized();
  v = w.cross(u);
}

void validate_look(const SurfaceLook& look, const char* name) {
  if (!(look.shininess > 0.0f)) {
    throw std::invalid_argument(std::string("scene style ") + name + ".shininess must be positive");
  }
}

SceneStyle normalised(SceneStyle style) {
  if (style.up.norm() == 0.0) throw std::invalid_argument("scene style up is zero");
  if (style.to_light.norm() == 0.0) throw std::invalid_argument("scene style to_light is zero");
  if (!(style.floor_gap >= 0.0)) {
    throw std::invalid_argument("scene style floor_gap must be >= 0");
  }
  if (!(style.floor_half_size > 0.0)) {
    throw std::invalid_argument("scene style floor_half_size must be positive");
  }
  validate_look(style.tissue, "tissue");
  validate_look(style.tool, "tool");
  validate_look(style.tool_in_contact, "tool_in_contact");
  validate_look(style.floor, "floor");
  validate_look(style.marker, "marker");
  style.up.normalize();
  style.to_light.normalize();
  return style;
}

void validate_tool(const ToolView& tool) {
  if (!tool.tip.allFinite()) throw std::invalid_argument("tool tip is not finite");
  if (!(tool.radius > 0.0)) throw std::invalid_argument("tool radius must be positive");
  if (!(tool.shaft_radius > 0.0)) throw std::invalid_argument("tool shaft_radius must be positive");
  if (!(tool.shaft_length >= 0.0)) throw std::invalid_argument("tool shaft_length must be >= 0");
  if (!(tool.shaft_direction.norm() > 0.0) || !tool.shaft_direction.allFinite()) {
    throw std::invalid_argument("tool shaft_direction must be non-zero and finite");
  }
}

}  // namespace

SceneRenderer::SceneRenderer(const SceneStyle& style)
    : style_(normalised(style)),
      backdrop_program_(backdrop_vertex_source, backdrop_fragment_source),
      backdrop_top_location_(backdrop_program_.uniform_location("top_colour")),
      backdrop_bottom_location_(backdrop_program_.uniform_location("bottom_colour")),
      lit_program_(lit_vertex_source, lit_fragment_source),
      view_projection_location_(lit_program_.uniform_location("view_projection")),
      model_location_(lit_program_.uniform_location("model")),
      normal_matrix_location_(lit_program_.uniform_location("normal_matrix")),
      eye_location_(lit_program_.uniform_location("eye")),
      to_light_location_(lit_program_.uniform_location("to_light")),
      ambient_location_(lit_program_.uniform_location("ambient")),
      diffuse_location_(lit_program_.uniform_location("diffuse")),
      albedo_location_(lit_program_.uniform_location("albedo")),
      specular_location_(lit_program_.uniform_location("specular")),
      shininess_location_(lit_program_.uniform_location("shininess")) {
  glGenVertexArrays(1, &empty_vertex_array_);
  upload(sphere_, unit_sphere(sphere_slices, sphere_stacks));
  upload(cylinder_, unit_cylinder(cylinder_slices));
  upload(square_, unit_square());
}

SceneRenderer::~SceneRenderer() {
  glDeleteVertexArrays(1, &empty_vertex_array_);
}

bool SceneRenderer::upload_tissue(const TissueView& tissue) {
  const int given = (tissue.V != nullptr) + (tissue.N != nullptr) + (tissue.F != nullptr);
  if (given == 0) return false;
  if (given != 3) throw std::invalid_argument("tissue needs all of V, N and F, or none");
  const auto& V = *tissue.V;
  const auto& N = *tissue.N;
  const auto& F = *tissue.F;
  if (N.rows() != V.rows()) {
    throw std::invalid_argument("tissue has " + std::to_string(V.rows()) + " vertices but " +
                                std::to_string(N.rows()) + " normals");
  }
  if (V.rows() == 0) return false;

  // Validate all faces before touching the cached ones, so that a rejected frame leaves the
  // cache equal to what the GPU holds.
  const auto vertex_count = static_cast<std::uint32_t>(V.rows());
  bool faces_changed = static_cast<std::size_t>(F.size()) != tissue_indices_.size();
  const int* face_data = F.data();
  for (Eigen::Index i = 0; i < F.size(); ++i) {
    const int index = face_data[i];
    if (index < 0 || static_cast<std::uint32_t>(index) >= vertex_count) {
      throw std::invalid_argument("tissue face " + std::to_string(i / 3) + " has vertex index " +
                                  std::to_string(index) + " outside [0, " +
                                  std::to_string(vertex_count) + ")");
    }
    if (!faces_changed && tissue_indices_[i] != static_cast<std::uint32_t>(index)) {
      faces_changed = true;
    }
  }

  tissue_vertices_.resize(static_cast<std::size_t>(V.rows()) * GlMesh::floats_per_vertex);
  Eigen::Vector3d low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d high = -low;
  double lowest = std::numeric_limits<double>::infinity();
  float* out = tissue_vertices_.data();
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    const Eigen::Vector3d p = V.row(v).transpose();
    if (!p.allFinite()) {
      throw std::invalid_argument("tissue vertex " + std::to_string(v) +
                                  " has a non-finite position");
    }
    low = low.cwiseMin(p);
    high = high.cwiseMax(p);
    lowest = std::min(lowest, style_.up.dot(p));
    for (int k = 0; k < 3; ++k) {
      out[k] = static_cast<float>(p[k]);
      out[3 + k] = static_cast<float>(N(v, k));
    }
    out += GlMesh::floats_per_vertex;
  }
  tissue_min_ = low;
  tissue_max_ = high;
  tissue_lowest_ = lowest;

  tissue_.set_vertices(tissue_vertices_);
  if (faces_changed) {
    tissue_indices_.assign(face_data, face_data + F.size());
    tissue_.set_indices(tissue_indices_);
  }
  return true;
}

void SceneRenderer::draw_lit(const GlMesh& mesh, const Eigen::Affine3d& model,
                             const SurfaceLook& look) const {
  const Eigen::Matrix4f model_matrix = model.matrix().cast<float>();
  // Normals transform with the inverse transpose, which differs from the rotation when the
  // model scales unevenly (the shaft: radius across, length along).
  const Eigen::Matrix3f normal_matrix = model.linear().inverse().transpose().cast<float>();
  glUniformMatrix4fv(model_location_, 1, GL_FALSE, model_matrix.data());
  glUniformMatrix3fv(normal_matrix_location_, 1, GL_FALSE, normal_matrix.data());
  glUniform3fv(albedo_location_, 1, look.albedo.data());
  glUniform1f(specular_location_, look.specular);
  glUniform1f(shininess_location_, look.shininess);
  mesh.draw();
}

void SceneRenderer::render(const Framebuffer& target, const Camera& camera,
                           const TissueView& tissue, const ToolView& tool) {
  render(target, camera, tissue, std::span<const ToolView>(&tool, 1));
}

void SceneRenderer::draw_tool(const ToolView& tool) const {
  const SurfaceLook& tool_look = tool.in_contact ? style_.tool_in_contact : style_.tool;
  Eigen::Affine3d sphere = Eigen::Affine3d::Identity();
  sphere.translate(tool.tip).scale(tool.radius);
  draw_lit(sphere_, sphere, tool_look);
  if (tool.shaft_length > 0.0) {
    // The unit cylinder's z axis becomes the shaft, starting at the tip's centre.
    Eigen::Matrix3d axes;
    Eigen::Vector3d across_1, across_2;
    const Eigen::Vector3d along = tool.shaft_direction.normalized();
    complete_basis(along, across_1, across_2);
    axes << across_1 * tool.shaft_radius, across_2 * tool.shaft_radius, along * tool.shaft_length;
    Eigen::Affine3d shaft = Eigen::Affine3d::Identity();
    shaft.translate(tool.tip);
    shaft.linear() = axes;
    draw_lit(cylinder_, shaft, tool_look);
  }
}

void SceneRenderer::render(const Framebuffer& target, const Camera& camera,
                           const TissueView& tissue, std::span<const ToolView> tools,
                           std::span<const MarkView> marks) {
  const double aspect = static_cast<double>(target.width()) / target.height();
  // Eigen stores column-major, as GL expects without transposing.
  const Eigen::Matrix4f view_projection =
      (projection_matrix(camera, aspect) * view_matrix(camera)).cast<float>();
  for (const ToolView& tool : tools)
    validate_tool(tool);
  for (const MarkView& mark : marks) {
    if (!mark.centre.allFinite() || !(mark.radius > 0.0)) {
      throw std::invalid_argument("a mark needs a finite centre and a positive radius");
    }
  }
  const bool has_tissue = upload_tissue(tissue);

  target.bind();
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);
  glClearDepth(1.0);
  glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  lit_program_.use();
  const Eigen::Vector3f eye = camera.eye.cast<float>();
  const Eigen::Vector3f to_light = style_.to_light.cast<float>();
  glUniformMatrix4fv(view_projection_location_, 1, GL_FALSE, view_projection.data());
  glUniform3fv(eye_location_, 1, eye.data());
  glUniform3fv(to_light_location_, 1, to_light.data());
  glUniform1f(ambient_location_, style_.ambient);
  glUniform1f(diffuse_location_, style_.diffuse);

  // Nearest first, so that the depth test spares shading hidden pixels of the larger shapes.
  for (const ToolView& tool : tools)
    draw_tool(tool);
  for (const MarkView& mark : marks) {
    Eigen::Affine3d sphere = Eigen::Affine3d::Identity();
    sphere.translate(mark.centre).scale(mark.radius);
    draw_lit(sphere_, sphere, style_.marker);
  }

  if (has_tissue) {
    draw_lit(tissue_, Eigen::Affine3d::Identity(), style_.tissue);

    // The unit square's plane z = 0 becomes the floor plane, its normal +z becomes up.
    const Eigen::Vector3d& up = style_.up;
    Eigen::Vector3d across_1, across_2;
    complete_basis(up, across_1, across_2);
    const Eigen::Vector3d centre = 0.5 * (tissue_min_ + tissue_max_);
    const double floor_height = tissue_lowest_ - style_.floor_gap;
    Eigen::Matrix3d axes;
    axes << across_1 * style_.floor_half_size, across_2 * style_.floor_half_size, up;
    Eigen::Affine3d floor = Eigen::Affine3d::Identity();
    floor.translate(centre + (floor_height - up.dot(centre)) * up);
    floor.linear() = axes;
    draw_lit(square_, floor, style_.floor);
  }

  // Backdrop last, only where nothing else was drawn (see backdrop_vertex_source).
  glDepthFunc(GL_LEQUAL);
  glDepthMask(GL_FALSE);
  backdrop_program_.use();
  glUniform3fv(backdrop_top_location_, 1, style_.backdrop_top.data());
  glUniform3fv(backdrop_bottom_location_, 1, style_.backdrop_bottom.data());
  glBindVertexArray(empty_vertex_array_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glDepthMask(GL_TRUE);
  glDepthFunc(GL_LESS);
}

}  // namespace incise::render
