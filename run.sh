#!/usr/bin/env bash
# activecal's one entry point on a fresh Debian machine.
#
#   ./run.sh paper [flags]   install what is missing, build, run activecal_puma_paper
#   ./run.sh test            install what is missing, build, run the whole test suite
#   ./run.sh plots [flags]   run activecal_puma_paper into paper_out/, then draw
#                            its figures with gnuplot into paper_out/plots/
#   ./run.sh build           install what is missing and build only
#   ./run.sh <program> [flags]  build, then run build/apps/<program>
#
# Environment: BUILD_DIR (default build), JOBS (default nproc).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
cd "$here"
build_dir="${BUILD_DIR:-build}"
jobs="${JOBS:-$(nproc)}"

packages=(build-essential cmake libceres-dev libeigen3-dev libgoogle-glog-dev
          libgflags-dev libgtest-dev libbenchmark-dev nlohmann-json3-dev
          libyaml-cpp-dev gnuplot-nox)

install_missing() {
  local missing=()
  for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "run.sh: installing missing Debian packages: ${missing[*]}" >&2
  local sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
}

build() {
  install_missing
  cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$build_dir" -j "$jobs" >&2
}

cmd="${1:-paper}"
[ $# -gt 0 ] && shift
case "$cmd" in
  build) build ;;
  test)
    build
    ctest --test-dir "$build_dir" --output-on-failure -j "$jobs" "$@" ;;
  paper)
    build
    exec "$build_dir/apps/activecal_puma_paper" "$@" ;;
  plots)
    build
    "$build_dir/apps/activecal_puma_paper" --out_dir=paper_out "$@" >/dev/null
    exec scripts/plot_paper.sh paper_out ;;
  *)
    build
    exec "$build_dir/apps/$cmd" "$@" ;;
esac
