#include "calculix.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace incise::sim::reference {

std::optional<std::filesystem::path> find_ccx() {
  for (const char* candidate : {"/usr/bin/ccx", "/usr/local/bin/ccx"}) {
    if (std::filesystem::exists(candidate)) return std::filesystem::path(candidate);
  }
  return std::nullopt;
}

namespace {

void write_input(const CalculixProblem& p, const std::filesystem::path& file) {
  const auto& mesh = *p.mesh;
  std::ofstream out(file);
  out.precision(15);  // ccx reads at most 20 characters per number
  out << "*HEADING\nincise reference problem\n*NODE, NSET=NALL\n";
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    out << i + 1 << ", " << mesh.rest(i, 0) << ", " << mesh.rest(i, 1) << ", " << mesh.rest(i, 2)
        << "\n";
  }
  // C3D4 numbers its nodes like our tets: the fourth lies on the side the first three's
  // right-hand normal points to (positive volume).
  out << "*ELEMENT, TYPE=C3D4, ELSET=EALL\n";
  for (int t = 0; t < mesh.num_tets(); ++t) {
    out << t + 1;
    for (int k = 0; k < 4; ++k)
      out << ", " << mesh.tets(t, k) + 1;
    out << "\n";
  }
  out << "*MATERIAL, NAME=TISSUE\n";
  if (p.material == CalculixMaterial::linear_elastic) {
    out << "*ELASTIC\n" << p.youngs_modulus << ", " << p.poisson_ratio << "\n";
  } else {
    const Real mu = p.youngs_modulus / (2 * (1 + p.poisson_ratio));
    const Real bulk = p.youngs_modulus / (3 * (1 - 2 * p.poisson_ratio));
    out << "*HYPERELASTIC, NEO HOOKE\n" << mu / 2 << ", " << 2 / bulk << "\n";
  }
  out << "*SOLID SECTION, ELSET=EALL, MATERIAL=TISSUE\n";
  // Zero displacements belong to the model; non-zero ones to the step (ccx refuses them before).
  if (!p.fixed_nodes.empty() || !p.prescribed.empty()) {
    out << "*BOUNDARY\n";
    for (const int n : p.fixed_nodes)
      out << n + 1 << ", 1, 3, 0.\n";
    for (const auto& d : p.prescribed) {
      if (d.value == 0) out << d.node + 1 << ", " << d.dof + 1 << ", " << d.dof + 1 << ", 0.\n";
    }
  }
  if (p.material == CalculixMaterial::linear_elastic) {
    out << "*STEP\n*STATIC\n";
  } else {
    const Real increment = 1.0 / std::max(1, p.increments);
    out << "*STEP, NLGEOM, INC=1000\n*STATIC\n"
        << increment << ", 1.0, 1e-6, " << increment << "\n";
  }
  const bool moves = std::any_of(p.prescribed.begin(), p.prescribed.end(),
                                 [](const PrescribedDof& d) { return d.value != 0; });
  if (moves) {
    out << "*BOUNDARY\n";
    for (const auto& d : p.prescribed) {
      if (d.value != 0) {
        out << d.node + 1 << ", " << d.dof + 1 << ", " << d.dof + 1 << ", " << d.value << "\n";
      }
    }
  }
  if (p.node_loads.rows() > 0) out << "*CLOAD\n";
  for (int i = 0; i < p.node_loads.rows(); ++i) {
    for (int d = 0; d < 3; ++d) {
      if (p.node_loads(i, d) != 0) {
        out << i + 1 << ", " << d + 1 << ", " << p.node_loads(i, d) << "\n";
      }
    }
  }
  out << "*NODE PRINT, NSET=NALL\nU\n*END STEP\n";
}

Points read_displacements(const std::filesystem::path& dat, int num_nodes) {
  std::ifstream in(dat);
  if (!in) throw std::runtime_error("ccx wrote no " + dat.string());
  Points u = Points::Constant(num_nodes, 3, std::numeric_limits<Real>::quiet_NaN());
  std::string line;
  bool in_block = false;
  int read = 0;
  while (std::getline(in, line)) {
    if (line.find("displacements") != std::string::npos) {
      in_block = true;  // one block per printed increment: the last one is the end of the step
      read = 0;
      continue;
    }
    if (!in_block) continue;
    std::istringstream fields(line);
    int node = 0;
    Real x = 0, y = 0, z = 0;
    if (fields >> node >> x >> y >> z) {
      if (node < 1 || node > num_nodes) throw std::runtime_error("ccx .dat: node out of range");
      u.row(node - 1) << x, y, z;
      ++read;
    }
  }
  if (read != num_nodes) {
    throw std::runtime_error("ccx .dat: read " + std::to_string(read) + " displacements of " +
                             std::to_string(num_nodes));
  }
  return u;
}

}  // namespace

Points solve_linear_static(const CalculixProblem& problem, const std::filesystem::path& dir) {
  const auto ccx = find_ccx();
  if (!ccx)
    throw std::runtime_error("CalculiX (ccx) is not installed: apt-get install calculix-ccx");
  std::filesystem::create_directories(dir);
  write_input(problem, dir / "job.inp");
  const std::string command =
      "cd '" + dir.string() + "' && '" + ccx->string() + "' -i job > ccx.log 2>&1";
  const int status = std::system(command.c_str());
  if (status != 0) {
    std::ifstream log(dir / "ccx.log");
    std::stringstream text;
    text << log.rdbuf();
    throw std::runtime_error("ccx failed (status " + std::to_string(status) + "): " + text.str());
  }
  return read_displacements(dir / "job.dat", problem.mesh->num_nodes());
}

}  // namespace incise::sim::reference
