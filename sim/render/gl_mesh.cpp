#include "sim/render/gl_mesh.h"

#include <algorithm>
#include <cstdint>

#include "sim/render/gl_api.h"

namespace incise::render {
namespace {

// Same size: overwrite in place. Otherwise (re)allocate; GL_DYNAMIC_DRAW since the tissue's
// contents change every frame.
void upload(GLenum target, const void* data, std::size_t bytes, std::size_t& allocated) {
  if (bytes == allocated && bytes > 0) {
    glBufferSubData(target, 0, static_cast<GLsizeiptr>(bytes), data);
  } else {
    glBufferData(target, static_cast<GLsizeiptr>(bytes), data, GL_DYNAMIC_DRAW);
    allocated = bytes;
  }
}

}  // namespace

GlMesh::GlMesh() {
  glGenVertexArrays(1, &vertex_array_);
  glGenBuffers(1, &vertex_buffer_);
  glGenBuffers(1, &index_buffer_);

  glBindVertexArray(vertex_array_);
  glBindBuffer(GL_ARRAY_BUFFER, vertex_buffer_);
  const GLsizei stride = floats_per_vertex * sizeof(float);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride,
                        reinterpret_cast<const void*>(3 * sizeof(float)));
  // The element buffer binding is part of the vertex array state.
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, index_buffer_);
  glBindVertexArray(0);
}

GlMesh::~GlMesh() {
  if (pattern_buffer_ != 0) glDeleteBuffers(1, &pattern_buffer_);
  glDeleteBuffers(1, &index_buffer_);
  glDeleteBuffers(1, &vertex_buffer_);
  glDeleteVertexArrays(1, &vertex_array_);
}

void GlMesh::set_vertices(std::span<const float> interleaved) {
  glBindBuffer(GL_ARRAY_BUFFER, vertex_buffer_);
  upload(GL_ARRAY_BUFFER, interleaved.data(), interleaved.size_bytes(), vertex_bytes_);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
}

void GlMesh::set_pattern_positions(std::span<const float> xyz) {
  if (pattern_buffer_ == 0) {
    glGenBuffers(1, &pattern_buffer_);
    glBindVertexArray(vertex_array_);
    glBindBuffer(GL_ARRAY_BUFFER, pattern_buffer_);
    glEnableVertexAttribArray(2);
    glVertexAttribPointer(2, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
    glBindVertexArray(0);
  }
  glBindBuffer(GL_ARRAY_BUFFER, pattern_buffer_);
  upload(GL_ARRAY_BUFFER, xyz.data(), xyz.size_bytes(), pattern_bytes_);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
}

void GlMesh::set_indices(std::span<const std::uint32_t> indices) {
  glBindVertexArray(vertex_array_);
  upload(GL_ELEMENT_ARRAY_BUFFER, indices.data(), indices.size_bytes(), index_bytes_);
  glBindVertexArray(0);
  index_count_ = static_cast<int>(indices.size());
}

void GlMesh::draw() const {
  if (index_count_ == 0) return;
  glBindVertexArray(vertex_array_);
  glDrawElements(GL_TRIANGLES, index_count_, GL_UNSIGNED_INT, nullptr);
  glBindVertexArray(0);
}

void GlMesh::draw(int first_triangle, int triangle_count) const {
  const int first = std::clamp(3 * first_triangle, 0, index_count_);
  const int count = std::clamp(3 * triangle_count, 0, index_count_ - first);
  if (count == 0) return;
  glBindVertexArray(vertex_array_);
  glDrawElements(
      GL_TRIANGLES, count, GL_UNSIGNED_INT,
      reinterpret_cast<const void*>(static_cast<std::uintptr_t>(first) * sizeof(std::uint32_t)));
  glBindVertexArray(0);
}

}  // namespace incise::render
