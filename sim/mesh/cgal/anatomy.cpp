#include "sim/mesh/cgal/anatomy.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "sim/mesh/boundary_surface.h"
#include "sim/mesh/cgal/mesh_generation.h"
#include "sim/mesh/tet_adjacency.h"

namespace incise::sim {
namespace {

constexpr Real kPi = std::numbers::pi;

void check_range(const char* what, const char* field, Real value, Real lo, bool lo_open, Real hi) {
  const bool ok = std::isfinite(value) && (lo_open ? value > lo : value >= lo) && value <= hi;
  if (ok) return;
  std::ostringstream message;
  message << what << ": " << field << " = " << value << " is outside " << (lo_open ? "(" : "[")
          << lo << ", " << hi << "]";
  throw std::invalid_argument(message.str());
}

MeshingCriteria criteria(Real cell_size, Real facet_size, Real facet_distance) {
  MeshingCriteria c;
  c.cell_size = cell_size;
  c.facet_size = facet_size;
  c.facet_distance = facet_distance;
  return c;
}

// The point where the segment from inside (f < 0) to outside (f > 0) crosses the surface of
// shape, by bisection to ~1e-12 of the segment.
Vec3 surface_crossing(const ImplicitShape& shape, Vec3 inside, Vec3 outside) {
  for (int i = 0; i < 40; ++i) {
    const Vec3 mid = (inside + outside) / 2;
    (implicit_value(shape, mid) < 0 ? inside : outside) = mid;
  }
  return (inside + outside) / 2;
}

// The boundary of a coarse CGAL mesh of shape: vertices on the implicit surface, oriented out.
SurfaceMesh bone_surface(const EllipsoidBlend& shape, Real facet_size) {
  Box3 bounds = implicit_extent(shape);
  const Vec3 pad = Vec3::Constant(facet_size);
  bounds = Box3(bounds.min() - pad, bounds.max() + pad);
  // Only the boundary is kept, yet interior cells larger than the facets make Mesh_3's sliver
  // passes 4-20 times slower (measured), so the cells are as large as the facets.
  const TetMesh mesh =
      mesh_implicit(shape, bounds, criteria(facet_size, facet_size, facet_size / 5));
  const BoundarySurface surface = boundary_surface(mesh);
  SurfaceMesh out;
  out.vertices.resize(static_cast<Eigen::Index>(surface.nodes.size()), 3);
  for (std::size_t i = 0; i < surface.nodes.size(); ++i) {
    out.vertices.row(static_cast<Eigen::Index>(i)) = mesh.rest.row(surface.nodes[i]);
  }
  out.triangles = surface.faces;
  return out;
}

// The highest crossing of the vertical line through (x, y) with the triangles (mesh node
// indices into points), or nothing if it misses them all.
std::optional<Vec3> drop_onto(const Points& points, const Triangles& faces, Real x, Real y) {
  std::optional<Vec3> best;
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const Vec3 a = row3(points, faces(f, 0));
    const Vec3 b = row3(points, faces(f, 1));
    const Vec3 c = row3(points, faces(f, 2));
    const Real area = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
    if (std::abs(area) < 1e-14) continue;  // a vertical face: the line grazes it at most
    const Real wb = ((x - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (y - a.y())) / area;
    const Real wc = ((b.x() - a.x()) * (y - a.y()) - (x - a.x()) * (b.y() - a.y())) / area;
    const Real wa = 1 - wb - wc;
    if (wa < 0 || wb < 0 || wc < 0) continue;
    const Vec3 hit = wa * a + wb * b + wc * c;
    if (!best || hit.z() > best->z()) best = hit;
  }
  return best;
}

// The boundary faces (mesh node indices, oriented out) of the tets of mesh carrying label.
Triangles labelled_boundary(const TetMesh& mesh, int label) {
  Tets part(std::count(mesh.labels.begin(), mesh.labels.end(), label), 4);
  Eigen::Index n = 0;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    if (mesh.labels[t] == label) part.row(n++) = mesh.tets.row(t);
  }
  return boundary_faces(part);
}

// ---------------------------------------------------------------------------------------------
// The knee. Sizes are those of an adult knee, rounded; all in metres.

constexpr Real kCompartmentX = 0.020;  // |x| of the medial and lateral compartment centres
constexpr Real kJointGap = 0.0025;     // condyle to plateau at the compartment centres
                                       // (the articular cartilage, not modelled)

EllipsoidBlend make_tibia() {
  EllipsoidBlend tibia;
  tibia.parts = {
      {Vec3(0, 0, -0.011), Vec3(0.042, 0.028, 0.011)},       // plateau, top near z = 0
      {Vec3(0, -0.002, -0.030), Vec3(0.030, 0.022, 0.025)},  // metaphysis
      {Vec3(0, -0.002, -0.060), Vec3(0.017, 0.016, 0.040)},  // shaft
  };
  tibia.blend_radius = 0.008;
  return tibia;
}

// The condyles sit kJointGap above the plateau; the shaft is a row of balls along the flexed
// axis (Ellipsoid is axis-aligned, so a slanted cylinder is built from spheres, their creases
// filled by the blend).
EllipsoidBlend make_femur(const EllipsoidBlend& tibia, Real flexion_deg) {
  const auto plateau_top = [&](Real x) {
    return surface_crossing(tibia, Vec3(x, 0, -0.005), Vec3(x, 0, 0.02)).z();
  };
  const Vec3 medial_radii(0.014, 0.026, 0.022);
  const Vec3 lateral_radii(0.013, 0.024, 0.021);
  const Real medial_z = plateau_top(-kCompartmentX) + kJointGap + medial_radii.z();
  const Real lateral_z = plateau_top(kCompartmentX) + kJointGap + lateral_radii.z();
  EllipsoidBlend femur;
  femur.parts = {
      {Vec3(-kCompartmentX, -0.002, medial_z), medial_radii},
      {Vec3(kCompartmentX, 0, lateral_z), lateral_radii},
      // The distal metaphysis and trochlea, bridging the condyles above the notch.
      {Vec3(0, 0.006, medial_z + 0.022), Vec3(0.036, 0.022, 0.022)},
  };
  const Real phi = flexion_deg * kPi / 180;
  const Vec3 axis(0, -std::sin(phi), std::cos(phi));  // the hip lies posterior when flexed
  const Vec3 start(0, 0, medial_z + 0.030);
  constexpr Real kShaftLength = 0.06, kShaftRadius = 0.015, kBallStep = 0.0075;
  for (Real s = 0; s <= kShaftLength + 1e-12; s += kBallStep) {
    femur.parts.push_back({start + s * axis, Vec3::Constant(kShaftRadius)});
  }
  femur.blend_radius = 0.008;
  return femur;
}

// A C-shaped meniscus around a compartment centre: in elliptic polar coordinates (rho, theta)
// with theta = 0 pointing away from the notch and theta > 0 anterior, it spans
// r_in <= rho <= r_out and |theta| <= horn_angle; its height above the plateau grows from h_in at
// the inner rim to h_out at the outer rim (a wedge); bones then carve it (see make_segmentation).
struct Meniscus {
  int label;
  Real cx, cy;
  Real side;     // -1 medial (outward is -x), +1 lateral
  Real scale_y;  // AP elongation of the C
  Real r_in, r_out, h_in, h_out, horn_angle;

  void polar(Real x, Real y, Real& rho, Real& theta) const {
    const Real u = side * (x - cx), v = (y - cy) / scale_y;
    rho = std::hypot(u, v);
    theta = std::atan2(v, u);
  }
  Vec3 at(Real rho, Real theta, Real z) const {
    return Vec3(cx + side * rho * std::cos(theta), cy + scale_y * rho * std::sin(theta), z);
  }
  // Inside the wedge, given the plateau's top at (x, y).
  bool contains(const Vec3& p, Real plateau_z) const {
    Real rho, theta;
    polar(p.x(), p.y(), rho, theta);
    if (rho < r_in || rho > r_out || std::abs(theta) > horn_angle) return false;
    const Real h = h_in + (h_out - h_in) * (rho - r_in) / (r_out - r_in);
    return p.z() <= plateau_z + h;
  }
};

// The medial meniscus is the larger, more open C; the lateral one is nearly a ring.
Meniscus medial_meniscus() {
  return {.label = kMedialMeniscusLabel,
          .cx = -kCompartmentX,
          .cy = -0.002,
          .side = -1,
          .scale_y = 1.15,
          .r_in = 0.009,
          .r_out = 0.017,
          .h_in = 0.0035,
          .h_out = 0.009,
          .horn_angle = 0.72 * kPi};
}
Meniscus lateral_meniscus() {
  return {.label = kLateralMeniscusLabel,
          .cx = kCompartmentX,
          .cy = 0,
          .side = 1,
          .scale_y = 1,
          .r_in = 0.008,
          .r_out = 0.015,
          .h_in = 0.0025,
          .h_out = 0.007,
          .horn_angle = 0.84 * kPi};
}

// The ACL as a capsule from the medial wall of the lateral condyle (posterior) to the anterior
// intercondylar area of the tibia; both ends start inside the bones, which carve them.
struct Ligament {
  Vec3 femoral_end = Vec3(0.010, -0.013, 0.020);
  Vec3 tibial_end = Vec3(0.001, 0.010, -0.004);
  Real radius = 0.0042;

  bool contains(const Vec3& p) const {
    const Vec3 d = tibial_end - femoral_end;
    const Real s = std::clamp((p - femoral_end).dot(d) / d.squaredNorm(), Real(0), Real(1));
    return (p - femoral_end - s * d).norm() < radius;
  }
};

struct KneeParts {
  Meniscus menisci[2] = {medial_meniscus(), lateral_meniscus()};
  Ligament ligament;
};

// The segmented volume: a voxel is tissue if it lies in a meniscus wedge or the ligament and
// more than clearance outside both bones, so tissue boundaries follow the bones at a small gap.
LabelVolume make_segmentation(const KneeParts& parts, const EllipsoidBlend& femur,
                              const EllipsoidBlend& tibia, Real h, Real clearance) {
  const Box3 box(Vec3(-0.042, -0.032, -0.016), Vec3(0.042, 0.030, 0.032));
  LabelVolume volume;
  volume.spacing = Vec3::Constant(h);
  volume.origin = box.min();
  for (int a = 0; a < 3; ++a)
    volume.dims[a] = static_cast<int>(std::ceil(box.sizes()[a] / h)) + 1;
  volume.labels.assign(static_cast<std::size_t>(volume.dims.prod()), 0);
  for (int j = 0; j < volume.dims.y(); ++j) {
    for (int i = 0; i < volume.dims.x(); ++i) {
      const Real x = box.min().x() + i * h, y = box.min().y() + j * h;
      // The plateau's top over this column (or none: the column misses the plateau).
      std::optional<Real> plateau_z;
      if (implicit_value(tibia, Vec3(x, y, -0.008)) < 0) {
        plateau_z = surface_crossing(tibia, Vec3(x, y, -0.008), Vec3(x, y, 0.02)).z();
      }
      for (int k = 0; k < volume.dims.z(); ++k) {
        const Vec3 p(x, y, box.min().z() + k * h);
        int label = 0;
        for (const Meniscus& m : parts.menisci) {
          if (plateau_z && m.contains(p, *plateau_z)) label = m.label;
        }
        if (label == 0 && parts.ligament.contains(p)) label = kLigamentLabel;
        if (label == 0) continue;
        if (implicit_value(tibia, p) <= clearance || implicit_value(femur, p) <= clearance)
          continue;
        volume.labels[static_cast<std::size_t>(i + volume.dims.x() * (j + volume.dims.y() * k))] =
            static_cast<std::uint8_t>(label);
      }
    }
  }
  return volume;
}

// The centroid of the voxels with label accepted by keep(voxel centre).
template <typename Keep>
Vec3 voxel_centroid(const LabelVolume& volume, int label, Keep keep) {
  Vec3 sum = Vec3::Zero();
  int count = 0;
  for (int k = 0; k < volume.dims.z(); ++k)
    for (int j = 0; j < volume.dims.y(); ++j)
      for (int i = 0; i < volume.dims.x(); ++i) {
        const std::size_t n =
            static_cast<std::size_t>(i + volume.dims.x() * (j + volume.dims.y() * k));
        const Vec3 p = volume.origin + volume.spacing.cwiseProduct(Vec3(i, j, k));
        if (volume.labels[n] == label && keep(p)) {
          sum += p;
          ++count;
        }
      }
  if (count == 0) throw std::runtime_error("knee: a landmark's tissue region is empty");
  return sum / count;
}

// Per node, the label of a tet using it (the last one; tissues do not share nodes here except at
// interfaces, where either answer marks the node as tissue).
std::vector<int> node_labels(const TetMesh& mesh) {
  std::vector<int> labels(static_cast<std::size_t>(mesh.num_nodes()), 0);
  for (int t = 0; t < mesh.num_tets(); ++t)
    for (int k = 0; k < 4; ++k)
      labels[static_cast<std::size_t>(mesh.tets(t, k))] = mesh.labels[t];
  return labels;
}

// Horn nodes (within kHornWindow of a horn's end) facing the tibia, and ligament nodes facing a
// bone: within one voxel of the clearance surface, where the attachment tissue would be.
std::vector<int> knee_held_nodes(const KneeAnatomy& knee, const KneeParts& parts, Real h) {
  constexpr Real kHornWindow = 0.35;  // [rad] of the C's arc
  const std::vector<int> labels = node_labels(knee.tissue);
  const Real near = knee.bone_clearance + h;
  std::vector<int> held;
  for (int n = 0; n < knee.tissue.num_nodes(); ++n) {
    const Vec3 p = row3(knee.tissue.rest, n);
    const int label = labels[static_cast<std::size_t>(n)];
    const Real to_tibia = implicit_value(knee.tibia_shape, p);
    if (label == kLigamentLabel) {
      if (std::min(to_tibia, implicit_value(knee.femur_shape, p)) <= near) held.push_back(n);
      continue;
    }
    for (const Meniscus& m : parts.menisci) {
      if (m.label != label) continue;
      Real rho, theta;
      m.polar(p.x(), p.y(), rho, theta);
      if (std::abs(theta) >= m.horn_angle - kHornWindow && to_tibia <= near) held.push_back(n);
    }
  }
  return held;
}

void add_knee_landmarks(KneeAnatomy& knee, const KneeParts& parts) {
  const EllipsoidBlend& femur = knee.femur_shape;
  for (int c = 0; c < 2; ++c) {
    // The condyle's lowest point and the plateau under it.
    const Ellipsoid& condyle = femur.parts[static_cast<std::size_t>(c)];
    const Vec3 low = condyle.centre - Vec3(0, 0, condyle.radii.z() + 0.005);
    const std::string side = c == 0 ? "medial" : "lateral";
    knee.landmarks.push_back(
        {side + "_femoral_condyle", surface_crossing(femur, condyle.centre, low)});
    const Vec3 above(condyle.centre.x(), condyle.centre.y(), 0.02);
    const Vec3 below(condyle.centre.x(), condyle.centre.y(), -0.008);
    knee.landmarks.push_back(
        {side + "_tibial_plateau", surface_crossing(knee.tibia_shape, below, above)});
  }
  constexpr Real kHornWindow = 0.3;
  for (const Meniscus& m : parts.menisci) {
    const std::string name = m.label == kMedialMeniscusLabel ? "medial" : "lateral";
    for (const Real sign : {Real(1), Real(-1)}) {
      const Vec3 horn = voxel_centroid(knee.segmentation, m.label, [&](const Vec3& p) {
        Real rho, theta;
        m.polar(p.x(), p.y(), rho, theta);
        return sign * theta >= m.horn_angle - kHornWindow;
      });
      knee.landmarks.push_back(
          {name + "_meniscus_" + (sign > 0 ? "anterior" : "posterior") + "_horn", horn});
    }
  }
  knee.landmarks.push_back({"acl_midpoint", voxel_centroid(knee.segmentation, kLigamentLabel,
                                                           [](const Vec3&) { return true; })});
}

// A radial line on the medial meniscus's posterior body, dropped onto its upper surface.
std::vector<Vec3> meniscus_cut_target(const TetMesh& tissue, const Meniscus& m) {
  constexpr Real kTheta = -0.9;  // [rad] posterior of the mid-body
  constexpr int kPoints = 5;
  const Triangles faces = labelled_boundary(tissue, m.label);
  const Real width = m.r_out - m.r_in;
  std::vector<Vec3> line;
  for (int i = 0; i < kPoints; ++i) {
    const Real rho = m.r_in + width * (0.2 + 0.6 * i / (kPoints - 1));
    const Vec3 p = m.at(rho, kTheta, 0);
    const std::optional<Vec3> hit = drop_onto(tissue.rest, faces, p.x(), p.y());
    if (!hit) throw std::runtime_error("knee: the cut target misses the medial meniscus mesh");
    line.push_back(*hit);
  }
  return line;
}

std::vector<Portal> knee_portals() {
  // Either side of the patellar tendon, a centimetre above the joint line, aimed at the notch.
  const Vec3 notch(0, -0.004, 0.008);
  std::vector<Portal> portals;
  for (const auto& [name, x] : {std::pair<const char*, Real>{"anterolateral", 0.016},
                                std::pair<const char*, Real>{"anteromedial", -0.016}}) {
    const Vec3 position(x, 0.042, 0.010);
    portals.push_back({name, position, (notch - position).normalized()});
  }
  return portals;
}

}  // namespace

void check_knee_options(const KneeOptions& o) {
  const char* what = "knee options";
  check_range(what, "voxel_size [m]", o.voxel_size, 0, true, 0.0015);
  check_range(what, "tissue_cell_size [m]", o.tissue_cell_size, o.voxel_size, false, 0.004);
  check_range(what, "bone_facet_size [m]", o.bone_facet_size, 0, true, 0.02);
  check_range(what, "flexion_deg", o.flexion_deg, 0, false, 90);
}

KneeAnatomy make_knee(const KneeOptions& options) {
  check_knee_options(options);
  const KneeParts parts;
  const Real h = options.voxel_size;
  KneeAnatomy knee;
  knee.tibia_shape = make_tibia();
  knee.femur_shape = make_femur(knee.tibia_shape, options.flexion_deg);
  knee.femur = bone_surface(knee.femur_shape, options.bone_facet_size);
  knee.tibia = bone_surface(knee.tibia_shape, options.bone_facet_size);
  knee.bone_clearance = h;
  knee.segmentation =
      make_segmentation(parts, knee.femur_shape, knee.tibia_shape, h, knee.bone_clearance);
  // A facet distance of one voxel: the surface follows the segmentation to within its own
  // resolution. A third of a voxel (as before) kept the tissues' volumes within ~6 % of their
  // voxels but made tets of 0.14 mm altitude where the condyles thin the menisci (smallest
  // dihedral angle 12 degrees: no slivers; the step was limited by tiny tets, not flat ones), a
  // stable step of 8.2 us at 3 mm cells. At one voxel the smallest altitude is 0.74 mm and the step
  // 43 us, for volumes 9-20 % under the voxels' (the inscribed facets cut a larger share of tissue
  // 2-9 voxels thick) (docs/anatomy.md).
  const Real cell = options.tissue_cell_size;
  knee.tissue = mesh_labelled_volume(knee.segmentation, criteria(cell, cell, h));
  knee.held_nodes = knee_held_nodes(knee, parts, h);
  knee.protected_labels = {kLigamentLabel};
  add_knee_landmarks(knee, parts);
  knee.portals = knee_portals();
  knee.cut_target = meniscus_cut_target(knee.tissue, parts.menisci[0]);
  return knee;
}

// ---------------------------------------------------------------------------------------------
// The liver.

void check_liver_options(const LiverOptions& o) {
  const char* what = "liver options";
  if (!o.centre.allFinite()) throw std::invalid_argument("liver options: centre is not finite");
  check_range(what, "length [m]", o.length, 0.05, false, 0.5);
  check_range(what, "cell_size [m]", o.cell_size, o.length / 60, false, o.length / 5);
  check_range(what, "cut_length [m]", o.cut_length, 0, true, o.length / 2);
  check_range(what, "cut_points", o.cut_points, 2, false, 1000);
}

LiverAnatomy make_liver_scene(const LiverOptions& o) {
  check_liver_options(o);
  const Real L = o.length;
  LiverAnatomy liver;
  liver.shape = liver_like_organ(o.centre, L);
  Box3 bounds = implicit_extent(liver.shape);
  bounds = Box3(bounds.min() - Vec3::Constant(0.05 * L), bounds.max() + Vec3::Constant(0.05 * L));
  liver.organ =
      mesh_implicit(liver.shape, bounds, criteria(o.cell_size, o.cell_size, o.cell_size / 8));
  const BoundarySurface surface = boundary_surface(liver.organ);
  // The flat face and the lowest strip of its rounded rim (within 1% of the length of the plane):
  // the organ rests and is held there, as on the tissue under it.
  const Real flat_tolerance = 0.01 * L;
  for (const int n : surface.nodes) {
    if (liver.organ.rest(n, 2) <= liver.shape.flat_side_z + flat_tolerance) {
      liver.held_nodes.push_back(n);
    }
  }
  // The gallbladder hangs under the right lobe (liver_like_organ's first lobe), towards +y.
  const Vec3 right_lobe = liver.shape.lobes.parts[0].centre;
  liver.gallbladder_centre =
      Vec3(right_lobe.x() + 0.05 * L, right_lobe.y() + 0.12 * L, liver.shape.flat_side_z);
  liver.gallbladder_radius = 0.1 * L;
  liver.organ.labels.setConstant(kLiverLabel);
  for (int t = 0; t < liver.organ.num_tets(); ++t) {
    Vec3 centroid = Vec3::Zero();
    for (int k = 0; k < 4; ++k)
      centroid += row3(liver.organ.rest, liver.organ.tets(t, k)) / 4;
    if ((centroid - liver.gallbladder_centre).norm() < liver.gallbladder_radius) {
      liver.organ.labels[t] = kGallbladderBedLabel;
    }
  }
  liver.protected_labels = {kGallbladderBedLabel};
  // The cut line runs along x over the top of the right lobe.
  const Triangles faces = boundary_faces(liver.organ.tets);
  for (int i = 0; i < o.cut_points; ++i) {
    const Real x = right_lobe.x() + o.cut_length * (Real(i) / (o.cut_points - 1) - 0.5);
    const std::optional<Vec3> hit = drop_onto(liver.organ.rest, faces, x, right_lobe.y());
    if (!hit) throw std::runtime_error("liver: the cut line misses the organ mesh");
    liver.cut_line.push_back(*hit);
  }
  const char* lobes[] = {"right_lobe", "left_lobe", "caudate_lobe"};
  for (int i = 0; i < 3; ++i)
    liver.landmarks.push_back(
        {lobes[i], liver.shape.lobes.parts[static_cast<std::size_t>(i)].centre});
  liver.landmarks.push_back({"cut_start", liver.cut_line.front()});
  liver.landmarks.push_back({"cut_end", liver.cut_line.back()});
  liver.landmarks.push_back({"gallbladder", liver.gallbladder_centre});
  return liver;
}

const Landmark& find_landmark(const std::vector<Landmark>& landmarks, const std::string& name) {
  for (const Landmark& l : landmarks) {
    if (l.name == name) return l;
  }
  throw std::out_of_range("no landmark named \"" + name + "\"");
}

}  // namespace incise::sim
