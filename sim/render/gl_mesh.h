#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace incise::render {

// A building block of incise_render's drawing classes (it appears in their headers only as a
// private member): one indexed triangle mesh in GL buffers, vertices interleaved as
// position xyz + normal xyz (6 floats), attributes 0 and 1. Replacing data of the same byte size
// updates the existing buffer in place (glBufferSubData) instead of reallocating it, so that a
// surface whose positions change every frame costs one copy per frame.
// Needs a current EglContext for its whole life.
class GlMesh {
 public:
  static constexpr int floats_per_vertex = 6;

  GlMesh();
  ~GlMesh();
  GlMesh(const GlMesh&) = delete;
  GlMesh& operator=(const GlMesh&) = delete;

  // interleaved: #vertices * 6 floats. The caller keeps indices within the vertex count.
  void set_vertices(std::span<const float> interleaved);
  void set_indices(std::span<const std::uint32_t> indices);

  // Per vertex xyz of a second position (attribute 2; until set, attribute 2 is off): where a
  // surface pattern is fixed, e.g. the rest shape of a tissue that deforms. #vertices * 3 floats.
  void set_pattern_positions(std::span<const float> xyz);

  // Draws the triangles with whatever program is in use; nothing when there are no indices.
  void draw() const;
  // Draws triangles [first, first + count) of the index list (clamped to it).
  void draw(int first_triangle, int triangle_count) const;

  int index_count() const { return index_count_; }

 private:
  // GL object names: vertex array, vertex buffer, index buffer.
  unsigned int vertex_array_ = 0;
  unsigned int vertex_buffer_ = 0;
  unsigned int index_buffer_ = 0;
  unsigned int pattern_buffer_ = 0;  // 0 until set_pattern_positions
  std::size_t vertex_bytes_ = 0;
  std::size_t pattern_bytes_ = 0;
  std::size_t index_bytes_ = 0;
  int index_count_ = 0;
};

}  // namespace incise::render
