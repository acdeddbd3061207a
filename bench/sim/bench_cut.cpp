// bench_cut: the per-frame update time of a progressive cut (ProgressiveCutter::update) with a
// blade crossing a ~5k-tet block at hand speed, and the tets created. Not a test.
// Block 0.1 x 0.1 x 0.05 m, 12 x 12 x 7 cells (5040 tets); the blade (0.1 m long, through the
// block's thickness, slightly tilted) moves at 0.1 m/s across it, one update per 1 ms haptic
// frame: 0.1 mm per frame, 1400 frames.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

#include "sim/cut/progressive_cutter.h"
#include "sim/mesh/box_mesher.h"

int main() {
  using namespace incise::sim;
  TetMesh mesh = make_box_mesh({0.1, 0.1, 0.05}, {12, 12, 7});
  const int tets_before = mesh.num_tets();
  cut::ProgressiveCutter cutter(mesh);
  const Vec3 along = Vec3(0.05, 0.02, 1).normalized();
  std::vector<double> ms, looked, skipped;
  int max_region = 0, max_temporary = 0;
  const int frames = 1400;
  for (int f = 0; f <= frames; ++f) {
    const Vec3 centre(-0.02 + 0.14 * f / frames, 0.0537 + 0.01 * f / frames, 0.025);
    const auto start = std::chrono::steady_clock::now();
    const cut::FrameReport& report = cutter.update(centre - 0.05 * along, centre + 0.05 * along);
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                     .count());
    (report.looked_for_cuts ? looked : skipped).push_back(ms.back());
    max_region = std::max(max_region, report.region_tets);
    max_temporary = std::max(max_temporary, report.temporary_tets);
  }
  cutter.end_stroke();
  std::sort(ms.begin(), ms.end());
  std::printf("tets %d -> %d (+%d committed), frames %d\n", tets_before, mesh.num_tets(),
              mesh.num_tets() - tets_before, frames + 1);
  std::printf("update ms: median %.3f p99 %.3f max %.3f\n", ms[ms.size() / 2],
              ms[ms.size() * 99 / 100], ms.back());
  for (auto* part : {&looked, &skipped}) {
    std::sort(part->begin(), part->end());
    if (part->empty()) continue;
    std::printf(
        "  %s: %zu frames, median %.3f ms, p99 %.3f ms\n",
        part == &looked ? "frames looking for complete cuts" : "front unchanged (temporary only)",
        part->size(), (*part)[part->size() / 2], (*part)[part->size() * 99 / 100]);
  }
  std::printf("region tets max %d, temporary pieces max %d\n", max_region, max_temporary);
  return 0;
}
