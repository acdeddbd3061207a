#pragma once

#include <cstdint>
#include <limits>
#include <map>
#include <memory>
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
  // Per face, non-zero for a wall a cut opened (drawn in SceneStyle::cut_wall); null or empty:
  // none. Its size must be #F otherwise.
  const std::vector<std::uint8_t>* cut_faces = nullptr;
  // Per face, the tissue label of its tet: a face of a label in SceneStyle::tissue_by_label is
  // drawn in that look, any other in SceneStyle::tissue. Null or empty: all in tissue. Its size
  // must be #F otherwise.
  const std::vector<std::uint8_t>* face_labels = nullptr;
  // #V by 3: each vertex's rest position [m], to which the looks' vessel patterns are fixed, so
  // that they move with the tissue rather than swim over it. Null: the current positions V.
  const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>* rest = nullptr;
};

// A tool's working end. The pose drawn is the pose simulated (sim/surgery/surgical_scene.h's tool
// frame): the tool points along d = -shaft_direction, and side is R e_x.
enum class ToolShape {
  probe,    // a sphere of `radius` centred at the tip
  scalpel,  // a blade: its edge runs from the tip back along the shaft for blade_length, its flat
            // faces +-side, its body rises from the edge along shaft_direction x side
  grasper,  // two jaws from the hinge at the tip, jaw_angle apart, opening symmetrically about d
            // in the plane of d and side
};

// A tool: its working end at the tip and a cylindrical shaft leaving it (behind the blade, for a
// scalpel).
struct ToolView {
  Eigen::Vector3d tip{0, 0, 0};              // [m]: a probe's sphere centre, a grasper's hinge
  double radius = 0.005;                     // the probe's sphere [m], > 0
  Eigen::Vector3d shaft_direction{0, 0, 1};  // from the tip back along the shaft, non-zero
  double shaft_length = 0.15;                // [m], >= 0 (0: no shaft)
  double shaft_radius = 0.0025;              // [m], > 0
  bool in_contact = false;                   // drawn in SceneStyle::tool_in_contact when true
  ToolShape shape = ToolShape::probe;
  // R e_x: the grasper's opening plane and the blade's flat; only its part orthogonal to the
  // shaft is used, which must not vanish for a scalpel or grasper.
  Eigen::Vector3d side{1, 0, 0};
  double jaw_angle = 0;        // grasper: the angle between the jaws [rad], in [0, pi)
  double jaw_length = 0.01;    // grasper: hinge to jaw tip [m], > 0
  double blade_length = 0.01;  // scalpel [m], > 0
};

// What a mark shows: the ink of a marked line (an opaque dot), or a task's zone, drawn as a
// translucent ball (SceneStyle::zone_opacity) so that the tissue shows through it.
enum class MarkKind {
  ink,             // SceneStyle::marker
  target,          // a landmark to reach: SceneStyle::target
  protected_zone,  // a structure to keep off: SceneStyle::protected_zone
  never_zone,      // one never to touch: SceneStyle::never_zone
};

// A mark in the scene, e.g. a dot of the line a surgeon marks to cut along (a small sphere in
// SceneStyle::marker), or a task's target or protected zone.
struct MarkView {
  Eigen::Vector3d centre{0, 0, 0};  // [m], finite
  double radius = 0.0015;           // [m], > 0
  MarkKind kind = MarkKind::ink;
};

// How one kind of surface looks under the scene's light (see SceneStyle for the formula).
struct SurfaceLook {
  Eigen::Vector3f albedo;  // linear RGB in [0, 1]
  float specular = 0.0f;   // strength of the highlight, 0 for matte
  float shininess = 1.0f;  // Blinn-Phong exponent, > 0
  // A procedural pattern of vessels: the albedo becomes mix(albedo, vessel_albedo, vessels * w),
  // w in [0, 1] the weight of a winding network of vessels of varying calibre, vessel_spacing_m
  // apart on average, with patches of finer capillaries between them, a function of the rest
  // position (TissueView::rest; a surrounding's own position), antialiased and faded out where
  // its lines are thinner than a pixel. vessels in [0, 1], 0: none (and no cost).
  float vessels = 0.0f;
  float vessel_spacing_m = 0.01f;  // > 0
  Eigen::Vector3f vessel_albedo{0.42f, 0.04f, 0.06f};
};

// A surface that does not move (a bone, the cavity's wall, a neighbouring organ), world
// coordinates [m]. Read by set_surroundings only.
struct StaticSurface {
  const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>* V = nullptr;  // #V by 3
  const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>* F = nullptr;     // into V
  SurfaceLook look;
  // Drawn only under a Camera::headlight (the scope, inside the body): a cavity's wall.
  bool inside_only = false;
};

// Colours, light and floor placement of a scene. Every lit pixel is
//   colour = clamp(albedo * (ambient + a diffuse * max(0, n.l)) + a specular * s, 0, 1),
//   s = max(0, n.h)^shininess if n.l > 0, else 0,
// with l = to_light / |to_light| and a = 1 (or, under a Camera::headlight, l the unit direction
// from the surface point to the eye and a = 1 / (1 + (d / light_falloff_m)^2), d the distance
// from the eye), v the unit direction from the surface point to the camera, and a further times
// 1/4 on the tissue and the floor where an instrument's working end (as a ball: the probe's, or
// one about the blade's middle or the jaws'; the first four tools; none for points inside the
// ball) lies between the point and the shadows'
// light (Camera::shadow_light_offset_m; for the directional light, 10 m along to_light from the
// tissue's centre), with a soft edge over the ball's outer fifth,
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
  SurfaceLook tissue{{0.80f, 0.45f, 0.40f}, 0.25f, 40.0f};  // wet: a tight highlight
  // Looks of tissue labels (TissueView::face_labels) other than `tissue`'s.
  std::map<int, SurfaceLook> tissue_by_label;
  SurfaceLook tool{{0.62f, 0.65f, 0.70f}, 0.45f, 48.0f};
  SurfaceLook tool_in_contact{{0.95f, 0.72f, 0.15f}, 0.45f, 48.0f};
  SurfaceLook floor{{0.30f, 0.31f, 0.30f}, 0.0f, 1.0f};
  SurfaceLook marker{{0.30f, 0.12f, 0.55f}, 0.0f, 1.0f};  // a surgical skin marker's violet
  // A blade's and the jaws' polished steel (also in contact: the shaft shows the contact).
  SurfaceLook steel{{0.78f, 0.80f, 0.84f}, 0.70f, 64.0f};
  // The walls a cut opened: the organ's interior, deeper red and wetter than its capsule.
  SurfaceLook cut_wall{{0.62f, 0.10f, 0.10f}, 0.35f, 32.0f};
  // Looks for the surroundings (StaticSurface): bone with its cartilage, the cavity's lining, a
  // neighbouring organ, fat.
  SurfaceLook bone{{0.86f, 0.80f, 0.60f}, 0.30f, 24.0f};
  SurfaceLook lining{{0.70f, 0.34f, 0.32f}, 0.20f, 24.0f};
  SurfaceLook organ{{0.66f, 0.46f, 0.47f}, 0.25f, 32.0f};
  SurfaceLook fat{{0.86f, 0.70f, 0.36f}, 0.30f, 32.0f};
  // A task's zones (MarkKind), blended over what lies behind them at zone_opacity in (0, 1]:
  // targets green, protected structures amber, never-zones red.
  SurfaceLook target{{0.20f, 0.85f, 0.35f}, 0.30f, 24.0f};
  SurfaceLook protected_zone{{0.95f, 0.70f, 0.10f}, 0.30f, 24.0f};
  SurfaceLook never_zone{{0.95f, 0.15f, 0.15f}, 0.30f, 24.0f};
  float zone_opacity = 0.4f;
  // Behind everything an endoscope sees (Camera::headlight): the unlit cavity.
  Eigen::Vector3f cavity{0.035f, 0.012f, 0.010f};
  // The floor is a square perpendicular to up, floor_gap below the lowest point (along up) of the
  // tissue and of the surroundings seen from outside (not inside_only), centred under the tissue's
  // bounding box, floor_half_size from centre to each edge.
  double floor_gap = 0.001;      // [m], >= 0
  double floor_half_size = 0.5;  // [m], > 0
};

// Draws a live scene: backdrop, floor, tissue, its surroundings and tools (without the floor, on
// the cavity's colour, under a Camera::headlight). One per render thread; needs a current
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

  // Replaces the surroundings drawn with every frame (none at first): uploads them once, with
  // area-weighted vertex normals. Throws std::invalid_argument, keeping the ones before, for a
  // surface without V or F, a face index outside [0, #V), a non-finite position or a look with a
  // non-positive shininess.
  void set_surroundings(std::span<const StaticSurface> surfaces);

  // The style as given, with up and to_light normalised.
  const SceneStyle& style() const { return style_; }

  // Draws backdrop, floor, tissue and tool seen from camera into target (aspect from the
  // target's size), overwriting all of it. Returns once the commands are issued; reading the
  // target back waits for them.
  // Throws std::invalid_argument, before drawing anything, for an invalid camera (a headlight
  // with a non-positive falloff), tissue (only some of V, N, F given, N's rows differing from
  // V's, a face index outside [0, #V), a non-finite position, cut_faces of the wrong size) or tool
  // (non-positive radius or shaft radius, negative shaft length, zero shaft direction,
  // non-finite tip; for a scalpel or grasper a side along the shaft, a non-positive length, a jaw
  // angle outside [0, pi)).
  void render(const Framebuffer& target, const Camera& camera, const TissueView& tissue,
              const ToolView& tool);
  // The same with any number of tools (a two-handed station's) and marks on the tissue; every
  // one is validated first (a mark: finite centre, positive radius).
  void render(const Framebuffer& target, const Camera& camera, const TissueView& tissue,
              std::span<const ToolView> tools, std::span<const MarkView> marks = {});

 private:
  // Validates and uploads the tissue; returns false when there is none.
  bool upload_tissue(const TissueView& tissue);
  // Draws mesh (triangles [first, first + count) of it, or all for a negative count); its vessel
  // pattern (if the look has one) from the mesh's pattern positions if pattern_attribute, else
  // from its positions.
  void draw_lit(const GlMesh& mesh, const Eigen::Affine3d& model, const SurfaceLook& look,
                int first_triangle = 0, int triangle_count = -1,
                bool pattern_attribute = false) const;
  // The translucent zones among marks, after everything opaque.
  void draw_zones(std::span<const MarkView> marks) const;
  void draw_tool(const ToolView& tool) const;
  // The unit box scaled to half-extents along the orthonormal axes a, b, c, centred at centre.
  void draw_box(const Eigen::Vector3d& centre, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                const Eigen::Vector3d& c, const Eigen::Vector3d& half,
                const SurfaceLook& look) const;

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
  int headlight_location_;
  int falloff_location_;
  int casters_location_;
  int caster_centre_location_;
  int caster_radius_location_;
  int shadow_light_location_;
  int vessels_location_;
  int vessel_scale_location_;
  int vessel_albedo_location_;
  int pattern_attribute_location_;
  int opacity_location_;

  unsigned int empty_vertex_array_ = 0;  // the backdrop's triangle comes from gl_VertexID alone
  GlMesh sphere_;
  GlMesh cylinder_;
  GlMesh square_;
  GlMesh box_;
  GlMesh tissue_;
  struct Surroundings {
    std::unique_ptr<GlMesh> mesh;
    SurfaceLook look;
    bool inside_only = false;
  };
  std::vector<Surroundings> surroundings_;
  // min over the vertices of the surroundings that are not inside_only of up . position [m].
  double surroundings_lowest_ = std::numeric_limits<double>::infinity();
  // The tissue as last uploaded, kept so that frames reuse memory and unchanged faces are not
  // sent again.
  std::vector<float> tissue_vertices_;
  std::vector<float> tissue_pattern_;   // the rest positions on the GPU (TissueView::rest)
  std::vector<float> ordered_pattern_;  // this frame's, compared with them
  bool tissue_has_rest_ = false;        // the last tissue came with rest positions
  // The capsule's faces grouped by label in ascending order, then the cut walls.
  std::vector<std::uint32_t> tissue_indices_;
  struct FaceGroup {
    int label = 0;  // -1: the cut walls
    int first = 0;  // triangle
    int count = 0;
  };
  std::vector<FaceGroup> tissue_groups_;
  std::vector<std::uint32_t> ordered_indices_;  // this frame's order, compared with the last
  std::vector<FaceGroup> ordered_groups_;
  Eigen::Vector3d tissue_min_ = Eigen::Vector3d::Zero();  // bounding box of the last tissue
  Eigen::Vector3d tissue_max_ = Eigen::Vector3d::Zero();
  double tissue_lowest_ = 0.0;  // min over vertices of up . position [m]
};

}  // namespace incise::render
