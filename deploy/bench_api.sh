#!/usr/bin/env bash
# The REST API under load (docs/benchmarks.md, "The API under load"): wrk against GET /api/me of
# a logged-in admin on a fresh demo server over loopback, first alone, then while 20 connections
# log in as fast as the server lets them (each login is an argon2id check), then while 20
# connections of the admin create users (each hashes a new password). Prints wrk's summary and
# latency percentiles of each run, and the logins and creations completed meanwhile.
#   deploy/bench_api.sh [SECONDS] [--postgresql]   (default 15 s per run)
# --postgresql keeps the server's data in a throwaway local PostgreSQL cluster
# (tests/support/postgres_cluster.sh) instead of an SQLite file.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
seconds=15
engine=sqlite
for arg in "$@"; do
  case "$arg" in
    --postgresql) engine=postgresql ;;
    *[!0-9]* | "") echo "bench_api: unknown argument $arg" >&2; exit 2 ;;
    *) seconds=$arg ;;
  esac
done

bash deploy/install-deps.sh --bench
bash deploy/build.sh > /dev/null
bin=${INCISE_BUILD_DIR:-build}/bin
work=$(mktemp -d)
# The cluster's directory must be open to the postgres user (mktemp's is not).
pg_dir=/tmp/incise-bench-pg-$$
server_pid=
trap 'kill $server_pid 2>/dev/null || true; wait 2>/dev/null || true; rm -rf "$work";
      if [ $engine = postgresql ]; then bash tests/support/postgres_cluster.sh stop "$pg_dir"; fi' EXIT

database=(--data "$work/data")
if [ $engine = postgresql ]; then
  database=(--database "$(bash tests/support/postgres_cluster.sh start "$pg_dir")")
fi
"$bin/incise-server" --port 0 "${database[@]}" --web web/dist --demo > "$work/server.out" \
  2> "$work/server.log" &
server_pid=$!
for _ in $(seq 1 100); do
  grep -q "listening on" "$work/server.out" 2>/dev/null && break
  sleep 0.1
done
url=$(sed -n 's/.*listening on \(http:\/\/[^ ]*\).*/\1/p' "$work/server.out")
login='{"username": "admin", "password": "incise-admin-demo"}'
cookie=$(curl -s -D - -o /dev/null -H 'Content-Type: application/json' -d "$login" \
  "$url/api/login" | sed -n 's/^Set-Cookie: \(incise_session=[0-9a-f]*\).*/\1/p')
[ -n "$cookie" ] || { echo "bench_api: cannot log in" >&2; exit 1; }

cat > "$work/login.lua" <<LUA
wrk.method = "POST"
wrk.body = '$login'
wrk.headers["Content-Type"] = "application/json"
LUA

echo "# GET /api/me alone, $engine: 2 threads, 32 connections, ${seconds} s ($(date -u +%F), git $(git rev-parse --short HEAD))"
wrk -t2 -c32 -d"${seconds}s" --latency -H "Cookie: $cookie" "$url/api/me"
echo
# GET /api/me while 20 connections run wrk's script $1 against $2 (started 2 s before, ended 2 s
# after); then what those connections completed, titled $3.
me_during() {
  wrk -t1 -c20 -d"$((seconds + 4))s" -s "$1" "$url$2" > "$work/load.txt" &
  local load_pid=$!
  sleep 2
  wrk -t2 -c32 -d"${seconds}s" --latency -H "Cookie: $cookie" "$url/api/me"
  wait $load_pid
  echo
  echo "# $3"
  cat "$work/load.txt"
}

echo "# GET /api/me while 20 connections log in"
me_during "$work/login.lua" /api/login "the logins meanwhile (POST /api/login, 20 connections)"

# Each request a new trainee, with a name no other request of this run uses.
cat > "$work/create.lua" <<LUA
local n = 0
request = function()
  n = n + 1
  local body = string.format(
    '{"username": "load-%d-%d", "password": "bench password %d", "role": "trainee"}',
    math.random(1, 1000000000), n, n)
  return wrk.format("POST", "/api/users", {["Content-Type"] = "application/json",
                                           ["Cookie"] = "$cookie"}, body)
end
LUA
echo
echo "# GET /api/me while 20 connections of the admin create users"
me_during "$work/create.lua" /api/users "the creations meanwhile (POST /api/users, 20 connections)"
