// Render benchmark (measures, asserts nothing; not a ctest test): the live view of a scene at
// 640x480, 300 frames while the tool circles over the tissue and presses a dent into it, through
// the streaming path (SceneRenderer + FrameEncoder). Prints one line for the scene as given and
// one for the same box meshed finer, to at least 8000 surface triangles (the size at which a frame
// should take 5-8 ms; docs/benchmarks.md).
//   bench_render [SCENE.json]     default: sim/scenes/palpation.json
// The tissue's positions change every frame (a smooth synthetic dent follows the tool), so the
// per-frame upload is measured too; the dent is computed outside the timed part.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "sim/io/scene_json.h"
#include "sim/mesh/boundary_surface.h"
#include "sim/mesh/box_mesher.h"
#include "sim/render/egl_context.h"
#include "sim/render/scene_renderer.h"

namespace {

using incise::sim::Points;
using incise::sim::Vec3;

constexpr int width = 640;
constexpr int height = 480;
constexpr int warm_up_frames = 10;  // llvmpipe compiles shaders at their first draw
constexpr int frames = 300;

double percentile(std::vector<double> values, double fraction) {
  const auto k = static_cast<std::size_t>(fraction * static_cast<double>(values.size() - 1) + 0.5);
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

int surface_triangles(const Eigen::Vector3i& cells) {
  return 4 * (cells.x() * cells.y() + cells.y() * cells.z() + cells.x() * cells.z());
}

incise::render::Camera camera_for(const incise::sim::Scene& scene) {
  incise::render::Camera camera;
  const Vec3 size = scene.mesh.box.size;
  if (scene.view) {
    camera.eye = scene.view->eye;
    camera.target = scene.view->target;
    camera.up = scene.view->up;
    camera.fov_y_deg = scene.view->fov_y_deg;
  } else {
    camera.target = 0.5 * size;
    camera.eye = camera.target + Vec3(0.0, -1.2, 1.2) * size.maxCoeff();
    camera.up = Vec3::UnitZ();
  }
  return camera;
}

void run(const incise::sim::Scene& scene, const Eigen::Vector3i& cells, const std::string& name) {
  const Vec3 size = scene.mesh.box.size;
  const incise::sim::TetMesh mesh = incise::sim::make_box_mesh(size, cells);
  const incise::sim::BoundarySurface surface = incise::sim::boundary_surface(mesh);
  const double radius = scene.tool ? scene.tool->radius : 0.005;
  const incise::render::Camera camera = camera_for(scene);

  incise::render::SceneRenderer renderer;
  incise::render::FrameEncoder encoder(width, height, 80);
  Points x = mesh.rest;
  Points V;
  Points N;
  std::vector<std::uint8_t> jpeg;
  std::vector<double> render_ms, readback_ms, encode_ms, total_ms, jpeg_kib;

  for (int frame = -warm_up_frames; frame < frames; ++frame) {
    // One circle over the top face per 300 frames, pressing up to 4 mm deep twice per circle.
    const double phase = 2.0 * std::numbers::pi * frame / frames;
    const Vec3 centre(0.5 * size.x() + 0.3 * size.x() * std::cos(phase),
                      0.5 * size.y() + 0.3 * size.y() * std::sin(phase), size.z());
    const double depth = std::max(0.0, 0.004 * std::sin(2.0 * phase));
    // A Gaussian dent under the tool, fading to nothing at the fixed bottom face.
    const double width_m = 2.0 * radius;
    for (int i = 0; i < mesh.num_nodes(); ++i) {
      const double r2 = (mesh.rest.row(i).head<2>() - centre.head<2>().transpose()).squaredNorm();
      x(i, 2) = mesh.rest(i, 2) -
                depth * std::exp(-r2 / (width_m * width_m)) * mesh.rest(i, 2) / size.z();
    }
    incise::sim::surface_vertices(surface, x, V, N);

    incise::render::ToolView tool;
    tool.radius = radius;
    tool.tip = centre + Vec3(0.0, 0.0, radius - depth);
    tool.shaft_direction = Vec3(0.3 * std::cos(phase), 0.3 * std::sin(phase), 1.0).normalized();
    tool.in_contact = depth > 0.0;
    const incise::render::TissueView tissue{&V, &N, &surface.faces};
    encoder.render_jpeg(renderer, camera, tissue, tool, jpeg);
    if (frame < 0) continue;
    const incise::render::FrameTimings& t = encoder.timings();
    render_ms.push_back(t.render_ms);
    readback_ms.push_back(t.readback_ms);
    encode_ms.push_back(t.encode_ms);
    total_ms.push_back(t.total_ms());
    jpeg_kib.push_back(static_cast<double>(jpeg.size()) / 1024.0);
  }

  std::printf("%-34s %9d %10.2f %11.2f %10.2f %10.2f %9.2f %9.1f\n", name.c_str(),
              static_cast<int>(surface.faces.rows()), percentile(render_ms, 0.5),
              percentile(readback_ms, 0.5), percentile(encode_ms, 0.5), percentile(total_ms, 0.5),
              percentile(total_ms, 0.95), percentile(jpeg_kib, 0.5));
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::string path = argc > 1 ? argv[1] : INCISE_SCENES_DIR "/palpation.json";
    const incise::sim::Scene scene = incise::sim::read_scene_file(path);
    const incise::render::EglContext context;
    std::printf("%s, %s; %dx%d, %d frames (after %d warm-up), JPEG quality 80; times in ms\n",
                context.renderer().c_str(), context.version().c_str(), width, height, frames,
                warm_up_frames);
    std::printf("%-34s %9s %10s %11s %10s %10s %9s %9s\n", "scene (box cells)", "triangles",
                "render", "readback", "encode", "total", "total p95", "JPEG KiB");
    std::printf("%-34s %9s %10s %11s %10s %10s %9s %9s\n", "", "", "median", "median", "median",
                "median", "", "median");

    const Eigen::Vector3i cells = scene.mesh.box.cells;
    const auto label = [&](const Eigen::Vector3i& c) {
      return std::filesystem::path(path).filename().string() + " (" + std::to_string(c.x()) + "x" +
             std::to_string(c.y()) + "x" + std::to_string(c.z()) + ")";
    };
    run(scene, cells, label(cells));
    // The same box, cells scaled up evenly until its surface has at least 8000 triangles.
    if (surface_triangles(cells) < 8000) {
      Eigen::Vector3i finer = cells;
      for (double scale = 1.0; surface_triangles(finer) < 8000; scale += 0.05) {
        finer = (cells.cast<double>() * scale).array().round().cast<int>().max(1);
      }
      run(scene, finer, label(finer));
    }
  } catch (const std::exception& error) {
    std::fprintf(stderr, "bench_render: %s\n", error.what());
    return 1;
  }
  return 0;
}
