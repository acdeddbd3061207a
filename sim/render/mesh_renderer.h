#pragma once

#include <Eigen/Core>

#include "sim/render/camera.h"
#include "sim/render/framebuffer.h"
#include "sim/render/gl_mesh.h"
#include "sim/render/shader_program.h"

namespace incise::render {

// How a surface is lit: one directional light plus ambient, Lambert's cosine law. Each pixel is
//   colour = clamp(albedo * (ambient + diffuse * max(0, dot(n, l))), 0, 1)
// with n the interpolated, renormalised vertex normal and l = to_light / |to_light|, written to the
// 8-bit target unchanged (no gamma curve).
struct Shading {
  Eigen::Vector3f albedo{0.80f, 0.45f, 0.40f};      // surface colour, linear RGB in [0, 1]
  Eigen::Vector3d to_light{0.3, 0.5, 1.0};          // world direction towards the light, non-zero
  float ambient = 0.25f;                            // light reaching every surface
  float diffuse = 0.75f;                            // light at normal incidence
  Eigen::Vector3f background{0.08f, 0.09f, 0.11f};  // clear colour, linear RGB in [0, 1]
};

// Draws one triangle surface (e.g. the boundary of a tissue mesh) into a Framebuffer. Faces are
// not culled, so cut surfaces stay visible from both sides; depth testing orders them.
// Needs a current EglContext for its whole life.
class MeshRenderer {
 public:
  MeshRenderer();  // compiles the shader; throws RenderError if it does not build
  MeshRenderer(const MeshRenderer&) = delete;
  MeshRenderer& operator=(const MeshRenderer&) = delete;

  // Uploads the surface, replacing the previous one.
  //   V  #V by 3 vertex positions [m], world coordinates
  //   N  #V by 3 vertex normals, non-zero (renormalised per pixel)
  //   F  #F by 3 vertex indices into V
  // Throws std::invalid_argument if the shapes disagree or an index is outside [0, #V).
  void set_mesh(const Eigen::MatrixXd& V, const Eigen::MatrixXd& N, const Eigen::MatrixXi& F);

  // Clears target to shading.background and draws the surface seen from camera; the image aspect
  // is the target's. Throws std::invalid_argument for an invalid camera or a zero to_light.
  void render(const Framebuffer& target, const Camera& camera, const Shading& shading) const;

 private:
  ShaderProgram program_;
  int view_projection_location_;
  int albedo_location_;
  int to_light_location_;
  int ambient_location_;
  int diffuse_location_;
  GlMesh mesh_;
};

}  // namespace incise::render
