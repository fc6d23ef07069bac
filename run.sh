#!/usr/bin/env bash
# raybench's two commands (see README.md):
#   ./run.sh report   install what is missing, build the release preset, measure profile-guided
#                     optimisation (./run.sh pgo; not with --quick or --no-pgo), run `raybench report`
#   ./run.sh test     install what is missing, build and run the tests whose subject is optimised
#                     code in the `exact` preset (target rb_tests_optimised, label `optimised`), then
#                     build and run the whole test suite in the `debug` preset (ASan+UBSan)
# Other targets: ./run.sh setup (packages only), ./run.sh build PRESET [cmake --build options],
#               ./run.sh install-check (cmake --install into a scratch prefix, then the installed
#               `raybench report` run from another folder, its history and a comparison),
#               ./run.sh pgo [--tuned] (profile-guided optimisation alone: train, rebuild, compare;
#               fills the PGO section of report/), ./run.sh pgo-test (the test suite built with the PGO profile),
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
# `./run.sh pgo [--tuned]`, run by `./run.sh report` before the report: an instrumented build
# (pgo-gen) is trained on a workload apart from the measured one, the PGO build (pgo-use) is compiled
# with that profile, and both builds run the measured workload in paired rounds; tools/pgo.py turns
# the rounds into the report's PGO section (ratios with intervals, what the profile changed, where
# PGO loses). Builds are incremental: the training runs again only when the instrumented code or
# the training workload changed, and the PGO build recompiles everything only when the training
# workload changed (otherwise just the files whose sources changed: the others keep a profile of the
# same code). --tuned adds a build trained on the measured workload itself (how much a profile of
# the very benchmark flatters). Training: other benchmark data (seed 7) and other scenes (SPD tetra,
# mount, teapot, the lecture's glass balls) with another ray seed; tetra at level 7 (65,536
# triangles) has leaves with fewer than 8 triangles, so the mesh packet path that handles them runs
# in training too.
PGO_OUT=build/pgo-results
PGO_PROFILES=build/pgo-profiles
PGO_TRACE_SCENES=(data/meshes/stanford-bunny.obj data/meshes/dragon_vrip_res3_bin.ply spd:balls:3)
PGO_TRAIN_SCENES=(spd:tetra:7 spd:mount:4 spd:teapot:4 lecture:five_glass_balls)
PGO_RAY_SETS=(primary shadow diffuse random)
PGO_PACKETS=(1 8)
PGO_ROUNDS=12
PGO_BENCH_FILTER='/(scalar|rays_in_lanes)/half$|^wide_node_slab/(fast|robust)/'
PGO_BENCH_MIN_TIME=0.04
PGO_TRACE_MIN_TIME=0.05
PGO_TRACE_REPS=3
PGO_TRACE_COUNT=131072
PGO_HONEST="raybench bench --seed 7 (other rays and primitives; every benchmark once for 0.01 s); traces of ${PGO_TRAIN_SCENES[*]} (${PGO_RAY_SETS[*]} rays, packets of ${PGO_PACKETS[*]}) with ray seed 7, 131072 rays"
PGO_TUNED="the measured workload itself: raybench bench on the default data (every benchmark once for 0.05 s); traces of ${PGO_TRACE_SCENES[*]} with ray seed 1, ${PGO_TRACE_COUNT} rays"
PGO_MEASURED="raybench bench --filter '${PGO_BENCH_FILTER}' (every kernel's scalar and 8-lane rays-in-lanes forms on rays that half hit, and the 8-wide node test; the 16-lane files are compiled without the profile) on the default data; traces of ${PGO_TRACE_SCENES[*]}: ${PGO_RAY_SETS[*]} rays, packets of ${PGO_PACKETS[*]}, ray seed 1, ${PGO_TRACE_COUNT} rays, 1 thread"

pgo_tag() {  # scene, ray set, packet -> a file name part
  echo "$1-$2-$3" | tr '/:.' '___'
}

pgo_trace() {  # binary, JSON file, seed, count, min time, repetitions, scene, ray set, packet; on CPU $PGO_CPU if set
  local pin=()
  [ -n "${PGO_CPU:-}" ] && pin=(taskset -c "$PGO_CPU")
  "${pin[@]}" "$1" trace "$7" --rays "$8" --packet "$9" --threads 1 --seed "$3" --count "$4" --min-time "$5" \
    -r "$6" --brute 0 --no-embree --json "$2" >/dev/null 2>&1 ||
    echo "[pgo] warning: trace $7 $8 K=$9 failed with $1" >&2
}

pgo_train() {  # profile name (honest | tuned); trains only when the instrumented code or the workload changed
  local name=$1 gen=build/pgo-gen/apps/raybench words
  [ -x "$gen" ] || { echo "error: no instrumented binary ($gen)" >&2; return 1; }
  [ "$name" = honest ] && words=$PGO_HONEST || words=$PGO_TUNED
  local want_bin want_work have=""
  # The code (.text), not the whole binary: every commit changes the revision the binary records
  # (a string in .rodata), which changes no count of the training.
  want_bin=$( (objcopy --dump-section .text=/dev/stdout "$gen" /dev/null 2>/dev/null || cat "$gen") | sha256sum | cut -c1-16)
  want_work=$(echo "$words" | sha256sum | cut -c1-16)
  [ -f "$PGO_PROFILES/$name.stamp" ] && have=$(cat "$PGO_PROFILES/$name.stamp")
  if [ -d "$PGO_PROFILES/$name" ] && [ "$have" = "$want_bin $want_work" ]; then
    echo "[pgo] the $name profile is up to date (same instrumented code, same training)"
    return
  fi
  # A new training workload invalidates every object compiled with the old profile.
  if [ "${have#* }" != "$want_work" ]; then
    local dir=build/pgo-use
    [ "$name" = tuned ] && dir=build/pgo-tuned
    [ -d "$dir" ] && cmake --build "$dir" --target clean >/dev/null 2>&1 || true
  fi
  rm -rf "$PGO_PROFILES/raw" "$PGO_PROFILES/$name"
  mkdir -p "$PGO_PROFILES"
  echo "[pgo] training the $name profile"
  local t0=$SECONDS
  local scenes=("${PGO_TRAIN_SCENES[@]}") seed=7 count=131072 min=0.01 scene rays k
  if [ "$name" = tuned ]; then
    scenes=("${PGO_TRACE_SCENES[@]}") seed=1 count=$PGO_TRACE_COUNT min=0.05
    "$gen" bench --repetitions 1 --min-time "$min" --json "$PGO_PROFILES/train-bench.json" >/dev/null 2>&1
  else
    "$gen" bench --seed 7 --repetitions 1 --min-time "$min" --json "$PGO_PROFILES/train-bench.json" >/dev/null 2>&1
  fi
  for scene in "${scenes[@]}"; do
    for rays in "${PGO_RAY_SETS[@]}"; do
      for k in "${PGO_PACKETS[@]}"; do
        pgo_trace "$gen" "$PGO_PROFILES/train-trace.json" "$seed" "$count" 0 1 "$scene" "$rays" "$k"
      done
    done
  done
  mv "$PGO_PROFILES/raw" "$PGO_PROFILES/$name"
  echo "$want_bin $want_work" >"$PGO_PROFILES/$name.stamp"
  echo "[pgo] $name profile: $(find "$PGO_PROFILES/$name" -name '*.gcda' | wc -l) .gcda files, trained in $((SECONDS - t0)) s"
}

pgo_build() {  # preset: builds raybench, and says how many files it compiled in how long
  local n log t0=$SECONDS
  echo "[pgo] building raybench in $1"
  cmake --preset "$1" >/dev/null
  log=$(mktemp /tmp/raybench-pgo-build.XXXXXX)
  if ! cmake --build --preset "$1" --target raybench >"$log" 2>&1; then
    tail -40 "$log" >&2
    rm -f "$log"
    echo "error: the $1 build failed (above)" >&2
    return 1
  fi
  n=$(grep -c 'Building CXX' "$log" || true)
  PGO_BUILT+=("$1 $n")
  echo "[pgo] $1: $n files compiled in $((SECONDS - t0)) s"
  n=$(grep -c 'Wmissing-profile' "$log" || true)
  [ "$n" -gt 0 ] && echo "[pgo] $1: $n functions compiled without a profile (never run in training)"
  rm -f "$log"
}

pgo() {
  setup
  local t0=$SECONDS tuned=0
  [ "${1:-}" = --tuned ] && tuned=1
  PGO_BUILT=()
  build release --target raybench || return 1
  pgo_build pgo-gen || return 1
  pgo_train honest || return 1
  pgo_build pgo-use || return 1
  local builds=(normal pgo)
  declare -A bins=([normal]=build/release/apps/raybench [pgo]=build/pgo-use/apps/raybench [tuned]=build/pgo-tuned/apps/raybench)
  if [ $tuned = 1 ]; then
    pgo_train tuned || return 1
    pgo_build pgo-tuned || return 1
    builds+=(tuned)
  fi
  # Paired rounds: in each, every build runs the workload once, back to back, the builds' order
  # rotated from round to round; the 1-minute load average after each round goes to load.txt.
  local n=${#builds[@]} round i b
  rm -rf "$PGO_OUT"
  for b in "${builds[@]}"; do mkdir -p "$PGO_OUT/$b"; done
  # The kernel benchmarks one at a time, one process each (a process starts in about 15 ms), so that
  # the two builds' runs of a benchmark lie a tenth of a second apart: this machine's speed moves by
  # up to a third over seconds, which pairs a family or a whole selection apart did not cancel.
  # Both builds' runs of a pair on one CPU (taskset; one of those this process may use), the CPU
  # changing from pair to pair: the guest's CPUs differ in speed from minute to minute (one ran
  # traces a third slower than the other for a few minutes while the machine was otherwise idle),
  # and new processes land on either.
  local names name r=0 t1=$SECONDS cpus ncpu
  mapfile -t cpus < <(/usr/bin/python3 -c 'import os; print(*sorted(os.sched_getaffinity(0)), sep="\n")')
  ncpu=${#cpus[@]}
  names=$("${bins[normal]}" bench --list --filter "$PGO_BENCH_FILTER")
  for round in $(seq 1 $PGO_ROUNDS); do
    echo "[pgo] kernel benchmarks, round $round of $PGO_ROUNDS"
    for name in $names; do
      r=$((r + 1))
      for i in $(seq 0 $((n - 1))); do
        b=${builds[$(( (i + round + r) % n ))]}
        taskset -c "${cpus[$(( (round + r) % ncpu ))]}" "${bins[$b]}" bench --filter "^$name\$" -r 1 --min-time $PGO_BENCH_MIN_TIME \
          --json "$PGO_OUT/$b/bench-$(echo "$name" | tr '/' '_')-r$round.json" >/dev/null 2>&1 ||
          echo "[pgo] warning: bench $name failed with ${bins[$b]}" >&2
      done
    done
    echo "bench-$round $(cut -d' ' -f1 /proc/loadavg)" >>"$PGO_OUT/load.txt"
  done
  local rows=$(( ${#PGO_TRACE_SCENES[@]} * ${#PGO_RAY_SETS[@]} * ${#PGO_PACKETS[@]} )) row=0 scene rays k tag
  for scene in "${PGO_TRACE_SCENES[@]}"; do
    for rays in "${PGO_RAY_SETS[@]}"; do
      for k in "${PGO_PACKETS[@]}"; do
        row=$((row + 1))
        echo "[pgo] traces $row of $rows: $scene, $rays rays, packets of $k ($PGO_ROUNDS rounds)"
        tag=$(pgo_tag "$scene" "$rays" "$k")
        for round in $(seq 1 $PGO_ROUNDS); do
          for i in $(seq 0 $((n - 1))); do
            b=${builds[$(( (i + round + row) % n ))]}
            PGO_CPU=${cpus[$(( (round + row) % ncpu ))]} pgo_trace "${bins[$b]}" "$PGO_OUT/$b/trace-$tag-r$round.json" 1 $PGO_TRACE_COUNT $PGO_TRACE_MIN_TIME \
              $PGO_TRACE_REPS "$scene" "$rays" "$k"
          done
        done
      done
    done
    echo "trace-$scene $(cut -d' ' -f1 /proc/loadavg)" >>"$PGO_OUT/load.txt"
  done
  echo "[pgo] measured in $((SECONDS - t1)) s"
  local extra=()
  [ $tuned = 1 ] && extra=(--tuned "$PGO_TUNED")
  /usr/bin/python3 tools/pgo.py "$PGO_OUT" "${PGO_REPORT_DIR:-report}" --honest "$PGO_HONEST" "${extra[@]}" \
    --measured "$PGO_MEASURED" --builds "files compiled: $(printf '%s, ' "${PGO_BUILT[@]}" | sed 's/, $//')" \
    --rounds $PGO_ROUNDS --bench-min-time $PGO_BENCH_MIN_TIME --trace-min-time $PGO_TRACE_MIN_TIME --trace-reps $PGO_TRACE_REPS \
    --binary normal=build/release/apps/raybench --binary pgo=build/pgo-use/apps/raybench \
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
  build) shift; setup; build "${1:-release}" "${@:2}" ;;
  report)
    shift
    setup
    build release --target raybench
    # Profile-guided optimisation first (its own builds and paired rounds; section "Profile-guided
    # optimisation"), unless --no-pgo or a --quick report; the report folder may be named by --out.
    out=report pgo_on=1 args=() want_out=0
    for a in "$@"; do
      if [ $want_out = 1 ]; then out=$a; want_out=0; continue; fi
      case "$a" in
        --no-pgo) pgo_on=0; continue ;;
        --quick) pgo_on=0 ;;
        --out=*) out=${a#--out=}; continue ;;
        -o | --out) want_out=1; continue ;;
      esac
      args+=("$a")
    done
    if [ $pgo_on = 1 ]; then
      mkdir -p "$out"
      rm -f "$out/pgo.md"
      PGO_REPORT_DIR=$out pgo || echo "[pgo] failed (above): the report's PGO section says it was not measured" >&2
    fi
    ./build/release/apps/raybench report --out "$out" "${args[@]}"
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
  pgo) shift; pgo "$@" ;;
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
    echo "usage: $0 report [--no-pgo] [raybench report options] | test | setup | build PRESET | pgo [--tuned] | pgo-test | install-check | report-check [DIR] | tsan | fuzz [RUNS [SEED]]" >&2
    exit 2
    ;;
esac
