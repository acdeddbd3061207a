#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "sim/render/camera.h"
#include "sim/render/frame_encoder.h"
#include "sim/render/framebuffer.h"
#include "sim/render/gl_mesh.h"
#include "sim/render/shader_program.h"

namespace incise::render {

// The tissue surface at one instant, world coordinates [m]. All three null: no tissue (and then
// no floor either). The matrices are read during render() only and may change between frames.
struct TissueView {
  const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>* V =
      nullptr;  // #V by 3 positions
  const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>* N =
      nullptr;  // #V by 3 unit normals
  const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>* F =
      nullptr;  // #F by 3 indices into V
};

// The tool: a sphere at the tip and a cylindrical shaft leaving it.
struct ToolView {
  Eigen::Vector3d tip{0, 0, 0};              // sphere centre [m]
  double radius = 0.005;                     // [m], > 0
  Eigen::Vector3d shaft_direction{0, 0, 1};  // from the tip back along the shaft, non-zero
  double shaft_length = 0.15;                // [m], >= 0 (0: no shaft)
  double shaft_radius = 0.0025;              // [m], > 0
  bool in_contact = false;                   // drawn in SceneStyle::tool_in_contact when true
};

// A mark drawn on the tissue, e.g. a dot of the line a surgeon marks to cut along: a small sphere
// in SceneStyle::marker.
struct MarkView {
  Eigen::Vector3d centre{0, 0, 0};  // [m], finite
  double radius = 0.0015;           // [m], > 0
};

// How one kind of surface looks under the scene's light (see SceneStyle for the formula).
struct SurfaceLook {
  Eigen::Vector3f albedo;  // linear RGB in [0, 1]
  float specular = 0.0f;   // strength of the highlight, 0 for matte
  float shininess = 1.0f;  // Blinn-Phong exponent, > 0
};

// Colours, light and floor placement of a scene. Every lit pixel is
//   colour = clamp(albedo * (ambient + diffuse * max(0, n.l)) + specular * s, 0, 1),
//   s = max(0, n.h)^shininess if n.l > 0, else 0,
// with l = to_light / |to_light|, v the unit direction from the surface point to the camera,
// h = (l + v) / |l + v| and n the interpolated, renormalised vertex normal, turned round if it
// points away from the side of the triangle the camera sees (so that both sides of the tissue
// and of cut surfaces are lit alike). No gamma curve: values go to the 8-bit target as they are.
struct SceneStyle {
  Eigen::Vector3d up{0.0, 0.0, 1.0};         // world up (the scenes' gravity points along -z)
  Eigen::Vector3d to_light{0.4, -0.3, 1.0};  // directional light, towards the light, non-zero
  float ambient = 0.25f;
  float diffuse = 0.75f;
  // Backdrop: a vertical gradient from the top row of the image to the bottom row.
  Eigen::Vector3f backdrop_top{0.30f, 0.34f, 0.40f};
  Eigen::Vector3f backdrop_bottom{0.08f, 0.09f, 0.11f};
  SurfaceLook tissue{{0.80f, 0.45f, 0.40f}, 0.15f, 24.0f};
  SurfaceLook tool{{0.62f, 0.65f, 0.70f}, 0.45f, 48.0f};
  SurfaceLook tool_in_contact{{0.95f, 0.72f, 0.15f}, 0.45f, 48.0f};
  SurfaceLook floor{{0.30f, 0.31f, 0.30f}, 0.0f, 1.0f};
  SurfaceLook marker{{0.30f, 0.12f, 0.55f}, 0.0f, 1.0f};  // a surgical skin marker's violet
  // The floor is a square perpendicular to up, floor_gap below the tissue's lowest point (along
  // up) and centred under the tissue's bounding box, floor_half_size from centre to each edge.
  double floor_gap = 0.001;      // [m], >= 0
  double floor_half_size = 0.5;  // [m], > 0
};

// Draws a live scene: backdrop, floor, tissue and tool. One per render thread; needs a current
// EglContext for its whole life and must be destroyed before it.
//
// The tissue's positions and normals are uploaded every frame into buffers that are reallocated
// only when the vertex count changes; its faces are compared with the previous frame's and
// uploaded only when they differ (topology changes are rare).
class SceneRenderer {
 public:
  // Compiles the shaders and builds the fixed shapes. Throws RenderError if a shader does not
  // build, std::invalid_argument for a style outside the ranges above.
  explicit SceneRenderer(const SceneStyle& style = {});
  ~SceneRenderer();
  SceneRenderer(const SceneRenderer&) = delete;
  SceneRenderer& operator=(const SceneRenderer&) = delete;

  // The style as given, with up and to_light normalised.
  const SceneStyle& style() const { return style_; }

  // Draws backdrop, floor, tissue and tool seen from camera into target (aspect from the
  // target's size), overwriting all of it. Returns once the commands are issued; reading the
  // target back waits for them.
  // Throws std::invalid_argument, before drawing anything, for an invalid camera, tissue (only
  // some of V, N, F given, N's rows differing from V's, a face index outside [0, #V), a
  // non-finite position) or tool (non-positive radius or shaft radius, negative shaft length,
  // zero shaft direction, non-finite tip).
  void render(const Framebuffer& target, const Camera& camera, const TissueView& tissue,
              const ToolView& tool);
  // The same with any number of tools (a two-handed station's) and marks on the tissue; every
  // one is validated first (a mark: finite centre, positive radius).
  void render(const Framebuffer& target, const Camera& camera, const TissueView& tissue,
              std::span<const ToolView> tools, std::span<const MarkView> marks = {});

 private:
  // Validates and uploads the tissue; returns false when there is none.
  bool upload_tissue(const TissueView& tissue);
  void draw_lit(const GlMesh& mesh, const Eigen::Affine3d& model, const SurfaceLook& look) const;
  void draw_tool(const ToolView& tool) const;

  SceneStyle style_;
  ShaderProgram backdrop_program_;
  int backdrop_top_location_;
  int backdrop_bottom_location_;
  ShaderProgram lit_program_;
  int view_projection_location_;
  int model_location_;
  int normal_matrix_location_;
  int eye_location_;
  int to_light_location_;
  int ambient_location_;
  int diffuse_location_;
  int albedo_location_;
  int specular_location_;
  int shininess_location_;

  unsigned int empty_vertex_array_ = 0;  // the backdrop's triangle comes from gl_VertexID alone
  GlMesh sphere_;
  GlMesh cylinder_;
  GlMesh square_;
  GlMesh tissue_;
  // The tissue as last uploaded, kept so that frames reuse memory and unchanged faces are not
  // sent again.
  std::vector<float> tissue_vertices_;
  std::vector<std::uint32_t> tissue_indices_;
  Eigen::Vector3d tissue_min_ = Eigen::Vector3d::Zero();  // bounding box of the last tissue
  Eigen::Vector3d tissue_max_ = Eigen::Vector3d::Zero();
  double tissue_lowest_ = 0.0;  // min over vertices of up . position [m]
};

}  // namespace incise::render
