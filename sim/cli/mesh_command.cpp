#include "sim/cli/mesh_command.h"

#include <charconv>
#include <cmath>
#include <exception>
#include <filesystem>
#include <optional>

#include "sim/cli/cli.h"
#include "sim/cli/scene_mesh.h"
#include "sim/mesh/cgal/mesh_generation.h"
#include "sim/mesh/mesh_info.h"
#include "sim/mesh/msh_writer.h"
#include "sim/mesh/nifti/nifti_segmentation.h"
#include "sim/mesh/tetgen_writer.h"
#include "sim/mesh/vtu_writer.h"

namespace incise::sim {
namespace {

int usage(std::ostream& err, const std::string& problem) {
  err << "incise: mesh: " << problem
      << " (usage: incise mesh VOLUME.nii[.gz] --labels 1=NAME,2=NAME --cell-size H --out "
         "MESH.msh|.vtu|.node)\n";
  return kExitUsage;
}

// "1=meniscus,2=ligament" -> {1: meniscus, 2: ligament}; nullopt with problem set if malformed.
std::optional<SegmentationTissues> parse_tissues(const std::string& text, std::string& problem) {
  SegmentationTissues tissues;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string item = text.substr(start, comma - start);
    const std::size_t equals = item.find('=');
    int label = 0;
    const auto [end, ec] =
        std::from_chars(item.data(), item.data() + std::min(equals, item.size()), label);
    if (equals == std::string::npos || ec != std::errc{} || end != item.data() + equals ||
        label < 1 || label > 255 || equals + 1 == item.size() || tissues.contains(label)) {
      problem = "--labels item \"" + item +
                "\" is not VALUE=NAME with a new label value in 1..255 and a name";
      return std::nullopt;
    }
    tissues[label] = item.substr(equals + 1);
    start = comma + 1;
  }
  return tissues;
}

std::optional<Real> parse_length(const std::string& text) {
  const auto value = parse_real(text);
  if (!value || *value <= 0) return std::nullopt;
  return value;
}

Real labelled_tet_volume(const TetMesh& mesh, int label) {
  Real total = 0;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    if (mesh.labels[t] != label) continue;
    const auto corner = [&](int k) -> Vec3 { return mesh.rest.row(mesh.tets(t, k)).transpose(); };
    total += signed_volume(corner(0), corner(1), corner(2), corner(3));
  }
  return total;
}

void print_volume(const std::string& file, const LabelVolume& v, std::ostream& out) {
  out << "volume: " << file << "\n"
      << "voxels: " << v.dims.x() << " x " << v.dims.y() << " x " << v.dims.z() << ", spacing ["
      << v.spacing.x() << ", " << v.spacing.y() << ", " << v.spacing.z() << "] m\n";
  static constexpr const char* kAxis[3] = {"i", "j", "k"};
  for (int a = 0; a < 3; ++a) {
    const Vec3 d = v.axes.col(a);
    out << "axis " << kAxis[a] << ": [" << d.x() << ", " << d.y() << ", " << d.z() << "]\n";
  }
  out << "orientation: " << (v.axes.determinant() < 0 ? "mirrored" : "right-handed") << "\n"
      << "origin: [" << v.origin.x() << ", " << v.origin.y() << ", " << v.origin.z()
      << "] m (the centre of voxel (0, 0, 0))\n";
}

}  // namespace

int run_mesh_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  const CommandArgs parsed = parse_command_args(args, {"--labels", "--cell-size", "--out"});
  if (!parsed.problem.empty()) return usage(err, parsed.problem);
  if (!parsed.file) return usage(err, "needs a volume file");
  for (const char* option : {"--labels", "--cell-size", "--out"})
    if (!parsed.options.contains(option)) return usage(err, std::string("needs ") + option);
  std::string problem;
  const std::optional<SegmentationTissues> tissues =
      parse_tissues(parsed.options.at("--labels"), problem);
  if (!tissues) return usage(err, problem);
  const std::optional<Real> cell_size = parse_length(parsed.options.at("--cell-size"));
  if (!cell_size) return usage(err, "--cell-size must be a length > 0 in metres");
  const std::filesystem::path mesh_file = parsed.options.at("--out");
  const std::string extension = mesh_file.extension().string();
  if (extension != ".msh" && extension != ".vtu" && extension != ".node")
    return usage(err, "--out must end in .msh, .vtu or .node");

  LabelVolume volume;
  try {
    volume = read_nifti_segmentation(*parsed.file, *tissues);
  } catch (const std::exception& e) {
    err << "incise: " << e.what() << "\n";
    return kExitUsage;
  }
  TetMesh mesh;
  try {
    mesh = mesh_labelled_volume(volume, segmentation_criteria(volume, *cell_size));
  } catch (const std::invalid_argument& e) {
    err << "incise: " << *parsed.file << ": " << e.what() << "\n";
    return kExitUsage;
  } catch (const std::exception& e) {
    err << "incise: " << *parsed.file << ": " << e.what() << "\n";
    return kExitFailed;
  }
  try {
    if (extension == ".msh") write_msh(mesh_file, mesh, MshVersion::k4_1);
    if (extension == ".vtu") write_vtu(mesh_file, mesh);
    if (extension == ".node") write_tetgen(mesh_file, mesh);
  } catch (const std::exception& e) {
    err << "incise: " << mesh_file.string() << ": " << e.what() << "\n";
    return kExitUsage;
  }
  print_volume(*parsed.file, volume, out);
  for (const auto& [label, name] : *tissues) {
    const Real voxels = voxel_volume_of(volume, label);
    const Real meshed = labelled_tet_volume(mesh, label);
    out << "tissue " << label << " " << name << ": " << voxels * 1e6 << " cm^3 in voxels, "
        << meshed * 1e6 << " cm^3 meshed (" << (meshed / voxels - 1) * 100 << " %)\n";
  }
  out << "mesh: " << mesh_file.string() << "\n";
  print_mesh_info(mesh, out);
  return kExitOk;
}

}  // namespace incise::sim
