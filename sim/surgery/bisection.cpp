#include "sim/surgery/bisection.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

#include "sim/mesh/tet_adjacency.h"

namespace incise::sim::surgery {

namespace {

using Tet = std::array<int, 4>;

struct Shape {
  Real altitude = 0;  // smallest: 3 V / the largest face
  Real quality = 0;   // altitude / the longest edge
};

Shape shape_of(const std::array<Vec3, 4>& p) {
  const Real volume = signed_volume(p[0], p[1], p[2], p[3]);
  const Real face =
      0.5 *
      std::max({(p[1] - p[0]).cross(p[2] - p[0]).norm(), (p[1] - p[0]).cross(p[3] - p[0]).norm(),
                (p[2] - p[0]).cross(p[3] - p[0]).norm(), (p[2] - p[1]).cross(p[3] - p[1]).norm()});
  Real longest = 0;
  for (const auto& e : kTetEdges) {
    longest = std::max(
        longest, (p[static_cast<std::size_t>(e[0])] - p[static_cast<std::size_t>(e[1])]).norm());
  }
  if (!(face > 0) || !(longest > 0)) return {};
  const Real altitude = 3 * volume / face;
  return {altitude, altitude / longest};
}

Real segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const Real len2 = ab.squaredNorm();
  const Real t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, Real(0), Real(1)) : Real(0);
  return (a + t * ab - p).norm();
}

int position_of(const Tet& tet, int node) {
  for (int k = 0; k < 4; ++k) {
    if (tet[static_cast<std::size_t>(k)] == node) return k;
  }
  return -1;
}

// The mesh as growable arrays while splits append nodes and tets, with each node's tets.
class Refiner {
 public:
  Refiner(TetMesh& mesh, const BisectionSettings& settings, std::span<const char> frozen)
      : mesh_(mesh), settings_(settings), frozen_(frozen) {
    const int n = mesh.num_nodes();
    const bool with_x = mesh.x.rows() == n;
    const bool with_v = mesh.v.rows() == n;
    with_x_ = with_x;
    with_v_ = with_v;
    for (int i = 0; i < n; ++i) {
      rest_.push_back(row3(mesh.rest, i));
      if (with_x) x_.push_back(row3(mesh.x, i));
      if (with_v) v_.push_back(row3(mesh.v, i));
    }
    node_tets_.resize(static_cast<std::size_t>(n));
    for (int t = 0; t < mesh.num_tets(); ++t) {
      Tet tet;
      for (int k = 0; k < 4; ++k)
        tet[static_cast<std::size_t>(k)] = mesh.tets(t, k);
      tets_.push_back(tet);
      labels_.push_back(mesh.labels.size() == mesh.num_tets() ? mesh.labels(t) : 0);
      origin_.push_back(t);
      for (const int v : tet)
        node_tets_[static_cast<std::size_t>(v)].push_back(t);
    }
    changed_mark_.assign(tets_.size(), 0);
    report_.tets_before = mesh.num_tets();
    report_.nodes_before = n;
  }

  Real length(int a, int b) const {
    return (rest_[static_cast<std::size_t>(a)] - rest_[static_cast<std::size_t>(b)]).norm();
  }

  // Every edge longer than the target within radius of centre, longest first.
  std::vector<std::pair<int, int>> candidates(const Vec3& centre, Real radius) const {
    std::vector<std::pair<int, int>> edges;
    for (const Tet& tet : tets_) {
      for (const auto& e : kTetEdges) {
        int a = tet[static_cast<std::size_t>(e[0])], b = tet[static_cast<std::size_t>(e[1])];
        if (a > b) std::swap(a, b);
        if (length(a, b) <= settings_.edge_length) continue;
        if (segment_distance(centre, rest_[static_cast<std::size_t>(a)],
                             rest_[static_cast<std::size_t>(b)]) > radius) {
          continue;
        }
        edges.emplace_back(a, b);
      }
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    std::stable_sort(edges.begin(), edges.end(), [&](const auto& p, const auto& q) {
      return length(p.first, p.second) > length(q.first, q.second);
    });
    return edges;
  }

  // Splits (a, b) after the longer edges on its propagation path. Returns false if a split on
  // the path was refused (the edge stays).
  bool split_along_path(int a, int b) {
    std::vector<std::pair<int, int>> path{{a, b}};
    while (!path.empty()) {
      if (report_.splits >= settings_.max_splits) return false;
      const auto [p, q] = path.back();
      ring(p, q);
      if (ring_.empty()) {  // split already, on another path
        path.pop_back();
        continue;
      }
      // The longest edge over the tets around (p, q), if longer than (p, q).
      const Real own = length(p, q);
      Real best = own * (1 + 1e-12);
      std::pair<int, int> longer{-1, -1};
      for (const int t : ring_) {
        const Tet& tet = tets_[static_cast<std::size_t>(t)];
        for (const auto& e : kTetEdges) {
          const int u = tet[static_cast<std::size_t>(e[0])],
                    w = tet[static_cast<std::size_t>(e[1])];
          const Real l = length(u, w);
          if (l > best) {
            best = l;
            longer = {std::min(u, w), std::max(u, w)};
          }
        }
      }
      if (longer.first >= 0) {
        if (path.size() >= kMaxPath) return false;
        path.push_back(longer);
        continue;
      }
      if (!split(p, q)) return false;
      path.pop_back();
    }
    return true;
  }

  BisectionReport finish() {
    const int n = static_cast<int>(rest_.size());
    mesh_.rest.resize(n, 3);
    if (with_x_) mesh_.x.resize(n, 3);
    if (with_v_) mesh_.v.resize(n, 3);
    for (int i = 0; i < n; ++i) {
      const std::size_t is = static_cast<std::size_t>(i);
      mesh_.rest.row(i) = rest_[is].transpose();
      if (with_x_) mesh_.x.row(i) = x_[is].transpose();
      if (with_v_) mesh_.v.row(i) = v_[is].transpose();
    }
    const int m = static_cast<int>(tets_.size());
    mesh_.tets.resize(m, 4);
    mesh_.labels.resize(m);
    for (int t = 0; t < m; ++t) {
      const std::size_t ts = static_cast<std::size_t>(t);
      for (int k = 0; k < 4; ++k)
        mesh_.tets(t, k) = tets_[ts][static_cast<std::size_t>(k)];
      mesh_.labels(t) = labels_[ts];
      if (changed_mark_[ts] != 0) {
        report_.changed.push_back(t);
        report_.parents.push_back(origin_[ts]);
      }
    }
    return std::move(report_);
  }

  void count_refused() { ++report_.refused; }
  int splits() const { return report_.splits; }

 private:
  static constexpr std::size_t kMaxPath = 64;

  bool frozen(int t) const {
    return !frozen_.empty() && t < static_cast<int>(frozen_.size()) &&
           frozen_[static_cast<std::size_t>(t)] != 0;
  }

  void ring(int a, int b) {
    ring_.clear();
    for (const int t : node_tets_[static_cast<std::size_t>(a)]) {
      if (position_of(tets_[static_cast<std::size_t>(t)], b) >= 0) ring_.push_back(t);
    }
  }

  bool acceptable(const Tet& tet, int replaced, const Vec3& point) const {
    std::array<Vec3, 4> p;
    for (std::size_t k = 0; k < 4; ++k) {
      p[k] = tet[k] == replaced ? point : rest_[static_cast<std::size_t>(tet[k])];
    }
    const Shape s = shape_of(p);
    return s.altitude >= settings_.min_altitude && s.quality >= settings_.min_quality &&
           s.altitude > 0;
  }

  // Splits (a, b) at its midpoint; ring_ holds the tets around it.
  bool split(int a, int b) {
    const std::size_t as = static_cast<std::size_t>(a), bs = static_cast<std::size_t>(b);
    const Vec3 mid = 0.5 * (rest_[as] + rest_[bs]);
    for (const int t : ring_) {
      const Tet& tet = tets_[static_cast<std::size_t>(t)];
      if (frozen(t) || !acceptable(tet, b, mid) || !acceptable(tet, a, mid)) return false;
    }
    const int m = static_cast<int>(rest_.size());
    rest_.push_back(mid);
    if (with_x_) x_.push_back(0.5 * (x_[as] + x_[bs]));
    if (with_v_) v_.push_back(0.5 * (v_[as] + v_[bs]));
    node_tets_.emplace_back();
    for (const int t : ring_) {
      const std::size_t ts = static_cast<std::size_t>(t);
      Tet second = tets_[ts];
      second[static_cast<std::size_t>(position_of(second, a))] = m;  // (.., m, .., b, ..)
      Tet& first = tets_[ts];
      first[static_cast<std::size_t>(position_of(first, b))] = m;  // (.., a, .., m, ..)
      const int appended = static_cast<int>(tets_.size());
      tets_.push_back(second);
      labels_.push_back(labels_[ts]);
      origin_.push_back(origin_[ts]);
      changed_mark_[ts] = 1;
      changed_mark_.push_back(1);
      // Node stars: b leaves the first half, m joins both, the second half joins its nodes.
      auto& b_tets = node_tets_[bs];
      b_tets.erase(std::find(b_tets.begin(), b_tets.end(), t));
      node_tets_[static_cast<std::size_t>(m)].push_back(t);
      for (const int v : second)
        node_tets_[static_cast<std::size_t>(v)].push_back(appended);
    }
    report_.bisections.push_back({m, a, b});
    ++report_.splits;
    return true;
  }

  TetMesh& mesh_;
  const BisectionSettings& settings_;
  std::span<const char> frozen_;
  bool with_x_ = false, with_v_ = false;
  std::vector<Vec3> rest_, x_, v_;
  std::vector<Tet> tets_;
  std::vector<int> labels_;
  std::vector<int> origin_;  // per slot: the slot before the call it is a part of
  std::vector<char> changed_mark_;
  std::vector<std::vector<int>> node_tets_;
  std::vector<int> ring_;
  BisectionReport report_;
};

}  // namespace

BisectionReport refine_ball(TetMesh& mesh, const Vec3& centre, Real radius,
                            const BisectionSettings& settings, std::span<const char> frozen) {
  if (!(settings.edge_length > 0 && std::isfinite(settings.edge_length))) {
    throw std::invalid_argument("bisection: edge_length must be > 0");
  }
  if (!(settings.min_altitude >= 0) || !(settings.min_quality >= 0 && settings.min_quality < 1)) {
    throw std::invalid_argument("bisection: min_altitude must be >= 0, min_quality in [0, 1)");
  }
  if (settings.max_splits < 0) throw std::invalid_argument("bisection: max_splits must be >= 0");
  if (!centre.allFinite() || !(radius >= 0 && std::isfinite(radius))) {
    throw std::invalid_argument("bisection: the region must be finite, radius >= 0");
  }
  if (!frozen.empty() && static_cast<int>(frozen.size()) != mesh.num_tets()) {
    throw std::invalid_argument("bisection: frozen has " + std::to_string(frozen.size()) +
                                " entries for " + std::to_string(mesh.num_tets()) + " tets");
  }
  Refiner refiner(mesh, settings, frozen);
  // Passes until no split is made: the halves of a split edge may still be too long.
  for (;;) {
    const int before = refiner.splits();
    int refused = 0;
    for (const auto& [a, b] : refiner.candidates(centre, radius)) {
      if (refiner.length(a, b) <= settings.edge_length) continue;
      if (!refiner.split_along_path(a, b)) ++refused;
    }
    if (refiner.splits() == before || refiner.splits() >= settings.max_splits) {
      for (int k = 0; k < refused; ++k)
        refiner.count_refused();
      break;
    }
  }
  return refiner.finish();
}

void remap_bisections(std::vector<Bisection>& bisections, std::span<const int> node_map) {
  const auto mapped = [&](int node) {
    return node >= 0 && node < static_cast<int>(node_map.size())
               ? node_map[static_cast<std::size_t>(node)]
               : -1;
  };
  std::vector<Bisection> kept;
  for (const Bisection& s : bisections) {
    const Bisection r{mapped(s.mid), mapped(s.a), mapped(s.b)};
    if (r.mid >= 0 && r.a >= 0 && r.b >= 0) kept.push_back(r);
  }
  bisections = std::move(kept);
}

CoarsenReport undo_bisections(TetMesh& mesh, std::vector<Bisection>& bisections,
                              const std::function<bool(const Vec3& rest)>& keep) {
  const int n = mesh.num_nodes();
  const int m = mesh.num_tets();
  for (const Bisection& s : bisections) {
    if (s.mid < 0 || s.mid >= n || s.a < 0 || s.a >= n || s.b < 0 || s.b >= n) {
      throw std::invalid_argument("bisection: a split's node is out of range");
    }
  }
  std::vector<std::vector<int>> node_tets(static_cast<std::size_t>(n));
  for (int t = 0; t < m; ++t) {
    for (int k = 0; k < 4; ++k)
      node_tets[static_cast<std::size_t>(mesh.tets(t, k))].push_back(t);
  }
  // How many splits stand on a node (as an end of their edge): it cannot go before they do.
  std::vector<int> uses(static_cast<std::size_t>(n), 0);
  for (const Bisection& s : bisections) {
    ++uses[static_cast<std::size_t>(s.a)];
    ++uses[static_cast<std::size_t>(s.b)];
  }
  std::vector<char> tet_gone(static_cast<std::size_t>(m), 0);
  std::vector<char> node_gone(static_cast<std::size_t>(n), 0);
  std::vector<char> undone(bisections.size(), 0);
  CoarsenReport report;
  using Key = std::pair<int, int>;
  std::vector<std::pair<Key, int>> with_a, with_b;
  for (std::size_t k = bisections.size(); k-- > 0;) {
    const Bisection& s = bisections[k];
    if (uses[static_cast<std::size_t>(s.mid)] > 0) continue;
    if (keep && keep(row3(mesh.rest, s.mid))) continue;
    // The star of mid must be the split's pairs.
    with_a.clear();
    with_b.clear();
    bool ok = true;
    for (const int t : node_tets[static_cast<std::size_t>(s.mid)]) {
      if (tet_gone[static_cast<std::size_t>(t)] != 0) continue;
      bool has_a = false, has_b = false;
      std::array<int, 2> others{};
      int count = 0;
      for (int j = 0; j < 4; ++j) {
        const int v = mesh.tets(t, j);
        if (v == s.a) {
          has_a = true;
        } else if (v == s.b) {
          has_b = true;
        } else if (v != s.mid && count < 2) {
          others[static_cast<std::size_t>(count++)] = v;
        }
      }
      if (has_a == has_b || count != 2) {
        ok = false;
        break;
      }
      const Key key{std::min(others[0], others[1]), std::max(others[0], others[1])};
      (has_a ? with_a : with_b).emplace_back(key, t);
    }
    if (!ok || with_a.empty() || with_a.size() != with_b.size()) continue;
    std::sort(with_a.begin(), with_a.end());
    std::sort(with_b.begin(), with_b.end());
    for (std::size_t i = 0; i < with_a.size() && ok; ++i) {
      ok = with_a[i].first == with_b[i].first && (i == 0 || with_a[i].first != with_a[i - 1].first);
    }
    if (!ok) continue;
    for (const auto& [key, t] : with_a)
      tet_gone[static_cast<std::size_t>(t)] = 1;
    for (const auto& [key, t] : with_b) {
      for (int j = 0; j < 4; ++j) {
        if (mesh.tets(t, j) == s.mid) mesh.tets(t, j) = s.a;
      }
      node_tets[static_cast<std::size_t>(s.a)].push_back(t);
    }
    node_gone[static_cast<std::size_t>(s.mid)] = 1;
    --uses[static_cast<std::size_t>(s.a)];
    --uses[static_cast<std::size_t>(s.b)];
    undone[k] = 1;
    ++report.undone;
  }
  if (report.undone == 0) return report;
  // Compaction, order kept.
  report.node_map.assign(static_cast<std::size_t>(n), -1);
  int nodes = 0;
  for (int i = 0; i < n; ++i) {
    if (node_gone[static_cast<std::size_t>(i)] == 0)
      report.node_map[static_cast<std::size_t>(i)] = nodes++;
  }
  report.tet_map.assign(static_cast<std::size_t>(m), -1);
  int tets = 0;
  for (int t = 0; t < m; ++t) {
    if (tet_gone[static_cast<std::size_t>(t)] == 0)
      report.tet_map[static_cast<std::size_t>(t)] = tets++;
  }
  const bool with_x = mesh.x.rows() == n, with_v = mesh.v.rows() == n;
  TetMesh out;
  out.rest.resize(nodes, 3);
  if (with_x) out.x.resize(nodes, 3);
  if (with_v) out.v.resize(nodes, 3);
  for (int i = 0; i < n; ++i) {
    const int to = report.node_map[static_cast<std::size_t>(i)];
    if (to < 0) continue;
    out.rest.row(to) = mesh.rest.row(i);
    if (with_x) out.x.row(to) = mesh.x.row(i);
    if (with_v) out.v.row(to) = mesh.v.row(i);
  }
  out.tets.resize(tets, 4);
  out.labels.resize(tets);
  for (int t = 0; t < m; ++t) {
    const int to = report.tet_map[static_cast<std::size_t>(t)];
    if (to < 0) continue;
    for (int j = 0; j < 4; ++j)
      out.tets(to, j) = report.node_map[static_cast<std::size_t>(mesh.tets(t, j))];
    out.labels(to) = mesh.labels.size() == m ? mesh.labels(t) : 0;
  }
  mesh = std::move(out);
  std::vector<Bisection> left;
  for (std::size_t k = 0; k < bisections.size(); ++k) {
    if (undone[k] == 0) left.push_back(bisections[k]);
  }
  remap_bisections(left, report.node_map);
  bisections = std::move(left);
  return report;
}

}  // namespace incise::sim::surgery
