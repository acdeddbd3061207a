#pragma once

#include <cstdint>
#include <vector>

namespace incise::render {

// Vertex and index data of a fixed shape, ready for a vertex buffer: 6 floats per vertex
// (position xyz, unit normal xyz) and triangles wound counter-clockwise seen from outside.
struct ShapeMesh {
  static constexpr int floats_per_vertex = 6;
  std::vector<float> vertices;         // #vertices * 6
  std::vector<std::uint32_t> indices;  // #triangles * 3 indices into the vertices

  int vertex_count() const { return static_cast<int>(vertices.size()) / floats_per_vertex; }
  int triangle_count() const { return static_cast<int>(indices.size()) / 3; }
};

// The unit sphere about the origin as a latitude-longitude grid: slices meridians (>= 3), stacks
// bands from pole to pole (>= 2). Normals are the exact sphere normals, so shading is smooth
// however coarse the grid. The seam and the poles repeat vertices, so that every vertex has one
// normal; 2 * slices * (stacks - 1) triangles. Throws std::invalid_argument for too few.
ShapeMesh unit_sphere(int slices, int stacks);

// The closed cylinder of radius 1 around the z axis, z in [0, 1]: the side with radial normals,
// and both caps with axial normals. Its volume is that of the inscribed prism,
// slices / 2 * sin(2 pi / slices). 4 * slices triangles. Throws std::invalid_argument if
// slices < 3.
ShapeMesh unit_cylinder(int slices);

// The square [-1, 1] x [-1, 1] in the plane z = 0, normal +z: two triangles.
ShapeMesh unit_square();

// The cube [-1, 1]^3 with flat faces: each face its own four vertices with the face's outward
// normal, so that edges stay sharp (a blade, a jaw). 12 triangles.
ShapeMesh unit_box();

}  // namespace incise::render
