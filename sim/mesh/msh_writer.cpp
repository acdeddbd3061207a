#include "sim/mesh/msh_writer.h"

#include <algorithm>
#include <map>
#include <stdexcept>
#include <vector>

#include "sim/mesh/mesh_text_writer.h"

namespace incise::sim {
namespace {

void append_position(std::string& out, const TetMesh& mesh, int i) {
  for (int c = 0; c < 3; ++c) {
    out += ' ';
    append_real(out, mesh.rest(i, c));
  }
}

void append_tet_nodes(std::string& out, const TetMesh& mesh, int t) {
  for (int k = 0; k < 4; ++k) {
    out += ' ';
    append_integer(out, mesh.tets(t, k) + 1);
  }
}

std::string format_v2(const TetMesh& mesh) {
  std::string out = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n";
  append_integer(out, mesh.num_nodes());
  out += '\n';
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    append_integer(out, i + 1);
    append_position(out, mesh, i);
    out += '\n';
  }
  out += "$EndNodes\n$Elements\n";
  append_integer(out, mesh.num_tets());
  out += '\n';
  for (int t = 0; t < mesh.num_tets(); ++t) {
    // tag, type 4, two tags: physical (the label), elementary (one per label, as gmsh does).
    append_integer(out, t + 1);
    out += " 4 2 ";
    append_integer(out, mesh.labels(t));
    out += ' ';
    append_integer(out, mesh.labels(t) + 1);
    append_tet_nodes(out, mesh, t);
    out += '\n';
  }
  out += "$EndElements\n";
  return out;
}

std::string format_v4(const TetMesh& mesh) {
  // One volume entity per distinct label, tagged 1, 2, ... in label order.
  std::map<int, int> volume_of_label;
  for (int t = 0; t < mesh.num_tets(); ++t)
    volume_of_label.emplace(mesh.labels(t), 0);
  int next_volume = 1;
  for (auto& [label, volume] : volume_of_label)
    volume = next_volume++;

  const Vec3 low = mesh.rest.colwise().minCoeff().transpose();
  const Vec3 high = mesh.rest.colwise().maxCoeff().transpose();
  std::string out = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n0 0 0 ";
  append_integer(out, static_cast<long long>(volume_of_label.size()));
  out += '\n';
  for (const auto& [label, volume] : volume_of_label) {
    append_integer(out, volume);
    for (int c = 0; c < 3; ++c) {
      out += ' ';
      append_real(out, low(c));
    }
    for (int c = 0; c < 3; ++c) {
      out += ' ';
      append_real(out, high(c));
    }
    out += label > 0 ? " 1 " + std::to_string(label) : std::string(" 0");
    out += " 0\n";  // no bounding surfaces: the file holds no surface entities
  }
  out += "$EndEntities\n$Nodes\n1 ";
  const std::string n = std::to_string(mesh.num_nodes());
  out += n + " 1 " + n + "\n3 1 0 " + n + "\n";
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    append_integer(out, i + 1);
    out += '\n';
  }
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    append_position(out, mesh, i);
    out += '\n';
  }

  // Runs of consecutive tets with the same label, one element block each.
  std::vector<int> run_starts;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    if (t == 0 || mesh.labels(t) != mesh.labels(t - 1)) run_starts.push_back(t);
  }
  run_starts.push_back(mesh.num_tets());
  out += "$EndNodes\n$Elements\n";
  const std::string m = std::to_string(mesh.num_tets());
  out += std::to_string(run_starts.size() - 1) + " " + m + " 1 " + m + "\n";
  for (std::size_t r = 0; r + 1 < run_starts.size(); ++r) {
    const int begin = run_starts[r];
    const int end = run_starts[r + 1];
    out += "3 " + std::to_string(volume_of_label.at(mesh.labels(begin))) + " 4 " +
           std::to_string(end - begin) + "\n";
    for (int t = begin; t < end; ++t) {
      append_integer(out, t + 1);
      append_tet_nodes(out, mesh, t);
      out += '\n';
    }
  }
  out += "$EndElements\n";
  return out;
}

}  // namespace

std::string format_msh(const TetMesh& mesh, MshVersion version) {
  if (mesh.labels.size() > 0 && mesh.labels.minCoeff() < 0) {
    throw std::invalid_argument("format_msh: negative label " +
                                std::to_string(mesh.labels.minCoeff()) +
                                " (gmsh physical tags are positive)");
  }
  return version == MshVersion::k2_2 ? format_v2(mesh) : format_v4(mesh);
}

void write_msh(const std::filesystem::path& path, const TetMesh& mesh, MshVersion version) {
  write_mesh_text(path.string(), format_msh(mesh, version));
}

}  // namespace incise::sim
