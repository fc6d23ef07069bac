#!/usr/bin/python3
"""The report's profile-guided optimisation section, from the runs of `./run.sh pgo`.

Usage: /usr/bin/python3 tools/pgo.py RESULTS OUT --honest TEXT [--tuned TEXT] [--minutes N]
                                     [--builds TEXT] [--binary BUILD=PATH ...] [--perf-rows N]

RESULTS holds one folder per build (normal, pgo and, when measured, tuned). Each has one kernel
benchmark JSON per benchmark and round (bench-NAME-rN.json: `raybench bench -r 1 --json`, Google
Benchmark) and one JSON per trace row and round (trace-TAG-rN.json: `raybench trace --json`); in
round N the builds ran each benchmark and each trace row back to back, their order alternating.
load.txt holds the load average after each round.

Every ratio is PGO over normal (above 1: the PGO build is faster): the median over the rounds of
that round's ratio, with the distribution-free 95 % interval of a median from the sign test (the
order statistics of the rounds' ratios; the interval `raybench` gives every paired ratio). A
kernel family's ratio in a round is the geometric mean of its benchmarks' ratios in that round.

With --binary normal=PATH --binary pgo=PATH the section also says what the profile changed in the
code (per function, from `nm`), and, where `perf` works, where the time of the rows PGO slowed
went in either build.

Writes OUT/pgo.json, OUT/pgo.md and two charts, and replaces the PGO section of OUT/index.md when
that file exists.
"""
import argparse
import glob
import json
import math
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import atomic_save  # noqa: E402

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

BUILDS = ("normal", "pgo", "tuned")
OTHERS = ("pgo", "tuned")
LEVEL = 0.95
TARGET_HALF_WIDTH = 0.05  # the protocol's aim for a ratio's interval, half its width over the ratio
PERF_HZ = 2000  # samples per second of `perf record` for the rows PGO slows


def load_json(path):
    with open(path) as f:
        # Google Benchmark writes NaN / Infinity as bare tokens
        return json.loads(re.sub(r":\s*-?(NaN|nan|Infinity|inf)\b", ": null", f.read()))


def round_of(path):
    m = re.search(r"-r?(\d+)\.json$", path)
    return int(m.group(1)) if m else 0


# ---- intervals ------------------------------------------------------------------------------------

def sign_interval(ratios, level=LEVEL):
    """The median of per-round ratios and its sign-test interval: sorted ratios q, the largest k with
    P(Binomial(n, 1/2) < k) <= (1 - level) / 2, the interval [q_k, q_(n+1-k)] (1-based) with coverage
    1 - 2 P(Binomial(n, 1/2) < k); too few rounds for the level (n <= 5 at 95 %): the whole range and
    the coverage it has. The same rule as `raybench`'s paired ratios (apps/results/stats.cpp)."""
    q = sorted(x for x in ratios if x is not None and x > 0 and math.isfinite(x))
    n = len(q)
    if n == 0:
        return None
    out = {"ratio": statistics.median(q), "lo": None, "hi": None, "coverage": None, "rounds": n}
    if n < 2:
        return out
    alpha2, tail, k = (1 - level) / 2, 0.0, 0
    for j in range(n // 2):
        nxt = tail + math.comb(n, j) / 2.0 ** n  # P(X <= j) = P(X < j + 1)
        if nxt > alpha2:
            break
        tail, k = nxt, j + 1
    if k == 0:
        out.update(lo=q[0], hi=q[-1], coverage=1 - 2 / 2.0 ** n)
    else:
        out.update(lo=q[k - 1], hi=q[n - k], coverage=1 - 2 * tail)
    return out


def verdict(iv):
    """faster (the whole interval above 1), slower (below 1), or within the noise (it holds 1)."""
    if not iv or iv["lo"] is None:
        return "not measured"
    if iv["lo"] > 1:
        return "faster"
    if iv["hi"] < 1:
        return "slower"
    return "within the noise"


def half_width(iv):
    if not iv or iv["lo"] is None or not iv["ratio"]:
        return None
    return (iv["hi"] - iv["lo"]) / 2 / iv["ratio"]


def interval_text(iv):
    if not iv:
        return "-"
    if iv["lo"] is None:
        return f"{iv['ratio']:.3f} (1 round)"
    return f"{iv['ratio']:.3f} [{iv['lo']:.3f}-{iv['hi']:.3f}]"


def gmean(xs):
    xs = [x for x in xs if x and x > 0]
    return math.exp(sum(math.log(x) for x in xs) / len(xs)) if xs else None


# ---- the measurements ---------------------------------------------------------------------------

def bench_rounds(folder):
    """Benchmark name -> {round: tests/s (the median of that round's repetitions)}, and the context of
    the last file (build flags, revision)."""
    rates, context = {}, {}
    for path in sorted(glob.glob(os.path.join(folder, "bench-*.json"))):
        j = load_json(path)
        context = j.get("context", context)
        per = {}
        for b in j.get("benchmarks", []):
            if b.get("run_type") == "iteration" and b.get("tests_per_s"):
                per.setdefault(b["run_name"], []).append(b["tests_per_s"])
        for name, v in per.items():
            rates.setdefault(name, {})[round_of(path)] = statistics.median(v)
    return rates, context


def trace_rate(j):
    """Mrays/s of the run (`raybench trace --json`: rays over the median timed pass)."""
    secs, rays = j.get("seconds"), j.get("rays")
    if isinstance(secs, list) and rays:
        ok = [x for x in secs if isinstance(x, (int, float)) and x > 0]
        if ok:
            return rays / statistics.median(ok) / 1e6
    return j.get("mrays_per_s")


def trace_rounds(folder):
    """(scene, ray set, packet) -> {round: Mrays/s}."""
    out = {}
    for path in sorted(glob.glob(os.path.join(folder, "trace-*.json"))):
        j = load_json(path)
        rate = trace_rate(j)
        if rate:
            key = (j.get("scene", "?"), j.get("ray_set", "?"), int(j.get("packet", 1)))
            out.setdefault(key, {})[round_of(path)] = rate
    return out


def per_round_ratios(base, other):
    """{round: other / base} over the rounds both builds ran."""
    return {r: other[r] / base[r] for r in base if r in other and base[r] > 0 and other[r] > 0}


def compare(results):
    present = [b for b in BUILDS if os.path.isdir(os.path.join(results, b))]
    bench = {b: bench_rounds(os.path.join(results, b)) for b in present}
    tr = {b: trace_rounds(os.path.join(results, b)) for b in present}
    others = [b for b in OTHERS if b in present]
    rows = []
    for name in sorted(bench.get("normal", ({}, {}))[0]):
        base = bench["normal"][0][name]
        row = {"benchmark": name, "kernel": name.split("/")[0], "normal_median": statistics.median(base.values())}
        for b in others:
            other = bench[b][0].get(name)
            if other:
                per = per_round_ratios(base, other)
                row[b] = {"median": statistics.median(other.values()), "round_ratios": per,
                          **(sign_interval(per.values()) or {})}
        rows.append(row)
    sizes = {"all kernels": len(rows)}
    for r in rows:
        sizes[r["kernel"]] = sizes.get(r["kernel"], 0) + 1
    families = {}
    for b in others:
        by_fam = {}
        for r in rows:
            for rnd, x in r.get(b, {}).get("round_ratios", {}).items():
                by_fam.setdefault(r["kernel"], {}).setdefault(rnd, []).append(x)
                by_fam.setdefault("all kernels", {}).setdefault(rnd, []).append(x)
        for fam, per in by_fam.items():
            g = [gmean(v) for v in per.values()]
            families.setdefault(fam, {"kernel": fam, "benchmarks": sizes[fam]})
            families[fam][b] = sign_interval(g)
    trows = []
    for key in sorted(tr.get("normal", {})):
        base = tr["normal"][key]
        row = {"scene": key[0], "ray_set": key[1], "packet": key[2], "normal_mrays_per_s": statistics.median(base.values())}
        for b in others:
            other = tr[b].get(key)
            if other:
                per = per_round_ratios(base, other)
                row[b] = {"mrays_per_s": statistics.median(other.values()), "round_ratios": per,
                          **(sign_interval(per.values()) or {})}
        trows.append(row)
    context = {b: bench[b][1] for b in present}
    fam_rows = sorted((f for k, f in families.items() if k != "all kernels"), key=lambda f: f["kernel"])
    return rows, fam_rows, families.get("all kernels"), trows, context, others


def machine_load(results):
    """The 1-minute load averages `./run.sh pgo` recorded after each measured round."""
    try:
        with open(os.path.join(results, "load.txt")) as f:
            return [float(line.split()[1]) for line in f if len(line.split()) > 1]
    except (OSError, ValueError):
        return []


# ---- what the profile changed in the code ----------------------------------------------------------

def short_name(sym):
    """A demangled symbol without its argument list: the template and the clone suffix stay."""
    clone = " ".join(re.findall(r"\[clone [^\]]*\]", sym))
    depth, i = 0, 0
    while i < len(sym):
        skip = next((w for w in ("operator()", "(anonymous namespace)") if sym.startswith(w, i)), None)
        if skip:
            i += len(skip)
            continue
        c = sym[i]
        if c in "<{":
            depth += 1
        elif c in ">}":
            depth -= 1
        elif c == "(" and depth == 0 and i > 0:  # the argument list
            return (sym[:i] + " " + clone).strip()
        i += 1
    return sym


def demangle(names):
    """The demangled form of each mangled name (c++filt; the names themselves where it is missing)."""
    try:
        out = subprocess.run(["c++filt"], input="\n".join(names), capture_output=True, text=True, check=True).stdout
        lines = out.split("\n")
        if len(lines) >= len(names):
            return lines[:len(names)]
    except (OSError, subprocess.CalledProcessError):
        pass
    return list(names)


def code_symbols(binary):
    """[(address, size, mangled name)] of the functions in BINARY's symbol table (`nm -S`), or None."""
    try:
        text = subprocess.run(["nm", "-S", "--defined-only", binary], capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return None
    return [(int(p[0], 16), int(p[1], 16), p[3]) for p in (line.split() for line in text.splitlines())
            if len(p) == 4 and p[2] in "tTwW"]


def engine_functions(binary):
    """{mangled name: (size in bytes, demangled name)} of the engine's functions (namespace rb) in
    BINARY's symbol table."""
    symbols = code_symbols(binary)
    if symbols is None:
        return None
    sizes = {}
    for _, size, name in symbols:
        sizes[name] = sizes.get(name, 0) + size
    names = list(sizes)
    return {m: (sizes[m], d) for m, d in zip(names, demangle(names)) if "rb::" in d}


def code_changes(normal_bin, pgo_bin, top=10):
    a, b = engine_functions(normal_bin), engine_functions(pgo_bin)
    if a is None or b is None:
        return None

    def total(d, keys=None):
        return sum(d[k][0] for k in (d if keys is None else keys))

    def cold(d):
        return [k for k, v in d.items() if "[clone .cold]" in v[1]]

    both = [k for k in set(a) & set(b) if "rb::app::" not in short_name(a[k][1])]  # the engine, not the command line
    changed = sorted(both, key=lambda k: -abs(b[k][0] - a[k][0]))
    only_a, only_b = set(a) - set(b), set(b) - set(a)
    return {
        "functions": [len(a), len(b)], "bytes": [total(a), total(b)],
        "cold_parts": [len(cold(a)), len(cold(b))], "cold_bytes": [total(a, cold(a)), total(b, cold(b))],
        "only_normal": [len(only_a), total(a, only_a)], "only_pgo": [len(only_b), total(b, only_b)],
        "largest_changes": [{"function": short_name(a[k][1]), "normal": a[k][0], "pgo": b[k][0]}
                            for k in changed[:top] if a[k][0] != b[k][0]],
        "sizes": (a, b),
    }


# ---- where the time went where PGO loses ---------------------------------------------------------

def perf_works():
    if not shutil.which("perf"):
        return False
    try:
        with tempfile.TemporaryDirectory() as d:
            subprocess.run(["perf", "record", "-q", "-e", "cpu-clock", "-o", os.path.join(d, "p"), "--", "true"],
                           capture_output=True, check=True, timeout=30)
        return True
    except (OSError, subprocess.SubprocessError):
        return False


CONDITIONAL_JUMP = re.compile(r"^j(?!mp)[a-z]+$")
# Scalar only: a scalar min/max or compare-and-jump is where GCC chooses between a branch and a
# branch-free selection; the vector ones are the source's own (xsimd), whose count changes only when
# code is duplicated or merged.
MIN_MAX = re.compile(r"^v?(min|max)s[sd]$")
COMPARE = re.compile(r"^v?u?comis[sd]$")


def code_mix(binary, mangled):
    """The kinds of instructions in one function's code (conditional jumps, scalar min/max, scalar
    floating-point compares), from `objdump`, with its size; None when it cannot be found. Counted over
    the whole function, not the instructions that took samples: a cpu-clock sample in a KVM guest
    lands where the timer interrupt finds the processor, so two profiles of one binary sample
    different subsets of a large function (tried: a hot walk's sampled min/max numbered 14 and 22
    in two runs of the same binary), while the code itself is the same in every run."""
    where = [(a, n) for a, n, name in code_symbols(binary) or () if name == mangled]
    if not where:
        return None
    start, size = where[0]
    try:
        asm = subprocess.run(["objdump", "-d", "--no-show-raw-insn", f"--start-address={start:#x}",
                              f"--stop-address={start + size:#x}", binary], capture_output=True, text=True,
                             check=True, timeout=120).stdout
    except (OSError, subprocess.SubprocessError):
        return None
    mix = {"size": size, "instructions": 0, "jumps": 0, "min_max": 0, "compares": 0}
    for line in asm.splitlines():
        m = re.match(r"\s*[0-9a-f]+:\s+(\S+)", line)
        if not m:
            continue
        op = m.group(1)
        mix["instructions"] += 1
        mix["jumps"] += bool(CONDITIONAL_JUMP.match(op))
        mix["min_max"] += bool(MIN_MAX.match(op))
        mix["compares"] += bool(COMPARE.match(op))
    return mix


def perf_profile(binary, args, limit=6):
    """Running BINARY ARGS under `perf record`: {"shares": [(self share %, mangled function)] of the
    functions that took the most time, "hot": the hottest engine function, "mix": the kinds of
    instructions in its code (code_mix), "cold_share": % of its samples in its `.cold` part, the
    blocks GCC moved out of its body as rarely run}; None when perf fails."""
    with tempfile.TemporaryDirectory() as d:
        data = os.path.join(d, "perf.data")
        try:
            subprocess.run(["perf", "record", "-q", "-e", "cpu-clock", "-F", str(PERF_HZ), "-o", data, "--", binary, *args,
                            "--json", os.path.join(d, "out.json")], capture_output=True, check=True, timeout=300)
            rep = subprocess.run(["perf", "report", "-i", data, "--stdio", "--no-children", "--no-demangle", "-g", "none",
                                  "--sort", "symbol", "-q", "--percent-limit", "1"],
                                 capture_output=True, text=True, check=True, timeout=300).stdout
        except (OSError, subprocess.SubprocessError):
            return None
    shares = []
    for line in rep.splitlines():
        m = re.match(r"\s*([\d.]+)%\s+\[[.k]\]\s+(\S+)", line)
        if m:
            shares.append((float(m.group(1)), m.group(2)))
    out = {"shares": shares[:limit]}
    engine = [fn for _, fn in shares if fn.startswith("_ZN2rb") or fn.startswith("_ZZN2rb")]
    if engine:
        hot = engine[0][:-len(".cold")] if engine[0].endswith(".cold") else engine[0]
        body = sum(x for x, fn in shares if fn == hot)
        cold = sum(x for x, fn in shares if fn == hot + ".cold")
        out.update(hot=hot, mix=code_mix(binary, hot), cold_share=100.0 * cold / (body + cold) if body + cold else 0.0)
    return out


def why_slower(entry):
    """(short, long) words on what differs between the two builds' code of the row's hottest
    function, by rules on code_mix; None without a profile of both builds."""
    n, p = entry.get("normal") or {}, entry.get("pgo") or {}
    if not n.get("mix") or not p.get("mix"):
        return None
    fn = short_name(demangle([n["hot"]])[0])
    if n["hot"] != p["hot"]:
        other = short_name(demangle([p["hot"]])[0])
        return ("another hottest function", f"the hottest function differs: `{fn[:100]}` in the normal build, `{other[:100]}` "
                "in the PGO build (code inlined into or split from it differently).")
    a, b = n["mix"], p["mix"]

    def moved(kind, share=0.10):  # a count changed by at least 3 and by at least SHARE of the normal build's
        return abs(b[kind] - a[kind]) >= max(3, share * a[kind])

    counts = (f"{a['jumps']} -> {b['jumps']} conditional jumps, {a['min_max']} -> {b['min_max']} scalar min/max, "
              f"{a['compares']} -> {b['compares']} scalar compares, {a['instructions']:,} -> {b['instructions']:,} "
              f"instructions in {a['size']:,} -> {b['size']:,} bytes")
    said = []
    if moved("min_max") and b["min_max"] < a["min_max"] and moved("compares") and b["compares"] > a["compares"]:
        said.append(("min/max became jumps", "the profile compiled selections as compares and jumps, which mispredict "
                                             "where the data go either way"))
    elif moved("min_max") and b["min_max"] > a["min_max"] and moved("jumps") and b["jumps"] < a["jumps"]:
        said.append(("jumps became min/max", "the profile turned conditional jumps into branch-free selections, which "
                                             "always do the work a well-predicted jump let the normal build skip"))
    if b["size"] >= 1.15 * a["size"]:
        said.append(("grew", "its code grew: paths duplicated or loops unrolled by the profile's counts"))
    if p.get("cold_share", 0) >= n.get("cold_share", 0) + 2:
        said.append(("time in .cold code", f"{p['cold_share']:.0f} % of its samples in its `.cold` part (normal "
                                           f"{n.get('cold_share', 0):.0f} %): blocks the training ran rarely run often here"))
    if said:
        return ("; ".join(s for s, _ in said), f"in `{fn[:100]}` ({counts}): " + "; ".join(w for _, w in said) + ".")
    if any(moved(k) for k in ("jumps", "min_max", "compares", "size")):
        return ("code changed, no rule", f"`{fn[:100]}` changed ({counts}) in no way the rules name; a cpu-clock "
                                         "profile cannot say which change costs the time.")
    return ("same code, slower",
            f"`{fn[:100]}` holds much the same instructions in both builds ({counts}): the same work, placed and "
            "ordered differently, runs slower; a cpu-clock profile cannot say whether branches, the "
            "instruction cache or the front end pay.")


def trace_key(r):
    return f"trace {r['scene']} {r['ray_set']} {r['packet']}"


def family_key(kernel):
    return f"family {kernel}"


def losing_profiles(rows_lost, binaries):
    """Per row PGO slowed (the worst few): its command, the top functions' time shares in both
    builds and what differs in the code of the hottest function."""
    out = []
    for key, label, args in rows_lost:
        entry = {"key": key, "row": label, "command": "raybench " + " ".join(args)}
        for b in ("normal", "pgo"):
            entry[b] = perf_profile(binaries[b], args)
        why = why_slower(entry)
        if why:
            entry["why_short"], entry["why"] = why
        out.append(entry)
    return out


# ---- charts ----------------------------------------------------------------------------------------

def interval_bars(ax, ys, items, b, colour, label, off):
    xs = [it.get(b) for it in items]
    for y, iv in zip(ys, xs):
        if iv and iv.get("lo") is not None:
            ax.errorbar([iv["ratio"]], [y + off], xerr=[[iv["ratio"] - iv["lo"]], [iv["hi"] - iv["ratio"]]], fmt="o",
                        color=colour, ms=4, capsize=2, label=label)
            label = None


def charts(out, fams, trows, others):
    colours = {"pgo": ("tab:blue", "honest profile (trained apart)"),
               "tuned": ("tab:orange", "profile of the measured workload")}
    for items, name, labels, title in (
            (fams, "pgo_kernels.png", [f["kernel"] for f in fams], "kernel families (geometric mean of the family's rows)"),
            (trows, "pgo_traces.png", [f"{os.path.basename(r['scene'])} {r['ray_set']} K={r['packet']}" for r in trows],
             "whole-scene traces, 1 thread")):
        if not items:
            continue
        fig, ax = plt.subplots(figsize=(9, 1.0 + 0.3 * len(items)))
        ys = list(range(len(items)))
        for i, b in enumerate(others):
            interval_bars(ax, ys, items, b, colours[b][0], colours[b][1], 0.15 * (i - (len(others) - 1) / 2))
        ax.axvline(1.0, color="black", lw=0.8)
        ax.set_yticks(ys)
        ax.set_yticklabels(labels, fontsize=7)
        ax.invert_yaxis()
        ax.set_xlabel("PGO / normal (above 1: PGO faster); median of paired rounds with its 95 % interval")
        ax.set_title("Profile-guided optimisation: " + title, fontsize=10)
        ax.legend(loc="lower right", fontsize=8)
        fig.tight_layout()
        atomic_save.savefig(fig, os.path.join(out, name), dpi=110)
        plt.close(fig)


# ---- the section -----------------------------------------------------------------------------------

def kib(n):
    return f"{n / 1024:,.1f} KiB"


def table_start(md, title, head, sep, others):
    """A subsection's title and its table's head, with a column for the tuned build when it ran."""
    if "tuned" in others:
        head += " tuned / normal [95 %] |"
        sep += "---:|"
    md += [f"### {title}", "", head, sep]


def markdown(data, args, load):
    rows, fams, allk, trows, context, others = (data[k] for k in ("benchmarks", "families", "all_kernels", "traces",
                                                                  "context", "others"))
    why = {e["key"]: e["why_short"] for e in data.get("losses") or [] if e.get("why_short")}

    def verdict_cell(key, iv):
        v = verdict(iv)
        if v != "slower":
            return v
        return f"slower: {why[key]}" if key in why else "slower (not profiled)"
    md = ["## Profile-guided optimisation", ""]
    normal_ctx = context.get("normal", {})
    md.append(f"Measured by `./run.sh pgo`, which `./run.sh report` runs before the report ({args.minutes} min; {args.builds}). "
              "The **normal** build is the release preset; the **PGO** build compiles the code the measured workload times (the "
              "kernels' benchmark loops, the BVH, the tracer, the scene model) again with a profile trained on a workload apart "
              "from the measured one, and links the release build's own objects for the libraries that time nothing (loaders, "
              "ray sets, renderer, operation tables, accuracy lab, Embree's wrapper, the report); the AVX-512 files (16 lanes) "
              "are compiled without a profile in both, since a profile may leave one of their inline functions out of line" +
              (" and the **tuned** build with a profile of the measured workload itself (how much a profile of the very "
               "benchmark flatters)" if "tuned" in others else "") + ". "
              f"Both builds ran the measured workload in {args.rounds} paired rounds, back to back in each round, their order "
              "alternating and both runs of a pair on the same CPU (`taskset`; the CPU changes from pair to pair): every kernel "
              "benchmark below in a process of its own for at least "
              f"{args.bench_min_time} s, and every trace row in a process of its own (1 thread, a warm-up, then the median "
              f"of {args.trace_reps} timed runs of at least {args.trace_min_time} s of passes each). A ratio is PGO over normal (above 1: PGO faster), the median of the rounds' "
              "ratios with its 95 % interval (sign test, as every paired ratio of this report); a kernel family's ratio in a "
              "round is the geometric mean of its benchmarks' ratios. **faster** / **slower**: the whole interval lies above / "
              "below 1; **within the noise**: it holds 1.")
    md.append("")
    if normal_ctx.get("raybench_git"):
        md.append(f"- Revision measured: `{normal_ctx['raybench_git']}`; CPU: {normal_ctx.get('raybench_cpu', '?')}; "
                  f"ISA: {normal_ctx.get('raybench_isa', '?')}.")
    if load:
        md.append(f"- Machine load (1-minute average after each round; the runs use one thread): {min(load):.2f} to "
                  f"{max(load):.2f}." + (" **Other work ran during the measurement.**" if max(load) > 1.6 else ""))
    md.append(f"- Training workload (the profile): {args.honest}.")
    if "tuned" in others and args.tuned:
        md.append(f"- Tuned training workload: {args.tuned}.")
    md.append(f"- Measured workload: {args.measured}.")
    for b in ("normal",) + tuple(others):
        if context.get(b, {}).get("raybench_build_flags"):
            md.append(f"- Flags, {b} build: `{context[b]['raybench_build_flags']}`")
    md.append("")
    widths = {what: [h for h in (half_width(x.get("pgo")) for x in items) if h is not None]
              for what, items in (("kernel families", fams), ("trace rows", trows), ("single kernel benchmarks", rows))}
    if fams:
        table_start(md, "Kernel families", "| family | benchmarks | PGO / normal [95 %] | verdict | rows faster / slower |",
                    "|---|---:|---:|---|---:|", others)
        for f in fams + ([allk] if allk else []):
            name = f["kernel"]
            sub = rows if name == "all kernels" else [r for r in rows if r["kernel"] == name]
            nf = sum(1 for r in sub if verdict(r.get("pgo")) == "faster")
            ns = sum(1 for r in sub if verdict(r.get("pgo")) == "slower")
            line = (f"| {'**all kernels**' if name == 'all kernels' else name} | {len(sub)} | {interval_text(f.get('pgo'))} | "
                    f"{verdict_cell(family_key(name), f.get('pgo'))} | {nf} / {ns} |")
            if "tuned" in others:
                line += f" {interval_text(f.get('tuned'))} |"
            md.append(line)
        md.append("")
        md.append("![PGO / normal per kernel family](pgo_kernels.png)")
        md.append("")
    if trows:
        table_start(md, "Whole-scene traces", "| scene | rays | packet | normal Mrays/s | PGO Mrays/s | PGO / normal [95 %] | verdict |",
                    "|---|---|---:|---:|---:|---:|---|", others)
        for r in trows:
            p = r.get("pgo") or {}
            line = (f"| {r['scene']} | {r['ray_set']} | {r['packet']} | {r['normal_mrays_per_s']:.2f} | "
                    f"{p.get('mrays_per_s', float('nan')):.2f} | {interval_text(p)} | {verdict_cell(trace_key(r), p)} |")
            if "tuned" in others:
                line += f" {interval_text(r.get('tuned'))} |"
            md.append(line)
        md.append("")
        md.append("![PGO / normal per trace](pgo_traces.png)")
        md.append("")
    if any(widths.values()):
        md.append("Intervals, half their width over the ratio (median; within "
                  f"{100 * TARGET_HALF_WIDTH:.0f} %): " +
                  "; ".join(f"{what} {100 * statistics.median(h):.1f} % ({sum(1 for x in h if x <= TARGET_HALF_WIDTH)} of {len(h)})"
                            for what, h in widths.items() if h) +
                  ". Every benchmark's own row: [pgo.json](pgo.json).")
        md.append("")
    cc = data.get("code")
    if cc:
        md.append("### What the profile changed in the code")
        md.append("")
        md.append("The engine's functions (namespace `rb`) in the two binaries, from their symbol tables (`nm`): a function "
                  "missing from the PGO build was inlined at every call or not emitted; a `.cold` part is a function's "
                  "rarely run blocks moved out of its body (GCC splits them by the profile's counts).")
        md.append("")
        md.append("| | normal | PGO |")
        md.append("|---|---:|---:|")
        md.append(f"| functions | {cc['functions'][0]:,} | {cc['functions'][1]:,} |")
        md.append(f"| their code | {kib(cc['bytes'][0])} | {kib(cc['bytes'][1])} |")
        md.append(f"| `.cold` parts | {cc['cold_parts'][0]:,} ({kib(cc['cold_bytes'][0])}) | {cc['cold_parts'][1]:,} "
                  f"({kib(cc['cold_bytes'][1])}) |")
        md.append(f"| functions in one build only | {cc['only_normal'][0]:,} ({kib(cc['only_normal'][1])}) | "
                  f"{cc['only_pgo'][0]:,} ({kib(cc['only_pgo'][1])}) |")
        md.append("")
        if cc["largest_changes"]:
            md.append("The largest changes of an engine function's size (bytes; the command line's plumbing left out):")
            md.append("")
            md.append("| function | normal | PGO |")
            md.append("|---|---:|---:|")
            for c in cc["largest_changes"]:
                md.append(f"| `{c['function'][:140]}` | {c['normal']:,} | {c['pgo']:,} |")
            md.append("")
    lost = data.get("losses") or []
    slower = [r for r in trows if verdict(r.get("pgo")) == "slower"] + [f for f in fams if verdict(f.get("pgo")) == "slower"]
    md.append("### Where PGO loses")
    md.append("")
    if not slower:
        md.append("No kernel family and no trace row is slower with the profile (no interval lies below 1).")
        md.append("")
    elif not lost:
        md.append(f"{len(slower)} rows are slower with the profile; no per-function profile of them was taken "
                  f"({data.get('perf_why', 'perf did not run')}).")
        md.append("")
    if slower and lost:
        md.append("Each row PGO slowed (the worst first) ran once more under `perf record -e cpu-clock` in each build. "
                  "**Why** compares the two builds' code of the row's hottest function, disassembled with `objdump`: "
                  "its size and its instructions by kind (conditional jumps, scalar min/max, scalar floating-point "
                  "compares), and "
                  "the share of its samples in its `.cold` part; a rule names what the profile changed there (a count "
                  "moved by at least 3 and 10 %, the size by 15 %, the share by 2 points).")
        md.append("")
    for e in lost:
        md.append(f"**{e['row']}** (`{e['command']}`): the functions that took the most time (`perf record -e cpu-clock`, "
                  "self time), with their size in each build.")
        md.append("")
        md.append("| build | share | function | size normal | size PGO |")
        md.append("|---|---:|---|---:|---:|")
        sizes = cc["sizes"] if cc else ({}, {})
        for b in ("normal", "pgo"):
            shares = (e.get(b) or {}).get("shares") or []
            names = demangle([fn for _, fn in shares])
            for (share, fn), name in zip(shares, names):
                sn, sp = sizes[0].get(fn, (None,))[0], sizes[1].get(fn, (None,))[0]
                md.append(f"| {b} | {share:.1f} % | `{short_name(name)[:140]}` | {'-' if sn is None else f'{sn:,}'} | "
                          f"{'-' if sp is None else f'{sp:,}'} |")
        md.append("")
        if e.get("why"):
            md.append(f"**Why**: {e['why']}")
            md.append("")
    md.append("Raw rows: [pgo.json](pgo.json). The PGO build passes the same tests: `./run.sh pgo-test`.")
    md.append("")
    return "\n".join(md) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("results")
    ap.add_argument("out")
    ap.add_argument("--honest", required=True, help="words naming the training workload")
    ap.add_argument("--tuned", default="", help="words naming the tuned build's training workload")
    ap.add_argument("--measured", default="?", help="words naming the measured workload")
    ap.add_argument("--builds", default="", help="words saying which builds were compiled and which were up to date")
    ap.add_argument("--minutes", default="?")
    ap.add_argument("--rounds", default="?")
    ap.add_argument("--bench-min-time", default="?")
    ap.add_argument("--trace-min-time", default="?")
    ap.add_argument("--trace-reps", default="?")
    ap.add_argument("--binary", action="append", default=[], help="BUILD=PATH of a measured binary (normal, pgo)")
    ap.add_argument("--perf-rows", type=int, default=8, help="rows PGO slowed to profile with perf (the worst first)")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rows, fams, allk, trows, context, others = compare(args.results)
    binaries = dict(x.split("=", 1) for x in args.binary if "=" in x)
    data = {"benchmarks": rows, "families": fams, "all_kernels": allk, "traces": trows, "context": context, "others": others}
    if "normal" in binaries and "pgo" in binaries:
        data["code"] = code_changes(binaries["normal"], binaries["pgo"])
        lost = sorted((r for r in trows if verdict(r.get("pgo")) == "slower"), key=lambda r: r["pgo"]["ratio"])
        jobs = [(trace_key(r), f"{r['scene']} {r['ray_set']} K={r['packet']}",
                 ["trace", r["scene"], "--rays", r["ray_set"], "--packet", str(r["packet"]), "--threads", "1", "-r", "3",
                  "--min-time", "0.5", "--brute", "0", "--no-embree"]) for r in lost[:args.perf_rows]]
        # A slower family is profiled on its slowest benchmark, the one that pulled it down.
        for f in sorted((f for f in fams if verdict(f.get("pgo")) == "slower"), key=lambda f: f["pgo"]["ratio"])[:args.perf_rows]:
            worst = min((r for r in rows if r["kernel"] == f["kernel"] and r.get("pgo")), key=lambda r: r["pgo"]["ratio"])
            jobs.append((family_key(f["kernel"]), f"kernel family {f['kernel']}, its slowest benchmark {worst['benchmark']} ({interval_text(worst['pgo'])})",
                         ["bench", "--filter", f"^{worst['benchmark']}$", "-r", "3", "--min-time", "0.3"]))
        if jobs and perf_works():
            data["losses"] = losing_profiles(jobs, binaries)
        elif jobs:
            data["perf_why"] = "perf is missing or not permitted here (Debian package linux-perf)"
    md = markdown(data, args, machine_load(args.results))
    if data.get("code"):
        data["code"] = {k: v for k, v in data["code"].items() if k != "sizes"}
    data.update(training=args.honest, tuned_training=args.tuned, measured=args.measured, minutes=args.minutes,
                interval="median of per-round ratios, sign-test 95 % interval (order statistics)")
    atomic_save.write_text(os.path.join(args.out, "pgo.json"), json.dumps(data, indent=2, default=str))
    charts(args.out, fams, trows, others)
    atomic_save.write_text(os.path.join(args.out, "pgo.md"), md)
    index = os.path.join(args.out, "index.md")
    if os.path.exists(index):
        with open(index) as f:
            text = f.read()
        block = "<!-- pgo-section -->\n" + md + "<!-- /pgo-section -->"
        new, n = re.subn(r"<!-- pgo-section -->.*?<!-- /pgo-section -->", lambda _: block, text, flags=re.S)
        if n:
            atomic_save.write_text(index, new)
    print(f"PGO section written: {os.path.join(args.out, 'pgo.md')} ({len(rows)} benchmarks, {len(trows)} traces)")
    return 0 if rows or trows else 1


if __name__ == "__main__":
    sys.exit(main())
