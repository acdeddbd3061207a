#include "sim/cut/progressive_cutter.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/LU>

#include "sim/cut/material_map.h"
#include "sim/mesh/tet_adjacency.h"

namespace incise::sim::cut {
namespace {

Box3 tet_box(const Points& positions, const Tets& tets, int t) {
  Box3 box;
  for (int k = 0; k < 4; ++k)
    box.extend(row3(positions, tets(t, k)));
  return box;
}

Box3 grown(const Box3& box, Real by) {
  return Box3(box.min().array() - by, box.max().array() + by);
}

}  // namespace

ProgressiveCutter::ProgressiveCutter(TetMesh& mesh, const CutOptions& options, Real pose_spacing,
                                     BladeSpace space)
    : mesh_(&mesh), options_(options), space_(space) {
  if (!(options.snap > 0 && options.snap < 0.5)) {
    throw std::invalid_argument("cut snap fraction " + std::to_string(options.snap) +
                                " is outside (0, 0.5)");
  }
  if (!(pose_spacing >= 0)) {
    throw std::invalid_argument("pose spacing " + std::to_string(pose_spacing) + " is negative");
  }
  committed_nodes_ = mesh.num_nodes();
  committed_tets_ = mesh.num_tets();
  pose_spacing_ = pose_spacing;
  if (pose_spacing_ == 0 && mesh.num_tets() > 0) {
    const Edges edges = unique_edges(mesh.tets);
    Real sum = 0;
    for (Eigen::Index e = 0; e < edges.rows(); ++e)
      sum += (row3(cut_positions(), edges(e, 0)) - row3(cut_positions(), edges(e, 1))).norm();
    pose_spacing_ = 0.25 * sum / static_cast<Real>(edges.rows());
  }
}

void ProgressiveCutter::undo_temporary() {
  for (auto it = saved_rows_.rbegin(); it != saved_rows_.rend(); ++it) {
    for (int k = 0; k < 4; ++k)
      mesh_->tets(it->first, k) = it->second[static_cast<std::size_t>(k)];
    frame_.changed_tets.push_back(it->first);
  }
  saved_rows_.clear();
  for (int t = committed_tets_; t < mesh_->num_tets(); ++t)
    frame_.changed_tets.push_back(t);
  mesh_->tets.conservativeResize(committed_tets_, 4);
  mesh_->labels.conservativeResize(committed_tets_);
  mesh_->rest.conservativeResize(committed_nodes_, 3);
  mesh_->x.conservativeResize(committed_nodes_, 3);
  mesh_->v.conservativeResize(committed_nodes_, 3);
}

void ProgressiveCutter::collect_region(const Box3& quad_box) {
  // Active: the tets within D (the largest tet diameter) of the newest quad's box. Region: every
  // tet sharing a node with an active one (the stars of their nodes).
  Real diameter = 0;
  for (int t = 0; t < mesh_->num_tets(); ++t)
    diameter = std::max(diameter, tet_box(cut_positions(), mesh_->tets, t).sizes().norm());
  const Box3 near = grown(quad_box, diameter);
  active_slots_.clear();
  for (int t = 0; t < mesh_->num_tets(); ++t) {
    if (tet_box(cut_positions(), mesh_->tets, t).intersects(near)) active_slots_.push_back(t);
  }
  collect_star(active_slots_);
  std::size_t next_active = 0;  // both lists ascending
  for (std::size_t k = 0; k < region_slots_.size(); ++k) {
    const bool active =
        next_active < active_slots_.size() && active_slots_[next_active] == region_slots_[k];
    if (active) ++next_active;
    region_active_[k] = active ? 1 : 0;
  }
}

void ProgressiveCutter::collect_star(const std::vector<int>& seeds) {
  // The region: every tet sharing a node with a seed (the seeds' stars), no tet active.
  if (marked_.size() < static_cast<std::size_t>(mesh_->num_nodes()))
    marked_.resize(static_cast<std::size_t>(mesh_->num_nodes()), 0);
  for (int t : seeds) {
    for (int k = 0; k < 4; ++k)
      marked_[static_cast<std::size_t>(mesh_->tets(t, k))] = 1;
  }
  region_slots_.clear();
  region_active_.clear();
  for (int t = 0; t < mesh_->num_tets(); ++t) {
    bool in = false;
    for (int k = 0; k < 4; ++k)
      in = in || marked_[static_cast<std::size_t>(mesh_->tets(t, k))] != 0;
    if (!in) continue;
    region_slots_.push_back(t);
    region_active_.push_back(0);
  }
  for (int t : seeds) {
    for (int k = 0; k < 4; ++k)
      marked_[static_cast<std::size_t>(mesh_->tets(t, k))] = 0;
  }
}

CutSurface ProgressiveCutter::region_surface() const {
  // The stroke's quads that meet the region (older parts of the strip cannot cross its edges).
  Box3 region_box;
  for (int i = 0; i < region_num_nodes_; ++i)
    region_box.extend(row3(region_.x, i));
  std::vector<int> quads;
  for (std::size_t k = 0; k + 1 < stroke_a_.size(); ++k) {
    Box3 box;
    for (const Vec3& p : {stroke_a_[k], stroke_b_[k], stroke_a_[k + 1], stroke_b_[k + 1]})
      box.extend(p);
    if (box.intersects(region_box)) quads.push_back(static_cast<int>(k));
  }
  CutSurface surface;
  surface.vertices.resize(4 * static_cast<Eigen::Index>(quads.size()), 3);
  surface.triangles.resize(2 * static_cast<Eigen::Index>(quads.size()), 3);
  for (std::size_t q = 0; q < quads.size(); ++q) {
    const auto k = static_cast<std::size_t>(quads[q]);
    const auto v = 4 * static_cast<int>(q);
    surface.vertices.row(v) = stroke_a_[k].transpose();
    surface.vertices.row(v + 1) = stroke_b_[k].transpose();
    surface.vertices.row(v + 2) = stroke_a_[k + 1].transpose();
    surface.vertices.row(v + 3) = stroke_b_[k + 1].transpose();
    surface.triangles.row(2 * static_cast<Eigen::Index>(q)) << v, v + 1, v + 3;
    surface.triangles.row(2 * static_cast<Eigen::Index>(q) + 1) << v, v + 3, v + 2;
  }
  return surface;
}

void ProgressiveCutter::commit_complete_cuts(const CutSurface& surface) {
  const CutReport committed = cut_mesh_active(region_, surface, region_active_, options_);
  frame_.committed_new_tets = write_back(false);
  report_committed_faces(committed.crack_faces);
}

void ProgressiveCutter::report_committed_faces(const Triangles& local_faces) {
  frame_.committed_crack_faces += static_cast<int>(local_faces.rows());
  std::vector<int> labels(static_cast<std::size_t>(local_faces.rows()), 0);
  if (local_faces.rows() > 0) {
    // The label of the piece each crack face bounds, found among the region's tets (each crack
    // face is a face of exactly one of them) before the blade's temporary split changes them.
    std::vector<std::pair<std::array<int, 3>, int>> faces;
    for (int t = 0; t < region_.num_tets(); ++t) {
      for (int k = 0; k < 4; ++k) {
        std::array<int, 3> key = {region_.tets(t, (k + 1) % 4), region_.tets(t, (k + 2) % 4),
                                  region_.tets(t, (k + 3) % 4)};
        std::sort(key.begin(), key.end());
        faces.push_back({key, region_.labels(t)});
      }
    }
    std::sort(faces.begin(), faces.end());
    for (Eigen::Index f = 0; f < local_faces.rows(); ++f) {
      std::array<int, 3> key = {local_faces(f, 0), local_faces(f, 1), local_faces(f, 2)};
      std::sort(key.begin(), key.end());
      const auto it = std::lower_bound(faces.begin(), faces.end(), std::make_pair(key, INT_MIN));
      if (it != faces.end() && it->first == key) labels[static_cast<std::size_t>(f)] = it->second;
    }
  }
  // write_back appended the new nodes to region_nodes_: every local node has its global index.
  const Eigen::Index before = frame_.committed_crack_face_nodes.rows();
  frame_.committed_crack_face_nodes.conservativeResize(before + local_faces.rows(), 3);
  for (Eigen::Index f = 0; f < local_faces.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      frame_.committed_crack_face_nodes(before + f, c) =
          region_nodes_[static_cast<std::size_t>(local_faces(f, c))];
    }
  }
  frame_.committed_crack_face_labels.insert(frame_.committed_crack_face_labels.end(),
                                            labels.begin(), labels.end());
  committed_nodes_ = mesh_->num_nodes();
  committed_tets_ = mesh_->num_tets();
}

void ProgressiveCutter::commit_partial_crack() {
  // Per committed tet, the tip's path from where it first enters to where it last leaves (or
  // ends): its chord.
  const Points& x = cut_positions();
  Box3 path_box;
  for (const Vec3& p : stroke_a_)
    path_box.extend(p);
  std::vector<FrontChord> chords;
  for (int t = 0; t < mesh_->num_tets(); ++t) {
    if (!tet_box(x, mesh_->tets, t).intersects(path_box)) continue;
    bool found = false, enters = false, leaves = false;
    Vec3 first = Vec3::Zero(), last = Vec3::Zero();
    for (std::size_t k = 0; k + 1 < stroke_a_.size(); ++k) {
      const Vec3& p = stroke_a_[k];
      const Vec3& q = stroke_a_[k + 1];
      Real s0 = 0, s1 = 1;
      if (!chord_in_tet(x, mesh_->tets, t, p, q, s0, s1)) continue;
      if (!found) {
        first = p + s0 * (q - p);
        enters = s0 > 0;  // through a face (else the path starts inside)
      }
      last = p + s1 * (q - p);
      leaves = s1 < 1;  // through a face (else the path ends inside)
      found = true;
    }
    const Vec3 along = last - first;
    if (!found || !(along.norm() > 0)) continue;
    // A chord hugging a face or an edge would leave slivers (the star's centre, on the chord, is
    // then near the tet's boundary): that tet stays whole, its sliver of crack closed.
    const Vec3 mid = 0.5 * (first + last);
    const Vec3 o = row3(x, mesh_->tets(t, 0));
    Mat3 m;
    for (int k = 1; k < 4; ++k)
      m.col(k - 1) = row3(x, mesh_->tets(t, k)) - o;
    const Vec3 l = m.partialPivLu().solve(mid - o);
    if (std::min({1 - l.sum(), l(0), l(1), l(2)}) < kPartialChordMargin) continue;
    // Where the path crosses a face, the chord reaches a little past it, so that the split finds
    // the face it pierces (an end exactly on the face is inside or outside by round-off).
    chords.push_back({t, enters ? Vec3(first - 0.01 * along) : first,
                      leaves ? Vec3(last + 0.01 * along) : last});
  }
  if (chords.empty()) return;
  std::vector<int> seeds;
  for (const FrontChord& c : chords)
    seeds.push_back(c.tet);
  collect_star(seeds);
  extract_region();
  frame_.region_tets = region_num_tets_;
  // The chords in region slots (region_slots_ is ascending, as the seeds).
  for (FrontChord& c : chords) {
    c.tet = static_cast<int>(std::lower_bound(region_slots_.begin(), region_slots_.end(), c.tet) -
                             region_slots_.begin());
  }
  const CutSurface surface = region_surface();
  const FrontSplitReport split = split_front_chords(region_, surface, chords, options_);
  frame_.front_tets = split.front_tets;
  frame_.committed_new_tets = write_back(false);
  report_committed_faces(split.crack_faces);
}

void ProgressiveCutter::extract_region() {
  if (local_of_.size() < static_cast<std::size_t>(mesh_->num_nodes()))
    local_of_.resize(static_cast<std::size_t>(mesh_->num_nodes()), -1);
  region_nodes_.clear();
  const auto num_tets = static_cast<Eigen::Index>(region_slots_.size());
  region_.tets.resize(num_tets, 4);
  region_.labels.resize(num_tets);
  for (Eigen::Index k = 0; k < num_tets; ++k) {
    const int slot = region_slots_[static_cast<std::size_t>(k)];
    for (int c = 0; c < 4; ++c) {
      int& local = local_of_[static_cast<std::size_t>(mesh_->tets(slot, c))];
      if (local < 0) {
        local = static_cast<int>(region_nodes_.size());
        region_nodes_.push_back(mesh_->tets(slot, c));
      }
      region_.tets(k, c) = local;
    }
    region_.labels(k) = mesh_->labels(slot);
  }
  const auto num_nodes = static_cast<Eigen::Index>(region_nodes_.size());
  region_.rest.resize(num_nodes, 3);
  region_.x.resize(num_nodes, 3);
  region_.v.resize(num_nodes, 3);
  // In material space the region's x holds the rest positions and its rest the current ones: the
  // cut finds crossings on x, and interpolates new nodes alike in both, so swapping is exact
  // (write_back swaps them back).
  const bool swap = space_ == BladeSpace::material;
  Points& region_rest = swap ? region_.x : region_.rest;
  Points& region_x = swap ? region_.rest : region_.x;
  for (Eigen::Index i = 0; i < num_nodes; ++i) {
    const int node = region_nodes_[static_cast<std::size_t>(i)];
    region_rest.row(i) = mesh_->rest.row(node);
    region_x.row(i) = mesh_->x.row(node);
    region_.v.row(i) = mesh_->v.row(node);
    local_of_[static_cast<std::size_t>(node)] = -1;  // reset for the next frame
  }
  region_num_nodes_ = static_cast<int>(num_nodes);
  region_num_tets_ = static_cast<int>(num_tets);
}

int ProgressiveCutter::write_back(bool save) {
  const int node_base = mesh_->num_nodes();
  const auto global = [&](int local) {
    return local < region_num_nodes_ ? region_nodes_[static_cast<std::size_t>(local)]
                                     : node_base + (local - region_num_nodes_);
  };
  for (int k = 0; k < region_num_tets_; ++k) {
    const int slot = region_slots_[static_cast<std::size_t>(k)];
    std::array<int, 4> row{};
    bool differs = false;
    for (int c = 0; c < 4; ++c) {
      row[static_cast<std::size_t>(c)] = global(region_.tets(k, c));
      differs = differs || row[static_cast<std::size_t>(c)] != mesh_->tets(slot, c);
    }
    if (!differs) continue;
    if (save) {
      saved_rows_.push_back({slot,
                             {mesh_->tets(slot, 0), mesh_->tets(slot, 1), mesh_->tets(slot, 2),
                              mesh_->tets(slot, 3)}});
    }
    for (int c = 0; c < 4; ++c)
      mesh_->tets(slot, c) = row[static_cast<std::size_t>(c)];
    frame_.changed_tets.push_back(slot);
  }
  const int new_nodes = region_.num_nodes() - region_num_nodes_;
  for (Points* points : {&mesh_->rest, &mesh_->x, &mesh_->v})
    points->conservativeResize(node_base + new_nodes, 3);
  const bool swap = space_ == BladeSpace::material;  // as extract_region
  const Points& region_rest = swap ? region_.x : region_.rest;
  const Points& region_x = swap ? region_.rest : region_.x;
  for (int i = 0; i < new_nodes; ++i) {
    mesh_->rest.row(node_base + i) = region_rest.row(region_num_nodes_ + i);
    mesh_->x.row(node_base + i) = region_x.row(region_num_nodes_ + i);
    mesh_->v.row(node_base + i) = region_.v.row(region_num_nodes_ + i);
    region_nodes_.push_back(node_base + i);
  }
  const int tet_base = mesh_->num_tets();
  const int new_tets = region_.num_tets() - region_num_tets_;
  mesh_->tets.conservativeResize(tet_base + new_tets, 4);
  mesh_->labels.conservativeResize(tet_base + new_tets);
  for (int k = 0; k < new_tets; ++k) {
    for (int c = 0; c < 4; ++c) {
      const int local = region_.tets(region_num_tets_ + k, c);
      // Nodes were appended above, so every local node now has its global index.
      mesh_->tets(tet_base + k, c) = region_nodes_[static_cast<std::size_t>(local)];
    }
    mesh_->labels(tet_base + k) = region_.labels(region_num_tets_ + k);
    region_slots_.push_back(tet_base + k);
    frame_.changed_tets.push_back(tet_base + k);
  }
  if (swap) {
    // The blade's pieces are oriented by split_front_chords on the region's "rest", which here is
    // the current configuration: orient them on the true rest positions.
    for (int t : frame_.changed_tets) {
      if (t >= mesh_->num_tets()) continue;
      const auto corner = [&](int k) { return row3(mesh_->rest, mesh_->tets(t, k)); };
      if (signed_volume(corner(0), corner(1), corner(2), corner(3)) < 0)
        std::swap(mesh_->tets(t, 0), mesh_->tets(t, 1));
    }
  }
  region_num_nodes_ = region_.num_nodes();
  region_num_tets_ = region_.num_tets();
  return new_tets;
}

const FrameReport& ProgressiveCutter::update(const Vec3& a, const Vec3& b) {
  if (!((a - b).norm() > 0)) throw std::invalid_argument("blade edge has zero length");
  frame_ = FrameReport{};
  frame_.tets_before = mesh_->num_tets();
  undo_temporary();
  if (space_ == BladeSpace::material) {
    const std::optional<MaterialMap> map =
        material_map_at(*mesh_, a, (a - b).norm() + 4 * pose_spacing_);
    if (!map || tangled_near(*mesh_, a, b, pose_spacing_)) {
      frame_.blade_unmapped = true;
      finish_changed();
      return frame_;
    }
    // The far end through the tissue near it (its own tet, or the nearest): extrapolating the
    // tip's tet over the whole blade would swing the far end about as that tet deforms, and the
    // strip would sweep material the blade never passed.
    const std::optional<MaterialMap> far = material_map_at(*mesh_, b, 4 * pose_spacing_);
    update_in_space(map->rest_of(a), far ? far->rest_of(b) : map->rest_of(b));
  } else {
    update_in_space(a, b);
  }
  finish_changed();
  return frame_;
}

void ProgressiveCutter::update_in_space(const Vec3& a, const Vec3& b) {
  // The previous pose stays in the strip if the blade has moved pose_spacing from the last kept
  // one; else the current pose replaces it (the strip's last quad stretches).
  if (stroke_a_.size() >= 2 &&
      std::max((stroke_a_[stroke_a_.size() - 2] - stroke_a_.back()).norm(),
               (stroke_b_[stroke_b_.size() - 2] - stroke_b_.back()).norm()) < pose_spacing_) {
    stroke_a_.pop_back();
    stroke_b_.pop_back();
  }
  stroke_a_.push_back(a);
  stroke_b_.push_back(b);
  const std::size_t poses = stroke_a_.size();
  if (poses < 2) return;
  // A tet is cut completely only once the blade has left it: while the set of front tets (those
  // the blade is inside) keeps its members, there is nothing to commit, and the frame only redoes
  // the blade's temporary pieces on the front's star. The check runs anyway every
  // kCommitEvery frames, for a tet thinner than the blade's travel in a frame, which the blade
  // can pass without being inside it at any frame.
  blade_front_tets(cut_positions(), mesh_->tets, a, b, front_);
  const bool commit = front_ != front_before_ || ++frames_since_commit_ >= kCommitEvery;
  frame_.looked_for_cuts = commit;
  if (commit) {
    frames_since_commit_ = 0;
    Box3 quad_box;
    for (const Vec3& p : {stroke_a_[poses - 2], stroke_b_[poses - 2], a, b})
      quad_box.extend(p);
    collect_region(quad_box);
  } else {
    collect_star(front_);
  }
  extract_region();
  frame_.region_tets = region_num_tets_;
  CutSurface surface = region_surface();
  if (commit) {
    commit_complete_cuts(surface);
    // The committed pieces took the front tets' slots and more: the front, as the next frame
    // will compare it.
    if (frame_.committed_new_tets > 0 || !frame_.changed_tets.empty()) {
      blade_front_tets(cut_positions(), mesh_->tets, a, b, front_);
    }
  }
  front_before_ = front_;
  if (front_.empty()) return;

  const FrontSplitReport front = split_front_tets(region_, surface, a, b, options_);
  frame_.front_tets = front.front_tets;
  write_back(true);
  frame_.temporary_tets =
      mesh_->num_tets() - committed_tets_ + static_cast<int>(saved_rows_.size());
  frame_.temporary_nodes = mesh_->num_nodes() - committed_nodes_;
  frame_.temporary_crack_faces = front.crack_faces;
  for (Eigen::Index f = 0; f < front.crack_faces.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int local = front.crack_faces(f, c);
      frame_.temporary_crack_faces(f, c) = region_nodes_[static_cast<std::size_t>(local)];
    }
  }
}

const FrameReport& ProgressiveCutter::end_stroke(bool keep_partial) {
  frame_ = FrameReport{};
  frame_.tets_before = mesh_->num_tets();
  undo_temporary();
  if (keep_partial && stroke_a_.size() >= 2) commit_partial_crack();
  stroke_a_.clear();
  stroke_b_.clear();
  front_before_.clear();
  frames_since_commit_ = 0;
  finish_changed();
  return frame_;
}

void ProgressiveCutter::finish_changed() {
  std::vector<int>& changed = frame_.changed_tets;
  std::sort(changed.begin(), changed.end());
  changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
  changed.erase(std::lower_bound(changed.begin(), changed.end(), mesh_->num_tets()), changed.end());
}

}  // namespace incise::sim::cut
