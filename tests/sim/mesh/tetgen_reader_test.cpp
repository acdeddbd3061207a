#include "sim/mesh/tetgen_reader.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "sample_files.h"
#include "sim/mesh/mesh_file_error.h"
#include "test_text.h"
#include "tests/support/temp_dir.h"

namespace incise::sim {
namespace {

namespace fs = std::filesystem;
using test::first_lines;
using test::kEle;
using test::kNode;
using test::replaced;
using test::throws_at;

void expect_sample_mesh(const TetMesh& mesh) {
  EXPECT_EQ(mesh.rest, test::expected_nodes());
  EXPECT_EQ(mesh.tets, test::expected_tets());
  EXPECT_EQ(mesh.labels, test::expected_labels());
}

TEST(TetgenReader, OneBasedWithCommentsAndRegionLabels) {
  expect_sample_mesh(read_tetgen_strings(kNode, kEle));
}

TEST(TetgenReader, ZeroBasedAsDeclaredByTheFirstPoint) {
  const std::string node = "5 3\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n4 1 1 1\n";
  const std::string ele = "2 4 1\n0 0 1 2 3 7\n1 1 3 2 4 0\n";
  expect_sample_mesh(read_tetgen_strings(node, ele));
}

TEST(TetgenReader, AttributesMarkersTenNodeTetsAndNoRegions) {
  // Point attributes and boundary markers are skipped; of 10 nodes the 4 corners count.
  const std::string node =
      "6 3 1 1\n1 0 0 0 9.5 1\n2 1 0 0 9.5 1\n3 0 1 0 9.5 0\n4 0 0 1 9.5 1\n5 1 1 1 9.5 1\n"
      "6 0.5 0 0 9.5 1\n";
  const std::string ele = "2 10 2\n1 1 2 3 4 6 6 6 6 6 6 7.0 3.5\n2 2 4 3 5 6 6 6 6 6 6 0 1\n";
  const TetMesh mesh = read_tetgen_strings(node, ele);
  expect_sample_mesh(mesh);  // node 6 (only a mid-edge node) is dropped
  const TetMesh unlabelled = read_tetgen_strings(kNode, "2 4 0\n1 1 2 3 4\n2 2 4 3 5\n");
  EXPECT_EQ(unlabelled.labels, Eigen::VectorXi::Zero(2));
}

TEST(TetgenReader, Errors) {
  const auto read = [](const std::string& node, const std::string& ele) {
    return [node, ele] { read_tetgen_strings(node, ele, "m.node", "m.ele"); };
  };
  EXPECT_TRUE(throws_at(read("# nothing\n", kEle), 1,
                        "truncated file: expected the .node header (#points dimension "
                        "#attributes #markers)"));
  EXPECT_TRUE(throws_at(read(first_lines(kNode, 5), kEle), 5,
                        "truncated file: expected point 4 of 5 (the declared count)"));
  EXPECT_TRUE(throws_at(read(kNode + "6 2 2 2\n", kEle), 9,
                        "bad count: more lines than the 5 points declared in the header"));
  EXPECT_TRUE(throws_at(read(replaced(kNode, "5 3 0 0", "2000000000 3 0 0"), kEle), 2,
                        "bad count: 2000000000 points declared, more than the rest of the file "
                        "holds"));
  EXPECT_TRUE(throws_at(read(kNode, replaced(kEle, "2 4 1\n", "3 4 1\n")), 3,
                        "truncated file: expected tetrahedron 3 of 3 (the declared count)"));
  EXPECT_TRUE(
      throws_at(read(kNode, replaced(kEle, "2 4 1\n", "100 4 1\n")), 1,
                "bad count: 100 tetrahedra declared, more than the rest of the file holds"));
  EXPECT_TRUE(throws_at(read(replaced(kNode, "5 3 0 0", "5 2 0 0"), kEle), 2,
                        "dimension 2 (only 3 is supported)"));
  EXPECT_TRUE(throws_at(read(replaced(kNode, "1 0 0 0", "2 0 0 0"), kEle), 3,
                        "the first point index is 2 (must be 0 or 1)"));
  EXPECT_TRUE(throws_at(read(replaced(kNode, "3 0 1 0", "7 0 1 0"), kEle), 5,
                        "point index 7 out of sequence (expected 3)"));
  EXPECT_TRUE(throws_at(read(replaced(kNode, "3 0 1 0", "3 0 nan 0"), kEle), 5,
                        "point 3 y: not finite ('nan')"));
  EXPECT_TRUE(throws_at(read(replaced(kNode, "3 0 1 0", "3 0 1"), kEle), 5,
                        "point (index x y z): expected 4 fields, found 3"));
  EXPECT_TRUE(throws_at(read(kNode, first_lines(kEle, 2)), 2,
                        "truncated file: expected tetrahedron 2 of 2 (the declared count)"));
  EXPECT_TRUE(throws_at(read(kNode, replaced(kEle, "2 4 1\n", "1 4 1\n")), 3,
                        "bad count: more lines than the 1 tetrahedra declared in the header"));
  EXPECT_TRUE(throws_at(read(kNode, replaced(kEle, "2 4 1\n", "2 5 1\n")), 1,
                        "nodes per tetrahedron is 5 (must be 4 or 10)"));
  EXPECT_TRUE(throws_at(read(kNode, replaced(kEle, "2 2 4 3 5 0", "2 2 4 3 6 0")), 3,
                        "node index 6 out of range [1, 5] of the .node file"));
  EXPECT_TRUE(throws_at(read(kNode, replaced(kEle, "2 2 4 3 5 0", "2 2 4 0 5 0")), 3,
                        "node index 0 out of range [1, 5] of the .node file"));
  EXPECT_TRUE(throws_at(read(kNode, replaced(kEle, "2 2 4 3 5 0", "2 2 4 3 5")), 3,
                        "tetrahedron (index 4 nodes attributes): expected 6 fields, found 5"));
  EXPECT_TRUE(throws_at(read(kNode, replaced(kEle, "2 2 4 3 5 0", "2 2 4 3 5 1.5")), 3,
                        "region attribute 1.5 is not a non-negative integer label"));
  EXPECT_TRUE(throws_at(read(kNode, replaced(kEle, "2 2 4 3 5 0", "2 2 4 3 2 0")), 3,
                        "tetrahedron repeats a node"));
  EXPECT_TRUE(
      throws_at(read(replaced(kNode, "5 1 1 1", "5 0.5 0.5 0"), kEle), 3,
                "degenerate tetrahedron (zero volume: its nodes are coplanar or coincide)"));
}

class TetgenFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    std::ofstream(dir_ / "organ.1.node") << kNode;
    std::ofstream(dir_ / "organ.1.ele") << kEle;
  }
  incise::test::TempDir tmp_{"incise-tetgen"};
  fs::path dir_ = tmp_.path();
};

TEST_F(TetgenFiles, ReadsByNodeEleOrBaseName) {
  expect_sample_mesh(read_tetgen(dir_ / "organ.1.node"));
  expect_sample_mesh(read_tetgen(dir_ / "organ.1.ele"));
  expect_sample_mesh(read_tetgen(dir_ / "organ.1"));
}

TEST_F(TetgenFiles, ErrorsNameTheFileTheyAreIn) {
  std::ofstream(dir_ / "organ.1.ele") << replaced(kEle, "2 2 4 3 5 0", "2 2 4 3 9 0");
  const std::string ele = (dir_ / "organ.1.ele").string();
  try {
    read_tetgen(dir_ / "organ.1");
    FAIL() << "no error";
  } catch (const MeshFileError& error) {
    EXPECT_EQ(error.what(), ele + ":3: node index 9 out of range [1, 5] of the .node file");
  }
  fs::remove(dir_ / "organ.1.ele");
  try {
    read_tetgen(dir_ / "organ.1.node");
    FAIL() << "no error";
  } catch (const MeshFileError& error) {
    EXPECT_EQ(error.what(), ele + ": cannot open file (No such file or directory)");
  }
}

}  // namespace
}  // namespace incise::sim
