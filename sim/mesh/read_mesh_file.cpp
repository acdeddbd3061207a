#include "sim/mesh/read_mesh_file.h"

#include "sim/mesh/mesh_file_error.h"
#include "sim/mesh/msh_reader.h"
#include "sim/mesh/tetgen_reader.h"

namespace incise::sim {

TetMesh read_mesh_file(const std::filesystem::path& path) {
  const std::filesystem::path extension = path.extension();
  if (extension == ".msh") return read_msh(path);
  if (extension == ".node" || extension == ".ele") return read_tetgen(path);
  if (std::filesystem::exists(tetgen_node_path(path))) return read_tetgen(path);
  if (std::filesystem::exists(path)) {
    throw MeshFileError(path.string(), 0,
                        "unknown mesh format (expected .msh, .node, .ele or a TetGen base name)");
  }
  throw MeshFileError(path.string(), 0,
                      "no such file (nor " + tetgen_node_path(path).string() + ")");
}

}  // namespace incise::sim
