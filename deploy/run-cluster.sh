#!/usr/bin/env bash
# Starts the platform as it runs beyond one machine, on this one (docs/scale_out.md): PostgreSQL,
# nginx as the load balancer, three incise-server nodes sharing the database, and the demo
# stations' simulated agents connected through the balancer. Ctrl-C stops them all.
#   INCISE_PORT (default 8080): the balancer's port; the nodes listen on the next three
#   INCISE_CLUSTER_DIR (default /var/tmp/incise-cluster-UID): PostgreSQL's data, nginx's files
#     and the logs; the database survives a restart (delete the directory to start afresh)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"

bash deploy/build.sh

port=${INCISE_PORT:-8080}
dir=${INCISE_CLUSTER_DIR:-/var/tmp/incise-cluster-$(id -u)}
bin=$root/${INCISE_BUILD_DIR:-build}/bin
pg_bin=$(ls -d /usr/lib/postgresql/*/bin 2>/dev/null | sort -V | tail -1)
mkdir -p "$dir/logs" "$dir/nginx"
# initdb and postgres refuse to run as root: then Debian's postgres user runs them.
as_owner=()
[ "$(id -u)" -eq 0 ] && as_owner=(runuser -u postgres --) && chown postgres "$dir" "$dir/logs"

pids=()
stop() {
  trap - INT TERM EXIT
  echo
  echo "Stopping..."
  for pid in "${pids[@]}"; do kill -TERM "$pid" 2>/dev/null || true; done
  wait 2>/dev/null || true
  "${as_owner[@]}" "$pg_bin/pg_ctl" -D "$dir/postgres" -m fast -w stop >/dev/null 2>&1 || true
  echo "Stopped."
}
trap stop INT TERM EXIT

# PostgreSQL on a Unix socket in $dir (no TCP port to clash with a system server).
if [ ! -f "$dir/postgres/PG_VERSION" ]; then
  "${as_owner[@]}" "$pg_bin/initdb" -D "$dir/postgres" -U postgres -A trust -E UTF8 --locale=C \
    > "$dir/logs/initdb.log"
fi
"${as_owner[@]}" "$pg_bin/pg_ctl" -D "$dir/postgres" -l "$dir/logs/postgres.log" -w \
  -o "-k $dir -c listen_addresses=''" start > /dev/null
"${as_owner[@]}" "$pg_bin/psql" -h "$dir" -U postgres -d postgres -tAc \
  "SELECT 1 FROM pg_database WHERE datname = 'incise'" | grep -q 1 \
  || "${as_owner[@]}" "$pg_bin/createdb" -h "$dir" -U postgres incise
export INCISE_DATABASE_URL="postgresql://postgres@/incise?host=$dir"

# Three nodes, one after another (the first creates the schema and the demo data). nginx on
# loopback is their trusted proxy: the clients' addresses come from X-Forwarded-For.
upstreams=""
for n in 1 2 3; do
  node_port=$((port + n))
  ready="$dir/logs/node-$n.ready"
  rm -f "$ready"
  "$bin/incise-server" --port "$node_port" --node-id "node-$n" --data "$dir/node-$n" \
    --web "$root/web/dist" --demo --trusted-proxy 127.0.0.1 \
    > "$ready" 2>> "$dir/logs/node-$n.log" &
  pids+=($!)
  for _ in $(seq 1 200); do
    grep -q "listening on" "$ready" 2>/dev/null && break
    kill -0 "${pids[-1]}" 2>/dev/null || { echo "run-cluster: node-$n did not start; see $dir/logs/node-$n.log" >&2; exit 1; }
    sleep 0.1
  done
  upstreams+="    server 127.0.0.1:$node_port max_fails=1 fail_timeout=10s;"$'\n'
done

# nginx with the configuration the cluster test uses (deploy/cluster/nginx.conf.in).
user_line=""
[ "$(id -u)" -eq 0 ] && user_line="user root;"
conf=$(< deploy/cluster/nginx.conf.in)
conf=${conf//@PREFIX@/$dir/nginx}
conf=${conf//@PORT@/$port}
conf=${conf//@USER@/$user_line}
conf=${conf//@UPSTREAMS@/$upstreams}
printf '%s\n' "$conf" > "$dir/nginx/nginx.conf"
/usr/sbin/nginx -p "$dir/nginx" -c "$dir/nginx/nginx.conf" -e "$dir/logs/nginx.log" &
nginx_pid=$!
pids+=($nginx_pid)
for _ in $(seq 1 50); do
  curl -fs "http://127.0.0.1:$port/api/ready" > /dev/null && break
  sleep 0.1
done

# The demo stations' agents, through the balancer: round robin spreads them over the nodes.
agent() {
  local token=$1 log=$2
  shift 2
  INCISE_STATION_TOKEN=$token "$bin/incise-agent" --server "ws://127.0.0.1:$port/agent" "$@" \
    2>> "$dir/logs/$log.log" &
  pids+=($!)
  sleep 0.5
}
agent incise-demo-station-token agent
agent incise-demo-surgical-station-token surgical-agent --script "$root/deploy/agent/liver_cut_demo.json"
agent incise-demo-arthroscopy-station-token arthroscopy-agent \
  --device "knee-scope:$root/deploy/agent/knee_scope_tour.json" \
  --device "knee-instrument:$root/deploy/agent/knee_probe_tour.json"

cat <<MSG

  Incise is running on three nodes behind nginx: http://127.0.0.1:$port/
  (nodes at http://127.0.0.1:$((port + 1))/, :$((port + 2)), :$((port + 3)); any of them serves
  any page: a call about a session another node runs is forwarded there)

  Demo logins as for deploy/run.sh (trainee / incise-trainee-demo, admin / incise-admin-demo, ...).
  PostgreSQL: $INCISE_DATABASE_URL
  Logs: $dir/logs/ (nginx's: $dir/nginx/error.log).
  Try: kill -9 a node, and within about 35 s (the 30 s heartbeat timeout and a beat) its
  sessions end and its station's agent moves to another node.
  Press Ctrl-C to stop.

MSG
# Until Ctrl-C, or the balancer stops: a node may die (that is the point), the stack goes on.
wait "$nginx_pid"
