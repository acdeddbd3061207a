#include "sim/mesh/nifti/nifti_segmentation.h"

#include <nifti2_io.h>

#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <mutex>
#include <numbers>
#include <sstream>

namespace incise::sim {
namespace {

struct NiftiImageFree {
  void operator()(nifti_image* image) const { nifti_image_free(image); }
};
using NiftiImage = std::unique_ptr<nifti_image, NiftiImageFree>;

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& problem) {
  throw SegmentationFileError(file.string() + ": " + problem);
}

bool has_nifti_name(const std::filesystem::path& file) {
  std::string name = file.filename().string();
  if (name.size() > 3 && name.ends_with(".gz")) name.resize(name.size() - 3);
  return name.ends_with(".nii") || name.ends_with(".hdr") || name.ends_with(".img");
}

// Whether voxels of the type can hold labels: the integer types, and the float types (which
// many tools write; each value must then be an integer).
bool is_label_type(int datatype) {
  switch (datatype) {
    case DT_UINT8:
    case DT_INT8:
    case DT_INT16:
    case DT_UINT16:
    case DT_INT32:
    case DT_UINT32:
    case DT_INT64:
    case DT_UINT64:
    case DT_FLOAT32:
    case DT_FLOAT64:
      return true;
    default:
      return false;
  }
}

template <typename T>
double value_of(const void* data, std::int64_t index) {
  T v;
  std::memcpy(&v, static_cast<const unsigned char*>(data) + index * sizeof(T), sizeof(T));
  return static_cast<double>(v);
}

// The voxel's value as a double, for a type is_label_type admits.
double voxel_value(const nifti_image& image, std::int64_t index) {
  switch (image.datatype) {
    case DT_UINT8:
      return value_of<std::uint8_t>(image.data, index);
    case DT_INT8:
      return value_of<std::int8_t>(image.data, index);
    case DT_INT16:
      return value_of<std::int16_t>(image.data, index);
    case DT_UINT16:
      return value_of<std::uint16_t>(image.data, index);
    case DT_INT32:
      return value_of<std::int32_t>(image.data, index);
    case DT_UINT32:
      return value_of<std::uint32_t>(image.data, index);
    case DT_INT64:
      return value_of<std::int64_t>(image.data, index);
    case DT_UINT64:
      return value_of<std::uint64_t>(image.data, index);
    case DT_FLOAT32:
      return value_of<float>(image.data, index);
    default:  // DT_FLOAT64: is_label_type admits no other
      return value_of<double>(image.data, index);
  }
}

std::string voxel_name(const Vec3i& dims, std::int64_t index) {
  const std::int64_t i = index % dims.x();
  const std::int64_t j = (index / dims.x()) % dims.y();
  const std::int64_t k = index / (static_cast<std::int64_t>(dims.x()) * dims.y());
  return "voxel (" + std::to_string(i) + ", " + std::to_string(j) + ", " + std::to_string(k) + ")";
}

std::string number(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

// Metres per unit of the file's spatial units.
double metres_per_unit(const std::filesystem::path& file, int xyz_units) {
  switch (xyz_units) {
    case NIFTI_UNITS_UNKNOWN:  // unset: millimetres, as every scanner and segmentation tool
    case NIFTI_UNITS_MM:
      return 1e-3;
    case NIFTI_UNITS_METER:
      return 1;
    case NIFTI_UNITS_MICRON:
      return 1e-6;
    default:
      fail(file,
           "spatial units code " + std::to_string(xyz_units) + " is not a length (m, mm or um)");
  }
}

// The 3 x 4 affine from voxel indices to the file's world (its units), by nibabel's rule.
Eigen::Matrix<double, 3, 4> voxel_to_world(const nifti_image& image, std::string& which) {
  Eigen::Matrix<double, 3, 4> affine = Eigen::Matrix<double, 3, 4>::Zero();
  const nifti_dmat44* m = nullptr;
  if (image.sform_code > 0) {
    m = &image.sto_xyz;
    which = "sform";
  } else if (image.qform_code > 0) {
    m = &image.qto_xyz;
    which = "qform";
  }
  if (m != nullptr) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c)
        affine(r, c) = m->m[r][c];
  } else {
    which = "voxel sizes (pixdim)";
    for (int a = 0; a < 3; ++a)
      affine(a, a) = image.pixdim[a + 1];
  }
  return affine;
}

void check_tissues(const SegmentationTissues& tissues) {
  for (const auto& [label, name] : tissues) {
    if (label < 1 || label > 255)
      throw std::invalid_argument("segmentation tissues: label " + std::to_string(label) +
                                  " is outside 1..255 (0 is the outside)");
    if (name.empty())
      throw std::invalid_argument("segmentation tissues: label " + std::to_string(label) +
                                  " has an empty tissue name");
  }
}

std::string mapped_labels(const SegmentationTissues& tissues) {
  std::string list;
  for (const auto& [label, name] : tissues)
    list += (list.empty() ? "" : ", ") + std::to_string(label) + " (" + name + ")";
  return list.empty() ? "none" : list;
}

}  // namespace

LabelVolume read_nifti_segmentation(const std::filesystem::path& file,
                                    const SegmentationTissues& tissues) {
  check_tissues(tissues);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) fail(file, "no such file");
  if (!has_nifti_name(file))
    fail(file, "not a NIfTI file name (.nii, .nii.gz, or a .hdr/.img pair)");
  // nifticlib reports its own errors on stderr unless told not to; ours are the messages.
  static std::once_flag quiet;
  std::call_once(quiet, [] { nifti_set_debug_level(0); });

  NiftiImage image(nifti_image_read(file.c_str(), 0));
  if (!image) fail(file, "no NIfTI-1 or NIfTI-2 header (not a NIfTI file, or cut short)");
  const nifti_image& nim = *image;
  const std::int64_t ndim = nim.dim[0];
  if (ndim < 3 || ndim > 7)
    fail(file, "the volume has " + std::to_string(ndim) +
                   " dimensions; a segmentation is one 3-D volume of labels");
  for (int d = 4; d <= ndim; ++d)
    if (nim.dim[d] != 1)
      fail(file, "the volume is " + std::to_string(ndim) + "-D (dimension " + std::to_string(d) +
                     " has " + std::to_string(nim.dim[d]) +
                     "); a segmentation is one 3-D volume of labels");
  for (int d = 1; d <= 3; ++d)
    if (nim.dim[d] < 1 || nim.dim[d] > kMaxSegmentationVoxels)
      fail(file,
           "dimension " + std::to_string(d) + " has " + std::to_string(nim.dim[d]) + " voxels");
  const std::int64_t count = nim.dim[1] * nim.dim[2] * nim.dim[3];
  if (count > kMaxSegmentationVoxels)
    fail(file, std::to_string(count) + " voxels is more than the " +
                   std::to_string(kMaxSegmentationVoxels) + " read (crop or resample the volume)");
  if (!is_label_type(nim.datatype))
    fail(file, std::string("voxel type ") + nifti_datatype_string(nim.datatype) +
                   " holds no labels (use an integer type such as uint8 or int16)");

  LabelVolume volume;
  volume.dims = Vec3i(static_cast<int>(nim.dim[1]), static_cast<int>(nim.dim[2]),
                      static_cast<int>(nim.dim[3]));
  const double unit = metres_per_unit(file, nim.xyz_units);
  std::string which;
  const Eigen::Matrix<double, 3, 4> affine = voxel_to_world(nim, which);
  if (!affine.allFinite()) fail(file, "the " + which + " affine is not finite");
  Mat3 directions;
  for (int a = 0; a < 3; ++a) {
    const double length = affine.col(a).norm();
    if (!(length > 0) || !std::isfinite(length))
      fail(file, "the " + which + " gives voxel axis " + std::to_string(a + 1) + " a length of " +
                     number(length) + ": the voxel spacing must be finite and > 0");
    volume.spacing[a] = length * unit;
    directions.col(a) = affine.col(a) / length;
  }
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b) {
      const double cosine = directions.col(a).dot(directions.col(b));
      if (std::abs(cosine) > 1e-4)
        fail(file, "the " + which + " shears the voxel axes (axes " + std::to_string(a + 1) +
                       " and " + std::to_string(b + 1) + " meet at " +
                       number(std::acos(std::clamp(cosine, -1.0, 1.0)) * 180 / std::numbers::pi) +
                       " degrees); resample the volume to perpendicular axes");
    }
  // The nearest orthonormal matrix (NIfTI-1 stores the sform in single precision), its
  // handedness kept.
  const Eigen::JacobiSVD<Mat3> svd(directions, Eigen::ComputeFullU | Eigen::ComputeFullV);
  volume.axes = svd.matrixU() * svd.matrixV().transpose();
  // Axis-aligned scans (the usual case) keep exact zeros, without the SVD's -0 and 1e-17.
  volume.axes = volume.axes.unaryExpr([](double x) { return std::abs(x) < 1e-12 ? 0.0 : x; });
  volume.origin = affine.col(3) * unit;

  if (nifti_image_load(image.get()) != 0 || nim.data == nullptr)
    fail(file, "the voxel data is shorter than the header's " + std::to_string(count) + " x " +
                   std::to_string(nim.nbyper) + " bytes (a truncated file?)");
  const bool scaled = nim.scl_slope != 0 && !(nim.scl_slope == 1 && nim.scl_inter == 0);
  std::array<std::int64_t, 256> voxels{};
  std::array<std::int64_t, 256> first{};
  volume.labels.resize(static_cast<std::size_t>(count));
  for (std::int64_t v = 0; v < count; ++v) {
    double value = voxel_value(nim, v);
    if (scaled) value = value * nim.scl_slope + nim.scl_inter;
    if (!(value >= 0 && value <= 255) || value != std::floor(value))
      fail(file, voxel_name(volume.dims, v) + " holds " + number(value) +
                     ", not a label (an integer in 0..255)");
    const int label = static_cast<int>(value);
    if (voxels[label]++ == 0) first[label] = v;
    volume.labels[static_cast<std::size_t>(v)] = static_cast<std::uint8_t>(label);
  }
  for (int label = 1; label < 256; ++label)
    if (voxels[label] > 0 && !tissues.contains(label))
      fail(file, "unknown label " + std::to_string(label) + " (" + std::to_string(voxels[label]) +
                     " voxels, the first at " + voxel_name(volume.dims, first[label]) +
                     ") is not mapped to a tissue; mapped: " + mapped_labels(tissues));
  for (const auto& [label, name] : tissues)
    if (voxels[label] == 0)
      fail(file, "empty label " + std::to_string(label) + " (" + name + ") has no voxels");
  return volume;
}

}  // namespace incise::sim
