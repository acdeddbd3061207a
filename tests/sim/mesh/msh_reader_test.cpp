#include "sim/mesh/msh_reader.h"

#include <gtest/gtest.h>

#include "sample_files.h"
#include "sim/mesh/mesh_file_error.h"
#include "test_text.h"

namespace incise::sim {
namespace {

using test::first_lines;
using test::kMsh22;
using test::kMsh41;
using test::replaced;
using test::throws_at;

void expect_sample_mesh(const TetMesh& mesh) {
  EXPECT_EQ(mesh.rest, test::expected_nodes());
  EXPECT_EQ(mesh.x, mesh.rest);
  EXPECT_EQ(mesh.v, Points::Zero(5, 3));
  EXPECT_EQ(mesh.tets, test::expected_tets());
  EXPECT_EQ(mesh.labels, test::expected_labels());
  const VecX volumes = tet_volumes(mesh.rest, mesh.tets);
  EXPECT_DOUBLE_EQ(volumes(0), 1.0 / 6);
  EXPECT_DOUBLE_EQ(volumes(1), 1.0 / 3);  // was -1/3 as written
}

TEST(MshReader, Version22TetsLabelsAndMappedNodeTags) {
  expect_sample_mesh(read_msh_string(kMsh22));
}

TEST(MshReader, Version41EntitiesBlocksAndParametricNodes) {
  expect_sample_mesh(read_msh_string(kMsh41));
}

TEST(MshReader, ToleratesCrlfLineEndingsAndUnknownSections) {
  std::string text =
      replaced(kMsh22, "$Nodes\n", "$Comments\nanything $Nodes-like\n$EndComments\n$Nodes\n");
  std::string crlf;
  for (const char c : text) {
    if (c == '\n') crlf += '\r';
    crlf += c;
  }
  expect_sample_mesh(read_msh_string(crlf));
}

TEST(MshReader, ErrorMessageNamesFileLineAndProblem) {
  try {
    read_msh_string(replaced(kMsh22, "30 0 1 0\n", "30 0 nan 0\n"), "liver.msh");
    FAIL() << "no error";
  } catch (const MeshFileError& error) {
    EXPECT_STREQ(error.what(), "liver.msh:12: node 30 y: not finite ('nan')");
    EXPECT_EQ(error.file(), "liver.msh");
  }
}

TEST(MshReader, MissingFileIsAnErrorWithoutLine) {
  try {
    read_msh("/nonexistent/mesh.msh");
    FAIL() << "no error";
  } catch (const MeshFileError& error) {
    EXPECT_STREQ(error.what(),
                 "/nonexistent/mesh.msh: cannot open file (No such file or directory)");
    EXPECT_EQ(error.line(), 0);
  }
}

TEST(MshReader, Version22Errors) {
  const auto read = [](const std::string& text) { return [text] { read_msh_string(text); }; };
  EXPECT_TRUE(throws_at(read(""), 1, "truncated file: expected $MeshFormat"));
  EXPECT_TRUE(
      throws_at(read("hello\n"), 1, "not a gmsh mesh: expected $MeshFormat, found 'hello'"));
  EXPECT_TRUE(throws_at(read(replaced(kMsh22, "2.2 0 8", "3.0 0 8")), 2,
                        "unsupported .msh version 3.0 (supported: 2.2, 4.1)"));
  EXPECT_TRUE(throws_at(read(replaced(kMsh22, "2.2 0 8", "2.2 1 8")), 2,
                        "binary .msh is not supported (save the mesh as ASCII)"));
  // Truncated in the middle of the nodes, of a line, and before $EndElements.
  EXPECT_TRUE(throws_at(read(first_lines(kMsh22, 11)), 11, "truncated file: expected node 3 of 6"));
  EXPECT_TRUE(throws_at(read(first_lines(kMsh22, 11) + "30 0 1"), 12,
                        "node (tag x y z): expected 4 fields, found 3"));
  EXPECT_TRUE(
      throws_at(read(first_lines(kMsh22, 22)), 22, "truncated file: expected $EndElements"));
  EXPECT_TRUE(throws_at(read(first_lines(kMsh22, 7)), 7, "truncated file: no $Nodes section"));
  // Counts that disagree with the records, both ways.
  EXPECT_TRUE(throws_at(read(replaced(kMsh22, "$Nodes\n6\n", "$Nodes\n7\n")), 16,
                        "bad count: $Nodes declares 7 nodes but $EndNodes follows 6"));
  EXPECT_TRUE(
      throws_at(read(replaced(kMsh22, "$Nodes\n6\n", "$Nodes\n5\n")), 15,
                "bad count: expected $EndNodes after 5 nodes (the declared count), found '99'"));
  EXPECT_TRUE(throws_at(read(replaced(kMsh22, "$Elements\n4\n", "$Elements\n-4\n")), 18,
                        "bad count: the element count is -4"));
  // Bad and missing indices.
  EXPECT_TRUE(throws_at(read(replaced(kMsh22, "1 10 20 30 40", "1 10 20 30 41")), 21,
                        "node tag 41 is not in $Nodes"));
  EXPECT_TRUE(throws_at(read(replaced(kMsh22, "1 10 20 30 40", "1 10 20 3x 40")), 21,
                        "tetrahedron node 3: expected an integer, found '3x'"));
  EXPECT_TRUE(throws_at(read(replaced(kMsh22, "1 10 20 30 40", "1 10 20 30")), 21,
                        "tetrahedron with 2 tags: expected 9 fields, found 8"));
  EXPECT_TRUE(
      throws_at(read(replaced(kMsh22, "20 1 0 0\n", "10 1 0 0\n")), 11, "duplicate node tag 10"));
  // Non-finite coordinates.
  EXPECT_TRUE(throws_at(read(replaced(kMsh22, "50 1 1 1", "50 1 1 inf")), 14,
                        "node 50 z: not finite ('inf')"));
  EXPECT_TRUE(throws_at(read(replaced(kMsh22, "50 1 1 1", "50 1 1 1e400")), 14,
                        "node 50 z: expected a number, found '1e400'"));
  // Tets that are not tets.
  EXPECT_TRUE(
      throws_at(read(replaced(kMsh22, "40 0 0 1\n", "40 1 1 0\n")), 21,
                "degenerate tetrahedron (zero volume: its nodes are coplanar or coincide)"));
  EXPECT_TRUE(throws_at(read(replaced(kMsh22, "1 10 20 30 40", "1 10 20 30 10")), 21,
                        "tetrahedron repeats a node"));
  EXPECT_TRUE(throws_at(
      read(replaced(replaced(kMsh22, "3 4 2 7 1 10 20 30 40\n", ""), "4 4 0 20 40 30 50\n", "")),
      21, "bad count: $Elements declares 4 elements but $EndElements follows 2"));
  EXPECT_TRUE(throws_at(read(replaced(replaced(replaced(kMsh22, "$Elements\n4\n", "$Elements\n2\n"),
                                               "3 4 2 7 1 10 20 30 40\n", ""),
                                      "4 4 0 20 40 30 50\n", "")),
                        21, "no tetrahedra (element type 4) in the file"));
}

TEST(MshReader, Version41Errors) {
  const auto read = [](const std::string& text) { return [text] { read_msh_string(text); }; };
  EXPECT_TRUE(throws_at(read(replaced(kMsh41, "4.1 0 8", "4.0 0 8")), 2,
                        "unsupported .msh version 4.0 (supported: 2.2, 4.1)"));
  EXPECT_TRUE(throws_at(read(replaced(kMsh41, "3 2 4 1\n", "3 3 4 1\n")), 35,
                        "volume entity 3 is not in $Entities"));
  EXPECT_TRUE(throws_at(read(replaced(kMsh41, "3 6 10 99\n", "3 7 10 99\n")), 12,
                        "bad count: $Nodes declares 7 nodes, its blocks hold 6"));
  EXPECT_TRUE(throws_at(read(replaced(kMsh41, "3 6 10 99\n", "3 5 10 99\n")), 21,
                        "bad count: node blocks hold more than the 5 nodes declared"));
  EXPECT_TRUE(throws_at(read(replaced(kMsh41, "2 1 1 2\n", "2 1 0 2\n")), 19,
                        "node (x y z): expected 3 fields, found 5"));
  EXPECT_TRUE(
      throws_at(read(replaced(kMsh41, "3 3 1 4\n", "4 3 1 4\n")), 37,
                "bad count: $Elements declares 4 element blocks but $EndElements follows 3"));
  EXPECT_TRUE(throws_at(read(replaced(kMsh41, "3 10 20 30 40\n", "3 10 20 30 40 50\n")), 34,
                        "tetrahedron (tag n1 n2 n3 n4): expected 5 fields, found 6"));
  EXPECT_TRUE(throws_at(read(replaced(kMsh41, "3 10 20 30 40\n", "3 10 20 30 77\n")), 34,
                        "node tag 77 is not in $Nodes"));
  EXPECT_TRUE(throws_at(read(replaced(kMsh41, "3 1 4 1\n", "2 1 4 1\n")), 33,
                        "tetrahedra in an entity of dimension 2"));
  EXPECT_TRUE(throws_at(read(replaced(kMsh41, "50\n0 1 0\n", "50\n0 -nan 0\n")), 25,
                        "node 30 y: not finite ('-nan')"));
  EXPECT_TRUE(
      throws_at(read(first_lines(kMsh41, 36)), 36, "truncated file: expected $EndElements"));
}

TEST(MshReader, Version41WithoutEntitiesGivesLabelZero) {
  // Entities are optional when there are no physical groups.
  std::string text = kMsh41;
  text.erase(text.find("$Entities\n"), text.find("$Nodes\n") - text.find("$Entities\n"));
  const TetMesh mesh = read_msh_string(text);
  EXPECT_EQ(mesh.tets, test::expected_tets());
  EXPECT_EQ(mesh.labels, Eigen::VectorXi::Zero(2));
}

}  // namespace
}  // namespace incise::sim
