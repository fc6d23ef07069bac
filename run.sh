#!/usr/bin/env bash
# raybench's two commands (see README.md):
#   ./run.sh report   install what is missing, build the release preset, run `raybench report`
#   ./run.sh test     install what is missing, build the test executables (target rb_tests) of the
#                     `exact` and `debug` (ASan+UBSan) presets, run the whole test suite in both
# Other targets: ./run.sh setup (packages only), ./run.sh build PRESET.
set -euo pipefail
cd "$(dirname "$0")"

# Debian 12 packages the build, tests and report need.
PACKAGES=(g++ cmake ninja-build git pkg-config
          libxsimd-dev xtl-dev libtbb-dev libbenchmark-dev libbenchmark-tools
          googletest libgtest-dev libcli11-dev nlohmann-json3-dev libfmt-dev
          libtinyobjloader-dev libgmp-dev libmpfr-dev libembree-dev
          python3-matplotlib)

setup() {
  local missing=()
  for p in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if [ ${#missing[@]} -eq 0 ]; then
    echo "[setup] all ${#PACKAGES[@]} Debian packages present"
    return
  fi
  echo "[setup] installing missing Debian packages: ${missing[*]}"
  if [ "$(id -u)" -ne 0 ]; then
    echo "error: packages missing (${missing[*]}) and this is not root." >&2
    echo "       run as root, or: sudo apt-get install ${missing[*]}" >&2
    exit 1
  fi
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}

build() {
  local preset=$1
  shift
  echo "[build] preset $preset"
  cmake --preset "$preset" >/dev/null
  cmake --build --preset "$preset" "$@"
}

case "${1:-}" in
  setup) setup ;;
  build) setup; build "${2:-release}" ;;
  report)
    shift
    setup
    build release --target raybench
    ./build/release/apps/raybench report --out report "$@"
    ;;
  test)
    setup
    build exact --target rb_tests
    ctest --preset exact
    build debug --target rb_tests
    ctest --preset debug
    ;;
  *)
    echo "usage: $0 report [raybench report options] | test | setup | build PRESET" >&2
    exit 2
    ;;
esac
