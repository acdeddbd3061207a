#pragma once

#include <string>

namespace incise::sim {

// Appends value in the shortest decimal form that reads back as the same double (std::to_chars),
// so that a written mesh reads back bit for bit.
void append_real(std::string& out, double value);

// Appends value in decimal.
void append_integer(std::string& out, long long value);

// Writes text to path, replacing the file; throws MeshFileError (no line) if it cannot.
void write_mesh_text(const std::string& path, const std::string& text);

}  // namespace incise::sim
