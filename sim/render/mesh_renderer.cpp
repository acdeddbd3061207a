#include "sim/render/mesh_renderer.h"

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/render/gl_api.h"

namespace incise::render {
namespace {

constexpr const char* vertex_source = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
uniform mat4 view_projection;
out vec3 world_normal;
void main() {
  world_normal = normal;
  gl_Position = view_projection * vec4(position, 1.0);
}
)";

// The Lambert + ambient formula documented on Shading.
constexpr const char* fragment_source = R"(#version 330 core
in vec3 world_normal;
uniform vec3 albedo;
uniform vec3 to_light;
uniform float ambient;
uniform float diffuse;
out vec4 colour;
void main() {
  float lambert = max(dot(normalize(world_normal), to_light), 0.0);
  colour = vec4(clamp(albedo * (ambient + diffuse * lambert), 0.0, 1.0), 1.0);
}
)";

constexpr int floats_per_vertex = GlMesh::floats_per_vertex;  // position xyz, normal xyz

}  // namespace

MeshRenderer::MeshRenderer()
    : program_(vertex_source, fragment_source),
      view_projection_location_(program_.uniform_location("view_projection")),
      albedo_location_(program_.uniform_location("albedo")),
      to_light_location_(program_.uniform_location("to_light")),
      ambient_location_(program_.uniform_location("ambient")),
      diffuse_location_(program_.uniform_location("diffuse")) {}

void MeshRenderer::set_mesh(const Eigen::MatrixXd& V, const Eigen::MatrixXd& N,
                            const Eigen::MatrixXi& F) {
  if (V.cols() != 3 || N.cols() != 3 || F.cols() != 3) {
    throw std::invalid_argument("mesh V, N and F must have 3 columns");
  }
  if (N.rows() != V.rows()) {
    throw std::invalid_argument("mesh has " + std::to_string(V.rows()) + " vertices but " +
                                std::to_string(N.rows()) + " normals");
  }
  if (F.size() > 0 && (F.minCoeff() < 0 || F.maxCoeff() >= V.rows())) {
    throw std::invalid_argument("mesh face index outside [0, " + std::to_string(V.rows()) + ")");
  }

  std::vector<float> vertices(V.rows() * floats_per_vertex);
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    for (int k = 0; k < 3; ++k) {
      vertices[v * floats_per_vertex + k] = static_cast<float>(V(v, k));
      vertices[v * floats_per_vertex + 3 + k] = static_cast<float>(N(v, k));
    }
  }
  std::vector<std::uint32_t> indices(F.size());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k)
      indices[f * 3 + k] = static_cast<std::uint32_t>(F(f, k));
  }

  mesh_.set_vertices(vertices);
  mesh_.set_indices(indices);
}

void MeshRenderer::render(const Framebuffer& target, const Camera& camera,
                          const Shading& shading) const {
  const double aspect = static_cast<double>(target.width()) / target.height();
  const Eigen::Matrix4f view_projection =
      (projection_matrix(camera, aspect) * view_matrix(camera)).cast<float>();
  if (shading.to_light.norm() == 0.0) throw std::invalid_argument("shading to_light is zero");
  const Eigen::Vector3f to_light = shading.to_light.normalized().cast<float>();

  target.clear(shading.background);
  if (mesh_.index_count() == 0) return;

  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);
  program_.use();
  // Eigen stores column-major, as GL expects without transposing.
  glUniformMatrix4fv(view_projection_location_, 1, GL_FALSE, view_projection.data());
  glUniform3fv(albedo_location_, 1, shading.albedo.data());
  glUniform3fv(to_light_location_, 1, to_light.data());
  glUniform1f(ambient_location_, shading.ambient);
  glUniform1f(diffuse_location_, shading.diffuse);
  mesh_.draw();
}

}  // namespace incise::render
