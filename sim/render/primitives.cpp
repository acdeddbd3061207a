#include "sim/render/primitives.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace incise::render {
namespace {

void add_vertex(ShapeMesh& mesh, double x, double y, double z, double nx, double ny, double nz) {
  for (const double value : {x, y, z, nx, ny, nz})
    mesh.vertices.push_back(static_cast<float>(value));
}

void add_triangle(ShapeMesh& mesh, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  mesh.indices.insert(mesh.indices.end(), {a, b, c});
}

}  // namespace

ShapeMesh unit_sphere(int slices, int stacks) {
  if (slices < 3 || stacks < 2) {
    throw std::invalid_argument("unit sphere needs slices >= 3 and stacks >= 2 (got " +
                                std::to_string(slices) + " and " + std::to_string(stacks) + ")");
  }
  ShapeMesh mesh;
  // theta runs from the +z pole (0) to the -z pole (pi), phi once round the z axis.
  for (int i = 0; i <= stacks; ++i) {
    const double theta = std::numbers::pi * i / stacks;
    for (int j = 0; j <= slices; ++j) {
      const double phi = 2.0 * std::numbers::pi * j / slices;
      const double x = std::sin(theta) * std::cos(phi);
      const double y = std::sin(theta) * std::sin(phi);
      const double z = std::cos(theta);
      add_vertex(mesh, x, y, z, x, y, z);
    }
  }
  // In each grid cell, a and b lie on the northern ring, c and d below them. Moving south (c - a)
  // then east (b - a) turns counter-clockwise about the outward normal (e_theta x e_phi = e_r).
  // The cell's northern triangle collapses at the north pole and the southern one at the south.
  const auto row = static_cast<std::uint32_t>(slices + 1);
  for (int i = 0; i < stacks; ++i) {
    for (int j = 0; j < slices; ++j) {
      const std::uint32_t a = i * row + j;
      const std::uint32_t b = a + 1;
      const std::uint32_t c = a + row;
      const std::uint32_t d = c + 1;
      if (i > 0) add_triangle(mesh, a, c, b);
      if (i < stacks - 1) add_triangle(mesh, b, c, d);
    }
  }
  return mesh;
}

ShapeMesh unit_cylinder(int slices) {
  if (slices < 3) {
    throw std::invalid_argument("unit cylinder needs slices >= 3 (got " + std::to_string(slices) +
                                ")");
  }
  ShapeMesh mesh;
  const auto ring = [&](double z, double nz, bool radial_normal) {
    for (int j = 0; j <= slices; ++j) {
      const double phi = 2.0 * std::numbers::pi * j / slices;
      const double x = std::cos(phi);
      const double y = std::sin(phi);
      add_vertex(mesh, x, y, z, radial_normal ? x : 0.0, radial_normal ? y : 0.0, nz);
    }
  };
  const auto row = static_cast<std::uint32_t>(slices + 1);

  // Side: bottom ring then top ring; east (b - a) then up (c - a) is counter-clockwise about the
  // outward radial normal (e_phi x e_z = e_r).
  ring(0.0, 0.0, true);
  ring(1.0, 0.0, true);
  for (std::uint32_t j = 0; j < static_cast<std::uint32_t>(slices); ++j) {
    const std::uint32_t a = j;
    const std::uint32_t b = j + 1;
    const std::uint32_t c = j + row;
    const std::uint32_t d = c + 1;
    add_triangle(mesh, a, b, c);
    add_triangle(mesh, b, d, c);
  }

  // Caps: a centre and its own ring, so that the cap normals stay axial.
  for (const double z : {0.0, 1.0}) {
    const double nz = z == 0.0 ? -1.0 : 1.0;
    const auto centre = static_cast<std::uint32_t>(mesh.vertex_count());
    add_vertex(mesh, 0.0, 0.0, z, 0.0, 0.0, nz);
    ring(z, nz, false);
    for (std::uint32_t j = 0; j < static_cast<std::uint32_t>(slices); ++j) {
      const std::uint32_t current = centre + 1 + j;
      // Counter-clockwise about +z at the top, about -z at the bottom.
      if (nz > 0.0) {
        add_triangle(mesh, centre, current, current + 1);
      } else {
        add_triangle(mesh, centre, current + 1, current);
      }
    }
  }
  return mesh;
}

ShapeMesh unit_square() {
  ShapeMesh mesh;
  add_vertex(mesh, -1.0, -1.0, 0.0, 0.0, 0.0, 1.0);
  add_vertex(mesh, 1.0, -1.0, 0.0, 0.0, 0.0, 1.0);
  add_vertex(mesh, 1.0, 1.0, 0.0, 0.0, 0.0, 1.0);
  add_vertex(mesh, -1.0, 1.0, 0.0, 0.0, 0.0, 1.0);
  add_triangle(mesh, 0, 1, 2);
  add_triangle(mesh, 0, 2, 3);
  return mesh;
}

ShapeMesh unit_box() {
  ShapeMesh mesh;
  // Face k of the six: normal +-e_axis; (u, v) the other two axes in right-handed order, so that
  // the corners (-u -v), (+u -v), (+u +v), (-u +v) turn counter-clockwise about +e_axis (and are
  // taken in the opposite order on the minus face).
  for (int axis = 0; axis < 3; ++axis) {
    for (const double sign : {1.0, -1.0}) {
      const int u = (axis + 1) % 3;
      const int v = (axis + 2) % 3;
      const auto first = static_cast<std::uint32_t>(mesh.vertex_count());
      constexpr double corner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
      for (const auto& c : corner) {
        double p[3];
        double n[3] = {0, 0, 0};
        p[axis] = sign;
        p[u] = c[0];
        p[v] = c[1];
        n[axis] = sign;
        add_vertex(mesh, p[0], p[1], p[2], n[0], n[1], n[2]);
      }
      if (sign > 0) {
        add_triangle(mesh, first, first + 1, first + 2);
        add_triangle(mesh, first, first + 2, first + 3);
      } else {
        add_triangle(mesh, first, first + 2, first + 1);
        add_triangle(mesh, first, first + 3, first + 2);
      }
    }
  }
  return mesh;
}

}  // namespace incise::render
