#pragma once

// What frames the simulated tissue in the picture without being simulated: the bones of a joint,
// the cavity's wall, the neighbouring organs. Static surfaces, built once with the scene and
// drawn every frame (the renderer uploads them once); nothing collides with them unless the
// scene also lists them as bones (SurgicalSceneSpec::bones).

#include <string>
#include <vector>

#include "sim/core/types.h"

namespace incise::sim::surgery {

// How a surrounding surface looks (the renderer's SceneStyle has a look for each).
enum class SurroundingKind {
  bone,   // cortical bone with its cartilage: ivory
  wall,   // the cavity's lining (peritoneum, synovium): pink, seen from inside
  organ,  // a neighbouring organ (stomach): pinker grey
  fat,    // omentum and fat pads: yellow
};

struct Surrounding {
  std::string name;
  SurroundingKind kind = SurroundingKind::organ;
  Points vertices;      // #V by 3 [m]
  Triangles triangles;  // indices into vertices
  // Seen only through the scope (the camera inside the body): a cavity's wall, which would hide
  // everything from a camera outside it.
  bool inside_only = false;
};

// An ellipsoid's surface as a latitude-longitude grid: slices meridians (>= 3), stacks bands
// (>= 2), the poles along z. Throws std::invalid_argument for too few or non-positive radii.
Surrounding ellipsoid_surrounding(std::string name, SurroundingKind kind, const Vec3& centre,
                                  const Vec3& radii, int slices = 48, int stacks = 24);

// The liver's surroundings, from the organ's rest bounding box and the height of the flat side
// it rests on: the posterior wall under it, the abdominal wall (inside only) enclosing organ and
// laparoscope, the stomach beside the left lobe (-x) and the omentum's fat in front (+y).
std::vector<Surrounding> liver_surroundings(const Box3& organ, Real flat_side_z);

// The knee's: its bones as given (vertices, triangles) and the joint capsule's synovium (inside
// only) enclosing them over box, the joint's extent.
std::vector<Surrounding> knee_surroundings(std::vector<Surrounding> bones, const Box3& joint);

}  // namespace incise::sim::surgery
