#include "sim/mesh/nifti/nifti_segmentation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

#include "sim/mesh/cgal/mesh_generation.h"
#include "tests/sim/mesh/nifti/nifti_test_file.h"
#include "tests/support/temp_dir.h"

namespace incise::sim {
namespace {

using test::directions;
using test::kNx;
using test::kNy;
using test::kNz;
using test::kOriginMm;
using test::kSpacingMm;
using test::NiftiTestFile;
using test::organ_labels;
using test::organ_with_sform;
using test::write_nifti;

const SegmentationTissues kTissues{{1, "parenchyma"}, {2, "tumour"}};

class NiftiSegmentation : public ::testing::Test {
 protected:
  std::filesystem::path path(const std::string& name) const { return tmp_.path() / name; }

  // The one-line message read_nifti_segmentation throws for the file, or "no error".
  std::string error_for(const std::filesystem::path& file,
                        const SegmentationTissues& tissues = kTissues) const {
    try {
      read_nifti_segmentation(file, tissues);
    } catch (const SegmentationFileError& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
      EXPECT_EQ(message.rfind(file.string() + ": ", 0), 0u) << message;
      return message;
    }
    return "no error";
  }

  incise::test::TempDir tmp_{"incise-nifti"};
};

TEST_F(NiftiSegmentation, TheVolumeKeepsItsAffineInMetres) {
  const auto file = path("organ.nii.gz");
  write_nifti(file, organ_with_sform());
  const LabelVolume v = read_nifti_segmentation(file, kTissues);
  EXPECT_EQ(v.dims, Vec3i(kNx, kNy, kNz));
  EXPECT_TRUE(v.spacing.isApprox(kSpacingMm * 1e-3, 1e-6)) << v.spacing.transpose();
  EXPECT_TRUE(v.origin.isApprox(kOriginMm * 1e-3, 1e-6)) << v.origin.transpose();
  EXPECT_TRUE(v.axes.isApprox(directions(), 1e-6)) << v.axes;
  EXPECT_LT(v.axes.determinant(), 0);  // the mirror is kept
  // Every voxel's centre, where the affine puts it, carries that voxel's label.
  const std::vector<std::int16_t> labels = organ_labels();
  for (int k = 0; k < kNz; ++k)
    for (int j = 0; j < kNy; ++j)
      for (int i = 0; i < kNx; ++i) {
        const Vec3 world_mm = kOriginMm + directions() * Vec3(i, j, k).cwiseProduct(kSpacingMm);
        ASSERT_EQ(label_at(v, world_mm * 1e-3), labels[i + kNx * (j + kNy * k)])
            << i << " " << j << " " << k;
      }
}

TEST_F(NiftiSegmentation, TheQformAndTheSformOfOnePlaceGiveOneVolume) {
  NiftiTestFile q = organ_with_sform();
  q.sform_code = 0;
  q.qform_code = NIFTI_XFORM_SCANNER_ANAT;
  q.quatern = {0, 0, float(std::sqrt(0.5))};  // a quarter turn about z
  q.pixdim[0] = -1;                           // qfac: k mirrored
  q.qoffset = {float(kOriginMm.x()), float(kOriginMm.y()), float(kOriginMm.z())};
  write_nifti(path("q.nii"), q);
  write_nifti(path("s.nii"), organ_with_sform());
  const LabelVolume a = read_nifti_segmentation(path("q.nii"), kTissues);
  const LabelVolume b = read_nifti_segmentation(path("s.nii"), kTissues);
  EXPECT_TRUE(a.axes.isApprox(b.axes, 1e-6)) << a.axes << "\n" << b.axes;
  EXPECT_TRUE(a.spacing.isApprox(b.spacing, 1e-6));
  EXPECT_TRUE(a.origin.isApprox(b.origin, 1e-6));
  EXPECT_EQ(a.labels, b.labels);

  // Neither code: the voxel sizes alone, at the origin.
  NiftiTestFile plain = organ_with_sform();
  plain.sform_code = 0;
  write_nifti(path("plain.nii"), plain);
  const LabelVolume p = read_nifti_segmentation(path("plain.nii"), kTissues);
  EXPECT_TRUE(p.axes.isApprox(Mat3::Identity()));
  EXPECT_TRUE(p.origin.isZero());
  EXPECT_TRUE(p.spacing.isApprox(kSpacingMm * 1e-3, 1e-6));

  // The same place written in metres.
  NiftiTestFile metres = organ_with_sform();
  metres.xyzt_units = NIFTI_UNITS_METER;
  for (auto& row : metres.srow)
    for (float& x : row)
      x /= 1000;
  write_nifti(path("metres.nii"), metres);
  const LabelVolume m = read_nifti_segmentation(path("metres.nii"), kTissues);
  EXPECT_TRUE(m.origin.isApprox(b.origin, 1e-6));
  EXPECT_TRUE(m.spacing.isApprox(b.spacing, 1e-6));
}

// The round trip the issue asks for: the meshed tissues lie where the volume's affine puts them.
TEST_F(NiftiSegmentation, TheMeshedOrganLiesWhereTheAffinePutsIt) {
  write_nifti(path("organ.nii.gz"), organ_with_sform());
  const LabelVolume v = read_nifti_segmentation(path("organ.nii.gz"), kTissues);
  MeshingCriteria c;
  c.cell_size = 0.002;
  c.facet_size = 0.002;
  c.facet_distance = 0.001;
  const TetMesh mesh = mesh_labelled_volume(v, c);
  const std::vector<std::int16_t> labels = organ_labels();
  for (int label : {1, 2}) {
    // The voxels' centroid, mapped by the affine (computed here, not by the reader).
    Vec3 voxel_sum = Vec3::Zero();
    int voxels = 0;
    for (int k = 0; k < kNz; ++k)
      for (int j = 0; j < kNy; ++j)
        for (int i = 0; i < kNx; ++i)
          if (labels[i + kNx * (j + kNy * k)] == label) {
            voxel_sum += 1e-3 * (kOriginMm + directions() * Vec3(i, j, k).cwiseProduct(kSpacingMm));
            ++voxels;
          }
    const Vec3 expected = voxel_sum / voxels;
    Vec3 moment = Vec3::Zero();
    Real volume = 0;
    for (int t = 0; t < mesh.num_tets(); ++t) {
      if (mesh.labels[t] != label) continue;
      Vec3 p[4];
      for (int n = 0; n < 4; ++n)
        p[n] = mesh.rest.row(mesh.tets(t, n)).transpose();
      const Real tv = (p[1] - p[0]).cross(p[2] - p[0]).dot(p[3] - p[0]) / 6;
      EXPECT_GT(tv, 0) << "tet " << t;
      moment += tv * (p[0] + p[1] + p[2] + p[3]) / 4;
      volume += tv;
    }
    ASSERT_GT(volume, 0) << "label " << label;
    const Vec3 centroid = moment / volume;
    EXPECT_LT((centroid - expected).norm(), 0.7e-3)
        << "label " << label << ": meshed " << centroid.transpose() << ", voxels "
        << expected.transpose();
    const Real voxel_volume = voxels * kSpacingMm.prod() * 1e-9;
    EXPECT_NEAR(volume / voxel_volume, 1, 0.2) << "label " << label;
  }
}

TEST_F(NiftiSegmentation, EachBadVolumeGetsOnePreciseLine) {
  const auto expect_error = [this](const std::string& name, const NiftiTestFile& f,
                                   const std::string& wanted,
                                   const SegmentationTissues& tissues = kTissues,
                                   std::size_t keep = static_cast<std::size_t>(-1)) {
    write_nifti(path(name), f, keep);
    const std::string message = error_for(path(name), tissues);
    EXPECT_NE(message.find(wanted), std::string::npos) << name << ": " << message;
  };
  const NiftiTestFile good = organ_with_sform();
  expect_error("unknown.nii", good, "unknown label 2 (", SegmentationTissues{{1, "parenchyma"}});
  expect_error("unknown.nii", good, "not mapped to a tissue; mapped: 1 (parenchyma)",
               SegmentationTissues{{1, "parenchyma"}});
  expect_error("empty.nii", good, "empty label 7 (vessel) has no voxels",
               SegmentationTissues{{1, "parenchyma"}, {2, "tumour"}, {7, "vessel"}});

  NiftiTestFile series = good;
  series.dim = {4, kNx, kNy, 8, 2, 1, 1, 1};  // the same bytes as 8 slices at 2 times
  expect_error("series.nii.gz", series, "the volume is 4-D (dimension 4 has 2)");
  NiftiTestFile slice = good;
  slice.dim = {2, kNx, kNy * kNz, 1, 1, 1, 1, 1};
  expect_error("slice.nii", slice, "the volume has 2 dimensions");

  expect_error("cut.nii", good, "voxel data is shorter than the header's 7680 x 2 bytes", kTissues,
               352 + 1000);
  expect_error("cut.nii.gz", good, "voxel data is shorter than the header's", kTissues, 352 + 1000);
  expect_error("header.nii", good, "no NIfTI-1 or NIfTI-2 header", kTissues, 100);

  NiftiTestFile fractional = good;
  std::vector<float> values(kNx * kNy * kNz, 0);
  values[5 + kNx * (6 + kNy * 7)] = 1.5f;
  fractional.set_voxels(kNx, kNy, kNz, values, DT_FLOAT32);
  expect_error("fraction.nii", fractional, "voxel (5, 6, 7) holds 1.5, not a label");
  std::vector<std::int16_t> negative(kNx * kNy * kNz, 1);
  negative[1] = -3;
  NiftiTestFile below = good;
  below.set_voxels(kNx, kNy, kNz, negative, DT_INT16);
  expect_error("negative.nii", below, "voxel (1, 0, 0) holds -3, not a label");

  NiftiTestFile rgb = good;
  rgb.datatype = DT_RGB24;
  rgb.bitpix = 24;
  expect_error("rgb.nii", rgb, "voxel type RGB24 holds no labels");

  NiftiTestFile sheared = good;
  sheared.srow[1][1] = 0.5f;  // j, along -x, leans towards i's +y
  expect_error("sheared.nii", sheared, "the sform shears the voxel axes (axes 1 and 2 meet at");
  NiftiTestFile flat = good;
  flat.srow[0][2] = flat.srow[1][2] = flat.srow[2][2] = 0;
  expect_error("flat.nii", flat, "the sform gives voxel axis 3 a length of 0");

  NiftiTestFile seconds = good;
  seconds.xyzt_units = 5;  // not a length code
  expect_error("units.nii", seconds, "spatial units code 5 is not a length");

  EXPECT_NE(error_for(path("missing.nii")).find("no such file"), std::string::npos);
  write_nifti(path("organ.raw"), good);
  EXPECT_NE(error_for(path("organ.raw")).find("not a NIfTI file name"), std::string::npos);
  EXPECT_THROW(read_nifti_segmentation(path("organ.raw"), {{0, "outside"}}), std::invalid_argument);
}

}  // namespace
}  // namespace incise::sim
