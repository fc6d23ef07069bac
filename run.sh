#!/usr/bin/env bash
# raybench's two commands (see README.md):
#   ./run.sh report   install what is missing, build the release preset, run `raybench report`
#   ./run.sh test     install what is missing, build and run the tests whose subject is optimised
#                     code in the `exact` preset (target rb_tests_optimised, label `optimised`), then
#                     build and run the whole test suite in the `debug` preset (ASan+UBSan)
# Other targets: ./run.sh setup (packages only), ./run.sh build PRESET,
#               ./run.sh install-check (cmake --install into a scratch prefix, then the installed
#               `raybench report` run from another folder, its history and a comparison),
#               ./run.sh pgo (profile-guided optimisation: train, rebuild, compare; fills the report's
#               PGO section), ./run.sh pgo-test (the test suite built with the PGO profile),
#               ./run.sh tsan (the threaded tests, label `threads`, under ThreadSanitizer),
#               ./run.sh fuzz [RUNS [SEED]] (seeded mutations of every scene format through info, trace
#               and render under ASan+UBSan; fuzz/scene_fuzz.cpp).
#               ./run.sh report-check [DIR] (installs Debian chromium, opens DIR/index.html headless:
#               fails on a broken image or link or a console error, writes DIR/screenshot.png).
set -euo pipefail
cd "$(dirname "$0")"

# Debian 12 packages the build, tests and report need.
PACKAGES=(g++ cmake ninja-build git pkg-config
          libxsimd-dev xtl-dev libtbb-dev libbenchmark-dev libbenchmark-tools
          googletest libgtest-dev libcli11-dev nlohmann-json3-dev libfmt-dev
          libtinyobjloader-dev libgmp-dev libmpfr-dev libembree-dev
          python3-matplotlib python3-scipy
          libstb-dev openmpi-bin libopenmpi-dev lld libsqlite3-dev)

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


# ---- profile-guided optimisation ---------------------------------------------------------------
# The measured workload is the report's: every kernel benchmark on the default data, and traces of
# the bunny, the dragon and SPD balls. The honest profile is trained on other data (benchmark seed
# 7, shorter runs) and other scenes (SPD tetra, mount, teapot, lecture glass balls) with another
# ray seed and count; the tuned profile is trained on the measured workload itself, to show how
# much a profile of the very benchmark flatters. Tetra at level 7 (65,536 triangles) has leaves
# with fewer than 8 triangles, so the mesh packet path that handles them runs in training too.
PGO_OUT=build/pgo-results
PGO_TRACE_SCENES=(data/meshes/stanford-bunny.obj data/meshes/dragon_vrip_res3_bin.ply spd:balls:3)
PGO_TRAIN_SCENES=(spd:tetra:7 spd:mount:4 spd:teapot:4 lecture:five_glass_balls)
PGO_RAY_SETS=(primary shadow diffuse random)
PGO_PACKETS=(1 8)

pgo_tag() {  # scene, ray set, packet -> a file name part
  echo "$1-$2-$3" | tr '/:.' '___'
}

pgo_trace() {  # binary, JSON file, seed, count, repetitions, scene, ray set, packet
  "$1" trace "$6" --rays "$7" --packet "$8" --threads 1 --seed "$3" --count "$4" \
    -r "$5" --brute 0 --no-embree --json "$2" >/dev/null 2>&1 ||
    echo "[pgo] warning: trace $6 $7 K=$8 failed with $1" >&2
}

pgo_traces() {  # binary, out dir, seed, count, repetitions, scenes...
  local bin=$1 dir=$2 seed=$3 count=$4 reps=$5
  shift 5
  mkdir -p "$dir"
  for scene in "$@"; do
    for rays in "${PGO_RAY_SETS[@]}"; do
      for k in "${PGO_PACKETS[@]}"; do
        pgo_trace "$bin" "$dir/trace-$(pgo_tag "$scene" "$rays" "$k").json" "$seed" "$count" "$reps" "$scene" "$rays" "$k"
      done
    done
  done
}

pgo_train() {  # name of the profile: honest | tuned
  local name=$1 gen=build/pgo-gen/apps/raybench prof=build/pgo-profiles
  rm -rf "$prof/raw" "$prof/$name"
  mkdir -p "$prof"
  echo "[pgo] training the $name profile"
  if [ "$name" = honest ]; then
    "$gen" bench --seed 7 --repetitions 1 --min-time 0.01 --json "$prof/train-bench.json" >/dev/null
    pgo_traces "$gen" "$prof/train-trace" 7 131072 1 "${PGO_TRAIN_SCENES[@]}"
  else
    "$gen" bench --repetitions 1 --min-time 0.05 --json "$prof/train-bench.json" >/dev/null
    pgo_traces "$gen" "$prof/train-trace" 1 524288 1 "${PGO_TRACE_SCENES[@]}"
  fi
  mv "$prof/raw" "$prof/$name"
  echo "[pgo] $name profile: $(find "$prof/$name" -name '*.gcda' | wc -l) .gcda files"
}

pgo() {
  setup
  local t0=$SECONDS
  build release --target raybench
  build pgo-gen --target raybench
  pgo_train honest
  pgo_train tuned
  build pgo-use --target raybench 2>&1 | grep -E 'missing-profile|error' || true
  build pgo-tuned --target raybench 2>&1 | grep -E 'missing-profile|error' || true
  rm -rf "$PGO_OUT"
  declare -A bins=([normal]=build/release/apps/raybench [pgo]=build/pgo-use/apps/raybench [tuned]=build/pgo-tuned/apps/raybench)
  # Back to back: three rounds of 2 repetitions per build, the build order rotated each round, then
  # the traces in rounds the same way (below).
  # The 1-minute load average after each run goes to load.txt: the report says whether the machine
  # was idle while it ran (read before a run, it would still show the build that preceded it).
  local order=(normal pgo tuned) i
  mkdir -p "$PGO_OUT"
  for round in 1 2 3; do
    for i in 0 1 2; do
      local b=${order[$(( (i + round - 1) % 3 ))]}
      echo "[pgo] kernel benchmarks, round $round of 3: $b build"
      mkdir -p "$PGO_OUT/$b"
      "${bins[$b]}" bench --repetitions 2 --min-time 0.05 --json "$PGO_OUT/$b/bench-$round.json" >/dev/null
      echo "bench-$round-$b $(cut -d' ' -f1 /proc/loadavg)" >>"$PGO_OUT/load.txt"
    done
  done
  # The traces: for each scene, ray set and packet size, five rounds of 2 repetitions per build, the
  # three builds back to back in each round and their order rotated (a trace's ratio is the median
  # of its per-round ratios, as for the kernels: a load change between builds moves one round).
  local s=0 scene rays k round tag
  for scene in "${PGO_TRACE_SCENES[@]}"; do
    echo "[pgo] traces: $scene"
    for rays in "${PGO_RAY_SETS[@]}"; do
      for k in "${PGO_PACKETS[@]}"; do
        tag=$(pgo_tag "$scene" "$rays" "$k")
        for round in 1 2 3 4 5; do
          for i in 0 1 2; do
            local b=${order[$(( (i + s + round) % 3 ))]}
            mkdir -p "$PGO_OUT/$b"
            pgo_trace "${bins[$b]}" "$PGO_OUT/$b/trace-$tag-r$round.json" 1 524288 2 "$scene" "$rays" "$k"
          done
        done
        s=$((s + 1))
      done
    done
    echo "trace-$scene $(cut -d' ' -f1 /proc/loadavg)" >>"$PGO_OUT/load.txt"
  done
  /usr/bin/python3 tools/pgo.py "$PGO_OUT" report \
    --honest "bench --seed 7 (other rays and primitives, 1 repetition of 0.01 s); traces of ${PGO_TRAIN_SCENES[*]} with ray seed 7, 131072 rays" \
    --tuned "the measured workload itself: bench on the default data; traces of ${PGO_TRACE_SCENES[*]} with ray seed 1, 524288 rays" \
    --minutes $(( (SECONDS - t0 + 59) / 60 ))
}

# ---- the report in a browser -------------------------------------------------------------------
# Debian's chromium, headless, opens REPORT/index.html from disk: every image and link must resolve
# beside the page (checked first, in Python), the page must log no console message (the page's own
# script logs every image that did not decode as a console error; a script error is one too), and
# a screenshot of the page's first 1280 x 2400 pixels is written beside it (screenshot.png).
report_check() {
  local dir=${1:-report}
  [ -f "$dir/index.html" ] || { echo "error: $dir/index.html not found: run ./run.sh report (or ./run.sh report --quick) first" >&2; exit 1; }
  if ! command -v chromium >/dev/null; then
    [ "$(id -u)" -eq 0 ] || { echo "error: Debian package chromium missing and this is not root: sudo apt-get install chromium" >&2; exit 1; }
    echo "[report-check] installing the Debian package chromium"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq --no-install-recommends chromium >/dev/null
  fi
  local page log
  page=$(realpath "$dir/index.html")
  log=$(mktemp /tmp/raybench-report-check.XXXXXX)
  /usr/bin/python3 - "$page" <<'PY'
import html.parser, os, sys
page = sys.argv[1]
base = os.path.dirname(page)
refs, ids = [], set()
class P(html.parser.HTMLParser):
    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if "id" in a: ids.add(a["id"])
        for k in ("src", "href"):
            if k in a: refs.append((tag, k, a[k] or ""))
P().feed(open(page, encoding="utf-8").read())
bad = []
for tag, k, v in refs:
    if "://" in v or v.startswith("//"): bad.append(f"<{tag} {k}={v}>: a network address")
    elif v.startswith("#"):
        if v[1:] not in ids: bad.append(f"<{tag} {k}={v}>: no element with this id")
    elif not os.path.isfile(os.path.join(base, v.split("#")[0])): bad.append(f"<{tag} {k}={v}>: no such file beside the page")
for b in bad: print("[report-check] broken:", b, file=sys.stderr)
print(f"[report-check] {len(refs)} images and links, {len(bad)} broken")
sys.exit(1 if bad else 0)
PY
  chromium --headless --no-sandbox --disable-gpu --hide-scrollbars --enable-logging=stderr --v=0 \
    --window-size=1280,2400 --virtual-time-budget=10000 --screenshot="$(dirname "$page")/screenshot.png" \
    "file://$page" >"$log" 2>&1 || { cat "$log" >&2; echo "[report-check] chromium failed" >&2; exit 1; }
  if grep -q 'CONSOLE' "$log"; then
    grep 'CONSOLE' "$log" >&2
    echo "[report-check] the page logged console messages (above): a broken image or a script error" >&2
    exit 1
  fi
  [ -s "$dir/screenshot.png" ] || { echo "[report-check] no screenshot written" >&2; exit 1; }
  echo "[report-check] ok: $page opened in $(chromium --version | head -1), no console message; screenshot: $dir/screenshot.png"
  rm -f "$log"
}

# ---- the installed binary -----------------------------------------------------------------------
# cmake --install into a scratch prefix, then from another folder: the installed `raybench report`
# (it finds its chart scripts and meshes in PREFIX/share/raybench), the run in its default history
# (results/history.sqlite of that folder), and the report compared with itself.
install_check() {
  setup
  build release --target raybench
  local prefix work
  prefix=$(mktemp -d /tmp/raybench-prefix.XXXXXX)
  work=$(mktemp -d /tmp/raybench-work.XXXXXX)
  cmake --install build/release --prefix "$prefix" >/dev/null
  echo "[install-check] installed into $prefix; running from $work"
  (
    cd "$work"
    export PATH="$prefix/bin:$PATH"
    raybench --version | tail -1
    raybench report --out report "$@" 2>&1 | tee report.log
    grep -q '^\[report 9/9, ' report.log || { echo "[install-check] the report's stages were not numbered" >&2; exit 1; }
    for f in report/index.md report/index.html report/summary.json report/bench.json report/simd_speedup.png results/history.sqlite; do
      [ -s "$f" ] || { echo "[install-check] missing: $work/$f" >&2; exit 1; }
    done
    raybench history >history.txt
    head -4 history.txt
    raybench compare report report --threshold 5 >/dev/null
  )
  echo "[install-check] ok: the installed raybench ran its report from $work"
  rm -rf "$prefix" "$work"
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
    # Optimised (-O3, contraction off except in the release-robustness file): the tests whose
    # subject is optimised code. Then every test under ASan+UBSan at -O0 (docs/DESIGN.md section 14).
    build exact --target rb_tests_optimised
    ctest --preset exact -L optimised
    build debug --target rb_tests
    ctest --preset debug
    ;;
  pgo) pgo ;;
  tsan)
    setup
    # The threaded tests (parallel build, tracer and renderer tiles at 1..256 threads, FTZ/DAZ of
    # the workers) under ThreadSanitizer, and a deliberate race that must be reported.
    build tsan --target rb_tests_threads
    ctest --preset tsan
    ;;
  fuzz)
    shift
    setup
    build debug --target raybench_fuzz
    mkdir -p build/fuzz
    ./build/debug/fuzz/raybench_fuzz --runs "${1:-1000}" --seed "${2:-1}" --keep build/fuzz/failures --json build/fuzz/fuzz.json
    ;;
  install-check) shift; install_check "$@" ;;
  report-check) shift; report_check "$@" ;;
  pgo-test)
    setup
    [ -d build/pgo-profiles/honest ] || { echo "error: no profile yet: run ./run.sh pgo first" >&2; exit 1; }
    build pgo-use --target rb_tests
    ctest --preset pgo-use
    ;;
  *)
    echo "usage: $0 report [raybench report options] | test | setup | build PRESET | pgo | pgo-test | install-check | report-check [DIR] | tsan | fuzz [RUNS [SEED]]" >&2
    exit 2
    ;;
esac
