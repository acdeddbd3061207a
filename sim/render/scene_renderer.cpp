#include "sim/render/scene_renderer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
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
layout(location = 2) in vec3 pattern_position;
uniform mat4 model;
uniform mat3 normal_matrix;
uniform mat4 view_projection;
uniform int pattern_attribute;
out vec3 world_position;
out vec3 world_normal;
out vec3 pattern;
void main() {
  vec4 world = model * vec4(position, 1.0);
  world_position = world.xyz;
  world_normal = normal_matrix * normal;
  pattern = pattern_attribute != 0 ? pattern_position : position;
  gl_Position = view_projection * world;
}
)";

// The formula documented on SceneStyle. The triangle's own normal, from the screen-space
// derivatives of the position, tells which side the camera sees; testing the interpolated
// normal against the view direction instead would flip it wrongly near silhouettes.
// The vessels (SurfaceLook::vessels): lines where a smooth value noise of the rest position crosses
// one half, so they wind and branch without ending; a hash of the lattice point (no texture to
// build or sample) keeps the pattern the same on every frame and machine.
constexpr const char* lit_fragment_source = R"(#version 330 core
in vec3 world_position;
in vec3 world_normal;
in vec3 pattern;
uniform float vessels;
uniform float vessel_scale;
uniform vec3 vessel_albedo;
uniform float opacity;
uniform vec3 eye;
uniform vec3 to_light;
uniform float ambient;
uniform float diffuse;
uniform vec3 albedo;
uniform float specular;
uniform float shininess;
uniform int headlight;
uniform float falloff;
// The instruments' working ends as balls (centre, radius), shadowing the surfaces that receive
// shadows from the point light at shadow_light.
const int max_casters = 4;
uniform int casters;
uniform vec3 caster_centre[max_casters];
uniform float caster_radius[max_casters];
uniform vec3 shadow_light;
out vec4 colour;
float lattice_hash(vec3 p) {
  p = fract(p * vec3(0.1031, 0.1030, 0.0973));
  p += dot(p, p.yxz + 33.33);
  return fract((p.x + p.y) * p.z);
}
float value_noise(vec3 x) {
  vec3 i = floor(x);
  vec3 f = fract(x);
  vec3 u = f * f * (3.0 - 2.0 * f);
  float a = mix(lattice_hash(i), lattice_hash(i + vec3(1.0, 0.0, 0.0)), u.x);
  float b = mix(lattice_hash(i + vec3(0.0, 1.0, 0.0)), lattice_hash(i + vec3(1.0, 1.0, 0.0)), u.x);
  float c = mix(lattice_hash(i + vec3(0.0, 0.0, 1.0)), lattice_hash(i + vec3(1.0, 0.0, 1.0)), u.x);
  float d = mix(lattice_hash(i + vec3(0.0, 1.0, 1.0)), lattice_hash(i + vec3(1.0, 1.0, 1.0)), u.x);
  return mix(mix(a, b, u.y), mix(c, d, u.y), u.z);
}
// 1 on a line where |n - 1/2| < width (n a noise value), 0 off it; the edge is a pixel wide, and
// a line thinner than a pixel fades out rather than flicker.
float vessel_line(float n, float width) {
  float d = abs(n - 0.5);
  float pixel = max(fwidth(d), 1e-6);
  float line = 1.0 - smoothstep(width - 0.5 * pixel, width + 0.5 * pixel, d);
  return line * clamp(2.0 * width / pixel - 1.0, 0.0, 1.0);
}
void main() {
  vec3 base = albedo;
  if (vessels > 0.0) {
    // Two noises: the first's contour is the vessels, the second (finer) varies their calibre
    // along them, and its own contour where the first is above one half is the capillaries,
    // which end where that patch ends.
    vec3 p = pattern * vessel_scale;
    float coarse = value_noise(p);
    float fine = value_noise(2.3 * p + vec3(17.0, 5.0, 11.0));
    float w = max(vessel_line(coarse, 0.03 * (0.3 + 1.4 * fine)),
                  0.6 * smoothstep(0.5, 0.6, coarse) * vessel_line(fine, 0.012));
    base = mix(albedo, vessel_albedo, vessels * w);
  }
  vec3 to_eye = eye - world_position;
  vec3 v = normalize(to_eye);
  vec3 face = cross(dFdx(world_position), dFdy(world_position));
  if (dot(face, v) < 0.0) face = -face;
  vec3 n = normalize(world_normal);
  if (dot(n, face) < 0.0) n = -n;
  vec3 l = to_light;
  float reach = 1.0;
  if (headlight != 0) {
    l = v;
    float d = length(to_eye) / falloff;
    reach = 1.0 / (1.0 + d * d);
  }
  // In an instrument's shadow the light's terms fall to a quarter, with a soft edge: the distance
  // from the ball's centre to the segment from here to the light against its radius.
  vec3 to_shadow_light = shadow_light - world_position;
  float ray2 = dot(to_shadow_light, to_shadow_light);
  for (int i = 0; i < casters; ++i) {
    vec3 offset = caster_centre[i] - world_position;
    // A point inside the ball (the blade or jaws in the tissue) is not shadowed by it.
    if (dot(offset, offset) < caster_radius[i] * caster_radius[i]) continue;
    float along = clamp(dot(offset, to_shadow_light) / ray2, 0.0, 1.0);
    float d = length(offset - along * to_shadow_light);
    reach *= mix(0.25, 1.0, smoothstep(0.8 * caster_radius[i], caster_radius[i], d));
  }
  float lambert = max(dot(n, l), 0.0);
  float highlight = 0.0;
  if (lambert > 0.0) highlight = pow(max(dot(n, normalize(l + v)), 0.0), shininess);
  colour = vec4(clamp(base * (ambient + reach * diffuse * lambert) + reach * specular * highlight,
                      0.0, 1.0), opacity);
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

void validate_look(const SurfaceLook& look, const std::string& name) {
  if (!(look.shininess > 0.0f)) {
    throw std::invalid_argument("scene style " + name + ".shininess must be positive");
  }
  if (!(look.vessels >= 0.0f && look.vessels <= 1.0f)) {
    throw std::invalid_argument("scene style " + name + ".vessels must be in [0, 1]");
  }
  if (!(look.vessel_spacing_m > 0.0f) || !std::isfinite(look.vessel_spacing_m)) {
    throw std::invalid_argument("scene style " + name + ".vessel_spacing_m must be positive");
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
  validate_look(style.steel, "steel");
  validate_look(style.cut_wall, "cut_wall");
  validate_look(style.bone, "bone");
  validate_look(style.lining, "lining");
  validate_look(style.organ, "organ");
  validate_look(style.fat, "fat");
  validate_look(style.target, "target");
  validate_look(style.protected_zone, "protected_zone");
  validate_look(style.never_zone, "never_zone");
  for (const auto& [label, look] : style.tissue_by_label)
    validate_look(look, "tissue_by_label[" + std::to_string(label) + "]");
  if (!(style.zone_opacity > 0.0f && style.zone_opacity <= 1.0f)) {
    throw std::invalid_argument("scene style zone_opacity must be in (0, 1]");
  }
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
  if (tool.shape == ToolShape::probe) return;
  const Eigen::Vector3d along = tool.shaft_direction.normalized();
  const Eigen::Vector3d across = tool.side - tool.side.dot(along) * along;
  if (!tool.side.allFinite() || !(across.norm() > 1e-9 * std::max(tool.side.norm(), 1.0))) {
    throw std::invalid_argument("tool side must be finite and not along the shaft");
  }
  if (tool.shape == ToolShape::scalpel && !(tool.blade_length > 0.0)) {
    throw std::invalid_argument("scalpel blade_length must be positive");
  }
  if (tool.shape == ToolShape::grasper) {
    if (!(tool.jaw_length > 0.0))
      throw std::invalid_argument("grasper jaw_length must be positive");
    if (!(tool.jaw_angle >= 0.0 && tool.jaw_angle < std::numbers::pi)) {
      throw std::invalid_argument("grasper jaw_angle must be in [0, pi)");
    }
  }
}

// The tool's frame: along (tip back along the shaft), across (side made orthogonal to it) and
// their cross product; validate_tool has checked that across does not vanish.
struct ToolFrame {
  Eigen::Vector3d along, across, third;
};
ToolFrame tool_frame(const ToolView& tool) {
  ToolFrame f;
  f.along = tool.shaft_direction.normalized();
  f.across = (tool.side - tool.side.dot(f.along) * f.along).normalized();
  f.third = f.along.cross(f.across);
  return f;
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
      shininess_location_(lit_program_.uniform_location("shininess")),
      headlight_location_(lit_program_.uniform_location("headlight")),
      falloff_location_(lit_program_.uniform_location("falloff")),
      casters_location_(lit_program_.uniform_location("casters")),
      caster_centre_location_(lit_program_.uniform_location("caster_centre")),
      caster_radius_location_(lit_program_.uniform_location("caster_radius")),
      shadow_light_location_(lit_program_.uniform_location("shadow_light")),
      vessels_location_(lit_program_.uniform_location("vessels")),
      vessel_scale_location_(lit_program_.uniform_location("vessel_scale")),
      vessel_albedo_location_(lit_program_.uniform_location("vessel_albedo")),
      pattern_attribute_location_(lit_program_.uniform_location("pattern_attribute")),
      opacity_location_(lit_program_.uniform_location("opacity")) {
  glGenVertexArrays(1, &empty_vertex_array_);
  upload(sphere_, unit_sphere(sphere_slices, sphere_stacks));
  upload(cylinder_, unit_cylinder(cylinder_slices));
  upload(square_, unit_square());
  upload(box_, unit_box());
}

SceneRenderer::~SceneRenderer() {
  glDeleteVertexArrays(1, &empty_vertex_array_);
}

void SceneRenderer::set_surroundings(std::span<const StaticSurface> surfaces) {
  // Everything is built before anything replaces the old ones, so that a rejected call keeps them.
  std::vector<Surroundings> built;
  double lowest = std::numeric_limits<double>::infinity();
  std::vector<float> vertices;
  std::vector<std::uint32_t> indices;
  for (std::size_t s = 0; s < surfaces.size(); ++s) {
    const StaticSurface& surface = surfaces[s];
    const std::string which = "surrounding " + std::to_string(s);
    if (surface.V == nullptr || surface.F == nullptr) {
      throw std::invalid_argument(which + " needs V and F");
    }
    validate_look(surface.look, "surrounding look");
    const auto& V = *surface.V;
    const auto& F = *surface.F;
    if (!V.allFinite()) throw std::invalid_argument(which + " has a non-finite position");
    Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> N =
        Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>::Zero(V.rows(), 3);
    indices.resize(static_cast<std::size_t>(F.size()));
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
      for (int k = 0; k < 3; ++k) {
        const int index = F(f, k);
        if (index < 0 || index >= V.rows()) {
          throw std::invalid_argument(which + " face " + std::to_string(f) +
                                      " has a vertex index outside [0, " +
                                      std::to_string(V.rows()) + ")");
        }
        indices[static_cast<std::size_t>(3 * f + k)] = static_cast<std::uint32_t>(index);
      }
      // The cross product's length is twice the area: normals weighted by area.
      const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
      const Eigen::Vector3d n = (b - a).cross(c - a);
      for (int k = 0; k < 3; ++k)
        N.row(F(f, k)) += n.transpose();
    }
    vertices.resize(static_cast<std::size_t>(V.rows()) * GlMesh::floats_per_vertex);
    for (Eigen::Index v = 0; v < V.rows(); ++v) {
      const double length = N.row(v).norm();
      for (int k = 0; k < 3; ++k) {
        vertices[static_cast<std::size_t>(v) * GlMesh::floats_per_vertex + k] =
            static_cast<float>(V(v, k));
        vertices[static_cast<std::size_t>(v) * GlMesh::floats_per_vertex + 3 + k] =
            length > 0.0 ? static_cast<float>(N(v, k) / length) : (k == 2 ? 1.0f : 0.0f);
      }
    }
    if (!surface.inside_only) {
      for (Eigen::Index v = 0; v < V.rows(); ++v)
        lowest = std::min(lowest, style_.up.dot(V.row(v).transpose()));
    }
    Surroundings entry{std::make_unique<GlMesh>(), surface.look, surface.inside_only};
    entry.mesh->set_vertices(vertices);
    entry.mesh->set_indices(indices);
    built.push_back(std::move(entry));
  }
  surroundings_ = std::move(built);
  surroundings_lowest_ = lowest;
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
  const std::vector<std::uint8_t>* cut = tissue.cut_faces;
  if (cut != nullptr && cut->empty()) cut = nullptr;
  if (cut != nullptr && static_cast<Eigen::Index>(cut->size()) != F.rows()) {
    throw std::invalid_argument("tissue has " + std::to_string(F.rows()) + " faces but " +
                                std::to_string(cut->size()) + " cut-face flags");
  }
  const std::vector<std::uint8_t>* labels = tissue.face_labels;
  if (labels != nullptr && labels->empty()) labels = nullptr;
  if (labels != nullptr && static_cast<Eigen::Index>(labels->size()) != F.rows()) {
    throw std::invalid_argument("tissue has " + std::to_string(F.rows()) + " faces but " +
                                std::to_string(labels->size()) + " face labels");
  }
  if (tissue.rest != nullptr && tissue.rest->rows() != V.rows()) {
    throw std::invalid_argument("tissue has " + std::to_string(V.rows()) + " vertices but " +
                                std::to_string(tissue.rest->rows()) + " rest positions");
  }
  if (V.rows() == 0) return false;

  // Validate all faces before touching the cached ones, so that a rejected frame leaves the
  // cache equal to what the GPU holds.
  const auto vertex_count = static_cast<std::uint32_t>(V.rows());
  const int* face_data = F.data();
  for (Eigen::Index i = 0; i < F.size(); ++i) {
    const int index = face_data[i];
    if (index < 0 || static_cast<std::uint32_t>(index) >= vertex_count) {
      throw std::invalid_argument("tissue face " + std::to_string(i / 3) + " has vertex index " +
                                  std::to_string(index) + " outside [0, " +
                                  std::to_string(vertex_count) + ")");
    }
  }
  // The capsule's faces by label (a draw per look), then the cut walls, each group in F's order:
  // a counting sort, slot 256 for the walls.
  constexpr std::size_t kWalls = 256;
  std::array<int, kWalls + 1> count{};
  const auto slot_of = [&](Eigen::Index f) -> std::size_t {
    const auto i = static_cast<std::size_t>(f);
    if (cut != nullptr && (*cut)[i]) return kWalls;
    return labels != nullptr ? (*labels)[i] : 0;
  };
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    ++count[slot_of(f)];
  std::array<std::size_t, kWalls + 1> at{};
  ordered_groups_.clear();
  std::size_t first = 0;
  for (std::size_t slot = 0; slot <= kWalls; ++slot) {
    at[slot] = 3 * first;
    if (count[slot] == 0) continue;
    ordered_groups_.push_back(
        {slot == kWalls ? -1 : static_cast<int>(slot), static_cast<int>(first), count[slot]});
    first += static_cast<std::size_t>(count[slot]);
  }
  ordered_indices_.resize(static_cast<std::size_t>(F.size()));
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    std::size_t& a = at[slot_of(f)];
    for (int k = 0; k < 3; ++k)
      ordered_indices_[a++] = static_cast<std::uint32_t>(face_data[3 * f + k]);
  }
  const bool faces_changed = ordered_indices_ != tissue_indices_;

  tissue_vertices_.resize(static_cast<std::size_t>(V.rows()) * GlMesh::floats_per_vertex);
  Eigen::Vector3d low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d high = -low;
  double lowest = std::numeric_limits<double>::infinity();
  const auto* rest = tissue.rest;
  ordered_pattern_.resize(rest != nullptr ? static_cast<std::size_t>(V.rows()) * 3 : 0);
  float* out = tissue_vertices_.data();
  float* pattern_out = ordered_pattern_.data();
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    const Eigen::Vector3d p = V.row(v).transpose();
    if (!p.allFinite()) {
      throw std::invalid_argument("tissue vertex " + std::to_string(v) +
                                  " has a non-finite position");
    }
    if (rest != nullptr) {
      const Eigen::Vector3d r = rest->row(v).transpose();
      if (!r.allFinite()) {
        throw std::invalid_argument("tissue vertex " + std::to_string(v) +
                                    " has a non-finite rest position");
      }
      for (int k = 0; k < 3; ++k)
        pattern_out[k] = static_cast<float>(r[k]);
      pattern_out += 3;
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
  // The rest shape changes only with the topology: sent again only when it differs. Without one
  // the pattern comes from the positions themselves (pattern_attribute off).
  tissue_has_rest_ = rest != nullptr;
  if (tissue_has_rest_ && ordered_pattern_ != tissue_pattern_) {
    tissue_pattern_.swap(ordered_pattern_);
    tissue_.set_pattern_positions(tissue_pattern_);
  }
  if (faces_changed) {
    tissue_indices_.swap(ordered_indices_);
    tissue_.set_indices(tissue_indices_);
  }
  tissue_groups_.swap(ordered_groups_);
  return true;
}

void SceneRenderer::draw_lit(const GlMesh& mesh, const Eigen::Affine3d& model,
                             const SurfaceLook& look, int first_triangle, int triangle_count,
                             bool pattern_attribute) const {
  const Eigen::Matrix4f model_matrix = model.matrix().cast<float>();
  // Normals transform with the inverse transpose, which differs from the rotation when the
  // model scales unevenly (the shaft: radius across, length along).
  const Eigen::Matrix3f normal_matrix = model.linear().inverse().transpose().cast<float>();
  glUniformMatrix4fv(model_location_, 1, GL_FALSE, model_matrix.data());
  glUniformMatrix3fv(normal_matrix_location_, 1, GL_FALSE, normal_matrix.data());
  glUniform3fv(albedo_location_, 1, look.albedo.data());
  glUniform1f(specular_location_, look.specular);
  glUniform1f(shininess_location_, look.shininess);
  glUniform1f(vessels_location_, look.vessels);
  glUniform1f(vessel_scale_location_, 1.0f / look.vessel_spacing_m);
  glUniform3fv(vessel_albedo_location_, 1, look.vessel_albedo.data());
  glUniform1i(pattern_attribute_location_, pattern_attribute ? 1 : 0);
  if (triangle_count < 0) {
    mesh.draw();
  } else {
    mesh.draw(first_triangle, triangle_count);
  }
}

void SceneRenderer::render(const Framebuffer& target, const Camera& camera,
                           const TissueView& tissue, const ToolView& tool) {
  render(target, camera, tissue, std::span<const ToolView>(&tool, 1));
}

void SceneRenderer::draw_box(const Eigen::Vector3d& centre, const Eigen::Vector3d& a,
                             const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                             const Eigen::Vector3d& half, const SurfaceLook& look) const {
  Eigen::Affine3d box = Eigen::Affine3d::Identity();
  box.translate(centre);
  box.linear() << a * half.x(), b * half.y(), c * half.z();
  draw_lit(box_, box, look);
}

void SceneRenderer::draw_tool(const ToolView& tool) const {
  const SurfaceLook& tool_look = tool.in_contact ? style_.tool_in_contact : style_.tool;
  const Eigen::Vector3d along = tool.shaft_direction.normalized();
  // Where the shaft starts: behind the blade for a scalpel, at the tip otherwise.
  Eigen::Vector3d shaft_start = tool.tip;
  double shaft_length = tool.shaft_length;
  switch (tool.shape) {
    case ToolShape::probe: {
      Eigen::Affine3d sphere = Eigen::Affine3d::Identity();
      sphere.translate(tool.tip).scale(tool.radius);
      draw_lit(sphere_, sphere, tool_look);
      break;
    }
    case ToolShape::scalpel: {
      // A plate: blade_length along the shaft, a third of that high, a fraction of a millimetre
      // thick; the edge on the tip's line.
      const ToolFrame f = tool_frame(tool);
      const double height = tool.blade_length / 3;
      const double thickness = std::min(0.0004, 0.1 * tool.shaft_radius);
      draw_box(tool.tip + 0.5 * tool.blade_length * f.along + 0.5 * height * f.third, f.along,
               f.third, f.across,
               Eigen::Vector3d(0.5 * tool.blade_length, 0.5 * height, 0.5 * thickness),
               style_.steel);
      shaft_start = tool.tip + tool.blade_length * along;
      shaft_length = std::max(0.0, tool.shaft_length - tool.blade_length);
      break;
    }
    case ToolShape::grasper: {
      // Jaw k runs from the hinge along cos(a / 2) d +- sin(a / 2) across (d = -along), a flat
      // bar as wide as the shaft and a third of it thick, its inner face on that line: closed,
      // the jaws meet on the axis.
      const ToolFrame f = tool_frame(tool);
      const double half_angle = 0.5 * tool.jaw_angle;
      const double width = 1.4 * tool.shaft_radius;
      const double thickness = 0.7 * tool.shaft_radius;
      for (const double sign : {1.0, -1.0}) {
        const Eigen::Vector3d jaw =
            -std::cos(half_angle) * f.along + sign * std::sin(half_angle) * f.across;
        // Away from the other jaw, in the opening plane.
        const Eigen::Vector3d outward =
            std::sin(half_angle) * f.along + sign * std::cos(half_angle) * f.across;
        draw_box(tool.tip + 0.5 * tool.jaw_length * jaw + 0.5 * thickness * outward, jaw, outward,
                 f.third, Eigen::Vector3d(0.5 * tool.jaw_length, 0.5 * thickness, 0.5 * width),
                 style_.steel);
      }
      break;
    }
  }
  if (shaft_length > 0.0) {
    // The unit cylinder's z axis becomes the shaft.
    Eigen::Matrix3d axes;
    Eigen::Vector3d across_1, across_2;
    complete_basis(along, across_1, across_2);
    axes << across_1 * tool.shaft_radius, across_2 * tool.shaft_radius, along * shaft_length;
    Eigen::Affine3d shaft = Eigen::Affine3d::Identity();
    shaft.translate(shaft_start);
    shaft.linear() = axes;
    draw_lit(cylinder_, shaft, tool_look);
  }
}

namespace {

// An instrument's working end as the shadow test sees it: a ball. Shafts cast none: the shadow
// that tells depth is the working end's, closing on the instrument as it reaches the tissue, and a
// ball costs a point-to-segment distance per pixel where a shaft's capsule costs a
// segment-to-segment one.
struct Caster {
  Eigen::Vector3d centre;
  double radius;
};
constexpr std::size_t kMaxCasters = 4;  // max_casters in the fragment shader

Caster caster_of(const ToolView& tool) {
  const Eigen::Vector3d along = tool.shaft_direction.normalized();
  switch (tool.shape) {
    case ToolShape::scalpel: {
      const ToolFrame f = tool_frame(tool);
      return {tool.tip + 0.5 * tool.blade_length * along + tool.blade_length / 6 * f.third,
              0.25 * tool.blade_length};
    }
    case ToolShape::grasper: {
      const double half_angle = 0.5 * tool.jaw_angle;
      return {tool.tip - 0.5 * std::cos(half_angle) * tool.jaw_length * along,
              0.7 * tool.shaft_radius + 0.5 * std::sin(half_angle) * tool.jaw_length};
    }
    case ToolShape::probe:
      break;
  }
  return {tool.tip, tool.radius};
}

// Where the instruments' shadows are cast from: under a headlight, shadow_light_offset_m below
// the eye in the image (the camera's up made orthogonal to its view direction); else far along
// the directional light from the tissue's centre.
Eigen::Vector3d shadow_light(const Camera& camera, const Eigen::Vector3d& centre,
                             const Eigen::Vector3d& to_light) {
  if (camera.headlight) {
    const Eigen::Vector3d forward = (camera.target - camera.eye).normalized();
    const Eigen::Vector3d up = (camera.up - camera.up.dot(forward) * forward).normalized();
    return camera.eye - camera.shadow_light_offset_m * up;
  }
  return centre + 10.0 * to_light;
}

}  // namespace

void SceneRenderer::render(const Framebuffer& target, const Camera& camera,
                           const TissueView& tissue, std::span<const ToolView> tools,
                           std::span<const MarkView> marks) {
  const double aspect = static_cast<double>(target.width()) / target.height();
  // Eigen stores column-major, as GL expects without transposing.
  const Eigen::Matrix4f view_projection =
      (projection_matrix(camera, aspect) * view_matrix(camera)).cast<float>();
  if (camera.headlight && !(camera.light_falloff_m > 0.0)) {
    throw std::invalid_argument("a headlight camera needs a positive light_falloff_m");
  }
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
  glUniform1i(headlight_location_, camera.headlight ? 1 : 0);
  glUniform1f(falloff_location_, static_cast<float>(camera.light_falloff_m));
  glUniform1i(casters_location_, 0);  // the instruments and marks receive no shadows
  glUniform1f(opacity_location_, 1.0f);

  // Nearest first, so that the depth test spares shading hidden pixels of the larger shapes.
  for (const ToolView& tool : tools)
    draw_tool(tool);
  for (const MarkView& mark : marks) {
    if (mark.kind != MarkKind::ink) continue;  // zones: translucent, after everything opaque
    Eigen::Affine3d sphere = Eigen::Affine3d::Identity();
    sphere.translate(mark.centre).scale(mark.radius);
    draw_lit(sphere_, sphere, style_.marker);
  }

  if (has_tissue || !surroundings_.empty()) {
    // The instruments' shadows on the tissue, its surroundings and the floor (Caster, above).
    const std::size_t count = std::min(tools.size(), kMaxCasters);
    std::array<float, 3 * kMaxCasters> centre{};
    std::array<float, kMaxCasters> radius{};
    for (std::size_t i = 0; i < count; ++i) {
      const Caster c = caster_of(tools[i]);
      for (int k = 0; k < 3; ++k)
        centre[3 * i + static_cast<std::size_t>(k)] = static_cast<float>(c.centre[k]);
      radius[i] = static_cast<float>(c.radius);
    }
    const Eigen::Vector3f light =
        shadow_light(camera, 0.5 * (tissue_min_ + tissue_max_), style_.to_light).cast<float>();
    glUniform1i(casters_location_, static_cast<int>(count));
    glUniform3fv(caster_centre_location_, kMaxCasters, centre.data());
    glUniform1fv(caster_radius_location_, kMaxCasters, radius.data());
    glUniform3fv(shadow_light_location_, 1, light.data());
    if (has_tissue) {
      for (const FaceGroup& group : tissue_groups_) {
        const auto labelled = style_.tissue_by_label.find(group.label);
        const SurfaceLook& look = group.label < 0                            ? style_.cut_wall
                                  : labelled != style_.tissue_by_label.end() ? labelled->second
                                                                             : style_.tissue;
        draw_lit(tissue_, Eigen::Affine3d::Identity(), look, group.first, group.count,
                 tissue_has_rest_);
      }
    }
    for (const Surroundings& s : surroundings_) {
      if (s.inside_only && !camera.headlight) continue;
      draw_lit(*s.mesh, Eigen::Affine3d::Identity(), s.look);
    }
  }
  if (has_tissue && !camera.headlight) {
    // The unit square's plane z = 0 becomes the floor plane, its normal +z becomes up.
    const Eigen::Vector3d& up = style_.up;
    Eigen::Vector3d across_1, across_2;
    complete_basis(up, across_1, across_2);
    const Eigen::Vector3d centre = 0.5 * (tissue_min_ + tissue_max_);
    const double floor_height = std::min(tissue_lowest_, surroundings_lowest_) - style_.floor_gap;
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
  glUniform3fv(backdrop_top_location_, 1,
               (camera.headlight ? style_.cavity : style_.backdrop_top).data());
  glUniform3fv(backdrop_bottom_location_, 1,
               (camera.headlight ? style_.cavity : style_.backdrop_bottom).data());
  glBindVertexArray(empty_vertex_array_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glDepthMask(GL_TRUE);
  glDepthFunc(GL_LESS);
  draw_zones(marks);
}

void SceneRenderer::draw_zones(std::span<const MarkView> marks) const {
  const auto zone = [](const MarkView& m) { return m.kind != MarkKind::ink; };
  if (std::none_of(marks.begin(), marks.end(), zone)) return;
  // Each ball's near half only (back faces culled), blended over what was drawn, without hiding
  // what comes after it: a zone inside the tissue shows where it breaks the surface.
  lit_program_.use();
  glUniform1i(casters_location_, 0);
  glUniform1f(opacity_location_, style_.zone_opacity);
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glEnable(GL_CULL_FACE);
  glCullFace(GL_BACK);
  glDepthMask(GL_FALSE);
  for (const MarkView& mark : marks) {
    if (!zone(mark)) continue;
    const SurfaceLook& look = mark.kind == MarkKind::target           ? style_.target
                              : mark.kind == MarkKind::protected_zone ? style_.protected_zone
                                                                      : style_.never_zone;
    Eigen::Affine3d sphere = Eigen::Affine3d::Identity();
    sphere.translate(mark.centre).scale(mark.radius);
    draw_lit(sphere_, sphere, look);
  }
  glDepthMask(GL_TRUE);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  glUniform1f(opacity_location_, 1.0f);
}

}  // namespace incise::render
