// A surgical scene's condensed far field: the tets outside the region of surgery, the nodes
// renumbered far field first, the hybrid condensed model, and the guard that keeps blades out.
#include "sim/surgery/surgical_scene_far_field.h"

#include <algorithm>
#include <cstddef>
#include <memory>
#include <utility>

#include "sim/cut/material_map.h"
#include "sim/models/hybrid_condensed_model.h"
#include "sim/surgery/surgical_scene_validation.h"

namespace incise::sim::surgery {
namespace {

// The far field's tets: no node within the region (rest).
std::vector<char> far_field_tets(const TetMesh& mesh, const FarFieldSpec& region) {
  std::vector<char> far(static_cast<std::size_t>(mesh.num_tets()), 1);
  for (int t = 0; t < mesh.num_tets(); ++t) {
    for (int k = 0; k < 4; ++k) {
      if ((row3(mesh.rest, mesh.tets(t, k)) - region.centre).norm() < region.radius) {
        far[static_cast<std::size_t>(t)] = 0;
      }
    }
  }
  return far;
}

// Renumbers the nodes so that the far field's come first, in their order, then the others: a
// compaction (sliver collapses, coarsening) removes operational nodes only and keeps the order,
// so the far field's tets keep their node numbers, which the condensed model holds them by.
void far_field_nodes_first(TetMesh& mesh, std::vector<char>& fixed, const std::vector<char>& far) {
  const int n = mesh.num_nodes();
  std::vector<char> in_far(static_cast<std::size_t>(n), 0);
  for (int t = 0; t < mesh.num_tets(); ++t) {
    if (far[static_cast<std::size_t>(t)] == 0) continue;
    for (int k = 0; k < 4; ++k)
      in_far[static_cast<std::size_t>(mesh.tets(t, k))] = 1;
  }
  std::vector<int> order;  // new -> old
  for (int pass = 1; pass >= 0; --pass) {
    for (int i = 0; i < n; ++i) {
      if (in_far[static_cast<std::size_t>(i)] == pass) order.push_back(i);
    }
  }
  std::vector<int> new_of(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k)
    new_of[static_cast<std::size_t>(order[static_cast<std::size_t>(k)])] = k;
  const auto permute = [&](Points& p) {
    if (p.rows() != n) return;
    Points q(n, 3);
    for (int k = 0; k < n; ++k)
      q.row(k) = p.row(order[static_cast<std::size_t>(k)]);
    p = std::move(q);
  };
  permute(mesh.rest);
  permute(mesh.x);
  permute(mesh.v);
  for (int t = 0; t < mesh.num_tets(); ++t) {
    for (int k = 0; k < 4; ++k)
      mesh.tets(t, k) = new_of[static_cast<std::size_t>(mesh.tets(t, k))];
  }
  std::vector<char> f(fixed.size(), 0);
  for (int k = 0; k < n && static_cast<std::size_t>(k) < fixed.size(); ++k)
    f[static_cast<std::size_t>(k)] =
        fixed[static_cast<std::size_t>(order[static_cast<std::size_t>(k)])];
  fixed = std::move(f);
}

}  // namespace

FarFieldSetup set_up_far_field(SurgicalSceneSpec& spec) {
  FarFieldSetup setup;
  setup.far = far_field_tets(spec.tissue, spec.far_field);
  const std::vector<char>& far = setup.far;
  const auto far_count = std::count(far.begin(), far.end(), 1);
  require(far_count > 0, "far_field: no tet lies outside the region (radius too large)");
  require(far_count < static_cast<long>(far.size()), "far_field: no tet lies inside the region");
  require(spec.fixed.size() == static_cast<std::size_t>(spec.tissue.num_nodes()),
          "fixed must have one entry per tissue node");
  far_field_nodes_first(spec.tissue, spec.fixed, far);
  // The guard: the longest edge of the operational tets that share a node with the far field.
  // A tet the blade passes through at a point more than that inside the region cannot hold a
  // far-field node (every one is outside the region), so neither it nor a tet sharing one of
  // its edges or faces (which holds that edge's or face's nodes) is a far-field tet: the cut
  // leaves the far field alone. The region less the guard is a ball, so the blade's ends
  // suffice.
  std::vector<char> far_node(static_cast<std::size_t>(spec.tissue.num_nodes()), 0);
  for (int t = 0; t < spec.tissue.num_tets(); ++t) {
    if (far[static_cast<std::size_t>(t)] == 0) continue;
    for (int k = 0; k < 4; ++k)
      far_node[static_cast<std::size_t>(spec.tissue.tets(t, k))] = 1;
  }
  Real longest = 0;
  for (int t = 0; t < spec.tissue.num_tets(); ++t) {
    bool interface = false;
    for (int k = 0; k < 4; ++k)
      interface = interface || far_node[static_cast<std::size_t>(spec.tissue.tets(t, k))] != 0;
    if (far[static_cast<std::size_t>(t)] != 0 || !interface) continue;
    for (int i = 0; i < 4; ++i) {
      for (int j = i + 1; j < 4; ++j) {
        longest = std::max(longest, (row3(spec.tissue.rest, spec.tissue.tets(t, i)) -
                                     row3(spec.tissue.rest, spec.tissue.tets(t, j)))
                                        .norm());
      }
    }
  }
  setup.guard = 1.1 * longest;  // a margin for the blade's material map
  const ModelFactory operational = spec.model;
  require(static_cast<bool>(operational), "model: no factory");
  setup.model = [operational, far, materials = spec.far_field.materials](const TetMesh& mesh) {
    std::vector<char> flags(far.size());
    for (std::size_t t = 0; t < far.size(); ++t)
      flags[t] = far[t] != 0 ? 0 : 1;
    return std::make_unique<HybridCondensedModel>(
        mesh, flags, materials,
        [operational](const TetMesh& m, const std::vector<ElementMaterial>&) {
          return operational(m);
        });
  };
  return setup;
}

bool SurgicalScene::blade_outside_region(const Vec3& a, const Vec3& b) const {
  const TetMesh& mesh = tissue_->mesh();
  const FarFieldSpec& region = spec_.far_field;
  for (const Vec3& p : {a, b}) {
    // Where the blade's end is in the material; where it cannot be mapped (in the air beyond
    // reach), its position stands for it.
    const auto map = cut::material_map_at(mesh, p, 2 * far_guard_);
    const Vec3 rest = map ? map->rest_of(p) : p;
    if ((rest - region.centre).norm() > region.radius - far_guard_) return true;
  }
  return false;
}

}  // namespace incise::sim::surgery
