#!/usr/bin/python3
"""Charts for `raybench report`: reads OUT/summary.json, writes PNGs into OUT.

Called by the report; run it by hand as: /usr/bin/python3 tools/charts.py report
"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import atomic_save  # noqa: E402

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def simd_speedup(out, summary):
    """One panel per case (hit, miss, half): a horizontal bar pair per kernel/method."""
    rows = summary.get("simd_vs_scalar", [])
    if not rows:
        return
    cases = [c for c in ("hit", "miss", "half") if any(r["case"] == c for r in rows)]
    methods = sorted({f"{r['kernel']}/{r['method']}" for r in rows}, reverse=True)
    by = {(f"{r['kernel']}/{r['method']}", r["case"]): r for r in rows}
    fig, axes = plt.subplots(1, len(cases), figsize=(5.2 * len(cases), 1.2 + 0.24 * len(methods)), sharey=True, squeeze=False)
    h = 0.4
    for ax, case in zip(axes[0], cases):
        y = range(len(methods))
        rays = [by[(m, case)]["speedup_rays_in_lanes"] if (m, case) in by else 0 for m in methods]
        prims = [by[(m, case)]["speedup_prims_in_lanes"] if (m, case) in by else 0 for m in methods]

        def err(mapping, values):
            # The 95 % interval of each bar (the rounds' ratios), as error bars; none where absent.
            lo, hi = [], []
            for m, v in zip(methods, values):
                iv = by.get((m, case), {}).get(f"speedup_{mapping}_interval") or {}
                a, b = iv.get("lo"), iv.get("hi")
                lo.append(max(v - a, 0) if a is not None else 0)
                hi.append(max(b - v, 0) if b is not None else 0)
            return [lo, hi]

        bars = dict(ecolor="0.2", capsize=1.5, error_kw=dict(lw=0.6))
        ax.barh([i + h / 2 for i in y], rays, h, xerr=err("rays_in_lanes", rays), label="8 rays x 1 primitive", **bars)
        ax.barh([i - h / 2 for i in y], prims, h, xerr=err("prims_in_lanes", prims), label="1 ray x 8 primitives", **bars)
        ax.axvline(8, color="grey", lw=0.8, ls=":", label="8 lanes")
        ax.axvline(6, color="red", lw=0.8, ls="--", label="6x goal: triangle, sphere, box")
        ax.axvline(4, color="orange", lw=0.8, ls="--", label="4x goal: every kernel")
        ax.set_yticks(list(y))
        ax.set_yticklabels(methods, fontsize=8)
        ax.set_ylim(-0.6, len(methods) - 0.4)
        ax.set_title(f"case: {case}", fontsize=10)
        ax.set_xlabel("speedup over true scalar (error bar: 95 % interval)")
        ax.grid(axis="x", lw=0.3)
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, fontsize=8, loc="lower center", ncol=len(labels))
    m = summary["machine"]
    fig.suptitle(f"SIMD speedup, L1-resident, one thread: {m['cpu']}, -ffp-contract={m['fp_contract']}, git {m['git']}", fontsize=10)
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    atomic_save.savefig(fig, os.path.join(out, "simd_speedup.png"), dpi=100)
    plt.close(fig)


def numbered_key(fig, ax, items, title):
    """Number the points instead of naming them (no label overlaps a point or another label): a
    small number beside each point, the key of numbers to names in a column right of the axes."""
    for i, (x, y, _) in enumerate(items, 1):
        ax.annotate(str(i), (x, y), fontsize=7, xytext=(4, 3), textcoords="offset points", color="0.25")
    key = "\n".join(f"{i:>2}  {name}" for i, (_, _, name) in enumerate(items, 1))
    ax.text(1.03, 0.0, title + "\n" + key, transform=ax.transAxes, fontsize=7, va="bottom", ha="left", family="monospace")


def trace_scaling(out, summary):
    """Log-log: time per ray against primitive count, raybench and Embree (primary rays, 1 thread)."""
    rows = summary.get("tracing", {}).get("by_size", [])
    if not rows:
        return
    rows = sorted(rows, key=lambda r: r["primitives"])
    fig, ax = plt.subplots(figsize=(9.5, 4.8))
    x = [r["primitives"] for r in rows]
    ax.loglog(x, [r["ns_per_ray"] for r in rows], "o", color="tab:blue", label="raybench (8-wide BVH, single rays)")
    e = [(r["primitives"], r["embree_ns_per_ray"]) for r in rows if r.get("embree_ns_per_ray") is not None]
    if e:
        ax.loglog([p[0] for p in e], [p[1] for p in e], "s", mfc="none", color="tab:orange", label="Embree 3 (rtcIntersect1)")
    numbered_key(fig, ax, [(r["primitives"], r["ns_per_ray"], f"{r['scene']} ({r['primitives']:,})") for r in rows],
                 "scenes (primitives)")
    ax.set_xlabel("primitives in the scene (log)")
    ax.set_ylabel("ns per primary ray, one thread (log)")
    ax.set_title("Time per ray against scene size", fontsize=10)
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=8, loc="lower left", bbox_to_anchor=(0.0, 1.08), ncol=2, frameon=False)
    fig.subplots_adjust(left=0.11, right=0.68, bottom=0.11, top=0.82)
    atomic_save.savefig(fig, os.path.join(out, "trace_scaling.png"), dpi=100)
    plt.close(fig)


def plan_models(out, summary):
    """Speed against failures per model (report section "What each scene needs"): one point per scene
    and model, a scene's three models joined by a grey line; failures of 0 drawn at the floor."""
    scenes = summary.get("plan", {}).get("scenes", [])
    if not scenes:
        return
    colors = {"fast": "tab:red", "auto": "tab:blue", "exact": "tab:green"}
    floor = 0.3
    fig, ax = plt.subplots(figsize=(10, 5.2))
    for s in scenes:
        pts = [(s[m]["mrays_per_s"], max(s[m]["failure_ppm"], floor)) for m in ("fast", "auto", "exact") if m in s]
        ax.plot([p[0] for p in pts], [p[1] for p in pts], color="0.8", lw=0.8, zorder=1)
    for m, c in colors.items():
        xs = [s[m]["mrays_per_s"] for s in scenes if m in s]
        ys = [max(s[m]["failure_ppm"], floor) for s in scenes if m in s]
        ax.scatter(xs, ys, color=c, label=m, s=28, zorder=2)
    # Number the scenes where the fast model fails (those are where the plan matters); the key of
    # numbers to scenes stands right of the axes, so no name overlaps a point or another name.
    failing = [(s["fast"]["mrays_per_s"], s["fast"]["failure_ppm"], s["scene"].replace("precision:", ""))
               for s in scenes if s.get("fast", {}).get("failure_ppm", 0) > 0]
    numbered_key(fig, ax, failing, "fast model fails on")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_ylim(floor / 1.5, 2e6)
    ax.axhline(floor, color="0.6", lw=0.6, ls=":")
    ax.text(ax.get_xlim()[0], floor * 1.15, " no failure", fontsize=7, color="0.4", va="bottom")
    ax.set_xlabel("primary rays, Mrays/s (one thread, 8-ray packets; log)")
    ax.set_ylabel("failures per million rays (log)")
    ax.set_title("Each scene under the three models: speed against failures")
    ax.legend(title="model", loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    fig.subplots_adjust(left=0.09, right=0.68, bottom=0.11, top=0.93)
    atomic_save.savefig(fig, os.path.join(out, "plan_models.png"), dpi=110)
    plt.close(fig)


def trace_matrix(out, summary):
    """Mrays/s per ray set and packet size, raybench beside Embree: one panel per mesh and thread count."""
    rows = summary.get("tracing", {}).get("matrix", [])
    if not rows:
        return
    meshes = list(dict.fromkeys(r["mesh"] for r in rows))
    sets = list(dict.fromkeys(r["ray_set"] for r in rows))
    packets = sorted({r["packet"] for r in rows})
    threads = sorted({r["threads"] for r in rows})
    colours = plt.get_cmap("tab10").colors
    fig, axes = plt.subplots(len(meshes), len(threads), figsize=(5.2 * len(threads) + 1.6, 2.9 * len(meshes)), squeeze=False,
                             sharey="row")
    width = 0.8 / (2 * len(packets))
    for mi, mesh in enumerate(meshes):
        for ti, th in enumerate(threads):
            ax = axes[mi][ti]
            for pi, p in enumerate(packets):
                for ei, (key, hatch, label) in enumerate([("mrays_per_s", None, "raybench"), ("embree_mrays_per_s", "///", "Embree")]):
                    xs, ys = [], []
                    for si, st in enumerate(sets):
                        r = next((r for r in rows if r["mesh"] == mesh and r["threads"] == th and r["packet"] == p and r["ray_set"] == st), None)
                        if r is None or r.get(key) is None:
                            continue
                        xs.append(si - 0.4 + width * (2 * pi + ei + 0.5))
                        ys.append(r[key])
                    ax.bar(xs, ys, width, color=colours[pi], alpha=1.0 if ei == 0 else 0.45, hatch=hatch, edgecolor="black", lw=0.3,
                           label=f"{label}, packet {p}" if mi == 0 and ti == 0 else None)
            ax.set_xticks(range(len(sets)))
            ax.set_xticklabels(sets)
            ax.set_title(f"{mesh}, {th} thread{'s' if th > 1 else ''}", fontsize=9)
            ax.grid(True, axis="y", lw=0.3)
            if ti == 0:
                ax.set_ylabel("Mrays/s (median)")
    fig.legend(loc="upper left", bbox_to_anchor=(0.86, 0.98), fontsize=8, frameon=False,
               title="solid: raybench\nhatched: Embree")
    fig.tight_layout(rect=(0, 0, 0.85, 1))
    atomic_save.savefig(fig, os.path.join(out, "trace_matrix.png"), dpi=100)
    plt.close(fig)


def render_speed(out, summary):
    """Per scene: the render's rate over primary-ray tracing and over its own rays traced alone, with
    their 95 % intervals as error bars and the two goals (0.5 and 0.8) as lines."""
    rows = [r for r in summary.get("render", []) if r.get("render_over_primary")]
    if not rows:
        return
    names = [r["scene"] for r in rows][::-1]
    by = {r["scene"]: r for r in rows}

    def series(get):
        v, lo, hi = [], [], []
        for n in names:
            iv = get(by[n]) or {}
            x = iv.get("ratio")
            v.append(x if x is not None else 0)
            a, b = iv.get("lo"), iv.get("hi")
            lo.append(max(x - a, 0) if x is not None and a is not None else 0)
            hi.append(max(b - x, 0) if x is not None and b is not None else 0)
        return v, [lo, hi]

    prim, prim_err = series(lambda r: r.get("render_over_primary"))
    alone, alone_err = series(lambda r: r.get("alone", {}).get("render_over_alone"))
    fig, ax = plt.subplots(figsize=(8.5, 1.2 + 0.32 * len(names)))
    h = 0.38
    y = range(len(names))
    bars = dict(ecolor="0.2", capsize=1.5, error_kw=dict(lw=0.6))
    ax.barh([i + h / 2 for i in y], alone, h, xerr=alone_err, label="render / its own rays traced alone", color="tab:blue", **bars)
    ax.barh([i - h / 2 for i in y], prim, h, xerr=prim_err, label="render / primary-ray tracing", color="tab:orange", **bars)
    ax.axvline(0.8, color="tab:blue", lw=0.8, ls="--", label="0.8 goal (overhead under 20 %)")
    ax.axvline(0.5, color="tab:orange", lw=0.8, ls="--", label="0.5 goal")
    ax.set_yticks(list(y))
    ax.set_yticklabels(names, fontsize=8)
    ax.set_ylim(-0.6, len(names) - 0.4)
    ax.set_xlabel("rate per ray, ratio of medians (error bar: 95 % interval)")
    ax.grid(axis="x", lw=0.3)
    ax.legend(fontsize=7, loc="lower right")
    m = summary["machine"]
    ax.set_title(f"Rendering speed: {m['cpu']}, git {m['git']}", fontsize=9)
    fig.tight_layout()
    atomic_save.savefig(fig, os.path.join(out, "render_speed.png"), dpi=100)
    plt.close(fig)


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "report"
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    simd_speedup(out, summary)
    trace_scaling(out, summary)
    trace_matrix(out, summary)
    plan_models(out, summary)
    render_speed(out, summary)


if __name__ == "__main__":
    main()
