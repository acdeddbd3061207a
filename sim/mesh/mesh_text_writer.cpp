#include "sim/mesh/mesh_text_writer.h"

#include <cerrno>
#include <charconv>
#include <cstring>
#include <fstream>

#include "sim/mesh/mesh_file_error.h"

namespace incise::sim {

void append_real(std::string& out, double value) {
  char buffer[32];  // the longest shortest double, "-2.2250738585072014e-308", has 24
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

void append_integer(std::string& out, long long value) {
  char buffer[24];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

void write_mesh_text(const std::string& path, const std::string& text) {
  std::ofstream stream(path, std::ios::binary | std::ios::trunc);
  if (!stream) {
    throw MeshFileError(path, 0, std::string("cannot write file (") + std::strerror(errno) + ")");
  }
  stream.write(text.data(), static_cast<std::streamsize>(text.size()));
  stream.close();
  if (!stream) throw MeshFileError(path, 0, "cannot write file");
}

}  // namespace incise::sim
