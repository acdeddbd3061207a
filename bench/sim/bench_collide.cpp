// Cost of the deformable-surface tree per simulation step on a ~10k-triangle surface: refit, a
// sphere contact query, a capsule contact query, a swept-sphere query, and a full rebuild for
// comparison. Prints the median over many steps [us]. Run by hand: ./bench_collide

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "sim/collide/surface_bvh.h"
#include "tests/sim/collide/collide_fixtures.h"

namespace {

using namespace incise::sim;
using namespace incise::sim::collide;
using Clock = std::chrono::steady_clock;

// Median time of work(k) over k < repeats; prepare(k) runs before each, untimed.
template <class Prepare, class Work>
double median_us(int repeats, Prepare&& prepare, Work&& work) {
  std::vector<double> samples(repeats);
  for (int k = 0; k < repeats; ++k) {
    prepare(k);
    const auto start = Clock::now();
    work(k);
    samples[k] = std::chrono::duration<double, std::micro>(Clock::now() - start).count();
  }
  std::nth_element(samples.begin(), samples.begin() + repeats / 2, samples.end());
  return samples[repeats / 2];
}

}  // namespace

int main() {
  // 70 rings x 72 segments: 10,080 triangles on a 5 cm sphere (edges ~2 mm).
  const testing::TestSurface rest =
      testing::jittered_sphere_surface(Vec3::Zero(), 0.05, 70, 72, 0.01, 1);
  Points x = rest.points;
  SurfaceBvh bvh;
  bvh.build(x, rest.triangles);
  std::vector<Contact> contacts;
  contacts.reserve(256);
  int touching = 0;
  const auto move = [&](int step) {
    // A slow wobble, as tissue under a tool.
    const Real phase = 0.01 * step;
    for (int i = 0; i < x.rows(); ++i) {
      x(i, 2) = rest.points(i, 2) + 0.002 * std::sin(40 * rest.points(i, 0) + phase);
    }
  };
  const int steps = 2000;
  const auto nothing = [](int) {};
  const double refit = median_us(steps, move, [&](int) { bvh.refit(x); });
  const Sphere probe{Vec3(0, 0, 0.052), 0.004};
  const double sphere = median_us(steps, nothing, [&](int) {
    bvh.contacts(x, probe, contacts);
    touching = static_cast<int>(contacts.size());
  });
  const double capsule = median_us(steps, nothing, [&](int) {
    bvh.contacts(x, Capsule{Vec3(0, 0, 0.051), Vec3(0.03, 0, 0.08), 0.003}, contacts);
  });
  SweepHit hit;
  const double sweep = median_us(steps, nothing, [&](int) {
    bvh.sweep(x, Sphere{Vec3(0, 0, 0.08), 0.002}, Vec3(0.001, 0, 0.02), hit);
  });
  const double rebuild = median_us(50, nothing, [&](int) { bvh.rebuild(x); });
  std::printf("triangles %d, nodes %d\n", bvh.num_live_triangles(), bvh.num_nodes());
  std::printf("refit                 %8.1f us (median of %d)\n", refit, steps);
  std::printf("sphere contacts       %8.2f us (%d triangles touched)\n", sphere, touching);
  std::printf("capsule contacts      %8.2f us\n", capsule);
  std::printf("swept sphere          %8.2f us\n", sweep);
  std::printf("rebuild               %8.1f us\n", rebuild);
  std::printf("looseness after wobble %.3f\n", bvh.looseness());
  return 0;
}
