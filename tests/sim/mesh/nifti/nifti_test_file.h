#pragma once
// Writes NIfTI-1 single files (.nii, or .nii.gz through zlib) byte by byte from nifti1.h's header
// struct, so that tests control every field the reader looks at: dimensions, voxel type, the
// sform and qform with their codes, units, scaling, and a file cut short.
#include <nifti1.h>
#include <zlib.h>

#include "sim/core/types.h"

#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace incise::sim::test {

struct NiftiTestFile {
  std::array<std::int16_t, 8> dim{3, 1, 1, 1, 1, 1, 1, 1};
  std::int16_t datatype = DT_UINT8;
  std::int16_t bitpix = 8;
  std::array<float, 4> pixdim{1, 1, 1, 1};  // [0] is qfac
  std::int16_t sform_code = 0;
  std::array<std::array<float, 4>, 3> srow{};  // the sform's rows
  std::int16_t qform_code = 0;
  std::array<float, 3> quatern{};  // b, c, d
  std::array<float, 3> qoffset{};
  char xyzt_units = NIFTI_UNITS_MM;
  float scl_slope = 0;
  float scl_inter = 0;
  std::vector<unsigned char> data;  // the voxels' bytes, x fastest

  // Voxels of one type from values, x fastest; sets dim, datatype and bitpix.
  template <typename T>
  void set_voxels(int nx, int ny, int nz, const std::vector<T>& values, std::int16_t type) {
    dim = {3,
           static_cast<std::int16_t>(nx),
           static_cast<std::int16_t>(ny),
           static_cast<std::int16_t>(nz),
           1,
           1,
           1,
           1};
    datatype = type;
    bitpix = static_cast<std::int16_t>(8 * sizeof(T));
    data.resize(values.size() * sizeof(T));
    std::memcpy(data.data(), values.data(), data.size());
  }
};

// Writes file to path (compressed if path ends in .gz), keeping only the first `keep` bytes.
inline void write_nifti(const std::filesystem::path& path, const NiftiTestFile& file,
                        std::size_t keep = static_cast<std::size_t>(-1)) {
  nifti_1_header h;
  std::memset(&h, 0, sizeof h);
  h.sizeof_hdr = 348;
  for (int d = 0; d < 8; ++d)
    h.dim[d] = file.dim[d];
  h.datatype = file.datatype;
  h.bitpix = file.bitpix;
  h.pixdim[0] = file.pixdim[0];
  for (int d = 1; d < 4; ++d)
    h.pixdim[d] = file.pixdim[d];
  for (int d = 4; d < 8; ++d)
    h.pixdim[d] = 1;
  h.vox_offset = 352;
  h.scl_slope = file.scl_slope;
  h.scl_inter = file.scl_inter;
  h.xyzt_units = file.xyzt_units;
  h.qform_code = file.qform_code;
  h.sform_code = file.sform_code;
  h.quatern_b = file.quatern[0];
  h.quatern_c = file.quatern[1];
  h.quatern_d = file.quatern[2];
  h.qoffset_x = file.qoffset[0];
  h.qoffset_y = file.qoffset[1];
  h.qoffset_z = file.qoffset[2];
  for (int c = 0; c < 4; ++c) {
    h.srow_x[c] = file.srow[0][c];
    h.srow_y[c] = file.srow[1][c];
    h.srow_z[c] = file.srow[2][c];
  }
  std::memcpy(h.magic, "n+1", 4);
  std::vector<unsigned char> bytes(352, 0);  // the header and an empty extension block
  std::memcpy(bytes.data(), &h, sizeof h);
  bytes.insert(bytes.end(), file.data.begin(), file.data.end());
  if (keep < bytes.size()) bytes.resize(keep);
  if (path.extension() == ".gz") {
    gzFile gz = gzopen(path.c_str(), "wb");
    gzwrite(gz, bytes.data(), static_cast<unsigned>(bytes.size()));
    gzclose(gz);
  } else {
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()),
               static_cast<std::streamsize>(bytes.size()));
  }
}

// A sample segmentation for the tests: a labelled organ in a rotated, mirrored scan.
inline constexpr int kNx = 24, kNy = 20, kNz = 16;
inline const Vec3 kSpacingMm(1.5, 1.0, 2.0);
inline const Vec3 kOriginMm(40, -25, 60);
// The voxel axes in the world: i along +y, j along -x, k along -z (a quarter turn about z and a
// mirror, as radiological storage has), each column scaled by its spacing.
inline Mat3 directions() {
  Mat3 d;
  d.col(0) = Vec3(0, 1, 0);
  d.col(1) = Vec3(-1, 0, 0);
  d.col(2) = Vec3(0, 0, -1);
  return d;
}

// Label 1: a box of voxels; label 2: a ball of radius 4 mm inside it, off the box's centre.
inline std::vector<std::int16_t> organ_labels() {
  const Vec3 ball(8, 10, 8);
  std::vector<std::int16_t> labels;
  for (int k = 0; k < kNz; ++k)
    for (int j = 0; j < kNy; ++j)
      for (int i = 0; i < kNx; ++i) {
        const bool box = i >= 3 && i <= 20 && j >= 3 && j <= 16 && k >= 2 && k <= 13;
        const Vec3 offset = (Vec3(i, j, k) - ball).cwiseProduct(kSpacingMm);
        labels.push_back(offset.norm() < 4 ? 2 : box ? 1 : 0);
      }
  return labels;
}

inline NiftiTestFile organ_with_sform() {
  NiftiTestFile f;
  f.set_voxels(kNx, kNy, kNz, organ_labels(), DT_INT16);
  f.pixdim = {1, float(kSpacingMm.x()), float(kSpacingMm.y()), float(kSpacingMm.z())};
  f.sform_code = NIFTI_XFORM_SCANNER_ANAT;
  const Mat3 m = directions() * kSpacingMm.asDiagonal();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c)
      f.srow[r][c] = float(m(r, c));
    f.srow[r][3] = float(kOriginMm[r]);
  }
  return f;
}

}  // namespace incise::sim::test
