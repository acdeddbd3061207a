#include "sim/cli/scene_mesh.h"

#include <algorithm>
#include <stdexcept>

#include "sim/mesh/box_mesher.h"
#include "sim/mesh/cgal/mesh_generation.h"
#include "sim/mesh/mesh_file_error.h"
#include "sim/mesh/nifti/nifti_segmentation.h"
#include "sim/mesh/read_mesh_file.h"
#include "sim/scene/scene_error.h"

namespace incise::sim {
namespace {

ImplicitShape shape_of(const GenerateSpec& g) {
  if (g.shape == "sphere") return Sphere{g.centre, g.radii.x()};
  if (g.shape == "ellipsoid") return Ellipsoid{g.centre, g.radii};
  return liver_like_organ(g.centre, 2 * g.radii.x());  // "liver": radii.x is half its length
}

}  // namespace

MeshingCriteria segmentation_criteria(const LabelVolume& volume, Real cell_size) {
  MeshingCriteria criteria;
  criteria.cell_size = cell_size;
  criteria.facet_size = cell_size;
  // A voxel is the volume's own resolution: following its surface closer only adds slivers where
  // the tissue thins (what the knee's menisci taught us, docs/anatomy.md).
  criteria.facet_distance = std::max(cell_size / 4, volume.spacing.minCoeff());
  return criteria;
}

TetMesh build_scene_mesh(const Scene& scene, const std::filesystem::path& scene_dir) {
  const MeshSpec& spec = scene.mesh;
  switch (spec.source) {
    case MeshSource::box:
      try {
        return make_box_mesh(spec.box.size, spec.box.cells);
      } catch (const std::invalid_argument& e) {
        throw SceneError("mesh", e.what());
      }
    case MeshSource::file: {
      const std::filesystem::path file = scene_dir / spec.file;
      try {
        return read_mesh_file(file);
      } catch (const std::exception& e) {
        throw SceneError("mesh.file", e.what());
      }
    }
    case MeshSource::segmentation: {
      const SegmentationSpec& g = spec.segmentation;
      LabelVolume volume;
      try {
        volume = read_nifti_segmentation(scene_dir / g.file, g.tissues);
      } catch (const std::exception& e) {
        throw SceneError("mesh.segmentation.file", e.what());
      }
      try {
        return mesh_labelled_volume(volume, segmentation_criteria(volume, g.cell_size));
      } catch (const std::exception& e) {
        throw SceneError("mesh.segmentation", e.what());
      }
    }
    case MeshSource::generate: {
      const GenerateSpec& g = spec.generate;
      try {
        const ImplicitShape shape = shape_of(g);
        MeshingCriteria criteria;
        criteria.cell_size = g.cell_size;
        criteria.facet_size = g.cell_size;
        criteria.facet_distance = g.cell_size / 4;
        Box3 bounds = implicit_extent(shape);
        const Vec3 margin = 0.05 * bounds.sizes();
        bounds.extend(bounds.max() + margin);
        bounds.extend(bounds.min() - margin);
        return mesh_implicit(shape, bounds, criteria);
      } catch (const std::exception& e) {
        throw SceneError("mesh.generate", e.what());
      }
    }
  }
  throw SceneError("mesh", "unknown mesh source");
}

}  // namespace incise::sim
