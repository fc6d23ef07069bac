#!/usr/bin/python3
"""Speed against accuracy, one PNG per primitive family, from `raybench accuracy --json`.

Usage: /usr/bin/python3 tools/accuracy_charts.py ACCURACY.json OUTDIR
Writes OUTDIR/accuracy_<family>.png: x = ns per test (median over the family's cases, timed in
the same run), y = the worst failure rate (left) and the worst p99 relative error of t (right),
both over the cases that at least one method passes, log scales; one point per method and
precision, coloured by precision (the key outside the axes). The right panel uses one unit for
every precision: the relative error |dt| / t, from the lab's error in ulps of the precision times
that precision's machine epsilon (2^-23 for float and 8-lane float SIMD, 2^-52 for double; an ulp
of t is between eps t / 2 and eps t, so the figure is within a factor 2). The Pareto front (no
other point both faster and better) is drawn as a line, and only its points are named; the
others are listed in the key beside the panel. A method without failures or error is drawn at
the floor of the panel.
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


COLORS = {"float": "tab:blue", "double": "tab:orange", "simd8": "tab:green"}
EPS = {"float": 2.0 ** -23, "simd8": 2.0 ** -23, "double": 2.0 ** -52}


def panel(ax, pts, floor, ylabel, title):
    shown = [(n, x, max(y, floor)) for n, x, y in pts]
    for prec, c in COLORS.items():
        xs = [x for n, x, y in shown if n.split()[-1] == prec]
        ys = [y for n, x, y in shown if n.split()[-1] == prec]
        if xs:
            ax.scatter(xs, ys, color=c, s=28, zorder=3, label=prec)
    fr = pareto(shown)
    if fr:
        ax.plot([p[0] for p in fr], [p[1] for p in fr], color="red", lw=1, ls="--", zorder=2, label="Pareto front")
    # The front's points are numbered (numbers only, beside the point) and named in a key below the
    # colour key, right of the axes: no name can overlap a point or another name.
    on_front = sorted({(x, y, n) for n, x, y in shown if (x, y) in fr})
    for i, (x, y, n) in enumerate(on_front, 1):
        ax.annotate(str(i), (x, y), fontsize=7, xytext=(4, 4 if i % 2 else -9), textcoords="offset points", color="darkred")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False, title="precision", title_fontsize=7)
    if on_front:
        ax.text(1.03, 0.58, "on the Pareto front:\n" + "\n".join(f"{i:>2} {n}" for i, (_, _, n) in enumerate(on_front, 1)),
                transform=ax.transAxes, fontsize=7, va="top", ha="left", family="monospace", color="darkred")
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
        fig, axes = plt.subplots(1, 2, figsize=(15, 5.0))
        panel(axes[0], [(n, x, f) for n, x, f, _ in pts], 0.1,
              "worst failure rate (per million tests; 0 drawn at 0.1)", f"{fam}: failures (false hits, misses, leaks, NaN, wrong roots)")
        rel = [(n, x, u * EPS.get(n.split()[-1], 2.0 ** -23)) for n, x, _, u in pts]
        panel(axes[1], rel, 1e-18, "worst p99 relative error of t, |dt| / t (0 drawn at 1e-18)", f"{fam}: error of t, one unit for every precision")
        fig.subplots_adjust(left=0.06, right=0.84, wspace=0.62, bottom=0.11, top=0.92)
        atomic_save.savefig(fig, os.path.join(out, f"accuracy_{fam}.png"), dpi=110)
        plt.close(fig)


if __name__ == "__main__":
    main()
