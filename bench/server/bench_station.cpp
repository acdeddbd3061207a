// What a trainee meets at the Surgical station, measured: the station liver
// (scenes/surgery/liver_station.json) run through the live sessions' SimEngine at its 2 ms tick,
// in four phases, and what the hand feels in the probing and grasping phases against a converged
// reference.
//   idle    the scalpel held 1 cm above the marked line, the grasper parked (1 s);
//   probe   a 4 mm probe in the right hand instead of the scalpel (the station's scene with that
//           one tool swapped) pressed 5 mm into the lobe 5 mm beyond the line's middle, along
//           the organ's surface normal there, over 0.5 s, then held still (1 s);
//   grasp   the grasper takes the lobe beside the line's middle, closes, lifts it 1 cm over 1 s
//           and holds it (1 s);
//   cut     the scalpel enters 6 mm deep at the line's start and cuts along it at 6.7 mm/s (7 s).
// Per phase: median and 95th percentile of the tick's wall time, the most tets, and the longest
// rest edge within 15 mm of a tool in contact (the probe's proxy, the grasper's jaws while they
// hold, the scalpel's blade while its stroke is open), sampled every 5th tick.
//
// The reference: the same scene meshed uniformly at --reference-cell (default 4 mm, 25k tets),
// adaptivity off, the same probe and grasp scripts; the runs settle in their holds (ambient
// damping 20/s: the motion decays as exp(-20 t)), so the end of each hold is a static
// equilibrium. Errors there: the force on the tool |F - F_ref| / |F_ref|, and the displacement
// field over the reference's nodes within 15 mm (rest) of where the tool acts,
// ||u - u_ref|| / ||u_ref|| (the station's field interpolated in its rest tets); the worst of the
// two phases is reported. No affordable mesh is converged (docs/station_accuracy.md), so the
// same measures between a mesh of 1.25 times the cell and the reference are printed beside them:
// the reference's own spread.
//
// Usage: bench_station --scene liver [--json] [--quick] [--phases-only] [--reference-cell m]
//                      [--patch '{json merge patch of the scene file}']
//   --json   one JSON object on stdout (keys in docs/benchmarks.md, "Station"); otherwise a table.
//   --quick  phases and holds at half length, the reference at 6 mm (a smoke run).
//   --phases-only  the four phases' figures alone, without the reference runs or the errors (to
//            profile the station's ticks).
//   --patch  an RFC 7386 merge patch applied to the scene file (to try settings).
// Exit 0 with a result, 2 for bad arguments (a line on stderr), 1 if the scene failed to load.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "bench/server/station_poses.h"
#include "server/live/scene_library.h"
#include "server/live/session_scene.h"
#include "server/live/sim_engine.h"
#include "sim/mesh/cgal/implicit_shape.h"
#include "sim/remesh/state_transfer.h"

namespace {

using namespace incise;
using bench::along_x;
using bench::down;
using bench::parked;
using server::live::SimEngine;
using sim::Vec3;
using Clock = std::chrono::steady_clock;
using Json = nlohmann::json;
constexpr double kTickS = 0.002;
constexpr double kNearToolM = 0.015;  // the "within 15 mm of a tool in contact"
constexpr int kEdgeSampleEvery = 5;   // ticks

struct Options {
  bool json = false;
  bool quick = false;
  bool phases_only = false;  // no reference runs (to profile the station's ticks)
  double reference_cell = 0.004;
  Json patch = Json::object();
};

// One phase's figures (times only for the timed run).
struct Phase {
  std::vector<double> us;
  int tets_peak = 0;
  std::optional<double> max_edge_near_tool;  // [m]
};

// Where a tool in contact acts, as a segment (a, b); none if it is not in contact.
struct Segment {
  Vec3 a, b;
};

double distance_to(const Segment& s, const Vec3& p) {
  const Vec3 d = s.b - s.a;
  const double t =
      d.squaredNorm() > 0 ? std::clamp((p - s.a).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
  return (p - (s.a + t * d)).norm();
}

std::vector<Segment> tools_in_contact(const sim::surgery::SurgicalScene& scene) {
  std::vector<Segment> out;
  for (int k = 0; k < scene.num_tools(); ++k) {
    const auto view = scene.tool_view(k);
    if (!view.touching) continue;
    switch (view.kind) {
      case sim::surgery::ToolKind::scalpel:
        if (view.blade_depth > 0) out.push_back({view.tip, view.tip - 0.012 * view.direction});
        break;
      case sim::surgery::ToolKind::grasper:
        if (view.jaws) out.push_back({view.tip, view.tip + 0.01 * view.direction});
        break;
      default:
        out.push_back({view.tip, view.tip});
    }
  }
  return out;
}

// The longest rest edge with an end (current position) within kNearToolM of a tool in contact.
std::optional<double> longest_edge_near(const sim::surgery::SurgicalScene& scene) {
  const auto tools = tools_in_contact(scene);
  if (tools.empty()) return std::nullopt;
  const auto& mesh = scene.tissue().mesh();
  std::vector<char> near(static_cast<std::size_t>(mesh.num_nodes()), 0);
  for (int v = 0; v < mesh.num_nodes(); ++v) {
    const Vec3 p = sim::row3(mesh.x, v);
    for (const Segment& s : tools)
      if (distance_to(s, p) <= kNearToolM) near[static_cast<std::size_t>(v)] = 1;
  }
  double longest = 0;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    for (int i = 0; i < 4; ++i) {
      for (int j = i + 1; j < 4; ++j) {
        const int a = mesh.tets(t, i), b = mesh.tets(t, j);
        if (!near[static_cast<std::size_t>(a)] && !near[static_cast<std::size_t>(b)]) continue;
        longest = std::max(longest, (sim::row3(mesh.rest, a) - sim::row3(mesh.rest, b)).norm());
      }
    }
  }
  return longest;
}

// A scripted run of one engine: each move interpolates both hands linearly over its seconds.
class Run {
 public:
  Run(std::string_view id, const Json& scene_json, bool timed)
      : timed_(timed), scene_(server::live::load_session_scene(id, scene_json.dump())) {
    engine_.emplace(scene_, kTickS, 2);
  }
  SimEngine& engine() { return *engine_; }
  const sim::surgery::SurgicalSceneSetup& setup() const { return scene_.setup(); }
  const sim::surgery::SurgicalScene& scene() const { return engine_->world().scene(); }

  void move(devices::DeviceState a0, devices::DeviceState a1, devices::DeviceState b0,
            devices::DeviceState b1, double seconds, Phase* phase = nullptr) {
    const auto n = std::max(1, static_cast<int>(std::lround(seconds / kTickS)));
    for (int i = 1; i <= n; ++i) {
      const double s = static_cast<double>(i) / n;
      const std::array<devices::DeviceState, 2> inputs = {bench::blend(a0, a1, s),
                                                          bench::blend(b0, b1, s)};
      const auto start = Clock::now();
      engine_->tick(inputs);
      const double us = std::chrono::duration<double, std::micro>(Clock::now() - start).count();
      if (phase == nullptr) continue;
      if (timed_) phase->us.push_back(us);
      phase->tets_peak = std::max(phase->tets_peak, scene().tissue().mesh().num_tets());
      if (++ticks_ % kEdgeSampleEvery != 0) continue;
      if (const auto e = longest_edge_near(scene())) {
        phase->max_edge_near_tool = std::max(phase->max_edge_near_tool.value_or(0), *e);
      }
    }
  }

 private:
  bool timed_;
  server::live::SessionScene scene_;
  std::optional<SimEngine> engine_;
  long ticks_ = 0;
};

Vec3 landmark(const sim::surgery::SurgicalSceneSetup& setup, const std::string& name) {
  for (const auto& l : setup.landmarks)
    if (l.name == name) return l.position;
  throw std::runtime_error("the scene has no landmark " + name);
}

// A static state to compare: the force on the tool and the displacement field.
struct Equilibrium {
  Vec3 force = Vec3::Zero();
  sim::Points rest, x;
  sim::Tets tets;
  Vec3 centre = Vec3::Zero();  // where the tool acts (rest)
  double residual_speed = 0;   // the nodes' root-mean-square speed at the end [m/s]
};

Equilibrium equilibrium(const Run& run, int hand, const Vec3& centre) {
  Equilibrium e;
  const auto& mesh = run.scene().tissue().mesh();
  e.force = run.scene().force_model(hand).force;
  e.rest = mesh.rest;
  e.x = mesh.x;
  e.tets = mesh.tets;
  e.centre = centre;
  e.residual_speed = mesh.v.rows() > 0 ? std::sqrt(mesh.v.squaredNorm() / mesh.v.rows()) : 0.0;
  return e;
}

struct Errors {
  double force = 0;
  double displacement = 0;
};

Errors compare(const Equilibrium& run, const Equilibrium& reference) {
  Errors out;
  out.force = (run.force - reference.force).norm() / std::max(reference.force.norm(), 1e-12);
  double diff = 0, norm = 0;
  for (Eigen::Index v = 0; v < reference.rest.rows(); ++v) {
    const Vec3 p = reference.rest.row(v).transpose();
    if ((p - reference.centre).norm() > kNearToolM) continue;
    const Vec3 u_ref = reference.x.row(v).transpose() - p;
    const Vec3 u = sim::remesh::displacement_at(run.rest, run.x, run.tets, nullptr, p);
    diff += (u - u_ref).squaredNorm();
    norm += u_ref.squaredNorm();
  }
  out.displacement = std::sqrt(diff / std::max(norm, 1e-30));
  return out;
}

struct Scripts {
  double scale = 1;  // --quick halves every length of time
  Vec3 start, end, lobe;
  // Where the probe presses, on the organ's own (implicit) surface, and the surface's outward
  // normal there: every mesh is pressed along the same line, so that a slope its facets get
  // wrong does not decide the force's direction.
  Vec3 probe_point, probe_normal;
};

Scripts scripts_for(const sim::surgery::SurgicalSceneSetup& setup, const Json& scene, bool quick) {
  Scripts s;
  s.scale = quick ? 0.5 : 1.0;
  s.start = landmark(setup, "cut_start");
  s.end = landmark(setup, "cut_end");
  // The grasper's hinge 0.5 mm above the surface, 5 mm before the line's middle; the probe 5 mm
  // after it.
  s.lobe = 0.5 * (s.start + s.end) + Vec3(-0.005, 0, 0.0005);
  const Json options = scene.value("anatomy_options", Json::object());
  const std::vector<double> c = options.value("centre", std::vector<double>{0, 0, 0});
  const sim::LobedOrgan organ =
      sim::liver_like_organ(Vec3(c.at(0), c.at(1), c.at(2)), options.value("length", 0.16));
  const auto f = [&](const Vec3& p) { return sim::implicit_value(organ, p); };
  const Vec3 p = 0.5 * (s.start + s.end) + Vec3(0.005, 0, 0);
  Vec3 inside = p - Vec3(0, 0, 0.02), outside = p + Vec3(0, 0, 0.02);
  if (!(f(inside) < 0 && f(outside) > 0)) throw std::runtime_error("no surface under the probe");
  for (int k = 0; k < 60; ++k) {
    const Vec3 mid = 0.5 * (inside + outside);
    (f(mid) < 0 ? inside : outside) = mid;
  }
  s.probe_point = 0.5 * (inside + outside);
  const double h = 1e-5;
  Vec3 gradient;
  for (int k = 0; k < 3; ++k) {
    const Vec3 e = h * Vec3::Unit(k);
    gradient(k) = (f(s.probe_point + e) - f(s.probe_point - e)) / (2 * h);
  }
  s.probe_normal = gradient.normalized();
  return s;
}

// The tool at tip pointing along direction (its shaft's d = R e_z).
devices::DeviceState pointing(const Vec3& tip, const Vec3& direction) {
  const auto q = Eigen::Quaternion<double>::FromTwoVectors(Vec3::UnitZ(), direction);
  devices::DeviceState s;
  s.position = {tip.x(), tip.y(), tip.z()};
  s.orientation = {q.w(), q.x(), q.y(), q.z()};
  return s;
}

const Vec3 kAbove(0, 0, 0.01);

// The probe 1 cm out from its point along the normal, pointing in.
devices::DeviceState probe_above(const Scripts& s) {
  return pointing(s.probe_point + 0.01 * s.probe_normal, -s.probe_normal);
}

Equilibrium probe_phase(Run& run, const Scripts& s, Phase& phase) {
  const double probe_radius = 0.004;
  const auto above = probe_above(s);
  // Its centre 5 mm deeper than touching.
  const auto pressed =
      pointing(s.probe_point + (probe_radius - 0.005) * s.probe_normal, -s.probe_normal);
  run.move(above, above, parked(), parked(), 0.05);
  run.move(above, pressed, parked(), parked(), 0.5 * s.scale, &phase);
  run.move(pressed, pressed, parked(), parked(), 1.0 * s.scale, &phase);
  return equilibrium(run, 0, s.probe_point);
}

Equilibrium grasp_phase(Run& run, const Scripts& s, Phase& phase) {
  const auto hold = down(s.start + kAbove);
  run.move(hold, hold, along_x(s.lobe + kAbove, 1), along_x(s.lobe, 1), 0.5 * s.scale, &phase);
  run.move(hold, hold, along_x(s.lobe, 1), along_x(s.lobe, 0), 0.3 * s.scale, &phase);
  run.move(hold, hold, along_x(s.lobe, 0), along_x(s.lobe + kAbove, 0), 1.0 * s.scale, &phase);
  run.move(hold, hold, along_x(s.lobe + kAbove, 0), along_x(s.lobe + kAbove, 0), 1.0 * s.scale,
           &phase);
  return equilibrium(run, 1, s.lobe);
}

void release_grasp(Run& run, const Scripts& s) {
  const auto hold = down(s.start + kAbove);
  run.move(hold, hold, along_x(s.lobe + kAbove, 0), along_x(s.lobe + kAbove, 1), 0.3);
  run.move(hold, hold, along_x(s.lobe + kAbove, 1), parked(), 0.01);
}

Json with_probe(Json scene) {
  Json tools = Json::array();
  tools.push_back({{"kind", "probe"}, {"device", 0}, {"radius", 0.004}});
  for (const auto& t : scene["tools"])
    if (t.value("device", 0) != 0) tools.push_back(t);
  scene["tools"] = tools;
  return scene;
}

Json stats_json(const Phase& p) {
  std::vector<double> us = p.us;
  std::sort(us.begin(), us.end());
  Json j;
  j["median_us"] = us.empty() ? 0.0 : us[us.size() / 2];
  j["p95_us"] = us.empty() ? 0.0 : us[std::min(us.size() - 1, us.size() * 95 / 100)];
  j["tets_peak"] = p.tets_peak;
  j["max_edge_near_tool_mm"] =
      p.max_edge_near_tool ? Json(*p.max_edge_near_tool * 1e3) : Json(nullptr);
  return j;
}

int bad_usage(const std::string& why) {
  std::fprintf(stderr, "bench_station: %s\n", why.c_str());
  std::fprintf(
      stderr,
      "usage: bench_station --scene liver [--json] [--quick] [--phases-only] [--reference-cell m] "
      "[--patch json]\n");
  return 2;
}

int run_liver(const Options& options) {
  const auto source = server::live::find_scene("scenes/surgery/liver_station.json");
  if (!source) throw std::runtime_error("scenes/surgery/liver_station.json not found");
  Json scene = Json::parse(source->text);
  scene.merge_patch(options.patch);

  std::array<Phase, 4> phases;  // idle, probe, grasp, cut
  Run station(source->id, scene, true);
  const Scripts s = scripts_for(station.setup(), scene, options.quick);
  const int tets_at_rest = station.scene().tissue().mesh().num_tets();
  const double settle_s = 0.2;
  station.move(down(s.start + kAbove), down(s.start + kAbove), parked(), parked(), settle_s);
  station.move(down(s.start + kAbove), down(s.start + kAbove), parked(), parked(), 1.0 * s.scale,
               &phases[0]);
  const Equilibrium grasped = grasp_phase(station, s, phases[2]);
  release_grasp(station, s);
  const Vec3 depth(0, 0, 0.006);
  station.move(down(s.start + kAbove), down(s.start - depth), parked(), parked(), 1.0 * s.scale,
               &phases[3]);
  station.move(down(s.start - depth), down(s.end - depth), parked(), parked(), 6.0 * s.scale,
               &phases[3]);
  const bool finite = station.engine().state_finite();
  const int station_tets = station.scene().tissue().mesh().num_tets();

  Run probing(source->id, with_probe(scene), true);
  probing.move(probe_above(s), probe_above(s), parked(), parked(), settle_s);
  const Equilibrium probed = probe_phase(probing, s, phases[1]);

  const char* names[4] = {"idle", "probe", "grasp", "cut"};
  if (options.phases_only) {
    Json out = {{"scene", "liver"},
                {"tets_at_rest", tets_at_rest},
                {"tick_us", static_cast<int>(std::lround(kTickS * 1e6))},
                {"phases", Json::object()}};
    for (int k = 0; k < 4; ++k)
      out["phases"][names[k]] = stats_json(phases[static_cast<std::size_t>(k)]);
    std::printf("%s\n", out.dump(options.json ? -1 : 2).c_str());
    return 0;
  }

  // The reference: the same scripts on the uniformly fine mesh without adaptivity, and on one 1.25
  // times coarser for the reference's spread.
  const double fine_cell = options.quick ? 0.006 : options.reference_cell;
  const double ratio = 1.25;
  struct Reference {
    double cell = 0;
    int tets = 0;
    Equilibrium grasped, probed;
  };
  std::array<Reference, 2> references;  // coarse, fine
  for (std::size_t k = 0; k < 2; ++k) {
    Reference& r = references[k];
    r.cell = k == 0 ? ratio * fine_cell : fine_cell;
    Json fine = scene;
    fine["anatomy_options"]["cell_size"] = r.cell;
    fine["adaptivity"]["enabled"] = false;
    Phase unused;
    Run fine_grasp(source->id, fine, false);
    r.tets = fine_grasp.scene().tissue().mesh().num_tets();
    fine_grasp.move(down(s.start + kAbove), down(s.start + kAbove), parked(), parked(),
                    settle_s + 1.0 * s.scale);
    r.grasped = grasp_phase(fine_grasp, s, unused);
    Run fine_probe(source->id, with_probe(fine), false);
    fine_probe.move(probe_above(s), probe_above(s), parked(), parked(), settle_s);
    r.probed = probe_phase(fine_probe, s, unused);
  }
  const Equilibrium& grasped_ref = references[1].grasped;
  const Equilibrium& probed_ref = references[1].probed;
  // How far the reference itself is from converged, as far as the two meshes tell.
  const Errors probe_spread = compare(references[0].probed, probed_ref);
  const Errors grasp_spread = compare(references[0].grasped, grasped_ref);
  const Errors probe_errors = compare(probed, probed_ref);
  const Errors grasp_errors = compare(grasped, grasped_ref);

  Json out;
  out["scene"] = "liver";
  out["tets_at_rest"] = tets_at_rest;
  out["tick_us"] = static_cast<int>(std::lround(kTickS * 1e6));
  out["phases"] = Json::object();
  for (int k = 0; k < 4; ++k)
    out["phases"][names[k]] = stats_json(phases[static_cast<std::size_t>(k)]);
  out["force_error"] = std::max(probe_errors.force, grasp_errors.force);
  out["displacement_error"] = std::max(probe_errors.displacement, grasp_errors.displacement);
  if (options.json) {
    std::printf("%s\n", out.dump().c_str());
    return 0;
  }
  std::printf(
      "Station liver: %d tets at rest, %d substeps of %.0f us a 2 ms tick; %d tets after "
      "the cut; finite %s\n",
      tets_at_rest, station.engine().substeps(), kTickS / station.engine().substeps() * 1e6,
      station_tets, finite ? "yes" : "no");
  {
    // Why the step is what it is: the explicit step follows the smallest altitude at rest.
    const auto& setup = station.setup();
    std::vector<double> alt;
    for (Eigen::Index t = 0; t < setup.spec.tissue.tets.rows(); ++t) {
      std::array<Vec3, 4> p;
      for (int k = 0; k < 4; ++k)
        p[static_cast<std::size_t>(k)] =
            sim::row3(setup.spec.tissue.rest, setup.spec.tissue.tets(t, k));
      const double v = std::abs((p[1] - p[0]).dot((p[2] - p[0]).cross(p[3] - p[0]))) / 6;
      const double f = 0.5 * std::max({(p[1] - p[0]).cross(p[2] - p[0]).norm(),
                                       (p[1] - p[0]).cross(p[3] - p[0]).norm(),
                                       (p[2] - p[0]).cross(p[3] - p[0]).norm(),
                                       (p[2] - p[1]).cross(p[3] - p[1]).norm()});
      alt.push_back(3 * v / f);
    }
    std::sort(alt.begin(), alt.end());
    const auto q = [&](double f) {
      return 1e3 * alt[static_cast<std::size_t>(f * (alt.size() - 1))];
    };
    std::printf("  smallest altitudes at rest: min %.2f, 1%% %.2f, 5%% %.2f, median %.2f mm\n",
                q(0), q(0.01), q(0.05), q(0.5));
  }
  std::printf("  %-6s %10s %10s %10s %22s\n", "phase", "median us", "p95 us", "tets peak",
              "longest edge near tool");
  for (int k = 0; k < 4; ++k) {
    const Json& p = out["phases"][names[k]];
    const std::string edge = p["max_edge_near_tool_mm"].is_null()
                                 ? std::string("-")
                                 : std::to_string(p["max_edge_near_tool_mm"].get<double>());
    std::printf("  %-6s %10.0f %10.0f %10d %19.5s mm\n", names[k], p["median_us"].get<double>(),
                p["p95_us"].get<double>(), p["tets_peak"].get<int>(), edge.c_str());
  }
  std::printf(
      "Reference: %d and %d tets (cells %.1f and %.1f mm); pull on the "
      "grasper %.3f and %.3f N, push on the probe %.3f and %.3f N; the nodes' rms "
      "speed at the ends %.1e m/s\n",
      references[0].tets, references[1].tets, references[0].cell * 1e3, references[1].cell * 1e3,
      references[0].grasped.force.norm(), references[1].grasped.force.norm(),
      references[0].probed.force.norm(), references[1].probed.force.norm(),
      std::max(grasped_ref.residual_speed, probed_ref.residual_speed));
  const auto line = [](const char* what, const Equilibrium& e, const Equilibrium& ref,
                       const Errors& err) {
    std::printf(
        "  %s: force (%.3f, %.3f, %.3f) N, reference (%.3f, %.3f, %.3f) N: error %.1f %%; "
        "displacement error %.1f %%\n",
        what, e.force.x(), e.force.y(), e.force.z(), ref.force.x(), ref.force.y(), ref.force.z(),
        100 * err.force, 100 * err.displacement);
  };
  line("probe", probed, probed_ref, probe_errors);
  line("grasp", grasped, grasped_ref, grasp_errors);
  std::printf(
      "  the reference's spread (%.1f against %.1f mm): probe force %.1f %%, displacement "
      "%.1f %%; grasp force %.1f %%, displacement %.1f %%\n",
      references[0].cell * 1e3, references[1].cell * 1e3, 100 * probe_spread.force,
      100 * probe_spread.displacement, 100 * grasp_spread.force, 100 * grasp_spread.displacement);
  const auto& st = station.scene();
  std::printf("Adaptivity (station run): %d splits, %d refused, %d undone\n", st.splits(),
              st.splits_refused(), st.splits_undone());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  std::string scene;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--json") {
      options.json = true;
    } else if (arg == "--quick") {
      options.quick = true;
    } else if (arg == "--phases-only") {
      options.phases_only = true;
    } else if (arg == "--scene" && has_value) {
      scene = argv[++i];
    } else if (arg == "--reference-cell" && has_value) {
      char* end = nullptr;
      options.reference_cell = std::strtod(argv[++i], &end);
      if (*end != '\0' || !(options.reference_cell >= 0.002 && options.reference_cell <= 0.02)) {
        return bad_usage("--reference-cell must be a cell size in metres, 0.002 to 0.02");
      }
    } else if (arg == "--patch" && has_value) {
      options.patch = Json::parse(argv[++i], nullptr, false);
      if (options.patch.is_discarded() || !options.patch.is_object()) {
        return bad_usage("--patch must be a JSON object");
      }
    } else {
      return bad_usage("unknown or incomplete argument " + arg);
    }
  }
  if (scene != "liver") return bad_usage("--scene liver is the one scene measured so far");
  try {
    return run_liver(options);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_station: %s\n", e.what());
    return 1;
  }
}
