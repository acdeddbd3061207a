#pragma once

#include <array>
#include <span>
#include <vector>

#include "sim/core/types.h"
#include "sim/mesh/tet_mesh.h"

namespace incise::sim::remesh {

using TetVertices = std::array<int, 4>;
// The vertex ids of a triangle, sorted ascending: a face's identity regardless of orientation.
using FaceKey = std::array<int, 3>;

FaceKey face_key(int a, int b, int c);

// Equality and order of keys element by element: std::array's operators go through memcmp and
// lexicographical_compare calls, which dominated the matching of faces in replace_tets.
inline bool same_key(const FaceKey& a, const FaceKey& b) {
  return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
}
inline bool key_less(const FaceKey& a, const FaceKey& b) {
  if (a[0] != b[0]) return a[0] < b[0];
  if (a[1] != b[1]) return a[1] < b[1];
  return a[2] < b[2];
}

// A tet to create: vertices (positively oriented) and tissue label.
struct NewTet {
  TetVertices v;
  int label = 0;
};

// A face that lies on a constrained surface: `parent` is the facet it is part of (see
// RemeshMesh).
struct ConstrainedFace {
  FaceKey key;
  int parent = -1;
};

// What one operation did, so that models can be updated locally: the tet ids that no longer
// hold the tets they held before, and the ids holding new tets afterwards (an id may appear in
// both when it was freed and reused).
struct TetChanges {
  std::vector<int> removed;
  std::vector<int> created;
};

// A mutable tetrahedral mesh in the rest (material) configuration, for local remeshing.
// Vertices and tets live in slots that are freed and reused; ids stay stable while alive.
// Tets are positively oriented; face k of a tet is the face opposite local vertex k, numbered
// as kTetFaces in sim/mesh/tet_adjacency.h. Each tet face knows the tet across it (-1 on the
// boundary) and, if it lies on a constrained surface, its parent facet.
// The constrained faces of the mesh it was built from are its boundary faces and the faces
// between tets of different labels. They are grouped into facets: maximal sets of edge-connected,
// exactly coplanar constrained faces with the same labels on the same sides (a side of a box is
// one facet; a curved organ surface has one facet per triangle). A facet's region never changes,
// but its triangulation may: insertions split its faces (the sub-faces keep the parent) and 2-2
// or 4-4 flips re-triangulate it inside its plane; nothing crosses or removes it.
// The vertices of the original mesh keep ids 0 .. #original vertices - 1.
class RemeshMesh {
 public:
  // From mesh.rest, mesh.tets and mesh.labels (x and v are not used).
  // Throws std::invalid_argument if a tet is not positively oriented (exact test), or if a
  // face is shared by more than two tets.
  explicit RemeshMesh(const TetMesh& mesh);

  int num_vertex_slots() const { return static_cast<int>(points_.size()); }
  int num_tet_slots() const { return static_cast<int>(tets_.size()); }
  int num_vertices() const { return num_vertices_; }
  int num_tets() const { return num_tets_; }
  int num_original_vertices() const { return num_original_vertices_; }
  bool is_original(int v) const { return v < num_original_vertices_; }

  bool vertex_alive(int v) const { return vertex_tet_[v] >= 0; }
  const Vec3& point(int v) const { return points_[v]; }
  // An alive tet incident to the alive vertex v.
  int vertex_tet(int v) const { return vertex_tet_[v]; }

  bool tet_alive(int t) const { return tets_[t][0] >= 0; }
  const TetVertices& tet(int t) const { return tets_[t]; }
  int label(int t) const { return labels_[t]; }
  // The tet across face k of t, or -1 on the boundary.
  int neighbor(int t, int k) const { return neighbors_[t][k]; }
  // The original constrained face that face k of t is part of, or -1 if unconstrained.
  int face_parent(int t, int k) const { return parents_[t][k]; }
  // The local index of vertex v in tet t, or -1.
  int local_index(int t, int v) const;

  // The constrained faces of the original mesh (plus faces frozen by constrain_face), each
  // oriented out of the tet it was taken from, and the facet each one belongs to.
  const std::vector<std::array<int, 3>>& original_constrained_faces() const {
    return original_faces_;
  }
  const std::vector<int>& original_face_facets() const { return original_facet_; }
  int num_facets() const { return num_facets_; }

  // The alive tets incident to vertex v, appended to `tets` (cleared first).
  void star(int v, std::vector<int>* tets) const;
  // The alive tets around the edge (a, b), reached from `start` (a tet holding both) across
  // faces holding both; returns true if the ring is open (the edge is on the boundary).
  bool edge_ring(int a, int b, int start, std::vector<int>* tets) const;
  // A tet holding both a and b, or -1.
  int find_edge_tet(int a, int b) const;

  // The low-level edit every operation goes through: removes the tets `old`, creates `created`
  // and links all faces. A face of a created tet is glued to the outside face of the old tets
  // with the same vertices (keeping its neighbour and parent), or to another created tet, or
  // else lies on the boundary; old boundary faces need not be kept. `constrained` gives the parent
  // of every new face that lies on a constrained surface (new boundary faces must be listed). The
  // created ids are written to `created_ids` if given. Throws std::logic_error if the new tets do
  // not close up with the old tets' outside (the caller checks geometry; this checks the
  // bookkeeping).
  void replace_tets(std::span<const int> old, std::span<const NewTet> created,
                    std::span<const ConstrainedFace> constrained, std::vector<int>* created_ids);

  // Makes the unconstrained interior face k of tet t a constrained face of its own (a new
  // original constrained face and facet, on both sides) and returns the facet id.
  int constrain_face(int t, int k);

  // Adds an unused vertex at rest position p and returns its id; it must get tets before the
  // next query (vertex_alive is false until then).
  int add_vertex(const Vec3& p);
  // Frees vertex v, which no tet may use any more.
  void free_vertex(int v);

  // Records the tet ids removed and created from now until end_changes.
  void begin_changes();
  TetChanges end_changes();

  // The mesh with compact indices: alive vertices in increasing id order, alive tets in
  // increasing id order; rest = x = positions, v = 0. vertex_ids (if given) gets, for each
  // node of the result, its vertex id here.
  TetMesh to_tet_mesh(std::vector<int>* vertex_ids = nullptr) const;

 private:
  struct Taken {
    int tet, face;
  };
  void group_facets(const std::vector<Taken>& taken);
  int allocate_tet();
  void free_tet(int t);

  std::vector<Vec3> points_;
  std::vector<int> vertex_tet_;    // -1 for a free or not yet used slot
  std::vector<TetVertices> tets_;  // [0] = -1 for a free slot
  std::vector<TetVertices> neighbors_;
  std::vector<TetVertices> parents_;
  std::vector<int> labels_;
  std::vector<int> free_vertices_;
  std::vector<int> free_tets_;
  std::vector<std::array<int, 3>> original_faces_;
  std::vector<int> original_facet_;
  int num_facets_ = 0;
  int num_original_vertices_ = 0;
  int num_vertices_ = 0;
  int num_tets_ = 0;

  bool journaling_ = false;
  std::vector<int> journal_removed_;
  std::vector<int> journal_created_;

  // Scratch for replace_tets (reused, so that an edit allocates only when a cavity is larger
  // than any before).
  struct OuterFace {
    FaceKey key;
    int tet;   // the tet outside the cavity, or -1
    int face;  // its local face index
    int parent;
    bool glued;
  };
  std::vector<OuterFace> outer_;
  std::vector<int> new_ids_;
  // Every face of the cavity's boundary and of the new tets, keyed once and sorted, so that
  // faces are matched in O(F log F) (a removal's cavity has tens of tets).
  struct FaceSlot {
    FaceKey key;
    int index;  // into outer_ (>= 0), or -(4 i + k) - 1 for face k of new_ids_[i]
  };
  std::vector<FaceSlot> face_slots_;
  std::vector<char> in_old_;  // by tet slot, set only during replace_tets
};

}  // namespace incise::sim::remesh
