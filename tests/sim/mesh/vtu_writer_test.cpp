#include "sim/mesh/vtu_writer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/mesh/box_mesher.h"
#include "sim/mesh/mesh_file_error.h"
#include "tests/support/temp_dir.h"

namespace incise::sim {
namespace {

// The parts of a .vtu text the test looks at, parsed from the XML with no VTK library: element
// nesting is checked (every tag closed in order), and each DataArray's text is kept by its
// enclosing section and name.
struct ParsedVtu {
  std::vector<std::string> tag_path_of_arrays;  // e.g. "VTKFile/UnstructuredGrid/Piece/Points"
  std::map<std::string, std::string>
      attributes;  // Piece's and section's attributes, "Piece.NumberOfPoints"
  std::map<std::string, std::vector<std::string>> arrays;  // "PointData/displacement" -> values
  std::map<std::string, std::string> array_types;          // same key -> type attribute
  std::map<std::string, std::string> array_components;     // same key -> NumberOfComponents
};

std::string attribute(const std::string& tag, const std::string& name) {
  const std::string key = " " + name + "=\"";
  const std::size_t at = tag.find(key);
  if (at == std::string::npos) return "";
  const std::size_t start = at + key.size();
  return tag.substr(start, tag.find('"', start) - start);
}

ParsedVtu parse_vtu(const std::string& text) {
  ParsedVtu parsed;
  std::vector<std::string> stack;
  std::size_t at = text.find("?>");  // after the XML declaration
  if (text.rfind("<?xml", 0) != 0 || at == std::string::npos)
    throw std::runtime_error("no XML declaration");
  while ((at = text.find('<', at)) != std::string::npos) {
    const std::size_t end = text.find('>', at);
    const std::string tag = text.substr(at, end - at + 1);
    if (tag[1] == '/') {
      const std::string name = tag.substr(2, tag.size() - 3);
      if (stack.empty() || stack.back() != name)
        throw std::runtime_error("unbalanced </" + name + ">");
      stack.pop_back();
    } else {
      const std::string name = tag.substr(1, tag.find_first_of(" >", 1) - 1);
      if (name == "Piece") {
        parsed.attributes["Piece.NumberOfPoints"] = attribute(tag, "NumberOfPoints");
        parsed.attributes["Piece.NumberOfCells"] = attribute(tag, "NumberOfCells");
      }
      if (name == "PointData") parsed.attributes["PointData.Vectors"] = attribute(tag, "Vectors");
      if (name == "CellData") parsed.attributes["CellData.Scalars"] = attribute(tag, "Scalars");
      if (name == "DataArray") {
        const std::size_t close = text.find("</DataArray>", end);
        std::istringstream values(text.substr(end + 1, close - end - 1));
        const std::string key = stack.back() + "/" + attribute(tag, "Name");
        std::string value;
        while (values >> value)
          parsed.arrays[key].push_back(value);
        parsed.array_types[key] = attribute(tag, "type");
        parsed.array_components[key] = attribute(tag, "NumberOfComponents");
        std::string path;
        for (const std::string& part : stack)
          path += (path.empty() ? "" : "/") + part;
        parsed.tag_path_of_arrays.push_back(path);
      }
      stack.push_back(name);
    }
    at = end;
  }
  if (!stack.empty()) throw std::runtime_error("unclosed <" + stack.back() + ">");
  return parsed;
}

// Values of a DataArray as numbers (strtod reads the shortest exact form back exactly).
std::vector<double> numbers(const std::vector<std::string>& values) {
  std::vector<double> result;
  for (const std::string& value : values)
    result.push_back(std::strtod(value.c_str(), nullptr));
  return result;
}

TEST(VtuWriter, WritesPositionsDisplacementLabelsAndExtraFields) {
  TetMesh mesh = make_box_mesh(Vec3(0.02, 0.03, 0.04), Vec3i(1, 2, 2));
  for (int t = 0; t < mesh.num_tets(); ++t)
    mesh.labels(t) = t % 3;
  for (int i = 0; i < mesh.num_nodes(); ++i)
    mesh.x.row(i) += Vec3(0.1 * i, -0.01, i / 7.0).transpose();
  VtuFields extra;
  extra.node_vectors.emplace_back("velocity", Points::Constant(mesh.num_nodes(), 3, 0.5));
  VecX stress(mesh.num_tets());
  for (int t = 0; t < mesh.num_tets(); ++t)
    stress(t) = 1000.0 / (t + 3);
  extra.tet_scalars.emplace_back("von_mises", stress);

  const ParsedVtu vtu = parse_vtu(format_vtu(mesh, extra));
  const int n = mesh.num_nodes();
  const int m = mesh.num_tets();
  EXPECT_EQ(vtu.attributes.at("Piece.NumberOfPoints"), std::to_string(n));
  EXPECT_EQ(vtu.attributes.at("Piece.NumberOfCells"), std::to_string(m));
  EXPECT_EQ(vtu.attributes.at("PointData.Vectors"), "displacement");
  EXPECT_EQ(vtu.attributes.at("CellData.Scalars"), "label");
  for (const std::string& path : vtu.tag_path_of_arrays) {
    EXPECT_EQ(path.rfind("VTKFile/UnstructuredGrid/Piece/", 0), 0u) << path;
  }

  // Points are the current positions, displacement is x - rest, both exactly.
  const std::vector<double> points = numbers(vtu.arrays.at("Points/"));
  const std::vector<double> displacement = numbers(vtu.arrays.at("PointData/displacement"));
  const std::vector<double> velocity = numbers(vtu.arrays.at("PointData/velocity"));
  ASSERT_EQ(points.size(), 3u * n);
  ASSERT_EQ(displacement.size(), 3u * n);
  ASSERT_EQ(velocity.size(), 3u * n);
  EXPECT_EQ(vtu.array_components.at("Points/"), "3");
  EXPECT_EQ(vtu.array_components.at("PointData/displacement"), "3");
  for (int i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(points[3 * i + c], mesh.x(i, c));
      EXPECT_EQ(displacement[3 * i + c], mesh.x(i, c) - mesh.rest(i, c));
      EXPECT_EQ(velocity[3 * i + c], 0.5);
    }
  }

  // Cells: connectivity is the tets, offsets 4, 8, ..., all VTK_TETRA (10).
  const std::vector<double> connectivity = numbers(vtu.arrays.at("Cells/connectivity"));
  const std::vector<double> offsets = numbers(vtu.arrays.at("Cells/offsets"));
  const std::vector<std::string>& types = vtu.arrays.at("Cells/types");
  ASSERT_EQ(connectivity.size(), 4u * m);
  ASSERT_EQ(offsets.size(), static_cast<std::size_t>(m));
  ASSERT_EQ(types.size(), static_cast<std::size_t>(m));
  EXPECT_EQ(vtu.array_types.at("Cells/types"), "UInt8");
  for (int t = 0; t < m; ++t) {
    for (int k = 0; k < 4; ++k)
      EXPECT_EQ(connectivity[4 * t + k], mesh.tets(t, k));
    EXPECT_EQ(offsets[t], 4 * (t + 1));
    EXPECT_EQ(types[t], "10");
  }

  const std::vector<double> labels = numbers(vtu.arrays.at("CellData/label"));
  const std::vector<double> von_mises = numbers(vtu.arrays.at("CellData/von_mises"));
  EXPECT_EQ(vtu.array_types.at("CellData/label"), "Int32");
  ASSERT_EQ(labels.size(), static_cast<std::size_t>(m));
  ASSERT_EQ(von_mises.size(), static_cast<std::size_t>(m));
  for (int t = 0; t < m; ++t) {
    EXPECT_EQ(labels[t], mesh.labels(t));
    EXPECT_EQ(von_mises[t], stress(t));
  }
}

TEST(VtuWriter, RejectsBadFields) {
  const TetMesh mesh = make_box_mesh(Vec3(1, 1, 1), Vec3i(1, 1, 1));
  const auto rejects = [&](const VtuFields& extra) {
    EXPECT_THROW(format_vtu(mesh, extra), std::invalid_argument);
  };
  rejects({{{"velocity", Points::Zero(mesh.num_nodes() - 1, 3)}}, {}});
  rejects({{}, {{"stress", VecX::Zero(mesh.num_tets() + 1)}}});
  rejects({{}, {{"", VecX::Zero(mesh.num_tets())}}});
  rejects({{}, {{"a\"b", VecX::Zero(mesh.num_tets())}}});
  rejects({{}, {{"label", VecX::Zero(mesh.num_tets())}}});
  rejects({{{"v", Points::Zero(mesh.num_nodes(), 3)}}, {{"v", VecX::Zero(mesh.num_tets())}}});
  VecX nan = VecX::Zero(mesh.num_tets());
  nan(2) = std::nan("");
  rejects({{}, {{"stress", nan}}});
  TetMesh blown = mesh;
  blown.x(3, 1) = std::numeric_limits<Real>::infinity();
  EXPECT_THROW(format_vtu(blown), std::invalid_argument);
}

TEST(VtuWriter, WritesTheFileOrReportsIt) {
  const TetMesh mesh = make_box_mesh(Vec3(1, 1, 1), Vec3i(1, 1, 1));
  const incise::test::TempDir dir{"incise-vtu"};
  const std::filesystem::path path = dir.path() / "box.vtu";
  write_vtu(path, mesh);
  std::ifstream stream(path);
  std::ostringstream text;
  text << stream.rdbuf();
  EXPECT_EQ(text.str(), format_vtu(mesh));
  std::filesystem::remove(path);
  EXPECT_THROW(write_vtu("/nonexistent/dir/out.vtu", mesh), MeshFileError);
}

}  // namespace
}  // namespace incise::sim
