#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# activecal's one entry point on a fresh Debian machine.
#
#   ./run.sh paper [flags]   install what is missing, build, run activecal_puma_paper
#   ./run.sh test            install what is missing, then everything CI checks:
#                            the test suite (Release, the Python module's
#                            pytest suite included), the GoogleTest suite
#                            built with AddressSanitizer + UBSan, and the fuzzers
#   ./run.sh unit            the Release test suite only (quick)
#   ./run.sh sanitize        the ASan + UBSan GoogleTest suite only
#                            (build-sanitize/, clang)
#   ./run.sh fuzz [seconds]  the libFuzzer targets (build-sanitize/, clang)
#   ./run.sh plots [flags]   run activecal_puma_paper into paper_out/, then draw
#                            its figures with gnuplot into paper_out/plots/
#   ./run.sh build           install what is missing and build only
#   ./run.sh python          build the Python module only, into build/python/
#                            (PYTHONPATH=build/python python3 -c "import activecal")
#   ./run.sh <program> [flags]  build, then run build/apps/<program>
#   ./run.sh --help, -h      this text (a program's flags: ./run.sh <program> --help)
#
# Environment: BUILD_DIR (default build), JOBS (default nproc).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
cd "$here"
build_dir="${BUILD_DIR:-build}"
jobs="${JOBS:-$(nproc)}"

packages=(build-essential cmake libceres-dev libeigen3-dev libgoogle-glog-dev
          libgflags-dev libgtest-dev libbenchmark-dev nlohmann-json3-dev
          libyaml-cpp-dev liburdfdom-dev liborocos-kdl-dev libkdl-parser-dev
          libboost-dev gnuplot-nox clang libclang-rt-dev
          pybind11-dev python3-dev python3-numpy python3-pytest
          libfcl-dev libassimp-dev libtinyxml2-dev
          python3-venv python3-build python3-pandas python3-yaml chromium)

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

# The Python module is built for Debian's interpreter, the one the packages
# above (python3-numpy, python3-pytest) are for, even when another python3
# (pyenv, a virtualenv) comes first on PATH.
python_flags=()
[ -x /usr/bin/python3 ] && python_flags=(-DPython3_EXECUTABLE=/usr/bin/python3)

configure() {
  install_missing
  cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release "${python_flags[@]}" >/dev/null
}

# The build's output without the lines of targets already up to date: a run
# with nothing to rebuild prints nothing about the build.
build_quietly() {
  cmake --build "$1" -j "$jobs" 2>&1 |
    { grep -vE '^\[ *[0-9]+%\] Built target |^gmake(\[[0-9]+\])?: (Entering|Leaving) directory' || true; } >&2
}

build() {
  configure
  build_quietly "$build_dir"
}

# The sanitizer tree (build-sanitize/): clang, AddressSanitizer +
# UndefinedBehaviorSanitizer on every library, the GoogleTest suite and the
# libFuzzer targets, so one instrumented build serves both. The programs,
# their command-line tests, the Python module, the benchmarks and the install
# check are left to the Release build: they are thin over the libraries the
# gtests run here, and the file parsers they read through are fuzzed here.
# -O1 -g1: quick to compile, stacks still readable; assertions (Eigen's
# bounds checks included) stay on.
sanitize_dir="${SANITIZE_BUILD_DIR:-build-sanitize}"
configure_sanitize() {
  install_missing
  CC=clang CXX=clang++ cmake -S . -B "$sanitize_dir" -DCMAKE_BUILD_TYPE=None \
    -DCMAKE_CXX_FLAGS="-O1 -g1" -DACTIVECAL_SANITIZE=ON \
    -DACTIVECAL_BUILD_FUZZERS=ON -DACTIVECAL_BUILD_APPS=OFF \
    -DACTIVECAL_BUILD_BENCHMARKS=OFF -DACTIVECAL_INSTALL=OFF >/dev/null
}

sanitize() {
  configure_sanitize
  build_quietly "$sanitize_dir"
  # Left to the Release run: the gtests that repeat one numeric path many
  # times (cross-validation curves, Monte Carlo sweeps, rounding sweeps, a
  # 90-pose compensation loop, keep/drop sweeps of the learned residual and
  # of the accuracy terms, selections run twice to compare them). Under the
  # sanitizers each took 28-56 s (measured in build-sanitize/, 2 cores)
  # while a lighter test of each subject runs the same code here:
  # ModelSelectionTest.CountsThatCouldNotBeTestedAreNamed,
  # FedorovFloatTest.SameResultForAnyThreadCount, the other TaskCriterion,
  # SelectDesignPool, DesignAlgorithms, Compensation, MonteCarlo and
  # LearnedResidual tests.
  local heavy=(ModelSelectionTest.CrossValidationKeepsTheMinimumOfItsCurve
    ModelSelectionTest.EachRuleChoosesByItsThreshold
    ModelSelectionTest.ValidationFileAndNoneAndTooFewPoses
    IdentifiabilityTest.RoundedRobotFilesKeepTheSameParametersAndConverge
    SelectDesignPoolTest.TaskCriterionDispatchesToTaskExchange
    SelectDesignPoolTest.TargetAndFailures
    SelectionTest.DeterminantAndEigenvalueCriteriaPickTheSamePoses
    FedorovFloatTest.FloatPoolAlwaysRunsOnSubPools
    TaskCriterionTest.ReducedPoolExchangeIsPolishedToAFullPoolOptimum
    DesignAlgorithmsTest.FedorovKeepsFixedPosesOfTheApproximateSupport
    MonteCarloTest.EmpiricalCovarianceMatchesPrediction
    MonteCarloTest.SameResultForAnyThreadCount
    CompensationTest.PumaLoopReachesThePredictedAccuracy
    TermSelection.KeepsATermExactlyWhenItIsThere
    LearnedResidual.KeptExactlyWhenASmoothNonGeometricErrorIsThere)
  local skip
  skip="^($(IFS='|'; echo "${heavy[*]}"))\$"
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --test-dir "$sanitize_dir" --output-on-failure -j "$jobs" -E "$skip"
}

usage() {
  # The header comment above: the commands.
  sed -n '4,/^set -euo/p' "$here/run.sh" | sed '$d' | sed 's/^# \{0,1\}//'
}

cmd="${1:-paper}"
[ $# -gt 0 ] && shift
case "$cmd" in
  -h|--help|help) usage ;;
  build) build ;;
  python)
    configure
    cmake --build "$build_dir" -j "$jobs" --target activecal_python >&2
    echo "run.sh: built $(ls "$build_dir"/python/activecal*.so); try:" >&2
    echo "  PYTHONPATH=$build_dir/python python3 -c \"import activecal\"" >&2 ;;
  unit)
    build
    ctest --test-dir "$build_dir" --output-on-failure -j "$jobs" "$@" ;;
  sanitize)
    sanitize ;;
  fuzz)
    configure_sanitize
    FUZZ_BUILD_DIR="$sanitize_dir" tests/fuzz/run.sh "${1:-30}" ;;
  test)
    build
    ctest --test-dir "$build_dir" --output-on-failure -j "$jobs" "$@"
    sanitize
    FUZZ_BUILD_DIR="$sanitize_dir" tests/fuzz/run.sh "${FUZZ_SECONDS:-15}" ;;
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
