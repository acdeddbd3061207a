#include "stability_suite.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <fstream>
#include <numbers>
#include <random>
#include <stdexcept>
#include <utility>

#include "sim/mesh/boundary_surface.h"

namespace incise::sim::surgery::stability {

namespace {

using Quat = Eigen::Quaternion<Real>;

// An orientation whose tool axis d = R e_z is `direction`, rolled about it by `roll` [rad].
Quat pointing(const Vec3& direction, Real roll) {
  const Vec3 d = direction.normalized();
  return Quat(Eigen::AngleAxis<Real>(roll, d)) * Quat::FromTwoVectors(Vec3::UnitZ(), d);
}

// Appends the moves of one sequence's device script; knows where the device's input is.
class ScriptBuilder {
 public:
  ScriptBuilder(const SceneGeometry& geometry, int device, const GeneratorSettings& settings,
                std::mt19937_64& rng)
      : g_(geometry), device_(device), s_(settings), rng_(rng) {
    script_.kind = geometry.tools[static_cast<std::size_t>(device)];
    const Portal* portal = this->portal();
    const Vec3 direction = portal != nullptr ? portal->direction : Vec3(-g_.up);
    script_.start.tip = portal != nullptr ? portal->position : g_.home;
    script_.out = portal != nullptr
                      ? Vec3(portal->position - DeviceScript::kOutOfPortal * direction)
                      : g_.home;
    script_.start.orientation = pointing(direction, 0);
    script_.start.jaw = 1;
    tip_ = script_.start.tip;
    orientation_ = script_.start.orientation;
    Vec3 lo = g_.targets.front(), hi = lo;
    for (const Vec3& p : g_.targets) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    stroke_length_ = std::clamp(0.25 * (hi - lo).norm(), 0.005, 0.05);
  }

  bool full() const { return steps_ >= s_.steps; }
  DeviceScript take() { return std::move(script_); }

  void segment() {
    const SegmentKind kind = pick();
    script_.segments.push_back(kind);
    switch (kind) {
      case SegmentKind::probe:
        probe();
        break;
      case SegmentKind::grasp:
        grasp();
        break;
      case SegmentKind::cut:
        cut(false);
        break;
      case SegmentKind::cross_cut:
        cut(true);
        break;
      case SegmentKind::jerk:
        jerk();
        break;
      case SegmentKind::sweep:
        sweep();
        break;
      case SegmentKind::retreat:
        retreat();
        break;
    }
  }

 private:
  Real uniform(Real a, Real b) { return std::uniform_real_distribution<Real>(a, b)(rng_); }
  int uniform_int(int a, int b) { return std::uniform_int_distribution<int>(a, b)(rng_); }
  bool chance(Real p) { return uniform(0, 1) < p; }
  Vec3 random_unit() {
    std::normal_distribution<Real> n(0, 1);
    Vec3 u(n(rng_), n(rng_), n(rng_));
    return u.norm() > 1e-9 ? Vec3(u.normalized()) : Vec3(Vec3::UnitX());
  }
  Vec3 perpendicular(const Vec3& a) {
    const Vec3 u = random_unit();
    const Vec3 p = u - u.dot(a) * a;
    return p.norm() > 1e-6 ? Vec3(p.normalized()) : Vec3(a.unitOrthogonal());
  }
  const Vec3& target() {
    return g_
        .targets[static_cast<std::size_t>(uniform_int(0, static_cast<int>(g_.targets.size()) - 1))];
  }
  const Portal* portal() const {
    const auto d = static_cast<std::size_t>(device_);
    if (d >= g_.entries.size()) return nullptr;
    return &g_.entries[d];
  }

  SegmentKind pick() {
    // Weights per tool: each tool does mostly what it is for, and every tool jerks and sweeps.
    std::vector<std::pair<SegmentKind, Real>> w;
    switch (script_.kind) {
      case ToolKind::probe:
      case ToolKind::scope:
        w = {{SegmentKind::probe, 3},
             {SegmentKind::jerk, 2},
             {SegmentKind::sweep, 2},
             {SegmentKind::retreat, 1}};
        break;
      case ToolKind::grasper:
        w = {{SegmentKind::grasp, 4},
             {SegmentKind::probe, 1},
             {SegmentKind::jerk, 2},
             {SegmentKind::sweep, 1},
             {SegmentKind::retreat, 1}};
        break;
      case ToolKind::scalpel:
        w = {{SegmentKind::cut, 3},
             {SegmentKind::cross_cut, 2},
             {SegmentKind::jerk, 1},
             {SegmentKind::sweep, 1},
             {SegmentKind::retreat, 1}};
        break;
    }
    Real total = 0;
    for (const auto& [k, x] : w)
      total += x;
    Real r = uniform(0, total);
    for (const auto& [k, x] : w) {
      if (r < x) return k;
      r -= x;
    }
    return w.back().first;
  }

  // The direction a tool comes in along towards p, and where it comes in from.
  std::pair<Vec3, Vec3> approach(const Vec3& p) {
    if (const Portal* portal = this->portal()) {
      // Along the line from the portal, from `approach` before p (or from the portal if nearer):
      // the instrument stays in the joint between tasks, as in an arthroscopy.
      const Vec3 line = p - portal->position;
      const Vec3 a = line.norm() > 1e-6 ? Vec3(line.normalized()) : portal->direction;
      return {a, line.norm() > s_.approach ? Vec3(p - s_.approach * a) : portal->position};
    }
    // From above, tilted by up to 30 degrees.
    const Vec3 tilt = perpendicular(g_.up);
    const Real angle = uniform(0, std::numbers::pi / 6);
    const Vec3 a = -(std::cos(angle) * g_.up + std::sin(angle) * tilt);
    return {a, p - s_.approach * a};
  }

  void add(const Vec3& tip, const Quat& q, Real jaw, int steps, bool jump = false) {
    steps = std::max(1, steps);
    script_.moves.push_back(
        {steps, tip, q, jaw, jump, static_cast<int>(script_.segments.size()) - 1});
    steps_ += steps;
    tip_ = tip;
    orientation_ = q;
    jaw_ = jaw;
  }
  // A move at speed [m/s] (at least one step; capped so that a slow move cannot overflow: the
  // sequence ends long before).
  void travel(const Vec3& tip, const Quat& q, Real jaw, Real speed) {
    speed = std::min(speed * s_.speed_scale, s_.max_speed);
    const Real steps = std::ceil((tip - tip_).norm() / (speed * g_.dt));
    add(tip, q, jaw, static_cast<int>(std::min<Real>(steps, 1e8)));
  }
  void hold(int steps) { add(tip_, orientation_, jaw_, steps); }
  // Moving to or from a task (mostly in the air): quick, so that a sequence's steps go to the
  // tasks (the knee's step is ~10 us: a hand's pace would spend them all travelling).
  Real reposition() { return uniform(0.5, s_.max_speed) / s_.speed_scale; }
  Real roll() { return uniform(-std::numbers::pi, std::numbers::pi); }

  void probe() {
    const Vec3 t = target();
    const auto [a, entry] = approach(t);
    const Quat q = pointing(a, roll());
    const Real jaw = script_.kind == ToolKind::grasper ? 0 : 1;
    travel(entry, q, jaw, reposition());
    const Vec3 pressed = t + uniform(0, s_.max_press) * a;
    travel(pressed, q, jaw, uniform(0.02, 0.5));
    hold(uniform_int(0, 200));
    if (chance(0.5)) {  // drag along the surface while pressed
      travel(pressed + uniform(0.003, stroke_length_) * perpendicular(a), q, jaw,
             uniform(0.02, 0.3));
    }
    travel(entry, q, jaw, reposition());
  }

  void grasp() {
    const Vec3 t = target();
    const auto [a, entry] = approach(t);
    const Quat q = pointing(a, roll());
    travel(entry, q, 1, reposition());
    const Vec3 bite = t + uniform(-0.002, 0.005) * a;
    travel(bite, q, 1, uniform(0.02, 0.3));
    add(bite, q, 0, uniform_int(10, 60));  // close
    const Vec3 pull = (-a + 0.8 * random_unit()).normalized();
    const Vec3 pulled = bite + uniform(0.005, 0.04) * pull;
    travel(pulled, q, 0, uniform(0.02, 0.5));
    hold(uniform_int(0, 100));
    if (chance(0.4)) {  // tear: yank far beyond what the grip holds
      travel(pulled + uniform(0.03, 0.06) * pull, q, 0, uniform(0.5, s_.max_speed));
    }
    add(tip_, q, 1, uniform_int(5, 30));  // release
    travel(entry, q, 1, reposition());
  }

  void cut(bool cross) {
    Vec3 p0, p1;
    if (cross) {
      // Across the previous stroke at its middle (or across the marked line).
      const Vec3 m = have_stroke_ ? Vec3(0.5 * (stroke_[0] + stroke_[1]))
                                  : Vec3(0.5 * (g_.cut_line.front() + g_.cut_line.back()));
      const Vec3 along = have_stroke_ ? Vec3(stroke_[1] - stroke_[0])
                                      : Vec3(g_.cut_line.back() - g_.cut_line.front());
      Vec3 across = approach(m).first.cross(along);
      across = across.norm() > 1e-9 ? Vec3(across.normalized()) : perpendicular(along.normalized());
      const Real half = 0.5 * uniform(0.4, 1) * stroke_length_;
      p0 = m - half * across;
      p1 = m + half * across;
    } else if (chance(0.5)) {
      const bool forward = chance(0.5);
      p0 = forward ? g_.cut_line.front() : g_.cut_line.back();
      p1 = forward ? g_.cut_line.back() : g_.cut_line.front();
    } else {
      const Vec3 t = target();
      const Vec3 along = perpendicular(approach(t).first);
      const Real half = 0.5 * uniform(0.3, 1) * stroke_length_;
      p0 = t - half * along;
      p1 = t + half * along;
    }
    stroke_ = {p0, p1};
    have_stroke_ = true;
    const auto [a, entry] = approach(p0);
    const Quat q = pointing(a, roll());
    const Real depth = uniform(0.001, 0.012);
    travel(entry, q, 1, reposition());
    travel(p0 + depth * a, q, 1, uniform(0.05, 0.5));
    // Mostly a surgeon's stroke; now and then a slash.
    const Real speed = chance(0.8) ? uniform(0.02, 0.3) : uniform(0.3, s_.max_speed);
    travel(p1 + depth * a, q, 1, speed);
    travel(p1 - s_.approach * a, q, 1, reposition());
  }

  void jerk() {
    Quat q = orientation_;
    if (chance(0.7)) {  // from inside the tissue
      const Vec3 t = target();
      const auto [a, entry] = approach(t);
      q = pointing(a, roll());
      travel(entry, q, 1, reposition());
      travel(t + uniform(0, s_.max_press) * a, q, 1, uniform(0.05, 0.5));
      if (script_.kind == ToolKind::grasper && chance(0.5)) add(tip_, q, 0, uniform_int(10, 40));
    }
    const int jumps = uniform_int(1, 3);
    for (int k = 0; k < jumps; ++k) {
      const Vec3 from = tip_;
      const Quat from_q = orientation_;
      const Quat turned =
          Quat(Eigen::AngleAxis<Real>(uniform(0, 0.5), random_unit())) * orientation_;
      add(tip_ + uniform(0.005, s_.max_jerk) * random_unit(), turned, jaw_, uniform_int(1, 30),
          true);
      if (chance(0.5)) add(from, from_q, jaw_, uniform_int(1, 30), true);
    }
    add(tip_, orientation_, 1, 1);
  }

  void sweep() {
    const Vec3 t = target();
    const auto [a, entry] = approach(t);
    const Vec3 across = perpendicular(a);
    const Quat q = pointing(a, roll());
    const Real depth = uniform(0, 0.01);
    const Real half = uniform(0.5, 1) * stroke_length_;
    const Vec3 s = t + depth * a - half * across;
    const Vec3 e = t + depth * a + half * across;
    travel(s - s_.approach * a, q, 1, reposition());
    travel(s, q, 1, uniform(0.1, 0.5));
    travel(e, q, 1, uniform(0.5, s_.max_speed));
    travel(e - s_.approach * a, q, 1, reposition());
  }

  void retreat() {
    travel(script_.start.tip, script_.start.orientation, 1, reposition());
    hold(uniform_int(20, 300));
  }

  const SceneGeometry& g_;
  int device_;
  const GeneratorSettings& s_;
  std::mt19937_64& rng_;
  DeviceScript script_;
  long steps_ = 0;
  Vec3 tip_ = Vec3::Zero();
  Quat orientation_ = Quat::Identity();
  Real jaw_ = 1;
  Real stroke_length_ = 0.02;
  std::array<Vec3, 2> stroke_{Vec3::Zero(), Vec3::Zero()};
  bool have_stroke_ = false;
};

// Keeps the first failure: what went wrong first is what a replay looks for.
void fail(SequenceResult& r, std::string why) {
  if (r.failure.empty()) r.failure = std::move(why);
  r.passed = false;
}

}  // namespace

SurgicalSceneSetup stability_scene(std::string_view name) {
  ToolSpec scalpel = make_tool(ToolKind::scalpel, 2);
  if (name == "liver") {
    LiverSceneOptions options;
    options.anatomy.cell_size = 0.01;
    scalpel.blade_length = 0.012;
    options.tools = LiverSceneOptions::default_tools();
    options.tools.push_back(scalpel);
    return make_liver_surgery(options);
  }
  if (name == "knee") {
    KneeSceneOptions options;
    options.anatomy.tissue_cell_size = 0.004;
    scalpel.blade_length = 0.01;
    scalpel.shaft_radius = 0.0015;
    options.tools = KneeSceneOptions::default_tools();
    options.tools.push_back(scalpel);
    return make_knee_surgery(options);
  }
  throw std::invalid_argument("stability_scene: unknown scene '" + std::string(name) +
                              "' (liver or knee)");
}

SceneGeometry geometry_of(const SurgicalSceneSetup& setup) {
  SceneGeometry g;
  g.name = setup.name;
  g.dt = setup.spec.dt;
  int devices = 0;
  for (const ToolSpec& t : setup.spec.tools)
    devices = std::max(devices, t.device + 1);
  g.tools.assign(static_cast<std::size_t>(devices), ToolKind::probe);
  for (const ToolSpec& t : setup.spec.tools)
    g.tools[static_cast<std::size_t>(t.device)] = t.kind;
  for (const Landmark& l : setup.landmarks)
    g.targets.push_back(l.position);
  for (const Vec3& p : setup.cut_target)
    g.targets.push_back(p);
  g.cut_line = setup.cut_target;
  const TetMesh& mesh = setup.spec.tissue;
  const BoundarySurface surface = boundary_surface(mesh);
  Points V, N;
  surface_vertices(surface, mesh.rest, V, N);
  // About 100 surface points; from above (no portals) only those facing up.
  const std::size_t every = std::max<std::size_t>(1, surface.nodes.size() / 100);
  for (std::size_t j = 0; j < surface.nodes.size(); j += every) {
    const auto row = static_cast<Eigen::Index>(j);
    if (setup.portals.empty() && N.row(row).dot(g.up) < 0.3) continue;
    g.targets.push_back(V.row(row).transpose());
  }
  if (!setup.portals.empty()) {
    // Knee: the scope through the anterolateral portal, the others through the anteromedial.
    auto find = [&](const std::string& name) {
      for (const Portal& p : setup.portals) {
        if (p.name == name) return p;
      }
      return setup.portals.front();
    };
    for (int d = 0; d < devices; ++d) {
      g.entries.push_back(find(g.tools[static_cast<std::size_t>(d)] == ToolKind::scope
                                   ? "anterolateral"
                                   : "anteromedial"));
    }
  }
  const Vec3 lo = mesh.rest.colwise().minCoeff().transpose();
  const Vec3 hi = mesh.rest.colwise().maxCoeff().transpose();
  g.home = Vec3(0.5 * (lo.x() + hi.x()), 0.5 * (lo.y() + hi.y()), hi.z() + 0.03);
  return g;
}

std::string_view to_string(SegmentKind kind) {
  switch (kind) {
    case SegmentKind::probe:
      return "probe";
    case SegmentKind::grasp:
      return "grasp";
    case SegmentKind::cut:
      return "cut";
    case SegmentKind::cross_cut:
      return "cross_cut";
    case SegmentKind::jerk:
      return "jerk";
    case SegmentKind::sweep:
      return "sweep";
    case SegmentKind::retreat:
      return "retreat";
  }
  return "?";
}

GeneratorSettings default_generator(std::string_view scene) {
  GeneratorSettings settings;
  if (scene == "knee") {
    settings.steps = 6000;
    settings.speed_scale = 10;
  }
  return settings;
}

Sequence make_sequence(const SceneGeometry& geometry, std::uint64_t seed,
                       const GeneratorSettings& settings) {
  if (settings.steps < 1) throw std::invalid_argument("make_sequence: steps must be >= 1");
  if (!(settings.max_jerk > 0.005) || !(settings.max_speed > 0.5) || !(settings.max_press >= 0) ||
      !(settings.approach > 0) || !(settings.speed_scale >= 1)) {
    throw std::invalid_argument(
        "make_sequence: need max_jerk > 5 mm, max_speed > 0.5 m/s, max_press >= 0, approach > 0, "
        "speed_scale >= 1");
  }
  if (geometry.targets.empty() || geometry.cut_line.size() < 2 || !(geometry.dt > 0)) {
    throw std::invalid_argument("make_sequence: the geometry needs targets, a cut line and dt");
  }
  Sequence sequence;
  sequence.seed = seed;
  sequence.steps = settings.steps;
  // One generator per sequence: devices drawn in turn, so a seed fixes everything.
  std::mt19937_64 rng(seed);
  for (int d = 0; d < static_cast<int>(geometry.tools.size()); ++d) {
    ScriptBuilder builder(geometry, d, settings, rng);
    while (!builder.full())
      builder.segment();
    sequence.devices.push_back(builder.take());
  }
  return sequence;
}

ScriptPlayer::ScriptPlayer(const DeviceScript& script) : script_(&script), from_(script.start) {}

int ScriptPlayer::segment() const {
  return move_ < script_->moves.size() ? script_->moves[move_].segment : -1;
}

ToolInput ScriptPlayer::next() {
  while (move_ < script_->moves.size() && step_ >= script_->moves[move_].steps) {
    const Move& done = script_->moves[move_];
    from_.tip = done.tip;
    from_.orientation = done.orientation;
    from_.jaw = done.jaw;
    ++move_;
    step_ = 0;
  }
  if (move_ >= script_->moves.size()) return from_;
  const Move& m = script_->moves[move_];
  ++step_;
  const Real s = m.jump ? 1 : static_cast<Real>(step_) / m.steps;
  ToolInput in;
  in.tip = from_.tip + s * (m.tip - from_.tip);
  in.orientation = from_.orientation.slerp(s, m.orientation);
  in.jaw = from_.jaw + s * (m.jaw - from_.jaw);
  return in;
}

SequenceResult run_sequence(const SurgicalSceneSpec& spec, const std::string& scene,
                            const Sequence& sequence, const RunSettings& settings) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  SequenceResult r;
  r.scene = scene;
  r.seed = sequence.seed;
  r.passed = true;
  for (const DeviceScript& d : sequence.devices) {
    for (const SegmentKind k : d.segments)
      ++r.segments[static_cast<std::size_t>(k)];
  }
  // Where the run is, for a failure's message (no string built per step).
  const char* phase = "setup";
  int at = 0;
  std::vector<ScriptPlayer> players;
  auto where = [&] {
    std::string text = std::string(phase) + " step " + std::to_string(at) + " (";
    for (std::size_t d = 0; d < players.size(); ++d) {
      const DeviceScript& script = sequence.devices[d];
      const int k = players[d].segment();
      text += std::string(d > 0 ? ", " : "") + std::string(to_string(script.kind)) + " " +
              (k >= 0 ? std::string(to_string(script.segments[static_cast<std::size_t>(k)])) +
                            " #" + std::to_string(k)
                      : std::string("done"));
    }
    return text + ")";
  };
  try {
    SurgicalScene s(spec);
    const TissueBody& tissue = s.tissue();
    r.initial_tets = r.peak_tets = tissue.mesh().num_tets();
    r.initial_nodes = r.peak_nodes = tissue.mesh().num_nodes();
    const std::size_t devices = sequence.devices.size();
    for (const DeviceScript& d : sequence.devices)
      players.emplace_back(d);
    std::vector<ToolInput> inputs(devices);
    // After each step: finite state and force models, the peaks; false stops the run.
    auto observe = [&]() {
      for (const SceneEvent& e : s.take_events())
        ++r.events[static_cast<std::size_t>(e.kind)];
      const TetMesh& mesh = tissue.mesh();
      r.peak_inverted = std::max(r.peak_inverted, tissue.model().health().inverted_elements);
      r.peak_tets = std::max(r.peak_tets, mesh.num_tets());
      r.peak_nodes = std::max(r.peak_nodes, mesh.num_nodes());
      r.peak_mass_scaled_nodes = std::max(r.peak_mass_scaled_nodes, tissue.mass_scaled_nodes());
      r.max_mass_scale = std::max(r.max_mass_scale, tissue.max_mass_scale());
      if (!s.state_finite()) {
        fail(r, "non-finite tissue state at " + where());
        return false;
      }
      for (std::size_t d = 0; d < devices; ++d) {
        const tools::LocalForceModel m = s.force_model(static_cast<int>(d));
        if (!m.force.allFinite() || !m.stiffness.allFinite()) {
          fail(r, "non-finite force model of device " + std::to_string(d) + " at " + where());
          return false;
        }
      }
      return true;
    };
    // --trace: how the run develops, to find where elements invert.
    int traced = 0;
    auto trace = [&] {
      if (settings.trace_every <= 0 || traced++ % settings.trace_every != 0) return;
      const TetMesh& mesh = tissue.mesh();
      const Real speed = mesh.v.rows() > 0 ? mesh.v.rowwise().norm().maxCoeff() : 0;
      std::fprintf(stderr, "  %-8s %5d  tets %5d  inverted %4d  speed %8.3g m/s  splits %d\n",
                   phase, at, mesh.num_tets(), tissue.model().health().inverted_elements,
                   static_cast<double>(speed), s.splits());
      // Each tool: whether it touches, where it is drawn (a probe's proxy), its input, the hand's
      // force (a proxy held far from its input shows here).
      for (std::size_t d = 0; d < devices; ++d) {
        const ToolView v = s.tool_view(static_cast<int>(d));
        const Vec3 f = s.force_model(static_cast<int>(d)).force;
        std::fprintf(stderr,
                     "    tool %zu  touching %d  at %7.4f %7.4f %7.4f  input %7.4f %7.4f %7.4f  "
                     "hand %7.3f %7.3f %7.3f N\n",
                     d, v.touching ? 1 : 0, v.tip.x(), v.tip.y(), v.tip.z(), inputs[d].tip.x(),
                     inputs[d].tip.y(), inputs[d].tip.z(), f.x(), f.y(), f.z());
      }
    };
    bool ok = true;
    for (int n = 0; n < sequence.steps && ok; ++n) {
      phase = "sequence";
      at = n;
      for (std::size_t d = 0; d < devices; ++d)
        inputs[d] = players[d].next();
      s.step(inputs);
      ++r.steps;
      ok = observe();
      trace();
    }
    // Every tool opened and taken out, then the tissue left alone.
    const std::vector<ToolInput> last = inputs;
    for (int n = 0; n < settings.retract_steps && ok; ++n) {
      phase = "retract";
      at = n;
      const Real t = static_cast<Real>(n + 1) / settings.retract_steps;
      for (std::size_t d = 0; d < devices; ++d) {
        inputs[d].tip = last[d].tip + t * (sequence.devices[d].out - last[d].tip);
        inputs[d].jaw = 1;
      }
      s.step(inputs);
      ++r.settle_steps;
      ok = observe();
      trace();
    }
    const int settle_min = std::max(
        settings.settle_min_steps, static_cast<int>(std::ceil(settings.settle_min_time / spec.dt)));
    const int settle_max = std::max(
        settings.settle_max_steps, static_cast<int>(std::ceil(settings.settle_max_time / spec.dt)));
    for (int n = 0; n < settle_max && ok; ++n) {
      phase = "settle";
      at = n;
      s.step(inputs);
      ++r.settle_steps;
      ok = observe();
      trace();
      if (ok && n + 1 >= settle_min && (n + 1) % 50 == 0 &&
          tissue.model().health().inverted_elements == 0) {
        break;
      }
    }
    r.inverted_at_end = tissue.model().health().inverted_elements;
    r.speed_at_end = tissue.mesh().v.rows() > 0 ? tissue.mesh().v.rowwise().norm().maxCoeff() : 0;
    r.final_tets = tissue.mesh().num_tets();
    r.mass_scale_at_end = tissue.max_mass_scale();
    r.collapses = s.collapses();
    r.splits = s.splits();
    r.splits_undone = s.splits_undone();
    r.cuts_refused = s.cuts_refused();
    r.inverted_tets_pulled = s.inverted_tets_pulled();
    if (ok && r.inverted_at_end > 0) {
      fail(r, std::to_string(r.inverted_at_end) + " elements still inverted after " +
                  std::to_string(r.settle_steps) + " settle steps");
    }
    if (ok && r.peak_tets > settings.max_growth * r.initial_tets) {
      fail(r, "the mesh grew to " + std::to_string(r.peak_tets) + " tets from " +
                  std::to_string(r.initial_tets));
    }
  } catch (const std::exception& e) {
    fail(r, "exception at " + where() + ": " + e.what());
  }
  r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return r;
}

long resident_kib() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  }
  return -1;
}

}  // namespace incise::sim::surgery::stability
