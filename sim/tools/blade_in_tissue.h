#pragma once

// How much of a straight blade is inside a tissue, found on the tissue's boundary: a closed
// surface whose faces point outwards (a tet mesh's boundary_surface), in a SurfaceBvh over the
// deforming positions. What the scalpel's cutting resistance needs (cutting_resistance.h).
//
// The blade runs from its tip back along -direction for `length`. Walking that line from the tip,
// a face crossed against its outward normal is a way into the tissue, one crossed along it a way
// out; the crossings on the blade, in order, bound its stretches inside. The walk keeps a state
// (in or out) and takes only the crossings that change it, so a line through an edge or a vertex
// (met by every face there, all the same way) counts once. Where the blade crosses no face it is
// wholly in or wholly out; the first crossing further back along the line, within `reach` of the
// blade's back end, says which (a way out: in). Faces parallel to the blade are not crossings (a
// crack the blade lies in). Crossings at one place are taken ways out first: the two sides of a
// closed crack (coincident faces, opposite normals) are a gap of no width inside the tissue, and
// the stretches on either side of it are one stretch; so are stretches less than `bridge` apart
// (a crack whose two sides do not quite meet: a cutter snaps its crossings to nearby nodes, and
// triangulates the two sides of a fresh crack differently).
//
// Cost: one tree query with the blade as a thin capsule, O(log n + k); while the blade crosses
// no face, up to reach / length more along the line. No allocation once `found` has grown.

#include <vector>

#include "sim/collide/surface_bvh.h"
#include "sim/core/types.h"

namespace incise::sim::tools {

// A stretch of the blade inside the tissue.
struct BladeStretch {
  Real from = 0;  // distance from the tip [m], >= 0
  Real to = 0;    // [m], in [from, length]
  int face = -1;  // the tree slot of a face bounding it (where it is entered or left)
};

// A face the blade's line crosses.
struct BladeCrossing {
  Real distance = 0;     // from the tip, along -direction [m]
  bool entering = true;  // walking from the tip, into the tissue
  int face = -1;         // tree slot
};

// What blade_in_tissue found, with its scratch (reuse one between calls).
struct BladeInTissue {
  Real depth = 0;                        // the blade's length inside the tissue [m], in [0, length]
  std::vector<BladeStretch> stretches;   // nearest the tip first
  std::vector<BladeCrossing> crossings;  // scratch: the last query's crossings
  std::vector<int> slots;                // scratch: the last query's faces
};

// The blade from tip [m] back along -direction (unit) for length [m] > 0, against the surface in
// bvh at positions x (the tree's last refit); reach [m] >= 0 is how far beyond the blade's back
// end to look when the blade crosses no face (the rest of the tool's shaft, which is outside);
// bridge [m] >= 0, the longest gap between two stretches taken as none.
// Throws std::invalid_argument for a non-finite tip, a direction not of unit length (off by more
// than 1e-6), length <= 0, reach < 0 or bridge < 0 (or non-finite).
void blade_in_tissue(const collide::SurfaceBvh& bvh, const Points& x, const Vec3& tip,
                     const Vec3& direction, Real length, Real reach, Real bridge,
                     BladeInTissue& found);

}  // namespace incise::sim::tools
