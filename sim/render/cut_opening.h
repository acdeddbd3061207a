#pragma once
// Opens the picture's cuts. A cut in the simulation leaves two walls at the same place: nothing
// pulls them apart (the tissue has no pre-stress), so seen from above a deep cut is a hairline.
// Living tissue is under tension and an incision gapes; the picture shows that by moving each
// vertex of a cut wall into its own side of the tissue, along the wall's outward normal averaged
// over the vertex's wall faces, by half the gape. Where the two walls meet (the crack's floor and
// its ends) their normals cancel and the vertex stays: the opening narrows to nothing there, a V
// in section. Only the drawn positions move; the simulation's do not.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace incise::render {

using SurfacePositions = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using SurfaceFaces = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;

// V: #V by 3 positions [m], moved in place; F: #F by 3 faces, counter-clockwise seen from outside
// the tissue; cut_faces: per face, non-zero for a cut wall (#F entries; fewer: nothing moves).
// A vertex moves by gape / 2 times |sum of its wall faces' area vectors| / (sum of their areas),
// against that sum's direction. scratch is reused between calls (no allocation once grown).
void open_cut_walls(const SurfaceFaces& F, const std::vector<std::uint8_t>& cut_faces, double gape,
                    SurfacePositions& V, std::vector<double>& scratch);

}  // namespace incise::render
