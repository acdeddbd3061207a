// Render benchmark (measures, asserts nothing; not a ctest test): the live view of a scene at
// 640x480, 300 frames, through the streaming path (SceneRenderer + FrameEncoder). For a block
// scene, while the tool circles over the tissue and presses a dent into it: one line for the scene
// as given and one for the same box meshed finer, to at least 8000 surface triangles (the size at
// which a frame should take 5-8 ms; docs/benchmarks.md). Without an argument, also the liver
// station as its trainee sees it (server/live: the held laparoscope, the scalpel's blade and the
// grasper's jaws, the marked line, the cut walls, the abdominal surroundings), the session ticking
// between frames while the blade cuts along the line (and once more with every vessel pattern
// off: their price in the same run), and the knee station through its arthroscope (bones,
// capsule, menisci and ACL with their vessels, the probe, two landmarks as visible targets) as
// the scope turns.
//   bench_render [SCENE.json]     default: sim/scenes/palpation.json, the liver and knee stations
//   bench_render --save DIR       also writes each station's frames 0, 150 and 299 and the last
//                                 one from outside, as DIR/liver_station_*.jpg and
//                                 DIR/knee_station_*.jpg
// The tissue's positions change every frame (a smooth synthetic dent follows the tool), so the
// per-frame upload is measured too; the dent is computed outside the timed part.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/server/station_poses.h"
#include "server/live/frame_streamer.h"
#include "server/live/scene_library.h"
#include "server/live/session_scene.h"
#include "server/live/sim_engine.h"
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

// The per-frame times of one scene's run, printed as one line of the table.
struct FrameTimes {
  std::vector<double> render_ms, readback_ms, encode_ms, total_ms, jpeg_kib;

  void add(const incise::render::FrameTimings& t, const std::vector<std::uint8_t>& jpeg) {
    render_ms.push_back(t.render_ms);
    readback_ms.push_back(t.readback_ms);
    encode_ms.push_back(t.encode_ms);
    total_ms.push_back(t.total_ms());
    jpeg_kib.push_back(static_cast<double>(jpeg.size()) / 1024.0);
  }
  void print(const std::string& name, int triangles) const {
    std::printf("%-34s %9d %10.2f %11.2f %10.2f %10.2f %9.2f %9.1f\n", name.c_str(), triangles,
                percentile(render_ms, 0.5), percentile(readback_ms, 0.5),
                percentile(encode_ms, 0.5), percentile(total_ms, 0.5), percentile(total_ms, 0.95),
                percentile(jpeg_kib, 0.5));
  }
};

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
  FrameTimes times;

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
    times.add(encoder.timings(), jpeg);
  }

  times.print(name, static_cast<int>(surface.faces.rows()));
}

void save(const std::string& path, const std::vector<std::uint8_t>& jpeg) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) throw std::runtime_error("cannot write " + path);
  const std::size_t written = std::fwrite(jpeg.data(), 1, jpeg.size(), file);
  std::fclose(file);
  if (written != jpeg.size()) throw std::runtime_error("cannot write " + path);
}

// A station's scene through the streaming path, as its viewers see it: the session ticks 10 ms
// between frames (not timed) with the inputs inputs_at(frame) gives, each frame is drawn from the
// camera picture_camera picks (the scene's scope once it reports), and one line is printed. With
// save_dir, frames 0, 150 and the last are written as DIR/<prefix>_<frame>.jpg, and the last also
// from outside as DIR/<prefix>_outside.jpg. zones: a task's visible zones, drawn in every frame.
// Without vessels, every look's vessel pattern is off: the same run's price of the vessels.
template <typename InputsAt>
void run_station(const incise::server::live::SessionScene& scene,
                 incise::server::live::SimEngine& engine, const char* label,
                 const std::string& save_dir, const std::string& prefix, InputsAt inputs_at,
                 std::vector<incise::render::MarkView> zones = {}, bool vessels = true) {
  using namespace incise;
  const render::Camera session = server::live::camera_for(scene);
  const render::Camera outside = server::live::outside_camera_for(scene);
  // Built once per scene, as the streamer does: the style and the surroundings' meshes.
  render::SceneStyle style = server::live::scene_style(scene.setup());
  if (!vessels) {
    for (render::SurfaceLook* look : {&style.tissue, &style.lining, &style.organ, &style.fat})
      look->vessels = 0;
    for (auto& [label, look] : style.tissue_by_label)
      look.vessels = 0;
  }
  render::SceneRenderer renderer(style);
  renderer.set_surroundings(server::live::static_surfaces(scene.setup(), renderer.style()));
  render::FrameEncoder encoder(width, height, 80);
  server::live::SnapshotPicture picture;
  picture.set_zones(std::move(zones));
  std::vector<std::uint8_t> jpeg;
  FrameTimes times;
  int triangles = 0;
  for (int frame = -warm_up_frames; frame < frames; ++frame) {
    const std::array<devices::DeviceState, 2> inputs = inputs_at(frame);
    for (int tick = 0; tick < 5; ++tick)
      engine.tick(inputs);
    const auto snapshot = server::live::make_snapshot(engine);
    picture.prepare(*snapshot);
    picture.encode(
        renderer, encoder,
        server::live::picture_camera(*snapshot, session, outside, false, double(width) / height),
        jpeg);
    triangles = static_cast<int>(snapshot->surface->faces.rows());
    if (!save_dir.empty() && (frame == 0 || frame == 150 || frame == frames - 1)) {
      save(save_dir + "/" + prefix + "_" + std::to_string(frame) + ".jpg", jpeg);
      if (frame == frames - 1) {
        std::vector<std::uint8_t> from_outside;
        picture.encode(renderer, encoder, outside, from_outside);
        save(save_dir + "/" + prefix + "_outside.jpg", from_outside);
      }
    }
    if (frame < 0) continue;
    times.add(encoder.timings(), jpeg);
  }
  times.print(label, triangles);
}

incise::server::live::SessionScene station_scene(const char* id) {
  const auto source = incise::server::live::find_scene(id);
  if (!source) throw std::runtime_error(std::string("no scene ") + id + " in the library");
  return incise::server::live::load_session_scene(source->id, source->text);
}

// The liver station's picture while the scalpel cuts 6 mm deep along the marked line and the
// grasper holds the lobe open beside it.
void run_liver_station(const std::string& save_dir, bool vessels) {
  using namespace incise;
  const auto scene = station_scene("scenes/surgery/liver_station.json");
  server::live::SimEngine engine(scene, 0.002, 2);
  const auto& line = scene.setup().cut_target;
  const Vec3 start = line.front(), end = line.back();
  const Vec3 depth(0, 0, 0.006), above(0, 0, 0.01);
  const Vec3 lobe = 0.5 * (start + end) + Vec3(-0.005, 0.012, 0.0005);
  run_station(
      scene, engine, vessels ? "liver station (laparoscope)" : "liver station, no vessels",
      save_dir, vessels ? "liver_station" : "liver_station_plain",
      [&](int frame) {
        // Into the tissue over the first tenth, along the line over six, out over one
        // (the cut is made as the blade leaves), and the opened cut seen for the last
        // fifth; the grasper's jaws close on the lobe over the first tenth. The stroke
        // takes 3 s, at the demo agent's pace.
        const double in = std::clamp((frame + warm_up_frames) / (0.1 * frames), 0.0, 1.0);
        const double along = std::clamp((frame - 0.1 * frames) / (0.6 * frames), 0.0, 1.0);
        const double out = std::clamp((frame - 0.7 * frames) / (0.1 * frames), 0.0, 1.0);
        const double s = in - out;  // how deep the blade is, 0 above .. 1 at depth
        const Vec3 blade = (1 - along) * start + along * end - s * depth + (1 - s) * above;
        return std::array<devices::DeviceState, 2>{
            bench::down(blade), bench::along_x(lobe, static_cast<float>(1 - in))};
      },
      {}, vessels);
  std::printf("  (the stroke cut %.0f mm^2; %s)\n", engine.damage().cut_area * 1e6,
              engine.state_finite() ? "finite" : "NOT FINITE");
}

// The knee station's picture through the arthroscope at the anterolateral portal as it turns
// from the medial meniscus's anterior horn to the lateral one, while the probe from the
// anteromedial portal reaches the medial horn; the two horns are the tour task's visible targets.
void run_knee_station(const std::string& save_dir) {
  using namespace incise;
  const auto scene = station_scene("scenes/surgery/knee_station.json");
  const auto& setup = scene.setup();
  server::live::SimEngine engine(scene, 0.002, 2);
  const auto portal = [&](const std::string& name) {
    for (const auto& p : setup.portals)
      if (p.name == name) return p.position;
    throw std::runtime_error("the knee has no portal " + name);
  };
  const Vec3 scope_portal = portal("anterolateral"), probe_portal = portal("anteromedial");
  const Vec3 medial = sim::find_landmark(setup.landmarks, "medial_meniscus_anterior_horn").position;
  const Vec3 lateral =
      sim::find_landmark(setup.landmarks, "lateral_meniscus_anterior_horn").position;
  run_station(
      scene, engine, "knee station (arthroscope)", save_dir, "knee_station",
      [&](int frame) {
        const double s =
            std::clamp((frame + warm_up_frames) / double(frames + warm_up_frames), 0.0, 1.0);
        const Vec3 look = ((1 - s) * medial + s * lateral - scope_portal).normalized();
        const Vec3 reach = medial - probe_portal;
        const double in = std::min(1.0, 2 * s);
        return std::array<devices::DeviceState, 2>{
            bench::pointing(scope_portal + 0.009 * look, look),
            bench::pointing(probe_portal + (0.1 + 0.85 * in) * reach, reach)};
      },
      {{medial, 0.004, render::MarkKind::target}, {lateral, 0.004, render::MarkKind::target}});
  std::printf("  (%s)\n", engine.state_finite() ? "finite" : "NOT FINITE");
}

}  // namespace

int main(int argc, char** argv) {
  try {
    std::string save_dir;
    std::string path = INCISE_SCENES_DIR "/palpation.json";
    bool block_only = false;
    for (int i = 1; i < argc; ++i) {
      const std::string arg = argv[i];
      if (arg == "--save" && i + 1 < argc) {
        save_dir = argv[++i];
      } else {
        path = arg;
        block_only = true;
      }
    }
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
    if (!block_only) {
      run_liver_station(save_dir, true);
      run_liver_station(save_dir, false);
      run_knee_station(save_dir);
    }
  } catch (const std::exception& error) {
    std::fprintf(stderr, "bench_render: %s\n", error.what());
    return 1;
  }
  return 0;
}
