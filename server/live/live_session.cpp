#include "server/live/live_session.h"

#include <chrono>
#include <iostream>

#include "db/bookings_repo.h"
#include "db/database.h"
#include "db/recordings_repo.h"
#include "db/session_events_repo.h"
#include "db/training_repo.h"
#include "server/live/scoring.h"
#include "server/live/tick_record.h"

namespace incise::server::live {
namespace {

using Clock = std::chrono::steady_clock;

// Beyond this much behind schedule the session stops catching up and drops the missed ticks
// (counted as late_ticks), so a stall never makes the tool race afterwards.
constexpr auto kMaxLag = std::chrono::milliseconds(100);

std::int64_t unix_now() {
  return std::chrono::duration_cast<std::chrono::seconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// The steady clock in seconds, for PaceMonitor.
double seconds_now() {
  return std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
}

Clock::duration period_of(double hz) {
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / hz));
}

const SessionScene& scene_of(const LiveSessionParams& params) {
  if (!params.scene) throw std::invalid_argument("a live session needs a scene");
  return *params.scene;
}

}  // namespace

int hands_for(const curriculum::Task& task) {
  return std::clamp(static_cast<int>(task.tools.size()), 1, SimEngine::kMaxHands);
}

const char* to_string(LiveState state) {
  switch (state) {
    case LiveState::running:
      return "running";
    case LiveState::paused:
      return "paused";
    case LiveState::finished:
      return "finished";
  }
  return "?";
}

// The session's recording: ticks are buffered and written as one chunk per chunk_s, each chunk in
// its own small transaction, so a crash loses at most the chunk being filled. A failed write
// (say the database stayed locked past its busy timeout) keeps the ticks buffered for the next
// try: the recording never gets a hole.
class Recorder {
 public:
  Recorder(db::Database& db, std::int64_t recording_id, std::int64_t ticks_per_chunk, double tick_s)
      : repo_(db), recording_id_(recording_id), ticks_per_chunk_(ticks_per_chunk), tick_s_(tick_s) {
    buffer_.reserve(static_cast<std::size_t>(ticks_per_chunk) * kTickRecordSize);
  }
  // Returns "" or why the chunk that became due could not be written.
  std::string add(const TickRecord& record) {
    if (buffered_ == 0) first_tick_ = record.tick;
    append_tick_record(record, buffer_);
    ++buffered_;
    return buffered_ >= ticks_per_chunk_ ? flush() : "";
  }
  std::string flush() {
    if (buffered_ == 0) return "";
    const auto t0_us = static_cast<std::int64_t>(static_cast<double>(first_tick_) * tick_s_ * 1e6);
    try {
      repo_.append_chunk(recording_id_, seq_, t0_us, buffer_,
                         static_cast<double>(flushed_ticks_ + buffered_) * tick_s_);
    } catch (const std::exception& e) {
      return e.what();
    }
    ++seq_;
    flushed_ticks_ += buffered_;
    buffer_.clear();
    buffered_ = 0;
    return "";
  }
  // Simulated time that is safely stored [s].
  double stored_s() const { return static_cast<double>(flushed_ticks_) * tick_s_; }
  // Simulated time waiting to be stored [s].
  double pending_s() const { return static_cast<double>(buffered_) * tick_s_; }

 private:
  db::RecordingsRepo repo_;
  std::int64_t recording_id_;
  std::int64_t ticks_per_chunk_;
  double tick_s_;
  std::vector<std::uint8_t> buffer_;
  std::int64_t buffered_ = 0;
  std::int64_t flushed_ticks_ = 0;
  std::int64_t seq_ = 0;
  std::uint32_t first_tick_ = 0;
};

// Beyond this much unwritten recording the session stops rather than run on unrecorded [s].
constexpr double kMaxUnrecordedS = 10.0;

LiveSession::LiveSession(LiveSessionParams params, AgentLink agent)
    : params_(std::move(params)),
      agent_(std::move(agent)),
      engine_(scene_of(params_), 1.0 / params_.tick_hz, hands_for(params_.task)),
      shed_plan_{engine_.world().setup().spec.adaptivity.enabled
                     ? sim::surgery::kMaxAdaptivityShedLevel
                     : 0},
      pace_(engine_.tick_s(), shed_plan_.max_level()) {
  publish_snapshot();
}

LiveSession::~LiveSession() {
  stop("server shutting down");
  streamer_.reset();  // its render thread reads this session: stop it first
}

void LiveSession::start() {
  {
    std::lock_guard lock(mutex_);
    running_since_ = std::chrono::steady_clock::now();
  }
  streamer_ = std::make_unique<FrameStreamer>(
      *this, camera_for(*params_.scene), outside_camera_for(*params_.scene),
      params_.scene->shared_setup(), task_zones(params_.task));
  thread_ = std::thread([this] { run(); });
}

LiveState LiveSession::state() const {
  std::lock_guard lock(mutex_);
  return state_;
}

std::string LiveSession::reason() const {
  std::lock_guard lock(mutex_);
  return reason_;
}

double LiveSession::sim_time_s() const {
  return sim_time_s_.load();
}

std::string LiveSession::pause(const std::string& reason) {
  {
    std::lock_guard lock(mutex_);
    if (state_ == LiveState::finished || stop_requested_) return "session has finished";
    if (state_ == LiveState::paused) return "session is already paused";
    state_ = LiveState::paused;
    reason_ = reason;
  }
  wake_.notify_all();
  return "";
}

std::string LiveSession::resume() {
  {
    std::lock_guard lock(mutex_);
    if (state_ == LiveState::finished || stop_requested_) return "session has finished";
    if (state_ == LiveState::running) return "session is already running";
    if (!agent_online_.load()) return "station agent is offline";
    state_ = LiveState::running;
    reason_.clear();
    running_since_ = std::chrono::steady_clock::now();
  }
  wake_.notify_all();
  return "";
}

void LiveSession::stop(const std::string& reason) {
  {
    std::unique_lock lock(mutex_);
    if (!stop_requested_) {
      stop_requested_ = true;
      if (state_ != LiveState::finished) reason_ = reason;
    }
  }
  wake_.notify_all();
  // Several callers may stop at once; one joins, the others wait for it.
  std::lock_guard join_lock(join_mutex_);
  if (thread_.joinable()) thread_.join();
  // A session that never started has no thread to mark it finished.
  std::lock_guard lock(mutex_);
  state_ = LiveState::finished;
}

void LiveSession::on_device_state(const devices::DeviceState& state, std::uint64_t timestamp_us) {
  if (state.device_index >= engine_.hands()) {
    ++ignored_states_;  // a device the task has no tool for
    return;
  }
  std::lock_guard lock(mutex_);
  Input& input = inputs_[state.device_index];
  input.state = state;
  input.received = true;
  input.timestamp_us = timestamp_us;
}

std::string stale_model_reason(const nlohmann::json& report) {
  const auto devices = report.find("devices");
  if (!report.is_object() || devices == report.end() || !devices->is_array()) return "";
  for (const auto& d : *devices) {
    if (!d.is_object() || d.value("fault", std::string()) != "stale model") continue;
    const auto age = d.value("model_age_ms", 0.0);
    return "the station's force model went stale (tool " + std::to_string(d.value("index", 0) + 1) +
           ": " + std::to_string(static_cast<long long>(std::llround(age))) +
           " ms old, over the agent's safety limit); resume when the link is steady";
  }
  return "";
}

void LiveSession::set_link_report(nlohmann::json report) {
  const auto stale = stale_model_reason(report);
  bool must_pause = false;
  {
    std::lock_guard lock(mutex_);
    link_report_ = std::move(report);
    must_pause = !stale.empty() && state_ == LiveState::running &&
                 std::chrono::steady_clock::now() - running_since_ >= params_.stale_model_grace;
  }
  if (must_pause) pause(stale);
}

void LiveSession::set_agent_online(bool online) {
  agent_online_.store(online);
  if (!online) pause("station agent offline");
}

nlohmann::json LiveSession::status() const {
  nlohmann::json out;
  bool ticking = false;  // running with a device state to tick from: the clock applies
  {
    std::lock_guard lock(mutex_);
    ticking = state_ == LiveState::running && inputs_[0].received;
    out["state"] = to_string(state_);
    out["reason"] = state_ == LiveState::running && !inputs_[0].received
                        ? "waiting for the first device state from the station"
                        : reason_;
  }
  out["agent_online"] = agent_online_.load();
  out["sim_rate_hz"] = sim_rate_hz_.load();
  out["late_ticks"] = late_ticks_.load();
  // Behind real time: the simulation advances slower than the clock or a tick hangs; the page
  // says so beside "Running" (never a frozen picture that claims to run).
  {
    PaceState pace;
    {
      std::lock_guard lock(pace_mutex_);
      pace = pace_.state_at(seconds_now());
    }
    if (!ticking) {
      pace.behind = false;
      pace.lag_s = 0;
    }
    out["behind_real_time"] = pace.behind;
    out["lag_ms"] = pace.lag_s * 1e3;
    out["real_time_factor"] = pace.real_time_factor;
    out["shed"] = shed_plan_.text(pace.shed_level);
  }
  out["force_models_sent"] = force_models_sent_.load();
  out["hands"] = engine_.hands();
  out["ignored_device_states"] = ignored_states_.load();
  {
    std::lock_guard lock(mutex_);
    if (!link_report_.is_null()) out["link"] = link_report_;
  }
  out["frame_latency_ms"] = frame_latency().median();
  if (streamer_) {
    const auto error = streamer_->error();
    if (!error.empty()) out["render_error"] = error;
  }
  return out;
}

void LiveSession::restart_pace() {
  std::lock_guard lock(pace_mutex_);
  pace_.restart(seconds_now());
}

void LiveSession::publish_snapshot() {
  snapshot_.publish(make_snapshot(engine_));
  if (streamer_) streamer_->poke();
}

void LiveSession::run() {
  const double tick_s = engine_.tick_s();
  const auto tick_period = period_of(params_.tick_hz);
  const auto ticks_per_force_model =
      std::max<std::int64_t>(1, std::llround(params_.tick_hz / params_.force_model_hz));
  const auto ticks_per_snapshot =
      std::max<std::int64_t>(1, std::llround(params_.tick_hz / params_.snapshot_hz));
  const auto ticks_per_chunk =
      std::max<std::int64_t>(1, std::llround(params_.tick_hz * params_.chunk_s));
  // The simulation's damage index every 0.1 s, for the review's timeline (the recording holds
  // the input, not what the simulation measured). An hour's samples are reserved up front.
  constexpr double kDamageSampleS = 0.1;
  const auto ticks_per_damage_sample =
      std::max<std::int64_t>(1, std::llround(params_.tick_hz * kDamageSampleS));
  std::vector<double> damage_samples;
  damage_samples.reserve(36'000);

  std::optional<db::Database> db;
  std::optional<Recorder> recorder;
  try {
    db.emplace(params_.database);
    recorder.emplace(*db, params_.recording_id, ticks_per_chunk, tick_s);
  } catch (const std::exception& e) {
    // Without its recording a session is worth nothing: end it at once and say why.
    std::cerr << "incise-server: session " << params_.session_id
              << " cannot open the database: " << e.what() << "\n";
    std::lock_guard lock(mutex_);
    stop_requested_ = true;
    reason_ = std::string("cannot open the database: ") + e.what();
  }
  std::string last_record_error;
  auto write_state = [&](LiveState state) {
    if (agent_.send_notice) {
      agent_.send_notice(state == LiveState::finished ? "idle" : to_string(state));
    }
    if (!db) return;
    try {
      const auto now = unix_now();
      db::TrainingRepo(*db).set_session_state(params_.session_id, to_string(state), now);
      // Bookings follow sessions: the rest of the slot is free once the session ends.
      if (state == LiveState::finished)
        db::BookingsRepo(*db).complete_for_session(params_.session_id, now);
    } catch (const std::exception& e) {
      std::cerr << "incise-server: session " << params_.session_id << ": " << e.what() << "\n";
    }
  };

  LiveState written = LiveState::running;
  if (agent_.send_notice) agent_.send_notice("running");
  auto next = Clock::now();
  auto rate_window_start = next;
  std::int64_t rate_window_ticks = 0;
  TickRecord record;
  int shed_level = 0;  // the pace monitor's, after the last tick
  restart_pace();
  while (true) {
    std::array<Input, SimEngine::kMaxHands> inputs;
    {
      std::unique_lock lock(mutex_);
      if (stop_requested_) break;
      if (state_ == LiveState::paused) {
        if (written != LiveState::paused) {
          lock.unlock();
          if (recorder) recorder->flush();  // a failure retries at the next chunk
          write_state(LiveState::paused);
          written = LiveState::paused;
          continue;
        }
        wake_.wait(lock, [this] { return stop_requested_ || state_ != LiveState::paused; });
        next = Clock::now();
        restart_pace();
        rate_window_start = next;
        rate_window_ticks = 0;
        continue;
      }
      inputs = inputs_;
    }
    if (written != LiveState::running) {
      write_state(LiveState::running);
      written = LiveState::running;
    }

    next += tick_period;
    const auto now = Clock::now();
    const double schedule_lag_s = std::chrono::duration<double>(now - next).count();
    if (now - next > kMaxLag) {
      late_ticks_ += (now - next) / tick_period;
      next = now;
    }
    std::this_thread::sleep_until(next);

    if (!inputs[0].received) {
      // Time starts with the first device state: the recording then begins where the tool is,
      // with no jump from a parked position into the scene (and none in the path length).
      next = Clock::now();
      restart_pace();
      continue;
    }
    // A second hand that has not reported yet waits parked, out of the scene.
    std::array<devices::DeviceState, SimEngine::kMaxHands> states;
    for (std::size_t h = 0; h < states.size(); ++h) {
      states[h] = inputs[h].state;
      states[h].device_index = static_cast<std::uint8_t>(h);
      if (!inputs[h].received) states[h].position = {0, 0, kParkedToolHeight};
    }
    // Shedding (pace_monitor.h), the physics' part first: recorded with the tick.
    engine_.set_shed_level(shed_plan_.physics_level(shed_level));
    engine_.tick(std::span<const devices::DeviceState>(states.data(),
                                                       static_cast<std::size_t>(engine_.hands())));
    record.tick = static_cast<std::uint32_t>(engine_.ticks() - 1);
    record.shed = static_cast<std::uint8_t>(engine_.shed_level());
    record.input = states[0];
    for (int i = 0; i < 3; ++i)
      record.force[i] = static_cast<float>(engine_.contact(0).force_on_tool[i]);
    record.has_second = engine_.hands() > 1;
    if (record.has_second) {
      record.second.input = states[1];
      for (int i = 0; i < 3; ++i)
        record.second.force[i] = static_cast<float>(engine_.contact(1).force_on_tool[i]);
    }
    if (recorder) {
      const auto error = recorder->add(record);
      if (!error.empty() && error != last_record_error) {
        std::cerr << "incise-server: session " << params_.session_id
                  << " could not write its recording (retrying): " << error << "\n";
      }
      last_record_error = error;
      if (recorder->pending_s() > kMaxUnrecordedS) {
        std::lock_guard lock(mutex_);
        stop_requested_ = true;
        reason_ = "recording failed: " + error;
      }
    }
    sim_time_s_.store(engine_.time_s());

    if (engine_.ticks() % ticks_per_force_model == 0 && agent_.send_force_model) {
      for (int h = 0; h < engine_.hands(); ++h) {
        const Input& input = inputs[static_cast<std::size_t>(h)];
        if (!input.received) continue;
        auto model = engine_.force_model(h);
        model.state_timestamp_us = input.timestamp_us;
        agent_.send_force_model(model);
        ++force_models_sent_;
      }
    }
    if (params_.after_tick) params_.after_tick();
    {
      const double now_s = seconds_now();
      std::lock_guard lock(pace_mutex_);
      pace_.on_tick(now_s, schedule_lag_s);
      shed_level = pace_.state_at(now_s).shed_level;
    }
    // Shedding, the picture's part: fewer snapshots, so fewer frames rendered beside the physics.
    if (engine_.ticks() % (ticks_per_snapshot * shed_plan_.render_divisor(shed_level)) == 0) {
      publish_snapshot();
    }
    if (engine_.ticks() % ticks_per_damage_sample == 0) {
      damage_samples.push_back(engine_.damage_index());
    }

    ++rate_window_ticks;
    const auto window = Clock::now() - rate_window_start;
    if (window >= std::chrono::seconds(1)) {
      sim_rate_hz_.store(static_cast<double>(rate_window_ticks) /
                         std::chrono::duration<double>(window).count());
      rate_window_start = Clock::now();
      rate_window_ticks = 0;
    }
    if (engine_.ticks() > static_cast<std::int64_t>(kMaxRecordedTick)) {
      // A tick number has 29 bits in the recording (tick_record.h).
      std::lock_guard lock(mutex_);
      stop_requested_ = true;
      reason_ = "session reached the longest recordable length";
    }
    if (!engine_.state_finite()) {
      std::lock_guard lock(mutex_);
      stop_requested_ = true;
      reason_ = "simulation became unstable (non-finite state); session stopped";
    }
  }

  publish_snapshot();
  // Close the recording and score the run.
  if (db) {
    try {
      const auto now = unix_now();
      double duration = 0;
      bool complete = false;
      if (recorder) {
        const auto error = recorder->flush();
        if (!error.empty()) {
          std::cerr << "incise-server: session " << params_.session_id << " lost "
                    << recorder->pending_s() << " s of its recording: " << error << "\n";
        }
        duration = recorder->stored_s();
        complete = recorder->pending_s() == 0;
      }
      // The final state belongs to the whole run: stored only if the whole run is recorded.
      db::RecordingsRepo recordings(*db);
      recordings.finish(params_.recording_id, duration, complete ? engine_.state_hash() : "");
      db::TrainingRepo(*db).set_signal(params_.session_id, "damage_index",
                                       {ticks_per_damage_sample * tick_s, damage_samples});
      const auto simulated = simulation_metrics(engine_.damage());
      score_session(*db, params_.session_id, params_.recording_id, params_.task, tick_s, now,
                    simulated);
      // After the score, which matters more: the review's markers of a surgical scene.
      std::vector<db::SessionEvent> events;
      for (const auto& e : engine_.scene_events().events())
        events.push_back({e.t_s, e.kind, e.hand, e.label});
      db::SessionEventsRepo(*db).set(params_.session_id, events);
    } catch (const std::exception& e) {
      std::cerr << "incise-server: session " << params_.session_id
                << " could not be scored: " << e.what() << "\n";
    }
    write_state(LiveState::finished);
  }
  {
    std::lock_guard lock(mutex_);
    state_ = LiveState::finished;
  }
}

}  // namespace incise::server::live
