// The mesh readers (sim/mesh/msh_reader.h for gmsh 2.2 and 4.1, tetgen_reader.h): a file either
// fails with MeshFileError or gives a mesh whose tets are positively oriented over finite nodes,
// with labels for every tet. The first byte picks the reader; for TetGen the rest is the .node
// text, a NUL, then the .ele text.
#include <cmath>

#include "fuzz/fuzz_target.h"
#include "sim/mesh/mesh_file_error.h"
#include "sim/mesh/msh_reader.h"
#include "sim/mesh/tet_mesh.h"
#include "sim/mesh/tetgen_reader.h"

using namespace incise;

namespace {
void check_mesh(const sim::TetMesh& mesh) {
  fuzz_check(mesh.labels.size() == mesh.num_tets());
  fuzz_check(mesh.rest.allFinite());
  for (int t = 0; t < mesh.num_tets(); ++t) {
    for (int k = 0; k < 4; ++k)
      fuzz_check(mesh.tets(t, k) >= 0 && mesh.tets(t, k) < mesh.num_nodes());
    const auto node = [&](int k) { return sim::Vec3(mesh.rest.row(mesh.tets(t, k))); };
    fuzz_check(sim::signed_volume(node(0), node(1), node(2), node(3)) > 0);
  }
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const auto text = fuzz::as_text(data + 1, size - 1);
  try {
    if ((data[0] & 1) == 0) {
      check_mesh(sim::read_msh_string(text));
    } else {
      const auto split = text.find('\0');
      const auto node = text.substr(0, split);
      const auto ele =
          split == std::string_view::npos ? std::string_view() : text.substr(split + 1);
      check_mesh(sim::read_tetgen_strings(node, ele));
    }
  } catch (const sim::MeshFileError& e) {
    fuzz_check(e.what()[0] != '\0');
  }
  return 0;
}
