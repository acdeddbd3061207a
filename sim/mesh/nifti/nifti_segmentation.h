#pragma once

// Labelled segmentation volumes in NIfTI (.nii, .nii.gz, or a .hdr/.img pair; NIfTI-1 or -2), the
// format 3D Slicer, ITK-SNAP and most segmentation tools write, read through Debian's nifticlib.
// nifticlib stays behind this door: only nifti_segmentation.cpp includes it.
//
// The volume keeps its place in the world: its affine (the sform when its code is set, else the
// qform when its code is set, else the voxel sizes alone: nibabel's rule) gives the voxel axes'
// directions, spacing and origin, converted from the file's units (mm when unset) to metres. A
// mirrored affine (negative determinant, as radiological orientation gives) is kept as it is;
// an affine that shears the voxel axes is refused (resample the volume first).

#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>

#include "sim/mesh/cgal/label_volume.h"

namespace incise::sim {

// A bad segmentation file. what() is one line: "FILE: problem".
class SegmentationFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The tissue each label value of a segmentation stands for (values 1 to 255; 0 is outside).
using SegmentationTissues = std::map<int, std::string>;

// Largest volume read [voxels]: 2^28, a 640^3 scan.
inline constexpr long long kMaxSegmentationVoxels = 1LL << 28;

// The labelled volume in file, its labels the file's label values.
//   tissues  every label value the volume holds (other than 0) with its tissue's name
// Throws std::invalid_argument for a tissue map with a value outside 1..255 or an empty name,
// and SegmentationFileError naming the problem for: a missing or unreadable file; no NIfTI
// header; not 3 dimensions (a 4-D series, a 2-D slice); more than kMaxSegmentationVoxels; a voxel
// type that holds no labels (complex, RGB) or a voxel value that is not an integer in 0..255;
// voxel data shorter than the header says (a truncated file); spacing that is not finite and > 0;
// a sheared or singular affine; spatial units other than m, mm or um; a label the tissue map does
// not name ("unknown label"); a mapped label with no voxel ("empty label").
LabelVolume read_nifti_segmentation(const std::filesystem::path& file,
                                    const SegmentationTissues& tissues);

}  // namespace incise::sim
