// Cost of a tool's contact per simulation step on a ~5k-triangle surface (the "collision
// query time per step"): a 4 mm probe pressed into a 5 x 5 x 2.3 cm box (26 x 26 x 12 cells,
// 5,200 surface triangles) and slid across it while the surface ripples (so the tree is
// refitted to moving positions every step). Timed per step, 2,000 steps:
//   refit         SurfaceBvh::refit
//   tool          SweptToolMotion::move + ToolContactResponse::apply (a scripted tool)
//   force model   sphere_force_model (F0, K for the haptic station)
//   probe         Probe::step (sweep, contacts, nearest free point, implicit push)
// Prints median and 99th percentile [us]. Run (Release):
//   bench_tool_contact

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "sim/collide/mesh_surface_faces.h"
#include "sim/collide/surface_bvh.h"
#include "sim/mesh/boundary_surface.h"
#include "sim/mesh/box_mesher.h"
#include "sim/models/corotational_fem.h"
#include "sim/solve/stable_time_step.h"
#include "sim/tools/force_model.h"
#include "sim/tools/probe.h"
#include "sim/tools/swept_tool_motion.h"
#include "sim/tools/tool_contact_response.h"

using namespace incise::sim;
using namespace incise::sim::tools;
using Clock = std::chrono::steady_clock;

namespace {

struct Figures {
  std::vector<double> samples;
  void add(Clock::time_point a, Clock::time_point b) {
    samples.push_back(std::chrono::duration<double, std::micro>(b - a).count());
  }
  void print(const char* name) {
    std::sort(samples.begin(), samples.end());
    const double median = samples[samples.size() / 2];
    const double p99 = samples[static_cast<std::size_t>(0.99 * (samples.size() - 1))];
    std::printf("%-12s median %8.2f us   p99 %8.2f us\n", name, median, p99);
  }
};

}  // namespace

int main() {
  const Vec3 size(0.05, 0.05, 0.023);
  TetMesh mesh = make_box_mesh(size, Vec3i(26, 26, 12));
  const CorotationalFem model(mesh, {{3000, 0.3, 1000, 0}}, RotationExtraction::polar);
  const Triangles faces = collide::mesh_surface_faces(boundary_surface(mesh));
  collide::SurfaceBvh bvh;
  bvh.build(mesh.x, faces);
  const Real dt = stable_time_step(mesh, 3000, 0.3, 1000);
  std::printf("%d nodes, %d tets, %d surface triangles, dt %.3g ms\n", mesh.num_nodes(),
              mesh.num_tets(), static_cast<int>(faces.rows()), 1e3 * dt);

  PenaltySettings penalty;
  penalty.time_step = dt;
  ToolContactResponse response(penalty);
  const Real radius = 0.004;
  SweptToolMotion motion(radius, 0.25 * radius);
  ProbeSettings probe_settings;
  probe_settings.radius = radius;
  probe_settings.allowed_penetration = 0.001;
  probe_settings.contact = penalty;
  const Vec3 start(0.01, 0.025, size.z() + radius + 0.001);
  Probe probe(probe_settings, start);
  Points forces = Points::Zero(mesh.num_nodes(), 3);
  Vec3 tool = start;

  const int steps = 2000;
  Figures refit, contact, force_model, probe_step;
  for (int s = 0; s < steps; ++s) {
    const Real t = Real(s) / steps;
    // The top ripples by up to 0.5 mm; the tool presses 2 mm and slides 3 cm in x.
    for (int i = 0; i < mesh.num_nodes(); ++i) {
      const Vec3 p = row3(mesh.rest, i);
      mesh.x(i, 2) = p.z() + 0.0005 * (p.z() / size.z()) * std::sin(200 * p.x() + 40 * t);
    }
    const Vec3 commanded = start + Vec3(0.03 * t, 0, -0.001 - 0.002 * std::min(Real(1), 10 * t));
    forces.setZero();

    auto a = Clock::now();
    bvh.refit(mesh.x);
    auto b = Clock::now();
    refit.add(a, b);

    a = Clock::now();
    const Vec3 next = motion.move(bvh, mesh.x, tool, commanded).centre;
    response.apply(bvh, mesh.x, mesh.v, model.masses(), collide::Sphere{next, radius},
                   (next - tool) / dt, forces);
    b = Clock::now();
    contact.add(a, b);
    tool = next;

    a = Clock::now();
    const LocalForceModel haptic =
        sphere_force_model(response.contacts(), mesh.x, collide::Sphere{tool, radius});
    b = Clock::now();
    force_model.add(a, b);
    if (!haptic.force.allFinite()) return 1;

    a = Clock::now();
    probe.step(commanded, bvh, mesh.x, mesh.v, model.masses(), forces);
    b = Clock::now();
    probe_step.add(a, b);
  }
  std::printf("tool in contact with %d triangles at the end\n", response.reaction().contacts);
  refit.print("refit");
  contact.print("tool");
  force_model.print("force model");
  probe_step.print("probe");
  return 0;
}
