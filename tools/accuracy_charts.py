#!/usr/bin/python3
"""Speed against accuracy, one PNG per primitive family, from `raybench accuracy --json`.

Usage: /usr/bin/python3 tools/accuracy_charts.py ACCURACY.json OUTDIR
Writes OUTDIR/accuracy_<family>.png: x = ns per test (median over the family's cases, timed in
the same run), y = the worst failure rate (left) and the worst p99 t error in ulps (right), both
over the cases that at least one method passes, log scales; one point per method and precision;
the Pareto front (no other point both faster and better) is drawn as a line. A method without
failures is drawn at the floor of the left panel, labelled "0".
"""
import json
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import atomic_save  # noqa: E402

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def secondary(r):
    return r["case"].startswith("secondary")


def points(rows, fam):
    rows = [r for r in rows if r["family"] == fam and not secondary(r)]
    passable = {r["case"] for r in rows if (r.get("failure_ppm") or 0) == 0} or {r["case"] for r in rows}
    pts = {}
    for r in rows:
        key = (r["method"], r["precision"])
        p = pts.setdefault(key, {"ns": [], "fail": 0.0, "ulp": 0.0})
        if r.get("ns_per_test") is not None:
            p["ns"].append(r["ns_per_test"])
        if r["case"] not in passable:
            continue
        p["fail"] = max(p["fail"], r.get("failure_ppm") or 0.0)
        if r.get("t_err_ulp_p99") is not None:
            p["ulp"] = max(p["ulp"], r["t_err_ulp_p99"])
    out = []
    for (m, prec), p in pts.items():
        if not p["ns"]:
            continue
        out.append((f"{m} {prec}", statistics.median(p["ns"]), p["fail"], p["ulp"]))
    return out


def pareto(pts):
    """Points no other point dominates (x and y both no larger, one smaller), sorted by x."""
    front = []
    for name, x, y in pts:
        if not any((x2 <= x and y2 <= y) and (x2 < x or y2 < y) for _, x2, y2 in pts):
            front.append((x, y))
    return sorted(front)


def panel(ax, pts, floor, ylabel, title):
    shown = [(n, x, max(y, floor)) for n, x, y in pts]
    colors = {"float": "tab:blue", "double": "tab:orange", "simd8": "tab:green"}
    for n, x, y in shown:
        ax.scatter([x], [y], color=colors.get(n.split()[-1], "grey"), s=28, zorder=3)
        ax.annotate(n, (x, y), fontsize=7, xytext=(3, 3), textcoords="offset points")
    fr = pareto(shown)
    if fr:
        ax.plot([p[0] for p in fr], [p[1] for p in fr], color="red", lw=1, ls="--", zorder=2, label="Pareto front")
        ax.legend(fontsize=7, loc="upper right")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.axhline(floor, color="grey", lw=0.5, ls=":")
    ax.set_xlabel("ns per test (median over the cases; same run)")
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=9)
    ax.grid(lw=0.3, which="both")


def main():
    src, out = sys.argv[1], sys.argv[2]
    with open(src) as f:
        rows = json.load(f)["rows"]
    fams = []
    for r in rows:
        if r["family"] not in fams:
            fams.append(r["family"])
    for fam in fams:
        pts = points(rows, fam)
        if not pts:
            continue
        fig, axes = plt.subplots(1, 2, figsize=(12, 4.6))
        panel(axes[0], [(n, x, f) for n, x, f, _ in pts], 0.1,
              "worst failure rate (ppm; 0 drawn at 0.1)", f"{fam}: failures (false hits, misses, leaks, NaN, wrong roots)")
        panel(axes[1], [(n, x, u) for n, x, _, u in pts], 0.1,
              "worst p99 t error (ulps of the precision)", f"{fam}: t error")
        fig.tight_layout()
        atomic_save.savefig(fig, os.path.join(out, f"accuracy_{fam}.png"), dpi=110)
        plt.close(fig)


if __name__ == "__main__":
    main()
