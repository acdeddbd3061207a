#pragma once

// The scalar and array types every part of sim/ uses. Per-node and per-element state is kept as
// structure of arrays: one row-major matrix per attribute, one row per node or element, so that a
// node's three coordinates are contiguous (like PositionBasedDynamics' ParticleData).

#include <cstdint>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace incise::sim {

using Real = double;
using Vec3 = Eigen::Matrix<Real, 3, 1>;
using Mat3 = Eigen::Matrix<Real, 3, 3>;
using VecX = Eigen::Matrix<Real, Eigen::Dynamic, 1>;
using Vec3i = Eigen::Vector3i;
using Box3 = Eigen::AlignedBox<Real, 3>;

// #nodes by 3 node attribute (positions [m], velocities [m/s], forces [N], ...).
using Points = Eigen::Matrix<Real, Eigen::Dynamic, 3, Eigen::RowMajor>;
// #nodes by 3 per-coordinate flags, 1 = set (e.g. the coordinate is prescribed).
using AxisMask = Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 3, Eigen::RowMajor>;
// #tets by 4 node indices.
using Tets = Eigen::Matrix<int, Eigen::Dynamic, 4, Eigen::RowMajor>;
// #edges by 2 node indices.
using Edges = Eigen::Matrix<int, Eigen::Dynamic, 2, Eigen::RowMajor>;
// #triangles by 3 node indices.
using Triangles = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;

// Row i of a #nodes by 3 array as a column vector.
inline Vec3 row3(const Points& points, int i) {
  return points.row(i).transpose();
}

}  // namespace incise::sim
