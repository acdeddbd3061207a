#include "sim/models/model.h"

#include <algorithm>
#include <atomic>
#include <stdexcept>

namespace incise::sim {
namespace {

// The triplets of K then D whose row node is at or below the column node: with the mirror of
// the off-diagonal ones they give the whole symmetric matrix.
bool on_or_below_block_diagonal(const Eigen::Triplet<Real>& t) {
  return t.row() / 3 >= t.col() / 3;
}

}  // namespace

void Model::update_elements(const TetMesh& mesh, const std::vector<char>& alive,
                            std::span<const int>) {
  if (alive.size() != static_cast<std::size_t>(mesh.num_tets())) {
    throw std::invalid_argument("update_elements: alive must have one entry per tet slot");
  }
  TetMesh compact;
  compact.rest = mesh.rest;
  compact.x = mesh.x.rows() == mesh.rest.rows() ? mesh.x : mesh.rest;
  compact.v = Points::Zero(mesh.rest.rows(), 3);
  const auto count = std::count_if(alive.begin(), alive.end(), [](char a) { return a != 0; });
  compact.tets.resize(count, 4);
  compact.labels.resize(count);
  Eigen::Index row = 0;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    if (alive[static_cast<std::size_t>(t)] == 0) continue;
    compact.tets.row(row) = mesh.tets.row(t);
    compact.labels(row) = mesh.labels.size() == 0 ? 0 : mesh.labels(t);
    ++row;
  }
  update_topology(compact);
}

std::uint64_t Model::next_topology_revision() {
  static std::atomic<std::uint64_t> counter{1};
  return counter.fetch_add(1, std::memory_order_relaxed);
}

// The defaults: one block per triplet on or below the block diagonal, holding its single entry.
bool Model::soften_element(int, Real) {
  return false;
}

void Model::system_blocks(std::vector<std::pair<int, int>>& blocks) const {
  std::vector<Eigen::Triplet<Real>> triplets;
  add_stiffness_triplets(triplets);
  add_damping_triplets(triplets);
  for (const auto& t : triplets) {
    if (on_or_below_block_diagonal(t)) blocks.emplace_back(t.row() / 3, t.col() / 3);
  }
}

void Model::add_system_blocks(Real damping_scale, Real stiffness_scale,
                              const BlockTarget& target) const {
  std::vector<Eigen::Triplet<Real>> triplets;
  add_stiffness_triplets(triplets);
  const std::size_t stiffness_count = triplets.size();
  add_damping_triplets(triplets);
  std::size_t k = 0;
  for (std::size_t t = 0; t < triplets.size(); ++t) {
    const auto& entry = triplets[t];
    if (!on_or_below_block_diagonal(entry)) continue;
    Mat3 block = Mat3::Zero();
    block(entry.row() % 3, entry.col() % 3) =
        (t < stiffness_count ? stiffness_scale : damping_scale) * entry.value();
    target.add(k++, block);
  }
}

}  // namespace incise::sim
