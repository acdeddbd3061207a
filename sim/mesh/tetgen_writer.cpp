#include "sim/mesh/tetgen_writer.h"

#include <stdexcept>

#include "sim/mesh/mesh_text_writer.h"
#include "sim/mesh/tetgen_reader.h"

namespace incise::sim {

std::string format_tetgen_node(const TetMesh& mesh) {
  std::string out = "# nodes: index x y z\n";
  append_integer(out, mesh.num_nodes());
  out += " 3 0 0\n";
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    append_integer(out, i + 1);
    for (int c = 0; c < 3; ++c) {
      out += ' ';
      append_real(out, mesh.rest(i, c));
    }
    out += '\n';
  }
  return out;
}

std::string format_tetgen_ele(const TetMesh& mesh) {
  if (mesh.labels.size() > 0 && mesh.labels.minCoeff() < 0) {
    throw std::invalid_argument("format_tetgen_ele: negative label " +
                                std::to_string(mesh.labels.minCoeff()) +
                                " (read_tetgen takes non-negative region attributes)");
  }
  std::string out = "# tetrahedra: index n1 n2 n3 n4 label\n";
  append_integer(out, mesh.num_tets());
  out += " 4 1\n";
  for (int t = 0; t < mesh.num_tets(); ++t) {
    append_integer(out, t + 1);
    for (int k = 0; k < 4; ++k) {
      out += ' ';
      append_integer(out, mesh.tets(t, k) + 1);
    }
    out += ' ';
    append_integer(out, mesh.labels(t));
    out += '\n';
  }
  return out;
}

void write_tetgen(const std::filesystem::path& base, const TetMesh& mesh) {
  write_mesh_text(tetgen_node_path(base).string(), format_tetgen_node(mesh));
  write_mesh_text(tetgen_ele_path(base).string(), format_tetgen_ele(mesh));
}

}  // namespace incise::sim
