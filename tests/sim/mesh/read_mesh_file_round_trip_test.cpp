// Write a mesh with the sim/mesh writers, read it back with the readers: identical nodes, tets
// and labels, bit for bit.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <utility>

#include "sim/mesh/box_mesher.h"
#include "sim/mesh/mesh_file_error.h"
#include "sim/mesh/msh_reader.h"
#include "sim/mesh/msh_writer.h"
#include "sim/mesh/read_mesh_file.h"
#include "sim/mesh/tetgen_reader.h"
#include "sim/mesh/tetgen_writer.h"
#include "tests/support/temp_dir.h"

namespace incise::sim {
namespace {

namespace fs = std::filesystem;

// A box mesh with coordinates that have no short decimal form and labels in runs of varying
// length (with label 0 among them), so that 4.1 needs several element blocks per volume.
TetMesh labelled_box() {
  TetMesh mesh = make_box_mesh(Vec3(0.1, 0.2 / 3, std::sqrt(2.0) / 10), Vec3i(2, 3, 2));
  for (int t = 0; t < mesh.num_tets(); ++t)
    mesh.labels(t) = (t / 7) % 3 + (t % 11 == 0 ? 5 : 0);
  mesh.rest.col(0) += mesh.rest.col(1) * (1.0 / 3);  // shear: irrational-looking doubles
  mesh.x = mesh.rest;
  return mesh;
}

void expect_identical(const TetMesh& read, const TetMesh& written) {
  EXPECT_EQ(read.rest, written.rest);  // exact: shortest round-trip decimal
  EXPECT_EQ(read.x, written.rest);
  EXPECT_EQ(read.tets, written.tets);
  EXPECT_EQ(read.labels, written.labels);
}

class RoundTrip : public ::testing::Test {
 protected:
  incise::test::TempDir tmp_{"incise-round-trip"};
  fs::path dir_ = tmp_.path();
};

TEST_F(RoundTrip, Msh22) {
  const TetMesh mesh = labelled_box();
  write_msh(dir_ / "box.msh", mesh, MshVersion::k2_2);
  expect_identical(read_msh(dir_ / "box.msh"), mesh);
  expect_identical(read_mesh_file(dir_ / "box.msh"), mesh);
}

TEST_F(RoundTrip, Msh41) {
  const TetMesh mesh = labelled_box();
  write_msh(dir_ / "box.msh", mesh, MshVersion::k4_1);
  expect_identical(read_msh(dir_ / "box.msh"), mesh);
}

TEST_F(RoundTrip, Tetgen) {
  const TetMesh mesh = labelled_box();
  write_tetgen(dir_ / "box", mesh);
  EXPECT_TRUE(fs::exists(dir_ / "box.node"));
  EXPECT_TRUE(fs::exists(dir_ / "box.ele"));
  expect_identical(read_tetgen(dir_ / "box"), mesh);
  expect_identical(read_mesh_file(dir_ / "box"), mesh);
  expect_identical(read_mesh_file(dir_ / "box.ele"), mesh);
}

TEST_F(RoundTrip, NegativelyOrientedTetsComeBackPositive) {
  // Writing each tet with its last two nodes swapped (all negative) and reading it back must
  // undo exactly that swap.
  const TetMesh mesh = labelled_box();
  TetMesh mirrored = mesh;
  mirrored.tets.col(2).swap(mirrored.tets.col(3));
  ASSERT_LT(tet_volumes(mirrored.rest, mirrored.tets).maxCoeff(), 0);
  expect_identical(read_msh_string(format_msh(mirrored, MshVersion::k2_2)), mesh);
  expect_identical(read_msh_string(format_msh(mirrored, MshVersion::k4_1)), mesh);
  expect_identical(read_tetgen_strings(format_tetgen_node(mirrored), format_tetgen_ele(mirrored)),
                   mesh);
}

TEST_F(RoundTrip, NegativeLabelsCannotBeWritten) {
  TetMesh mesh = labelled_box();
  mesh.labels(4) = -1;
  EXPECT_THROW(format_msh(mesh, MshVersion::k2_2), std::invalid_argument);
  EXPECT_THROW(format_tetgen_ele(mesh), std::invalid_argument);
}

TEST_F(RoundTrip, UnknownFormatAndMissingFileAreErrors) {
  EXPECT_THROW(read_mesh_file(dir_ / "nothing"), MeshFileError);
  write_msh(dir_ / "box.txt", labelled_box(), MshVersion::k2_2);
  try {
    read_mesh_file(dir_ / "box.txt");
    FAIL() << "no error";
  } catch (const MeshFileError& error) {
    EXPECT_EQ(error.problem(),
              "unknown mesh format (expected .msh, .node, .ele or a TetGen base name)");
  }
}

}  // namespace
}  // namespace incise::sim
