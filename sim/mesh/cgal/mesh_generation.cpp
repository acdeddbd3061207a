#include "sim/mesh/cgal/mesh_generation.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <functional>
#include <stdexcept>
#include <string>
#include <tuple>
#include <unordered_map>
#include <utility>
#include <vector>

// CGAL behind a door (STYLE.md): in sim/mesh/cgal/ only this file includes it. The project's
// other CGAL include is sim/remesh/predicates.cpp (exact predicates for remeshing).
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/Random.h>
#include <CGAL/make_mesh_3.h>

namespace incise::sim {
namespace {

// The typedef chain of CGAL's Mesh_3 examples: exact predicates so that the Delaunay refinement
// never takes a wrong branch on round-off, inexact (double) constructions for speed.
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Domain = CGAL::Labeled_mesh_domain_3<Kernel>;
using Triangulation = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
using Complex = CGAL::Mesh_complex_3_in_triangulation_3<Triangulation>;
using Criteria = CGAL::Mesh_criteria_3<Triangulation>;
using Point = Kernel::Point_3;

// The subdomain (tissue label, 0 = outside) at a point.
using Labelling = std::function<int(const Point&)>;

// Mesh_3 starts from points on the surfaces. Labeled_mesh_domain_3 finds them by shooting random
// rays from the bounds' centre until enough hit a surface, which misses components that few rays
// reach and can search for minutes for a small shape off-centre. This domain hands Mesh_3 the
// points seed_surfaces found on a grid instead, so every component and every interface larger
// than about the facet size is seeded, in a time that does not depend on luck.
class SeededDomain : public Domain {
 public:
  using Domain::Domain;

  std::vector<std::pair<Point, Index>> seeds;

  struct Construct_initial_points {
    const SeededDomain& domain;
    template <class OutputIterator>
    OutputIterator operator()(OutputIterator out, int /*wanted: we give all seeds*/ = 0) const {
      for (const auto& seed : domain.seeds)
        *out++ = seed;
      return out;
    }
  };
  // Hides Domain's version: make_mesh_3 is a template on the domain's type and calls this one.
  Construct_initial_points construct_initial_points_object() const { return {*this}; }
};

// Samples labelling on a grid of step about `step` [m] over box (at most kMaxGridPoints per axis)
// and returns one surface point, found by the domain's bisection, per grid edge whose ends differ
// in label, keeping points at least `spacing` [m] apart so the seeds are no denser than the
// surface mesh the criteria ask for.
constexpr int kMaxGridPoints = 128;
std::vector<std::pair<Point, Domain::Index>> seed_surfaces(const Domain& domain,
                                                           const Labelling& labelling,
                                                           const Box3& box, Real step,
                                                           Real spacing) {
  Eigen::Vector3i n;
  Vec3 h;
  for (int a = 0; a < 3; ++a) {
    n[a] = std::clamp(static_cast<int>(std::ceil(box.sizes()[a] / step)) + 1, 2, kMaxGridPoints);
    h[a] = box.sizes()[a] / (n[a] - 1);
  }
  const auto node = [&](int i, int j, int k) {
    const Vec3 p = box.min() + Vec3(i, j, k).cwiseProduct(h);
    return Point(p.x(), p.y(), p.z());
  };
  const auto id = [&](int i, int j, int k) {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(n.x()) *
               (static_cast<std::size_t>(j) + static_cast<std::size_t>(n.y()) * k);
  };
  std::vector<int> label(static_cast<std::size_t>(n.prod()));
  for (int k = 0; k < n.z(); ++k)
    for (int j = 0; j < n.y(); ++j)
      for (int i = 0; i < n.x(); ++i)
        label[id(i, j, k)] = labelling(node(i, j, k));

  // Kept seeds hashed by the cell of size `spacing` they fall in, to test distances locally.
  std::unordered_map<long long, std::vector<int>> near;
  const auto cell_of = [&](const Point& p, int di, int dj, int dk) {
    const Vec3 c = ((Vec3(p.x(), p.y(), p.z()) - box.min()) / spacing).array().floor();
    return ((static_cast<long long>(c.x()) + di) * 1048576LL + static_cast<long long>(c.y()) + dj) *
               1048576LL +
           static_cast<long long>(c.z()) + dk;
  };
  std::vector<std::pair<Point, Domain::Index>> seeds;
  const auto construct_intersection = domain.construct_intersection_object();
  for (int k = 0; k < n.z(); ++k)
    for (int j = 0; j < n.y(); ++j)
      for (int i = 0; i < n.x(); ++i)
        for (int a = 0; a < 3; ++a) {
          const Eigen::Vector3i e = Eigen::Vector3i(i, j, k) + Eigen::Vector3i::Unit(a);
          if (e[a] >= n[a] || label[id(i, j, k)] == label[id(e.x(), e.y(), e.z())]) continue;
          const auto hit =
              construct_intersection(Kernel::Segment_3(node(i, j, k), node(e.x(), e.y(), e.z())));
          if (std::get<2>(hit) == 0) continue;  // no crossing found
          const Point& p = std::get<0>(hit);
          bool crowded = false;
          for (int di = -1; di <= 1 && !crowded; ++di)
            for (int dj = -1; dj <= 1 && !crowded; ++dj)
              for (int dk = -1; dk <= 1 && !crowded; ++dk) {
                const auto it = near.find(cell_of(p, di, dj, dk));
                if (it == near.end()) continue;
                for (int s : it->second) {
                  crowded =
                      crowded || CGAL::squared_distance(seeds[s].first, p) < spacing * spacing;
                }
              }
          if (crowded) continue;
          near[cell_of(p, 0, 0, 0)].push_back(static_cast<int>(seeds.size()));
          seeds.emplace_back(p, std::get<1>(hit));
        }
  return seeds;
}

// Boundary vertices are placed by bisection to this fraction of the bounds' diagonal.
constexpr Real kRelativeErrorBound = 1e-5;
// Above this many tets (estimated) the criteria are taken for a mistake, not a request.
constexpr Real kMaxEstimatedTets = 5e6;

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what);
}

void check_size(Real value, const char* name) {
  require(std::isfinite(value) && value > 0, std::string("meshing criteria: ") + name +
                                                 " must be finite and > 0, got " +
                                                 std::to_string(value));
}

// Refuses criteria whose element count over box would run for hours: a tet of circumradius R
// is at most as large as the regular one, 8 R^3 / (9 sqrt 3) ~ 0.513 R^3.
void check_mesh_size(const Box3& box, const MeshingCriteria& c) {
  const Real r = std::min(c.cell_size, c.facet_size);
  const Real estimate = box.volume() / (0.513 * r * r * r);
  require(estimate <= kMaxEstimatedTets, "meshing criteria: sizes of " + std::to_string(r) +
                                             " m over the shape would need ~" +
                                             std::to_string(static_cast<long long>(estimate)) +
                                             " tets (limit 5e6); coarsen cell_size or facet_size");
}

Vec3 to_vec3(const Point& p) {
  return Vec3(p.x(), p.y(), p.z());
}

// The cells of the complex (tets inside a subdomain) as our arrays, vertices numbered in the
// order the cells first use them, each tet positively oriented.
TetMesh to_tet_mesh(const Complex& complex) {
  std::unordered_map<const void*, int> node_of;  // vertex address -> our node index
  std::vector<Vec3> nodes;
  const auto num_cells = static_cast<Eigen::Index>(complex.number_of_cells_in_complex());
  Tets tets(num_cells, 4);
  Eigen::VectorXi labels(num_cells);
  Eigen::Index t = 0;
  for (auto cell = complex.cells_in_complex_begin(); cell != complex.cells_in_complex_end();
       ++cell, ++t) {
    for (int k = 0; k < 4; ++k) {
      const auto vertex = cell->vertex(k);
      const auto [it, inserted] = node_of.try_emplace(&*vertex, static_cast<int>(nodes.size()));
      if (inserted) nodes.push_back(to_vec3(vertex->point().point()));
      tets(t, k) = it->second;
    }
    labels[t] = static_cast<int>(complex.subdomain_index(cell));
  }
  Points rest(static_cast<Eigen::Index>(nodes.size()), 3);
  for (std::size_t i = 0; i < nodes.size(); ++i)
    rest.row(static_cast<Eigen::Index>(i)) = nodes[i];
  for (Eigen::Index i = 0; i < tets.rows(); ++i) {
    const Real v = signed_volume(row3(rest, tets(i, 0)), row3(rest, tets(i, 1)),
                                 row3(rest, tets(i, 2)), row3(rest, tets(i, 3)));
    if (v < 0) std::swap(tets(i, 2), tets(i, 3));
    if (!(v != 0)) throw std::runtime_error("CGAL Mesh_3 produced a flat tet (zero volume)");
  }
  return make_tet_mesh(std::move(rest), std::move(tets), std::move(labels));
}

// Meshes the subdomains with label != 0 of labelling inside bounds; the surfaces are sought on a
// grid of step `step` over `shape_box` (the part of bounds holding the shape).
TetMesh mesh_labelling(const Labelling& labelling, const Box3& bounds, const Box3& shape_box,
                       Real step, const MeshingCriteria& c) {
  CGAL::Random random(0);
  const Kernel::Iso_cuboid_3 box(bounds.min().x(), bounds.min().y(), bounds.min().z(),
                                 bounds.max().x(), bounds.max().y(), bounds.max().z());
  SeededDomain domain(labelling, box, kRelativeErrorBound, CGAL::Null_subdomain_index(), &random);
  domain.seeds = seed_surfaces(domain, labelling, shape_box, step, c.facet_size);
  // A shape little larger than the facet size gets too few seeds for a first tetrahedron: seed it
  // as densely as the grid allows.
  if (domain.seeds.size() < 8) {
    domain.seeds = seed_surfaces(domain, labelling, shape_box, step, step / 2);
  }
  if (domain.seeds.size() < 4) {
    throw std::runtime_error("CGAL Mesh_3: found " + std::to_string(domain.seeds.size()) +
                             " surface points on a grid of step " + std::to_string(step) +
                             " m: the shape is too small for the criteria (lower facet_size)");
  }
  namespace params = CGAL::parameters;
  const Criteria criteria(
      params::facet_angle = c.facet_angle_deg, params::facet_size = c.facet_size,
      params::facet_distance = c.facet_distance,
      params::cell_radius_edge_ratio = c.cell_radius_edge_ratio, params::cell_size = c.cell_size);
  Complex complex;
  try {
    // time_limit = 0: no wall-clock limit, so the result does not depend on the machine's speed.
    if (c.odt_iterations > 0) {
      complex = CGAL::make_mesh_3<Complex>(
          domain, criteria,
          params::odt(params::time_limit = 0,
                      params::max_iteration_number = static_cast<std::size_t>(c.odt_iterations)),
          params::perturb(params::time_limit = 0, params::sliver_bound = c.sliver_bound_deg),
          params::exude(params::time_limit = 0, params::sliver_bound = c.sliver_bound_deg));
    } else {
      complex = CGAL::make_mesh_3<Complex>(
          domain, criteria,
          params::perturb(params::time_limit = 0, params::sliver_bound = c.sliver_bound_deg),
          params::exude(params::time_limit = 0, params::sliver_bound = c.sliver_bound_deg));
    }
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("CGAL Mesh_3 failed: ") + e.what());
  }
  if (complex.number_of_cells_in_complex() == 0) {
    throw std::runtime_error(
        "CGAL Mesh_3 produced no tets: the shape is too thin or small for the criteria "
        "(lower facet_size and facet_distance)");
  }
  return to_tet_mesh(complex);
}

}  // namespace

void check_meshing_criteria(const MeshingCriteria& c) {
  check_size(c.cell_size, "cell_size");
  check_size(c.facet_distance, "facet_distance");
  check_size(c.facet_size, "facet_size");
  require(std::isfinite(c.facet_angle_deg) && c.facet_angle_deg > 0 && c.facet_angle_deg <= 30,
          "meshing criteria: facet_angle_deg must be in (0, 30] (Mesh_3 terminates only up to "
          "30), got " +
              std::to_string(c.facet_angle_deg));
  require(std::isfinite(c.cell_radius_edge_ratio) && c.cell_radius_edge_ratio >= 2,
          "meshing criteria: cell_radius_edge_ratio must be >= 2 (Mesh_3 terminates only from "
          "2), got " +
              std::to_string(c.cell_radius_edge_ratio));
  require(c.odt_iterations >= 0 && c.odt_iterations <= 1000,
          "meshing criteria: odt_iterations must be in [0, 1000], got " +
              std::to_string(c.odt_iterations));
  require(std::isfinite(c.sliver_bound_deg) && c.sliver_bound_deg >= 0 && c.sliver_bound_deg < 30,
          "meshing criteria: sliver_bound_deg must be in [0, 30), got " +
              std::to_string(c.sliver_bound_deg));
}

TetMesh mesh_implicit(const ImplicitShape& shape, const Box3& bounds,
                      const MeshingCriteria& criteria) {
  check_implicit_shape(shape);
  check_meshing_criteria(criteria);
  require(bounds.min().allFinite() && bounds.max().allFinite() && !bounds.isEmpty() &&
              bounds.volume() > 0,
          "mesh_implicit: bounds must be a finite box of positive volume");
  const Box3 extent = implicit_extent(shape);
  require(bounds.contains(extent),
          "mesh_implicit: the shape's extent does not fit inside bounds (the shape would be "
          "clipped)");
  check_mesh_size(extent, criteria);
  // Sample around the shape, one step beyond it, so the grid's outer nodes are outside.
  const Real step = criteria.facet_size / 2;
  const Box3 shape_box =
      Box3(extent.min() - Vec3::Constant(step), extent.max() + Vec3::Constant(step))
          .intersection(bounds);
  return mesh_labelling(
      [&shape](const Point& p) { return implicit_value(shape, to_vec3(p)) < 0 ? 1 : 0; }, bounds,
      shape_box, step, criteria);
}

TetMesh mesh_labelled_volume(const LabelVolume& volume, const MeshingCriteria& criteria) {
  check_label_volume(volume);
  check_meshing_criteria(criteria);
  // One voxel of label 0 all round, so that the tissue's outer surface lies inside the bounds.
  const Box3 extent = label_volume_extent(volume);
  const Vec3 margin = Vec3::Constant(volume.spacing.maxCoeff());
  const Box3 bounds(extent.min() - margin, extent.max() + margin);
  check_mesh_size(extent, criteria);
  const Real step = std::min(volume.spacing.minCoeff(), criteria.facet_size / 2);
  return mesh_labelling([&volume](const Point& p) { return label_at(volume, to_vec3(p)); }, bounds,
                        bounds, step, criteria);
}

}  // namespace incise::sim
