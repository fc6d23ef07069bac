#!/usr/bin/python3
"""The report's profile-guided optimisation section, from the runs of `./run.sh pgo`.

Usage: /usr/bin/python3 tools/pgo.py RESULTS OUT --honest TEXT --tuned TEXT [--minutes N]

RESULTS holds one folder per build (normal, pgo, tuned), each with the kernel benchmark JSON of
every round (bench-N.json, Google Benchmark, every repetition kept; round N of each build ran back
to back) and one JSON per trace (trace-*.json, `raybench trace --json`), and load.txt (the load
average after each measured run). Writes OUT/pgo.json, OUT/pgo.md and two charts, and
replaces the PGO section of OUT/index.md when that file exists.
"""
import argparse
import glob
import json
import math
import os
import re
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import atomic_save  # noqa: E402

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

try:
    from scipy.stats import mannwhitneyu
except ImportError:  # the table then has no p-values, and says so
    mannwhitneyu = None

BUILDS = ("normal", "pgo", "tuned")


def load_json(path):
    with open(path) as f:
        # Google Benchmark writes NaN / Infinity as bare tokens
        return json.loads(re.sub(r":\s*-?(NaN|nan|Infinity|inf)\b", ": null", f.read()))


def bench_reps(folder):
    """Benchmark name -> {round file: list of tests/s, one per repetition}."""
    reps, context = {}, {}
    for path in sorted(glob.glob(os.path.join(folder, "bench-*.json"))):
        j = load_json(path)
        context = j.get("context", context)
        rnd = os.path.basename(path)
        for b in j.get("benchmarks", []):
            if b.get("run_type") != "iteration":
                continue
            rate = b.get("tests_per_s")
            if rate:
                reps.setdefault(b["run_name"], {}).setdefault(rnd, []).append(rate)
    return reps, context


def flat(by_round):
    return [x for r in sorted(by_round) for x in by_round[r]]


def paired_ratio(base, other):
    """Median over rounds of (other's median / base's median) in that round. The builds of one round
    ran back to back, so a disturbance that hits one round moves one term, not the result."""
    per = [statistics.median(other[r]) / statistics.median(base[r]) for r in sorted(base) if r in other]
    return (statistics.median(per) if per else None), per


def traces(folder):
    """(scene, ray set, packet) -> {round: the trace JSON}. `./run.sh pgo` writes one JSON per round
    (trace-TAG-rN.json); a file without a round number is round 0."""
    out = {}
    for path in sorted(glob.glob(os.path.join(folder, "trace-*.json"))):
        j = load_json(path)
        m = re.search(r"-r(\d+)\.json$", path)
        key = (j.get("scene", "?"), j.get("ray_set", "?"), int(j.get("packet", 1)))
        out.setdefault(key, {})[int(m.group(1)) if m else 0] = j
    return out


def trace_reps(j):
    """Mrays/s of every timed run (`raybench trace --json` keeps each run's seconds)."""
    secs, rays = j.get("seconds"), j.get("rays")
    if isinstance(secs, list) and rays and all(isinstance(x, (int, float)) and x > 0 for x in secs):
        return [rays / x / 1e6 for x in secs]
    return [j["mrays_per_s"]] if j.get("mrays_per_s") else []


def utest(a, b):
    if mannwhitneyu is None or len(a) < 2 or len(b) < 2:
        return None
    return float(mannwhitneyu(a, b, alternative="two-sided").pvalue)


def gmean(xs):
    xs = [x for x in xs if x and x > 0]
    return math.exp(sum(math.log(x) for x in xs) / len(xs)) if xs else None


def fmt_ratio(r):
    return "-" if r is None else f"{r:.3f}"


def fmt_p(p):
    return "-" if p is None else (f"{p:.3f}" if p >= 0.001 else "<0.001")


def compare(results):
    bench = {b: bench_reps(os.path.join(results, b)) for b in BUILDS}
    rows = []
    for name in sorted(bench["normal"][0]):
        base = bench["normal"][0][name]
        row = {"benchmark": name, "kernel": name.split("/")[0], "variant": name.split("/")[2] if name.count("/") >= 2 else "",
               "normal_median": statistics.median(flat(base))}
        for b in ("pgo", "tuned"):
            other = bench[b][0].get(name)
            if not other:
                continue
            ratio, per_round = paired_ratio(base, other)
            if ratio is None:
                continue
            row[f"{b}_median"] = statistics.median(flat(other))
            row[f"{b}_ratio"] = ratio
            row[f"{b}_round_ratios"] = per_round
            row[f"{b}_p"] = utest(flat(base), flat(other))
        rows.append(row)
    tr = {b: traces(os.path.join(results, b)) for b in BUILDS}
    trows = []
    for key in sorted(tr["normal"]):
        base = {r: trace_reps(j) for r, j in tr["normal"][key].items()}
        base = {r: v for r, v in base.items() if v}
        if not base:
            continue
        row = {"scene": key[0], "ray_set": key[1], "packet": key[2], "normal_mrays_per_s": statistics.median(flat(base))}
        for b in ("pgo", "tuned"):
            other = {r: trace_reps(j) for r, j in tr[b].get(key, {}).items()}
            other = {r: v for r, v in other.items() if v}
            ratio, per_round = paired_ratio(base, other)
            if ratio is None:
                continue
            row[f"{b}_mrays_per_s"] = statistics.median(flat(other))
            row[f"{b}_ratio"] = ratio
            row[f"{b}_round_ratios"] = per_round
            row[f"{b}_p"] = utest(flat(base), flat(other))
        trows.append(row)
    flags = {b: bench[b][1].get("raybench_build_flags", "?") for b in BUILDS}
    return rows, trows, flags


def machine_load(results):
    """The 1-minute load averages `./run.sh pgo` recorded after each measured run."""
    try:
        with open(os.path.join(results, "load.txt")) as f:
            return [float(line.split()[1]) for line in f if len(line.split()) > 1]
    except (OSError, ValueError):
        return []


def group(rows, key, field):
    g = {}
    for r in rows:
        if field in r:
            g.setdefault(r[key], []).append(r[field])
    return g


def charts(out, rows, trows):
    fams = sorted({r["kernel"] for r in rows})
    if fams:
        fig, ax = plt.subplots(figsize=(10, 0.8 + 0.32 * len(fams)))
        for off, b, colour in ((-0.18, "pgo", "tab:blue"), (0.18, "tuned", "tab:orange")):
            g = group(rows, "kernel", f"{b}_ratio")
            for i, fam in enumerate(fams):
                ys = g.get(fam, [])
                ax.scatter(ys, [i + off] * len(ys), s=10, color=colour, alpha=0.6,
                           label=("honest profile" if b == "pgo" else "profile of the measured workload") if i == 0 else None)
                if ys:
                    ax.plot([statistics.median(ys)] * 2, [i + off - 0.15, i + off + 0.15], color=colour, lw=2.5)
        ax.axvline(1.0, color="black", lw=0.8)
        ax.set_yticks(range(len(fams)))
        ax.set_yticklabels(fams)
        ax.set_xlabel("PGO tests/s divided by normal tests/s (one dot per benchmark, bar = median)")
        ax.set_title("Profile-guided optimisation, kernel benchmarks")
        ax.legend(loc="lower right", fontsize=8)
        fig.tight_layout()
        atomic_save.savefig(fig, os.path.join(out, "pgo_kernels.png"), dpi=110)
        plt.close(fig)
    if trows:
        labels = [f"{os.path.basename(r['scene'])} {r['ray_set']} K={r['packet']}" for r in trows]
        fig, ax = plt.subplots(figsize=(10, 0.8 + 0.28 * len(trows)))
        y = range(len(trows))
        ax.barh([i - 0.2 for i in y], [r.get("pgo_ratio", 0) for r in trows], 0.4, label="honest profile")
        ax.barh([i + 0.2 for i in y], [r.get("tuned_ratio", 0) for r in trows], 0.4, label="profile of the measured workload")
        ax.axvline(1.0, color="black", lw=0.8)
        lo = min([r.get(k, 1) for r in trows for k in ("pgo_ratio", "tuned_ratio")] + [0.9])
        ax.set_xlim(max(0.0, lo - 0.05), None)
        ax.set_yticks(list(y))
        ax.set_yticklabels(labels, fontsize=7)
        ax.set_xlabel("PGO Mrays/s divided by normal Mrays/s")
        ax.set_title("Profile-guided optimisation, whole-scene traces (1 thread)")
        ax.legend(loc="lower right", fontsize=8)
        fig.tight_layout()
        atomic_save.savefig(fig, os.path.join(out, "pgo_traces.png"), dpi=110)
        plt.close(fig)


def markdown(rows, trows, flags, args, load):
    md = ["## Profile-guided optimisation", ""]
    md.append(f"Measured by `./run.sh pgo` ({args.minutes} min). Three builds of the same source: **normal** (the release "
              "preset), **PGO** (trained on a workload apart from the measured one) and **tuned** (trained on the measured "
              "workload itself: a sensitivity check of how much a profile of the very benchmark flatters). The kernel "
              "benchmarks ran in three rounds of 2 repetitions per build, the three builds back to back in each round and their "
              "order rotated from round to round; a benchmark's ratio is the median over the rounds of that round's ratio of "
              "medians, so a disturbance of one round moves one term, not the result. The traces ran the same way: for each "
              "scene, ray set and packet size, five rounds of 2 repetitions per build (1 thread), the builds back to back in "
              "each round and their order rotated, a trace's ratio the median of its per-round ratios. Ratios > 1 "
              "mean the PGO build is faster; p is the two-sided Mann-Whitney U-test over all repetitions (as Google "
              "Benchmark's compare.py computes it).")
    md.append("")
    if load:
        md.append(f"- Machine load (1-minute average, read after each measured run; the runs use one thread): "
                  f"{min(load):.2f} to {max(load):.2f}." +
                  (" **The machine was not idle: other work ran during the measurement.**" if max(load) > 1.6 else ""))
    md.append(f"- Honest training workload: {args.honest}.")
    md.append(f"- Tuned training workload: {args.tuned}.")
    for b in BUILDS:
        md.append(f"- Flags, {b} build: `{flags[b]}`")
    md.append("")
    if rows:
        md.append("### Median ratio per kernel family")
        md.append("")
        md.append("| kernel | benchmarks | PGO median ratio | PGO min | PGO max | slower (p < 0.05) | tuned median ratio |")
        md.append("|---|---:|---:|---:|---:|---:|---:|")
        gp, gt = group(rows, "kernel", "pgo_ratio"), group(rows, "kernel", "tuned_ratio")
        for fam in sorted(gp):
            slower = sum(1 for r in rows if r["kernel"] == fam and r.get("pgo_ratio", 1) < 1 and (r.get("pgo_p") or 1) < 0.05)
            md.append(f"| {fam} | {len(gp[fam])} | {statistics.median(gp[fam]):.3f} | {min(gp[fam]):.3f} | {max(gp[fam]):.3f} "
                      f"| {slower} | {fmt_ratio(statistics.median(gt[fam]) if gt.get(fam) else None)} |")
        md.append("")
        gv, gvt = group(rows, "variant", "pgo_ratio"), group(rows, "variant", "tuned_ratio")
        md.append("| variant | PGO median ratio | tuned median ratio |")
        md.append("|---|---:|---:|")
        for v in sorted(gv):
            md.append(f"| {v} | {statistics.median(gv[v]):.3f} | {fmt_ratio(statistics.median(gvt[v]) if gvt.get(v) else None)} |")
        allp = [r["pgo_ratio"] for r in rows if "pgo_ratio" in r]
        allt = [r["tuned_ratio"] for r in rows if "tuned_ratio" in r]
        sig_slow = [r for r in rows if r.get("pgo_ratio", 1) < 1 and (r.get("pgo_p") or 1) < 0.05]
        sig_fast = [r for r in rows if r.get("pgo_ratio", 1) > 1 and (r.get("pgo_p") or 1) < 0.05]
        md.append("")
        md.append(f"Over all {len(allp)} kernel benchmarks the honest profile's median ratio is {statistics.median(allp):.3f} "
                  f"(geometric mean {gmean(allp):.3f}); {len(sig_fast)} got faster and {len(sig_slow)} slower with p < 0.05. "
                  f"The tuned profile's median ratio is {statistics.median(allt):.3f} (geometric mean {gmean(allt):.3f}).")
        md.append("")
        md.append("![PGO ratios per kernel family](pgo_kernels.png)")
        md.append("")
    if trows:
        md.append("### Whole-scene traces")
        md.append("")
        md.append("| scene | rays | packet | normal Mrays/s | PGO Mrays/s | ratio | p | tuned Mrays/s | tuned ratio |")
        md.append("|---|---|---:|---:|---:|---:|---:|---:|---:|")
        for r in trows:
            md.append(f"| {r['scene']} | {r['ray_set']} | {r['packet']} | {r['normal_mrays_per_s']:.2f} | "
                      f"{r.get('pgo_mrays_per_s', float('nan')):.2f} | {fmt_ratio(r.get('pgo_ratio'))} | {fmt_p(r.get('pgo_p'))} | "
                      f"{r.get('tuned_mrays_per_s', float('nan')):.2f} | {fmt_ratio(r.get('tuned_ratio'))} |")
        gs = group(trows, "scene", "pgo_ratio")
        md.append("")
        md.append("Median trace ratio per scene (honest profile): " +
                  ", ".join(f"{s} {statistics.median(v):.3f}" for s, v in sorted(gs.items())) + ".")
        md.append("")
        md.append("![PGO ratios per scene](pgo_traces.png)")
        md.append("")
        if "hot-bb-count-fraction" in flags.get("pgo", ""):
            md.append("Why the traces once lost 5-10 % with PGO: GCC calls a block hot when its training count is at least the "
                      "largest counter of the whole training divided by 10,000. The kernel benchmarks set that counter (about 1e9), "
                      "so every call site of the BVH traversal (under 1e5 runs in training) was cold, and GCC stopped inlining its "
                      "small lambdas (\"call is unlikely and code size would grow\"): a mesh leaf's vertex load became a call "
                      "returning 8-lane vectors through memory, three per ray and leaf, and 8-ray packets ran 33 % more instructions "
                      "than the normal build (callgrind, bunny, primary rays). The PGO builds here pass "
                      "`--param=hot-bb-count-fraction=1000000`, so any block that ran in training may be hot, and the traversal is inlined as in the "
                      "normal build (instruction counts with and without it: docs/DESIGN.md, section 11).")
            md.append("")
    if not rows and not trows:
        md.append("_No results were found: the PGO runs failed; see the output of `./run.sh pgo`._")
        md.append("")
    if mannwhitneyu is None:
        md.append("_p-values are missing: scipy is not installed (Debian package python3-scipy)._")
        md.append("")
    md.append("Raw rows: [pgo.json](pgo.json). The PGO build passes the same tests: `./run.sh pgo-test`.")
    md.append("")
    return "\n".join(md) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("results")
    ap.add_argument("out")
    ap.add_argument("--honest", required=True, help="words naming the honest training workload")
    ap.add_argument("--tuned", required=True, help="words naming the tuned training workload")
    ap.add_argument("--minutes", default="?")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rows, trows, flags = compare(args.results)
    atomic_save.write_text(os.path.join(args.out, "pgo.json"),
                           json.dumps({"benchmarks": rows, "traces": trows, "flags": flags, "honest_training": args.honest,
                                       "tuned_training": args.tuned}, indent=2))
    charts(args.out, rows, trows)
    md = markdown(rows, trows, flags, args, machine_load(args.results))
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
