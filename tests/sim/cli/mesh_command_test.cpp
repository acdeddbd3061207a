// `incise mesh` and scenes that name a segmentation, run as a user would (the real binary).

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>
#include <set>
#include <string>

#include "sim/mesh/read_mesh_file.h"
#include "tests/sim/cli_fixture.h"
#include "tests/sim/mesh/nifti/nifti_test_file.h"

namespace incise::sim {
namespace {

using nlohmann::json;
using test::CliRun;

class MeshCommand : public test::CliFixture {
 protected:
  void SetUp() override { test::write_nifti(dir_ / "organ.nii.gz", test::organ_with_sform()); }
};

TEST_F(MeshCommand, MeshesTheVolumeWhereItsAffineIsAndReportsTheQuality) {
  const CliRun run =
      incise("mesh organ.nii.gz --labels 1=parenchyma,2=tumour --cell-size 0.002 --out organ.msh");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.err, "");
  EXPECT_NE(run.out.find("voxels: 24 x 20 x 16, spacing [0.0015, 0.001, 0.002] m\n"),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("axis j: [-1, 0, 0]\n"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("orientation: mirrored\n"), std::string::npos);
  EXPECT_NE(run.out.find("tissue 1 parenchyma: "), std::string::npos);
  EXPECT_NE(run.out.find("tissue 2 tumour: "), std::string::npos);

  // The written mesh holds both tissues inside the scan's box in the world: x from -(20 - 1/2)
  // voxels of j to +1/2 voxel about the origin's 40 mm, and so on.
  const TetMesh mesh = read_mesh_file(dir_ / "organ.msh");
  std::set<int> labels(mesh.labels.begin(), mesh.labels.end());
  EXPECT_EQ(labels, (std::set<int>{1, 2}));
  const Vec3 low = mesh.rest.colwise().minCoeff().transpose();
  const Vec3 high = mesh.rest.colwise().maxCoeff().transpose();
  EXPECT_GE(low.x(), 0.040 - 19.5e-3 - 1e-6);
  EXPECT_LE(high.x(), 0.040 + 0.5e-3 + 1e-6);
  EXPECT_GE(low.y(), -0.025 - 0.75e-3 - 1e-6);
  EXPECT_LE(high.y(), -0.025 + 23.5 * 1.5e-3 + 1e-6);
  EXPECT_GE(low.z(), 0.060 - 15.5 * 2e-3 - 1e-6);
  EXPECT_LE(high.z(), 0.060 + 1e-3 + 1e-6);

  // The quality report is mesh-info's of the written file.
  const CliRun info = incise("mesh-info organ.msh");
  ASSERT_EQ(info.exit_code, 0) << info.err;
  const std::string report = run.out.substr(run.out.find("mesh: organ.msh\n") + 16);
  EXPECT_EQ(report, info.out.substr(info.out.find('\n') + 1));
  EXPECT_NE(report.find("dihedral"), std::string::npos);
}

TEST_F(MeshCommand, BadVolumesAndArgumentsAreOneLineAndExitCode2) {
  const auto expect_usage = [this](const std::string& arguments, const std::string& wanted) {
    const CliRun run = incise(arguments);
    EXPECT_EQ(run.exit_code, 2) << arguments;
    EXPECT_EQ(run.out, "") << arguments;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    EXPECT_NE(run.err.find(wanted), std::string::npos) << arguments << ": " << run.err;
  };
  expect_usage("mesh organ.nii.gz --labels 1=parenchyma --cell-size 0.002 --out o.msh",
               "incise: organ.nii.gz: unknown label 2 (");
  expect_usage("mesh organ.nii.gz --labels 1=a,2=b,3=c --cell-size 0.002 --out o.msh",
               "empty label 3 (c) has no voxels");
  expect_usage("mesh organ.nii.gz --labels 1=a,x=b --cell-size 0.002 --out o.msh",
               "--labels item \"x=b\" is not VALUE=NAME");
  expect_usage("mesh organ.nii.gz --labels 1=a,2=b --cell-size -1 --out o.msh",
               "--cell-size must be a length > 0");
  expect_usage("mesh organ.nii.gz --labels 1=a,2=b --cell-size 0.002 --out o.stl",
               "--out must end in .msh, .vtu or .node");
  expect_usage("mesh organ.nii.gz --labels 1=a,2=b --out o.msh", "needs --cell-size");
  expect_usage("mesh nothing.nii --labels 1=a --cell-size 0.002 --out o.msh",
               "nothing.nii: no such file");
  EXPECT_FALSE(std::filesystem::exists(dir_ / "o.msh"));
}

TEST_F(MeshCommand, ASceneNamesTheSegmentationAndItsTissuesMaterials) {
  json scene = json::parse(R"({
    "mesh": {"segmentation": {"file": "organ.nii.gz", "labels": {"1": "parenchyma", "2": "tumour"},
                              "cell_size": 0.003}},
    "material": {"model": "corotational_polar", "E": 3000, "nu": 0.45, "density": 1000},
    "materials": {"tumour": {"E": 30000, "nu": 0.45, "density": 1100}},
    "solver": {"integrator": "symplectic_euler", "dt": 1e-5, "steps": 20}
  })");
  write("scene.json", scene.dump());
  const CliRun run = incise("solve scene.json --out result.json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const json result = json::parse(test::read_file(dir_ / "result.json"));
  EXPECT_GT(result["tets"].get<int>(), 100);
  EXPECT_TRUE(result["finite"].get<bool>());
  // The rest positions are the scan's world coordinates (x within the origin's -19.5..0.5 mm).
  for (const json& p : result["rest"]) {
    ASSERT_GE(p[0].get<double>(), 0.040 - 19.5e-3 - 1e-6);
    ASSERT_LE(p[0].get<double>(), 0.040 + 0.5e-3 + 1e-6);
  }

  scene["materials"] = json::parse(R"({"tumor": {"E": 30000, "nu": 0.45, "density": 1100}})");
  write("scene.json", scene.dump());
  CliRun bad = incise("solve scene.json --out result.json");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("materials.tumor: is neither a label nor a tissue"), std::string::npos)
      << bad.err;

  scene["materials"] = json::object();
  scene["mesh"]["segmentation"]["labels"] = json::parse(R"({"1": "parenchyma"})");
  write("scene.json", scene.dump());
  bad = incise("solve scene.json --out result.json");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("mesh.segmentation.file: "), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("unknown label 2"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace incise::sim
