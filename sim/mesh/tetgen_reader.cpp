#include "sim/mesh/tetgen_reader.h"

#include <cmath>
#include <vector>

#include "sim/mesh/mesh_from_file_data.h"
#include "sim/mesh/mesh_text_reader.h"

namespace incise::sim {
namespace {

constexpr double kMaxLabel = 2'000'000'000;  // labels are ints

// A point or tet record; the end of the file before all count records is a truncation.
void expect_record(MeshTextReader& in, std::string_view what, int index, int count) {
  if (!in.next_line()) {
    in.fail_truncated(std::string(what) + " " + std::to_string(index + 1) + " of " +
                      std::to_string(count) + " (the declared count)");
  }
}

// A header's count of records must fit in the rest of the file (a record line takes at least 2
// bytes), checked before allocating for it: a corrupt count is an error, not a huge allocation.
void check_room(const MeshTextReader& in, int count, const std::string& what) {
  if (2 * static_cast<std::size_t>(count) > in.remaining_bytes()) {
    in.fail("bad count: " + std::to_string(count) + " " + what +
            " declared, more than the rest of the file holds");
  }
}

void expect_no_more(MeshTextReader& in, const std::string& what, int count) {
  if (in.next_line()) {
    in.fail("bad count: more lines than the " + std::to_string(count) + " " + what +
            " declared in the header");
  }
}

struct NodeFile {
  Points points;
  long long first_index = 0;  // 0 or 1
};

NodeFile read_node_file(MeshTextReader& in) {
  in.expect_line("the .node header (#points dimension #attributes #markers)");
  in.expect_at_least(1, ".node header");
  NodeFile file;
  const int count = in.count(0, "the point count");
  if (in.size() > 1 && in.integer(1, "dimension") != 3) {
    in.fail("dimension " + std::string(in.token(1)) + " (only 3 is supported)");
  }
  const int attributes = in.size() > 2 ? in.count(2, "the attribute count") : 0;
  const long long markers = in.size() > 3 ? in.integer(3, "boundary marker flag") : 0;
  if (markers != 0 && markers != 1) in.fail("boundary marker flag must be 0 or 1");
  const std::size_t fields = 4 + static_cast<std::size_t>(attributes + markers);
  const std::string record = std::string("point (index x y z") +
                             (attributes > 0 ? " attributes" : "") +
                             (markers != 0 ? " marker)" : ")");
  check_room(in, count, "points");
  file.points.resize(count, 3);
  for (int i = 0; i < count; ++i) {
    expect_record(in, "point", i, count);
    in.expect_exactly(fields, record);
    const long long index = in.integer(0, "point index");
    if (i == 0) {
      if (index != 0 && index != 1) {
        in.fail("the first point index is " + std::to_string(index) + " (must be 0 or 1)");
      }
      file.first_index = index;
    } else if (index != file.first_index + i) {
      in.fail("point index " + std::to_string(index) + " out of sequence (expected " +
              std::to_string(file.first_index + i) + ")");
    }
    file.points.row(i) << in.real(1, {"point ", index, " x"}), in.real(2, {"point ", index, " y"}),
        in.real(3, {"point ", index, " z"});
  }
  expect_no_more(in, "points", count);
  return file;
}

TetMesh read_ele_file(MeshTextReader& in, const NodeFile& node_file) {
  in.expect_line("the .ele header (#tets nodes-per-tet #attributes)");
  in.expect_at_least(1, ".ele header");
  const int count = in.count(0, "the tetrahedron count");
  const long long per_tet = in.size() > 1 ? in.integer(1, "nodes per tetrahedron") : 4;
  if (per_tet != 4 && per_tet != 10) {
    in.fail("nodes per tetrahedron is " + std::to_string(per_tet) + " (must be 4 or 10)");
  }
  const int attributes = in.size() > 2 ? in.count(2, "the attribute count") : 0;
  const std::size_t fields = 1 + static_cast<std::size_t>(per_tet + attributes);
  const long long num_points = node_file.points.rows();
  check_room(in, count, "tetrahedra");
  Tets tets(count, 4);
  Eigen::VectorXi labels = Eigen::VectorXi::Zero(count);
  std::vector<int> lines(static_cast<std::size_t>(count));
  const std::string record = "tetrahedron (index " + std::to_string(per_tet) + " nodes" +
                             (attributes > 0 ? " attributes)" : ")");
  for (int t = 0; t < count; ++t) {
    expect_record(in, "tetrahedron", t, count);
    in.expect_exactly(fields, record);
    in.integer(0, "tetrahedron index");
    for (int k = 0; k < 4; ++k) {
      const long long node = in.integer(1 + k, {"tetrahedron node ", k + 1, ""});
      if (node < node_file.first_index || node >= node_file.first_index + num_points) {
        in.fail("node index " + std::to_string(node) + " out of range [" +
                std::to_string(node_file.first_index) + ", " +
                std::to_string(node_file.first_index + num_points - 1) + "] of the .node file");
      }
      tets(t, k) = static_cast<int>(node - node_file.first_index);
    }
    if (attributes > 0) {
      const double region = in.real(1 + static_cast<std::size_t>(per_tet), "region attribute");
      if (region < 0 || region > kMaxLabel || region != std::floor(region)) {
        in.fail("region attribute " + std::string(in.token(1 + static_cast<std::size_t>(per_tet))) +
                " is not a non-negative integer label");
      }
      labels(t) = static_cast<int>(region);
    }
    lines[static_cast<std::size_t>(t)] = in.line_number();
  }
  expect_no_more(in, "tetrahedra", count);
  if (count == 0) in.fail_at(in.line_number(), "no tetrahedra in the file");
  return mesh_from_file_data(node_file.points, std::move(tets), std::move(labels), lines,
                             in.name());
}

std::filesystem::path tetgen_path(const std::filesystem::path& path, const char* extension) {
  const std::filesystem::path ext = path.extension();
  std::filesystem::path result = path;
  if (ext == ".node" || ext == ".ele") {
    result.replace_extension(extension);
  } else {
    result += extension;  // a base name, possibly "mesh.1"
  }
  return result;
}

}  // namespace

std::filesystem::path tetgen_node_path(const std::filesystem::path& node_or_ele_or_base) {
  return tetgen_path(node_or_ele_or_base, ".node");
}

std::filesystem::path tetgen_ele_path(const std::filesystem::path& node_or_ele_or_base) {
  return tetgen_path(node_or_ele_or_base, ".ele");
}

TetMesh read_tetgen_strings(std::string_view node_text, std::string_view ele_text,
                            const std::string& node_name, const std::string& ele_name) {
  MeshTextReader node_in(node_text, node_name, '#');
  const NodeFile node_file = read_node_file(node_in);
  MeshTextReader ele_in(ele_text, ele_name, '#');
  return read_ele_file(ele_in, node_file);
}

TetMesh read_tetgen(const std::filesystem::path& node_or_ele_or_base) {
  const std::string node_name = tetgen_node_path(node_or_ele_or_base).string();
  const std::string ele_name = tetgen_ele_path(node_or_ele_or_base).string();
  const std::string node_text = read_mesh_text(node_name);
  const std::string ele_text = read_mesh_text(ele_name);
  return read_tetgen_strings(node_text, ele_text, node_name, ele_name);
}

}  // namespace incise::sim
