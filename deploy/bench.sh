#!/usr/bin/env bash
# Runs the benchmarks (they measure; the tests assert correctness) and writes their output to
# results/bench-<UTC time>.txt. Takes about ten minutes; run it on a quiet machine, and quote
# the figures of one run together. Usage: bash deploy/bench.sh [--quick]  (--quick: 10 s runs)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"

seconds=60
live_seconds=30
if [ "${1:-}" = "--quick" ]; then
  seconds=10
  live_seconds=10
fi

bash deploy/build.sh
bin=${INCISE_BUILD_DIR:-build}/bin
mkdir -p results
out=results/bench-$(date -u +%Y%m%dT%H%M%SZ).txt
{
  echo "# incise benchmarks, $(date -u +%Y-%m-%dT%H:%M:%SZ), $(nproc) cores, git $(git rev-parse --short HEAD 2>/dev/null || echo '?')"
  echo
  echo "## render + readback + encode (demo scene, 640x480)"
  "$bin/bench_render"
  echo
  echo "## one 2 ms simulation tick of the demo scene"
  "$bin/bench_live_step"
  echo
  echo "## the simulation's damage tracker in a tick; review and scoring of a 2 min recording"
  "$bin/bench_scoring"
  echo
  echo "## the liver at a surgical station: a tick idle, grasping and cutting, by cell size"
  "$bin/bench_surgery_live"
  echo
  echo "## the station liver: ticks per phase, what the hand feels against a converged reference"
  if [ "${1:-}" = "--quick" ]; then "$bin/bench_station" --scene liver --quick; else "$bin/bench_station" --scene liver; fi
  echo
  echo "## seeking in a replay of a 3-minute liver attempt"
  "$bin/bench_replay_seek"
  echo
  echo "## per-tet kernels against this machine's limit"
  "$bin/bench_kernels"
  echo
  echo "## agent haptic loop, ${seconds} s"
  "$bin/bench_agent_loop" --seconds "$seconds"
  echo
  echo "## device-state traffic with and without the deadband, scripted task"
  "$bin/bench_agent_traffic"
  echo
  echo "## force error against network delay and loss (simulated time)"
  "$bin/bench_haptic_network"
  echo
  echo "## live path on loopback (server + agent + one viewer), ${live_seconds} s"
  "$bin/bench_live" --seconds "$live_seconds"
  echo
  echo "## the REST API under load (wrk): GET /api/me alone and during 20 parallel logins, on SQLite"
  bash deploy/bench_api.sh "$live_seconds"
  echo
  echo "## the same on PostgreSQL (a throwaway local cluster)"
  bash deploy/bench_api.sh "$live_seconds" --postgresql
  echo
  echo "## three local nodes on PostgreSQL behind nginx: three stations' sessions, two viewers each (one forwarded), ${live_seconds} s"
  pg_dir=/tmp/incise-bench-cluster-$$
  INCISE_TEST_DATABASE=$(bash tests/support/postgres_cluster.sh start "$pg_dir") \
    "$bin/bench_cluster" --seconds "$live_seconds" 2>/dev/null || echo "bench_cluster failed"
  bash tests/support/postgres_cluster.sh stop "$pg_dir"
  echo
  echo "## speed against error: every model x integrator (results/accuracy.csv, results/*.svg)"
  if [ "${1:-}" = "--quick" ]; then "$bin/bench_accuracy" --quick; else "$bin/bench_accuracy"; fi
  echo
  echo "## per-tet kernels and implicit steps (Google Benchmark)"
  "$bin/bench_models"
  echo
  echo "## remeshing: one insertion / one removal"
  "$bin/bench_remesh"
  "$bin/bench_refinement"
  "$bin/bench_remesh_pass"
  echo
  echo "## probing as in Paloc 2006, Figure 6: low / high / adaptive mesh (results/probing*.csv, results/probing_*.svg)"
  "$bin/bench_probing" results/probing.csv
  echo
  echo "## active region: a local poke on a 5.8k-tet box, with and without"
  "$bin/bench_active_region" 3000 20 0.02 5e-5 1e-4
  echo
  echo "## liver-like organ (~5k tets) probed by a scripted tool, full against active region"
  "$bin/bench_liver" 4000 0.0085 5e-5 1e-4
  echo
  echo "## liver-like organ: fine / active region / coarse / adaptive, steps/s and error"
  "$bin/bench_liver_adaptive" corotational
  "$bin/bench_liver_adaptive" mss
  echo
  echo "## planning: minimum-penetration paths among 3 to 10 obstacles, degree 3 and 5 (seed 004)"
  "$bin/bench_planning"
  echo
  echo "## calibration: seed 004's cube, node moduli by ga, cmaes and lm; noise; mass-spring to FEM"
  "$bin/bench_calibration"
  echo
  echo "## collision: the surface tree's refit and queries on a ~10k-triangle surface"
  "$bin/bench_collide"
  echo
  echo "## tool contact per simulation step on a ~5k-triangle surface"
  "$bin/bench_tool_contact"
  echo
  echo "## progressive cutting: the cut update per haptic frame on a 5,040-tet block"
  "$bin/bench_cut"
  echo
  echo "## the condensed far field against the full model"
  "$bin/bench_condensed"
  echo
  echo "## the surgical scenes (liver, knee): step, collision queries, cuts"
  "$bin/bench_surgery"
} 2>&1 | tee "$out"
echo "deploy/bench.sh: wrote $out"
