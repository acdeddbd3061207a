// Runs `incise mesh-info` as the real binary (INCISE_CLI_PATH, from CMake) as a user would.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "sample_files.h"
#include "sim/mesh/box_mesher.h"
#include "sim/mesh/msh_writer.h"
#include "sim/mesh/tetgen_writer.h"
#include "test_text.h"

#include "tests/sim/cli_fixture.h"

namespace incise::sim {
namespace {

namespace fs = std::filesystem;
using test::CliRun;

// The value after "key: " on the line that starts with key.
std::string value_of(const std::string& out, const std::string& key) {
  const std::size_t at = out.find("\n" + key + ": ");
  if (at == std::string::npos) return "<missing " + key + ">";
  const std::size_t start = at + key.size() + 3;
  return out.substr(start, out.find('\n', start) - start);
}

class MeshInfoCli : public test::CliFixture {};

TEST_F(MeshInfoCli, ReportsCountsLabelsBoxVolumeAndQuality) {
  // 2 x 2 x 1 cubic cells of edge 0.05: 18 nodes, 20 tets (4 regular, 16 right-corner).
  TetMesh mesh = make_box_mesh(Vec3(0.1, 0.1, 0.05), Vec3i(2, 2, 1));
  for (int t = 0; t < 5; ++t)
    mesh.labels(t) = 3;
  write_msh(dir_ / "box.msh", mesh, MshVersion::k4_1);
  const CliRun run = incise("mesh-info box.msh");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.err, "");
  const std::string out = "\n" + run.out;
  EXPECT_EQ(value_of(out, "file"), "box.msh");
  EXPECT_EQ(value_of(out, "nodes"), "18");
  EXPECT_EQ(value_of(out, "tets"), "20");
  EXPECT_EQ(value_of(out, "labels (label: tets)"), "0: 15, 3: 5");
  EXPECT_EQ(value_of(out, "bounding box [m]"), "[0, 0, 0] to [0.1, 0.1, 0.05]");
  EXPECT_NEAR(std::stod(value_of(out, "total volume [m^3]")), 0.1 * 0.1 * 0.05, 1e-9);
  EXPECT_EQ(value_of(out, "inverted tets"), "0");
  EXPECT_EQ(value_of(out, "degenerate tets"), "0");
  // Aspect 1 (regular) to (1 + sqrt 3) / 2 = 1.36603 (right corner), 6 significant digits.
  EXPECT_EQ(value_of(out, "aspect ratio (longest edge / (2 sqrt(6) inradius), 1 = regular)")
                .substr(0, 22),
            "min 1, max 1.36603, me");
  EXPECT_EQ(value_of(out, "min dihedral angle [deg]").substr(0, 25), "min 54.7356, max 70.5288,");
  EXPECT_EQ(value_of(out, "aspect ratio histogram (bucket count)"),
            "[1, 1.5) 20, [1.5, 2) 0, [2, 3) 0, [3, 5) 0, [5, 10) 0, [10, inf] 0");
}

TEST_F(MeshInfoCli, ReadsTetgenByBaseName) {
  write("organ.node", test::kNode);
  write("organ.ele", test::kEle);
  for (const std::string name : {"organ", "organ.node", "organ.ele"}) {
    const CliRun run = incise("mesh-info " + name);
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const std::string out = "\n" + run.out;
    EXPECT_EQ(value_of(out, "nodes"), "5");
    EXPECT_EQ(value_of(out, "labels (label: tets)"), "0: 1, 7: 1");
    EXPECT_EQ(value_of(out, "total volume [m^3]"), "0.5");  // 1/6 + 1/3
  }
}

TEST_F(MeshInfoCli, BadFileExits2WithOneLineNamingFileAndLine) {
  write("bad.msh", test::replaced(test::kMsh22, "30 0 1 0\n", "30 0 nan 0\n"));
  CliRun run = incise("mesh-info bad.msh");
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_EQ(run.out, "");
  EXPECT_EQ(run.err, "incise: bad.msh:12: node 30 y: not finite ('nan')\n");

  write("cut.msh", test::first_lines(test::kMsh22, 11));
  run = incise("mesh-info cut.msh");
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_EQ(run.err, "incise: cut.msh:11: truncated file: expected node 3 of 6\n");

  write("flat.node", test::replaced(test::kNode, "5 1 1 1", "5 0.5 0.5 0"));
  write("flat.ele", test::kEle);
  run = incise("mesh-info flat");
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_EQ(run.err,
            "incise: flat.ele:3: degenerate tetrahedron (zero volume: its nodes are coplanar or "
            "coincide)\n");

  run = incise("mesh-info missing.msh");
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_EQ(run.err, "incise: missing.msh: cannot open file (No such file or directory)\n");
}

TEST_F(MeshInfoCli, UsageErrors) {
  for (const std::string arguments : {"mesh-info", "mesh-info a.msh b.msh", "mesh-info --fast"}) {
    const CliRun run = incise(arguments);
    EXPECT_EQ(run.exit_code, 2) << arguments;
    EXPECT_NE(
        run.err.find("usage: incise solve SCENE.json --out RESULT.json, incise mesh-info MESH"),
        std::string::npos)
        << arguments << ": " << run.err;
  }
  const CliRun help = incise("--help");
  EXPECT_NE(help.out.find("incise mesh-info MESH"), std::string::npos);
}

}  // namespace
}  // namespace incise::sim
