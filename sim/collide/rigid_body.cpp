// The only file that includes FCL (the one door, see rigid_body.h).

#include "sim/collide/rigid_body.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/math/bv/AABB.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/collision_object.h>
#include <fcl/narrowphase/distance.h>

#include "sim/collide/triangle_geometry.h"

namespace incise::sim::collide {

namespace {

using Model = fcl::BVHModel<fcl::OBBRSSd>;

void check_pose(const Eigen::Isometry3d& pose) {
  if (!pose.matrix().allFinite()) {
    throw std::invalid_argument("RigidBody: the pose is not finite");
  }
}

void check_radius(Real radius, const char* where) {
  if (!(radius > 0) || !std::isfinite(radius)) {
    throw std::invalid_argument(std::string("RigidBody::") + where +
                                ": the tool radius must be finite and > 0, got " +
                                std::to_string(radius));
  }
}

// The tool as an FCL object in world coordinates. A capsule is FCL's capsule (axis along its
// local z, centred) rotated onto [a, b]; a capsule with a == b is a sphere.
fcl::CollisionObjectd sphere_object(const Sphere& sphere) {
  fcl::Transform3d transform = fcl::Transform3d::Identity();
  transform.translation() = sphere.centre;
  return fcl::CollisionObjectd(std::make_shared<fcl::Sphered>(sphere.radius), transform);
}

fcl::CollisionObjectd capsule_object(const Capsule& capsule) {
  const Vec3 axis = capsule.b - capsule.a;
  const Real length = axis.norm();
  if (!(length > 1e-12 * capsule.radius)) {
    return sphere_object(Sphere{(capsule.a + capsule.b) / 2, capsule.radius});
  }
  fcl::Transform3d transform = fcl::Transform3d::Identity();
  transform.linear() = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), axis).toRotationMatrix();
  transform.translation() = (capsule.a + capsule.b) / 2;
  return fcl::CollisionObjectd(std::make_shared<fcl::Capsuled>(capsule.radius, length), transform);
}

}  // namespace

struct RigidBody::Impl {
  Points vertices;  // body frame
  Triangles triangles;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  std::shared_ptr<Model> model;
  // Built once: FCL's CollisionObject constructor recomputes the model's local box over every
  // vertex, which per query cost more than the query (a third of a knee step, measured).
  std::unique_ptr<fcl::CollisionObjectd> body;

  void place_body() {
    fcl::Transform3d transform;
    transform.matrix() = pose.matrix();
    if (!body) {
      body = std::make_unique<fcl::CollisionObjectd>(model, transform);
    } else {
      body->setTransform(transform);
      body->computeAABB();
    }
  }

  // The contact point `world` snapped onto triangle t: the point in world coordinates and its
  // barycentric coordinates.
  void on_triangle(int t, const Vec3& world, Vec3& point, Vec3& barycentric) const {
    const Vec3 local = pose.inverse() * world;
    const Vec3 a = row3(vertices, triangles(t, 0));
    const Vec3 b = row3(vertices, triangles(t, 1));
    const Vec3 c = row3(vertices, triangles(t, 2));
    barycentric = closest_point_barycentric(local, a, b, c);
    point = pose * (barycentric[0] * a + barycentric[1] * b + barycentric[2] * c);
  }

  // Whether the box around the segment [a, b] grown by radius meets the body's world box. FCL
  // fits an oriented box to the tool's shape on every query before it looks at the body's tree,
  // which costs more than the query when the tool is nowhere near (a shaft outside the joint).
  bool may_touch(const Vec3& a, const Vec3& b, Real radius) const {
    const fcl::AABBd tool(a.cwiseMin(b) - Vec3::Constant(radius),
                          a.cwiseMax(b) + Vec3::Constant(radius));
    return body->getAABB().overlap(tool);
  }

  void collide(const fcl::CollisionObjectd& tool, int max_contacts,
               std::vector<Contact>& contacts) const {
    contacts.clear();
    if (max_contacts <= 0) return;
    fcl::CollisionRequestd request(static_cast<std::size_t>(max_contacts), true);
    fcl::CollisionResultd result;
    fcl::collide(body.get(), &tool, request, result);
    for (std::size_t k = 0; k < result.numContacts(); ++k) {
      const fcl::Contactd& found = result.getContact(k);
      Contact contact;
      contact.triangle = static_cast<int>(found.b1);
      // FCL's normal points from object 1 (the body) to object 2 (the tool). FCL 0.7's
      // sphere-triangle test reports the depth negated (fixed upstream after 0.7, fcl PR #569);
      // its magnitude is right, and the GJK/EPA path (capsules) reports it positive.
      contact.normal = found.normal.normalized();
      contact.depth = std::abs(found.penetration_depth);
      on_triangle(contact.triangle, found.pos, contact.point, contact.barycentric);
      contacts.push_back(contact);
    }
  }

  // FCL finds the nearest triangle; the closest points on it are then computed exactly in the
  // body frame from the tool's axis [a, b] (FCL 0.7 reports a mesh-shape pair's nearest points
  // in each object's local frame, and nothing meaningful once they overlap).
  RigidDistance distance(const fcl::CollisionObjectd& tool, const Vec3& a, const Vec3& b,
                         Real radius) const {
    fcl::DistanceRequestd request;
    fcl::DistanceResultd result;
    fcl::distance(body.get(), &tool, request, result);
    RigidDistance out;
    out.triangle = static_cast<int>(result.b1);
    if (out.triangle < 0 || out.triangle >= triangles.rows()) {
      throw std::logic_error("RigidBody::distance: FCL returned no triangle");
    }
    const Eigen::Isometry3d to_body = pose.inverse();
    const Vec3 a_body = to_body * a;
    const Vec3 b_body = to_body * b;
    const Vec3 ta = row3(vertices, triangles(out.triangle, 0));
    const Vec3 tb = row3(vertices, triangles(out.triangle, 1));
    const Vec3 tc = row3(vertices, triangles(out.triangle, 2));
    const SegmentTriangleClosest closest = segment_triangle_closest(a_body, b_body, ta, tb, tc);
    const Vec3& w = closest.barycentric;
    const Vec3 on_body = w[0] * ta + w[1] * tb + w[2] * tc;
    const Vec3 on_axis = a_body + closest.s * (b_body - a_body);
    const Vec3 towards_body =
        closest.distance > 0 ? Vec3((on_body - on_axis) / closest.distance) : Vec3::Zero();
    out.distance = std::max(Real(0), closest.distance - radius);
    out.point_on_body = pose * on_body;
    out.point_on_tool = pose * Vec3(on_axis + std::min(radius, closest.distance) * towards_body);
    return out;
  }
};

RigidBody::RigidBody(const Points& vertices, const Triangles& triangles,
                     const Eigen::Isometry3d& pose)
    : impl_(std::make_unique<Impl>()) {
  if (vertices.rows() == 0) throw std::invalid_argument("RigidBody: the mesh has no vertices");
  if (triangles.rows() == 0) throw std::invalid_argument("RigidBody: the mesh has no triangles");
  for (int v = 0; v < vertices.rows(); ++v) {
    if (!vertices.row(v).allFinite()) {
      throw std::invalid_argument("RigidBody: vertex " + std::to_string(v) + " is not finite");
    }
  }
  for (int t = 0; t < triangles.rows(); ++t) {
    for (int k = 0; k < 3; ++k) {
      if (triangles(t, k) < 0 || triangles(t, k) >= vertices.rows()) {
        throw std::invalid_argument("RigidBody: triangle " + std::to_string(t) + " has index " +
                                    std::to_string(triangles(t, k)) + " outside [0, " +
                                    std::to_string(vertices.rows()) + ")");
      }
    }
  }
  check_pose(pose);
  impl_->vertices = vertices;
  impl_->triangles = triangles;
  impl_->pose = pose;

  std::vector<fcl::Vector3d> points(vertices.rows());
  for (int v = 0; v < vertices.rows(); ++v)
    points[v] = row3(vertices, v);
  std::vector<fcl::Triangle> faces(triangles.rows());
  for (int t = 0; t < triangles.rows(); ++t) {
    faces[t] = fcl::Triangle(triangles(t, 0), triangles(t, 1), triangles(t, 2));
  }
  impl_->model = std::make_shared<Model>();
  impl_->model->beginModel(static_cast<int>(faces.size()), static_cast<int>(points.size()));
  impl_->model->addSubModel(points, faces);
  impl_->model->endModel();
  impl_->model->computeLocalAABB();
  impl_->place_body();
}

RigidBody::~RigidBody() = default;
RigidBody::RigidBody(RigidBody&&) noexcept = default;
RigidBody& RigidBody::operator=(RigidBody&&) noexcept = default;

void RigidBody::set_pose(const Eigen::Isometry3d& pose) {
  check_pose(pose);
  impl_->pose = pose;
  impl_->place_body();
}

const Eigen::Isometry3d& RigidBody::pose() const {
  return impl_->pose;
}

int RigidBody::num_vertices() const {
  return static_cast<int>(impl_->vertices.rows());
}

int RigidBody::num_triangles() const {
  return static_cast<int>(impl_->triangles.rows());
}

void RigidBody::contacts(const Sphere& sphere, std::vector<Contact>& contacts,
                         int max_contacts) const {
  check_radius(sphere.radius, "contacts");
  if (!impl_->may_touch(sphere.centre, sphere.centre, sphere.radius)) {
    contacts.clear();
    return;
  }
  impl_->collide(sphere_object(sphere), max_contacts, contacts);
}

void RigidBody::contacts(const Capsule& capsule, std::vector<Contact>& contacts,
                         int max_contacts) const {
  check_radius(capsule.radius, "contacts");
  if (!impl_->may_touch(capsule.a, capsule.b, capsule.radius)) {
    contacts.clear();
    return;
  }
  impl_->collide(capsule_object(capsule), max_contacts, contacts);
}

RigidDistance RigidBody::distance(const Sphere& sphere) const {
  check_radius(sphere.radius, "distance");
  return impl_->distance(sphere_object(sphere), sphere.centre, sphere.centre, sphere.radius);
}

RigidDistance RigidBody::distance(const Capsule& capsule) const {
  check_radius(capsule.radius, "distance");
  return impl_->distance(capsule_object(capsule), capsule.a, capsule.b, capsule.radius);
}

}  // namespace incise::sim::collide
