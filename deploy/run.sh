#!/usr/bin/env bash
# Starts the product: the server with its SQLite database (created with demo data on first run)
# and the demo stations' simulated agents. Ctrl-C stops them all.
#   INCISE_PORT (default 8080), INCISE_HOST (default 127.0.0.1), INCISE_DATA (default ./data)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"

bash deploy/build.sh

port=${INCISE_PORT:-8080}
host=${INCISE_HOST:-127.0.0.1}
data=${INCISE_DATA:-$root/data}
bin=${INCISE_BUILD_DIR:-build}/bin
log_dir="$data/logs"
mkdir -p "$log_dir"

server_pid=""
agent_pid=""
surgical_agent_pid=""
knee_agent_pid=""
stop() {
  trap - INT TERM EXIT
  echo
  echo "Stopping..."
  [ -n "$agent_pid" ] && kill -TERM "$agent_pid" 2>/dev/null || true
  [ -n "$surgical_agent_pid" ] && kill -TERM "$surgical_agent_pid" 2>/dev/null || true
  [ -n "$knee_agent_pid" ] && kill -TERM "$knee_agent_pid" 2>/dev/null || true
  [ -n "$server_pid" ] && kill -TERM "$server_pid" 2>/dev/null || true
  wait 2>/dev/null || true
  echo "Stopped."
}
trap stop INT TERM EXIT

ready="$log_dir/server.ready"
rm -f "$ready"
"$bin/incise-server" --host "$host" --port "$port" --data "$data" --web "$root/web/dist" --demo \
  > >(tee "$ready") 2> >(tee -a "$log_dir/server.log" >&2) &
server_pid=$!
for _ in $(seq 1 100); do
  grep -q "listening on" "$ready" 2>/dev/null && break
  if ! kill -0 "$server_pid" 2>/dev/null; then
    echo "run.sh: the server did not start; see above" >&2
    exit 1
  fi
  sleep 0.1
done

# The demo station's agent, with the simulated (scripted) device. Tokens go in the environment,
# not on the command line, where any local user could read them in ps.
INCISE_STATION_TOKEN=incise-demo-station-token "$bin/incise-agent" --server "ws://$host:$port/agent" \
  2>> "$log_dir/agent.log" &
agent_pid=$!
# The surgical station's agent: its simulated scalpel cuts along the liver's marked line every 12 s
# (deploy/agent/liver_cut_demo.json); its grasper (device 1) is not connected.
INCISE_STATION_TOKEN=incise-demo-surgical-station-token "$bin/incise-agent" \
  --server "ws://$host:$port/agent" --script "$root/deploy/agent/liver_cut_demo.json" 2>> "$log_dir/surgical-agent.log" &
surgical_agent_pid=$!
# The arthroscopy station's agent: a simulated arthroscope at the knee's anterolateral portal and
# a probe at the anteromedial one, touring the joint's landmarks every 28 s
# (deploy/agent/knee_scope_tour.json, knee_probe_tour.json).
INCISE_STATION_TOKEN=incise-demo-arthroscopy-station-token "$bin/incise-agent" \
  --server "ws://$host:$port/agent" --device "knee-scope:$root/deploy/agent/knee_scope_tour.json" \
  --device "knee-instrument:$root/deploy/agent/knee_probe_tour.json" \
  2>> "$log_dir/arthroscopy-agent.log" &
knee_agent_pid=$!

cat <<MSG

  Incise is running: http://$host:$port/

  Demo logins (username / password):
    trainee     / incise-trainee-demo   (at the start of the course)
    resident    / incise-resident-demo  (palpation mastered: the liver and knee tasks are open)
    instructor  / incise-instructor-demo
    admin       / incise-admin-demo

  Station 1 (palpation) is connected through a simulated station agent (log: $log_dir/agent.log);
  the Surgical station (the liver task) through another (log: $log_dir/surgical-agent.log), and
  the Arthroscopy station (the knee) through a third (log: $log_dir/arthroscopy-agent.log).
  Database: $data/incise.db.   Press Ctrl-C to stop.

MSG
wait "$server_pid"
