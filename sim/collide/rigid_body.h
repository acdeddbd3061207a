#pragma once

// Rigid anatomy (a bone) as a triangulated surface with a pose, for tool contacts through FCL.
// FCL stays behind this door: only rigid_body.cpp includes it (pimpl), so no FCL type appears
// here and users of incise_sim_collide do not compile against FCL.
//
// The mesh is held as FCL's BVHModel<OBBRSS>: oriented boxes fit a bone's long, slanted shaft
// far tighter than axis-aligned ones (fewer false overlaps in fcl::collide), and the RSS
// (rectangle swept sphere) half answers fcl::distance queries with tight lower bounds. Both live
// in the body frame, so a new pose costs nothing (no refit, unlike a deforming surface).
//
// The body is a surface, not a solid: a tool entirely inside the bone touches no triangle and
// gets no contact. Tools are kept outside by the contacts they get on the way in.

#include <memory>
#include <vector>

#include "sim/collide/contact.h"
#include "sim/collide/tool_shapes.h"
#include "sim/core/types.h"

namespace incise::sim::collide {

// The closest points of a tool and a rigid body.
struct RigidDistance {
  Real distance = 0;                  // separation [m]; 0 when they touch or overlap
  Vec3 point_on_body = Vec3::Zero();  // world frame [m]
  Vec3 point_on_tool = Vec3::Zero();  // world frame [m], on the tool's surface
  int triangle = -1;                  // the body triangle of point_on_body
};

class RigidBody {
 public:
  // vertices  #V by 3 positions in the body frame [m], all finite
  // triangles #T by 3 indices into vertices, oriented with the right-hand normal out of the body
  // pose      body frame -> world frame
  // Throws std::invalid_argument for no vertices, no triangles, an index outside [0, #V), a
  // non-finite vertex or a non-finite pose.
  RigidBody(const Points& vertices, const Triangles& triangles,
            const Eigen::Isometry3d& pose = Eigen::Isometry3d::Identity());
  ~RigidBody();
  RigidBody(RigidBody&&) noexcept;
  RigidBody& operator=(RigidBody&&) noexcept;

  // Throws std::invalid_argument for a non-finite pose.
  void set_pose(const Eigen::Isometry3d& pose);
  const Eigen::Isometry3d& pose() const;
  int num_vertices() const;
  int num_triangles() const;

  // Contacts of the tool with the body's triangles (fcl::collide with contact generation), at
  // most max_contacts, into `contacts` (cleared first), in world coordinates: point on the
  // touched triangle, normal from the body to the tool, depth > 0, the triangle and the point's
  // barycentric coordinates on it. Throws std::invalid_argument for a non-positive or non-finite
  // radius. FCL allocates internally: this is not an allocation-free query.
  void contacts(const Sphere& sphere, std::vector<Contact>& contacts, int max_contacts = 64) const;
  void contacts(const Capsule& capsule, std::vector<Contact>& contacts,
                int max_contacts = 64) const;

  // Closest points of the tool and the body: fcl::distance finds the nearest triangle, the points
  // on it are computed exactly (triangle_geometry.h). distance = 0 when they touch or overlap.
  // Throws like contacts().
  RigidDistance distance(const Sphere& sphere) const;
  RigidDistance distance(const Capsule& capsule) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace incise::sim::collide
