// The hybrid condensed model's partition: the region meshes, the far field's nodes split into
// retained and interior ones, and a far-field matrix split into the blocks of that split.
#include "sim/models/hybrid_condensed_partition.h"

#include <algorithm>

#include "sim/mesh/boundary_surface.h"
#include "sim/models/hybrid_condensed_model.h"

namespace incise::sim {

Eigen::RowVector4i sorted_tet(const Tets& tets, Eigen::Index row) {
  Eigen::RowVector4i t = tets.row(row);
  std::sort(t.data(), t.data() + 4);
  return t;
}

TetMesh region_mesh(const TetMesh& mesh, const std::vector<char>& operational, bool keep) {
  TetMesh region;
  region.rest = mesh.rest;
  region.x = mesh.rest;
  region.v = Points::Zero(mesh.rest.rows(), 3);
  const auto count = std::count_if(operational.begin(), operational.end(),
                                   [keep](char o) { return (o != 0) == keep; });
  region.tets.resize(count, 4);
  region.labels.resize(count);
  Eigen::Index row = 0;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    if ((operational[static_cast<std::size_t>(t)] != 0) != keep) continue;
    region.tets.row(row) = mesh.tets.row(t);
    region.labels(row) = mesh.labels.size() == 0 ? 0 : mesh.labels(t);
    ++row;
  }
  return region;
}

Partition partition(const Triplets& entries, const std::vector<int>& local, Eigen::Index s_dofs,
                    Eigen::Index i_dofs) {
  Partition p;
  p.ss = Eigen::MatrixXd::Zero(s_dofs, s_dofs);
  Triplets si, is, ii;
  for (const auto& e : entries) {
    const int r = local[static_cast<std::size_t>(e.row())];
    const int c = local[static_cast<std::size_t>(e.col())];
    if (r < 0 || c < 0) continue;
    if (r < s_dofs && c < s_dofs) {
      p.ss(r, c) += e.value();
    } else if (r < s_dofs) {
      si.emplace_back(r, c - s_dofs, e.value());
    } else if (c < s_dofs) {
      is.emplace_back(r - s_dofs, c, e.value());
    } else {
      ii.emplace_back(r - s_dofs, c - s_dofs, e.value());
    }
  }
  p.si.resize(s_dofs, i_dofs);
  p.is.resize(i_dofs, s_dofs);
  p.ii.resize(i_dofs, i_dofs);
  p.si.setFromTriplets(si.begin(), si.end());
  p.is.setFromTriplets(is.begin(), is.end());
  p.ii.setFromTriplets(ii.begin(), ii.end());
  return p;
}

std::vector<int> HybridCondensedModel::partition_nodes(const TetMesh& mesh, const TetMesh& far,
                                                       const std::vector<char>& operational) {
  const int n = mesh.num_nodes();
  // Retained: far-field nodes on the body's surface or on an operational tet.
  std::vector<char> in_far(static_cast<std::size_t>(n), 0), keep(static_cast<std::size_t>(n), 0);
  for (int t = 0; t < far.num_tets(); ++t) {
    for (int a = 0; a < 4; ++a)
      in_far[static_cast<std::size_t>(far.tets(t, a))] = 1;
  }
  for (const int node : boundary_surface(mesh).nodes)
    keep[static_cast<std::size_t>(node)] = 1;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    if (operational[static_cast<std::size_t>(t)] == 0) continue;
    for (int a = 0; a < 4; ++a)
      keep[static_cast<std::size_t>(mesh.tets(t, a))] = 1;
  }
  condensed_.assign(static_cast<std::size_t>(n), 0);
  for (int i = 0; i < n; ++i) {
    const std::size_t is = static_cast<std::size_t>(i);
    if (in_far[is] == 0) continue;
    if (keep[is] != 0) {
      retained_.push_back(i);
    } else {
      interior_.push_back(i);
      condensed_[is] = 1;
    }
  }
  const Eigen::Index s_dofs = 3 * static_cast<Eigen::Index>(retained_.size());
  std::vector<int> local(3 * static_cast<std::size_t>(n), -1);
  for (std::size_t k = 0; k < retained_.size(); ++k) {
    for (int c = 0; c < 3; ++c)
      local[3 * static_cast<std::size_t>(retained_[k]) + c] = static_cast<int>(3 * k) + c;
  }
  for (std::size_t k = 0; k < interior_.size(); ++k) {
    for (int c = 0; c < 3; ++c) {
      local[3 * static_cast<std::size_t>(interior_[k]) + c] =
          static_cast<int>(s_dofs + 3 * static_cast<Eigen::Index>(k)) + c;
    }
  }
  return local;
}

}  // namespace incise::sim
