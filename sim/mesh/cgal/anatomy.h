#pragma once

// Generated anatomy for the two surgical scenes (docs/anatomy.md): a knee-like joint for
// arthroscopy (rigid femur and tibia as closed surfaces; menisci and ACL as one labelled tet mesh
// from a segmented voxel volume, as in Knee Arthroscopy VR, section V) and a liver-like organ for
// laparoscopy. Each builder returns plain arrays plus the task data a scene needs: held nodes,
// protected tissue labels, named landmarks, portals and a cut target. Everything is deterministic
// (see mesh_generation.h): the same options give the same arrays on every run.
//
// Knee frame (SI units, metres), a right knee: origin at the top of the tibial plateau between
// the two compartments; x lateral (medial side at x < 0), y anterior, z proximal along the tibial
// shaft. The femoral shaft leans posteriorly by the flexion angle (0 = full extension); the
// condyles and the soft tissue keep their extended pose (flexion only moves the shaft).

#include <string>
#include <vector>

#include "sim/core/types.h"
#include "sim/mesh/cgal/implicit_shape.h"
#include "sim/mesh/cgal/label_volume.h"
#include "sim/mesh/tet_mesh.h"

namespace incise::sim {

// A closed, manifold triangle surface with the right-hand normal of every triangle pointing out
// (positive enclosed volume): what collide::RigidBody takes.
struct SurfaceMesh {
  Points vertices;      // #V by 3 [m]
  Triangles triangles;  // #F by 3 indices into vertices
};

struct Landmark {
  std::string name;
  Vec3 position;  // [m], rest frame
};

// An instrument entry point and the direction [unit] the instrument points when inserted.
struct Portal {
  std::string name;
  Vec3 position;   // [m], outside bones and soft tissue
  Vec3 direction;  // unit, from the portal towards the intercondylar notch
};

// Soft-tissue labels of KneeAnatomy::tissue (label 0, outside, is never meshed).
inline constexpr int kMedialMeniscusLabel = 1;
inline constexpr int kLateralMeniscusLabel = 2;
inline constexpr int kLigamentLabel = 3;  // the anterior cruciate ligament (ACL)

struct KneeOptions {
  Real voxel_size = 0.001;        // [m] spacing of the segmented volume, in (0, 0.0015]
  Real tissue_cell_size = 0.002;  // [m] tet and surface element size of the soft tissue, in
                                  // [voxel_size, 0.004]
  Real bone_facet_size = 0.005;   // [m] triangle size of the bone surfaces, in (0, 0.02]
  Real flexion_deg = 10;          // knee flexion [degrees], in [0, 90]
};

struct KneeAnatomy {
  // The bones as implicit shapes (implicit_value < 0 inside, ~ signed distance [m]) and as
  // closed surfaces meshed from them (vertices on the implicit surface, facets within
  // bone_facet_size / 5 of it; the facets are chords, so the surfaces lie just inside the shapes).
  EllipsoidBlend femur_shape;
  EllipsoidBlend tibia_shape;
  SurfaceMesh femur;
  SurfaceMesh tibia;
  // The segmented volume (labels 0..3) and the tet mesh of its tissue, labels per tet 1..3.
  // Tissue voxels keep bone_clearance from both bones, so the soft tissue does not enter a bone at
  // rest: the menisci lie on the plateau under the condyles, the ACL ends at both bones.
  LabelVolume segmentation;
  TetMesh tissue;
  Real bone_clearance = 0;  // [m] = voxel_size
  // Tissue nodes attached to bone (ascending, into tissue): the meniscus horns' nodes facing the
  // tibia and the ACL's nodes at its femoral and tibial ends.
  std::vector<int> held_nodes;
  std::vector<int> protected_labels;  // tissue labels tools must not cut or touch: {kLigamentLabel}
  // Named points: femoral condyles and tibial plateaus (on the bone surfaces), meniscus horns and
  // the ACL midpoint (inside their tissue): see docs/anatomy.md for the names.
  std::vector<Landmark> landmarks;
  std::vector<Portal> portals;  // "anterolateral" (scope) and "anteromedial" (probe)
  // A radial tear line on the upper surface of the medial meniscus's posterior body, from its inner
  // rim outwards: the target of the meniscus cut (points on the tissue mesh surface).
  std::vector<Vec3> cut_target;
};

// Throws std::invalid_argument naming the field, its value and the allowed range.
void check_knee_options(const KneeOptions& options);

// Builds the knee (about a second at default options; docs/anatomy.md has the figures).
// Throws std::invalid_argument for invalid options; std::runtime_error if meshing fails.
KneeAnatomy make_knee(const KneeOptions& options);

// Labels of LiverAnatomy::organ.
inline constexpr int kLiverLabel = 1;
inline constexpr int kGallbladderBedLabel = 2;  // liver tissue under the gallbladder: protected

struct LiverOptions {
  Vec3 centre = Vec3::Zero();
  Real length = 0.16;      // [m] along x, in [0.05, 0.5]
  Real cell_size = 0.008;  // [m] tet and surface element size, in [length / 60, length / 5]
  Real cut_length = 0.04;  // [m] length of the marked cut line, in (0, length / 2]
  int cut_points = 9;      // points on the cut line, >= 2
};

struct LiverAnatomy {
  LobedOrgan shape;  // liver_like_organ(centre, length)
  TetMesh organ;     // labels kLiverLabel, and kGallbladderBedLabel inside the gallbladder ball
  // Boundary nodes on the flat (visceral) side, within length / 100 of its plane, held fixed
  // (ascending).
  std::vector<int> held_nodes;
  // The gallbladder, a ball touching the flat side under the right lobe: tets whose centroid lies
  // in it carry kGallbladderBedLabel.
  Vec3 gallbladder_centre;  // [m]
  Real gallbladder_radius = 0;
  std::vector<int> protected_labels;  // {kGallbladderBedLabel}
  // The marked cut line: cut_points points evenly spaced along x over cut_length, above the right
  // lobe, each dropped vertically onto the mesh's upper surface.
  std::vector<Vec3> cut_line;
  std::vector<Landmark> landmarks;  // lobes (on the upper surface), cut ends, gallbladder
};

// Throws std::invalid_argument naming the field, its value and the allowed range.
void check_liver_options(const LiverOptions& options);

// Builds the liver scene's organ. Throws like make_knee.
LiverAnatomy make_liver_scene(const LiverOptions& options);

// The landmark called name; throws std::out_of_range naming it if there is none.
const Landmark& find_landmark(const std::vector<Landmark>& landmarks, const std::string& name);

}  // namespace incise::sim
