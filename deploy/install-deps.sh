#!/usr/bin/env bash
# Installs every system and npm package that the build, the run and the tests need.
# Idempotent: it installs only what is missing, so the run and test commands call it every time.
#   --fuzz   also clang with libFuzzer and the sanitizer runtimes (deploy/fuzz.sh)
#   --bench  also the HTTP load generator wrk (deploy/bench_api.sh)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")

apt_packages=(
  build-essential cmake ninja-build pkg-config git clang-format
  libeigen3-dev libcgal-dev libboost1.74-dev libfcl-dev libnifti2-dev
  nlohmann-json3-dev libsqlite3-dev sqlite3
  libpq-dev postgresql
  nginx-light python3 python3-yaml
  libegl-dev libgl-dev libopengl-dev libegl-mesa0 libgl1-mesa-dri libgles-dev
  libturbojpeg0-dev libsodium-dev libssl-dev openssl
  libgtest-dev libgmock-dev libbenchmark-dev
  calculix-ccx
  chromium curl ca-certificates
)

for extra in "$@"; do
  case "$extra" in
    --fuzz) apt_packages+=(clang libclang-rt-14-dev) ;;
    --bench) apt_packages+=(wrk) ;;
    *) echo "install-deps: unknown option $extra" >&2; exit 2 ;;
  esac
done

missing=()
for p in "${apt_packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# kubectl renders deploy/kubernetes/ in the tests (kubectl kustomize): Debian's, unless a kubectl
# is already installed (Debian's package would clash with it).
if ! command -v kubectl >/dev/null 2>&1; then missing+=(kubernetes-client); fi
# Node.js with npm: any recent node >= 18 will do; Debian's packages are the fallback.
if ! command -v npm >/dev/null 2>&1; then missing+=(nodejs npm); fi

if [ ${#missing[@]} -gt 0 ]; then
  echo "install-deps: installing ${missing[*]}"
  sudo_cmd=""
  [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo_cmd apt-get update -q
  $sudo_cmd apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

# Front-end toolchain and browser-test driver, pinned by web/package-lock.json.
if [ -f "$root/web/package.json" ]; then
  if [ ! -d "$root/web/node_modules" ] || [ "$root/web/package-lock.json" -nt "$root/web/node_modules/.package-lock.json" ]; then
    echo "install-deps: npm ci in web/"
    (cd "$root/web" && npm ci --no-audit --no-fund)
  fi
fi
