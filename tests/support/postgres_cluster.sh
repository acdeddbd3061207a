#!/usr/bin/env bash
# Starts or stops a throwaway PostgreSQL cluster for the tests: DIR holds its data, its log and its
# Unix socket (no TCP port, so it cannot clash with any other server on the machine). Durability is
# off (fsync, synchronous_commit): the data lives as long as one test run.
#   postgres_cluster.sh start DIR   initdb + pg_ctl start; prints the URL to reach it
#   postgres_cluster.sh stop DIR    pg_ctl stop, then removes DIR
# initdb refuses to run as root (as CI does): then the server runs as Debian's `postgres` user.
set -euo pipefail
action=${1:?start or stop}
dir=${2:?the cluster directory}
bindir=$(pg_config --bindir 2>/dev/null || true)
[ -x "$bindir/initdb" ] || bindir=$(ls -d /usr/lib/postgresql/*/bin 2>/dev/null | sort -V | tail -1)
if [ ! -x "$bindir/initdb" ]; then
  echo "postgres_cluster: no initdb (install the postgresql package: deploy/install-deps.sh)" >&2
  exit 1
fi
as_owner=()
[ "$(id -u)" -eq 0 ] && as_owner=(runuser -u postgres --)

stop() {
  if [ -f "$dir/data/postmaster.pid" ]; then
    "${as_owner[@]}" "$bindir/pg_ctl" -D "$dir/data" -m immediate -w stop >/dev/null 2>&1 || true
  fi
  rm -rf "$dir"
}

case "$action" in
  start)
    stop
    mkdir -p "$dir"
    [ ${#as_owner[@]} -gt 0 ] && chown postgres "$dir"
    "${as_owner[@]}" "$bindir/initdb" -D "$dir/data" -U postgres -A trust -E UTF8 --locale=C \
      --no-sync >"$dir/initdb.log" 2>&1 || { cat "$dir/initdb.log" >&2; exit 1; }
    "${as_owner[@]}" "$bindir/pg_ctl" -D "$dir/data" -l "$dir/server.log" -w -t 60 \
      -o "-k $dir -c listen_addresses='' -c fsync=off -c synchronous_commit=off \
          -c full_page_writes=off -c max_connections=200" start >/dev/null \
      || { cat "$dir/server.log" >&2; exit 1; }
    echo "postgresql://postgres@/postgres?host=$dir"
    ;;
  stop) stop ;;
  *) echo "postgres_cluster: unknown action $action (start or stop)" >&2; exit 2 ;;
esac
