#include "sim/mesh/vtu_writer.h"

#include <cmath>
#include <set>
#include <stdexcept>

#include "sim/mesh/mesh_text_writer.h"

namespace incise::sim {
namespace {

constexpr int kVtkTetra = 10;

void check_name(const std::string& name, std::set<std::string>& names) {
  if (name.empty()) throw std::invalid_argument("format_vtu: a field has an empty name");
  for (const char c : name) {
    const bool allowed = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                         (c >= '0' && c <= '9') || c == '_' || c == '-' || c == '.';
    if (!allowed) {
      throw std::invalid_argument("format_vtu: field name '" + name +
                                  "' has a character other than letters, digits, _ - .");
    }
  }
  if (!names.insert(name).second) {
    throw std::invalid_argument("format_vtu: field name '" + name + "' is used twice");
  }
}

template <typename Matrix>
void check_values(const std::string& name, const Matrix& values, Eigen::Index rows) {
  if (values.rows() != rows) {
    throw std::invalid_argument("format_vtu: field '" + name + "' has " +
                                std::to_string(values.rows()) + " rows, expected " +
                                std::to_string(rows));
  }
  for (Eigen::Index i = 0; i < values.rows(); ++i) {
    for (Eigen::Index c = 0; c < values.cols(); ++c) {
      if (!std::isfinite(values(i, c))) {
        throw std::invalid_argument("format_vtu: field '" + name + "' is not finite at row " +
                                    std::to_string(i));
      }
    }
  }
}

template <typename Matrix>
void append_float_array(std::string& out, const std::string& name, const Matrix& values) {
  out += "        <DataArray type=\"Float64\"";
  if (!name.empty()) out += " Name=\"" + name + "\"";
  out += " NumberOfComponents=\"" + std::to_string(values.cols()) + "\" format=\"ascii\">\n";
  for (Eigen::Index i = 0; i < values.rows(); ++i) {
    out += "         ";
    for (Eigen::Index c = 0; c < values.cols(); ++c) {
      out += ' ';
      append_real(out, values(i, c));
    }
    out += '\n';
  }
  out += "        </DataArray>\n";
}

}  // namespace

std::string format_vtu(const TetMesh& mesh, const VtuFields& extra) {
  const Eigen::Index n = mesh.num_nodes();
  const Eigen::Index m = mesh.num_tets();
  std::set<std::string> names = {"displacement", "label"};
  check_values("positions (mesh.x)", mesh.x, n);
  check_values("rest positions (mesh.rest)", mesh.rest, n);
  for (const auto& [name, values] : extra.node_vectors) {
    check_name(name, names);
    check_values(name, values, n);
  }
  for (const auto& [name, values] : extra.tet_scalars) {
    check_name(name, names);
    check_values(name, values, m);
  }
  if (mesh.labels.size() != m) throw std::invalid_argument("format_vtu: labels has the wrong size");

  std::string out =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
      "header_type=\"UInt64\">\n"
      "  <UnstructuredGrid>\n";
  out += "    <Piece NumberOfPoints=\"" + std::to_string(n) + "\" NumberOfCells=\"" +
         std::to_string(m) + "\">\n";
  out += "      <PointData Vectors=\"displacement\">\n";
  append_float_array(out, "displacement", Points(mesh.x - mesh.rest));
  for (const auto& [name, values] : extra.node_vectors)
    append_float_array(out, name, values);
  out += "      </PointData>\n      <CellData Scalars=\"label\">\n";
  out += "        <DataArray type=\"Int32\" Name=\"label\" format=\"ascii\">\n";
  for (Eigen::Index t = 0; t < m; ++t) {
    out += "          ";
    append_integer(out, mesh.labels(t));
    out += '\n';
  }
  out += "        </DataArray>\n";
  for (const auto& [name, values] : extra.tet_scalars)
    append_float_array(out, name, values);
  out += "      </CellData>\n      <Points>\n";
  append_float_array(out, "", mesh.x);
  out += "      </Points>\n      <Cells>\n";
  out += "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (Eigen::Index t = 0; t < m; ++t) {
    out += "         ";
    for (int k = 0; k < 4; ++k) {
      out += ' ';
      append_integer(out, mesh.tets(t, k));
    }
    out += '\n';
  }
  out += "        </DataArray>\n";
  out += "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (Eigen::Index t = 0; t < m; ++t) {
    out += "          ";
    append_integer(out, 4 * (t + 1));
    out += '\n';
  }
  out += "        </DataArray>\n";
  out += "        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (Eigen::Index t = 0; t < m; ++t)
    out += "          " + std::to_string(kVtkTetra) + "\n";
  out += "        </DataArray>\n      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  return out;
}

void write_vtu(const std::filesystem::path& path, const TetMesh& mesh, const VtuFields& extra) {
  write_mesh_text(path.string(), format_vtu(mesh, extra));
}

}  // namespace incise::sim
