#!/usr/bin/python3
"""Charts for `raybench report`: reads OUT/summary.json, writes PNGs into OUT.

Called by the report; run it by hand as: /usr/bin/python3 tools/charts.py report
"""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def simd_speedup(out, summary):
    rows = summary.get("simd_vs_scalar", [])
    if not rows:
        return
    labels, rays, prims = [], [], []
    for r in rows:
        labels.append(f"{r['kernel']}/{r['method']}\n{r['case']}")
        rays.append(r["speedup_rays_in_lanes"])
        prims.append(r["speedup_prims_in_lanes"])
    fig, ax = plt.subplots(figsize=(max(8, 0.55 * len(labels)), 5))
    x = range(len(labels))
    w = 0.4
    ax.bar([i - w / 2 for i in x], rays, w, label="8 rays x 1 primitive")
    ax.bar([i + w / 2 for i in x], prims, w, label="1 ray x 8 primitives")
    ax.axhline(8, color="grey", lw=0.8, ls=":", label="8 lanes")
    ax.axhline(6, color="red", lw=0.8, ls="--", label="target 6x")
    ax.set_xticks(list(x))
    ax.set_xticklabels(labels, rotation=60, ha="right", fontsize=7)
    ax.set_ylabel("speedup over true scalar (median tests/s ratio)")
    m = summary["machine"]
    ax.set_title(f"SIMD speedup, L1-resident, one thread\n{m['cpu']}, -ffp-contract={m['fp_contract']}, git {m['git']}", fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "simd_speedup.png"), dpi=110)
    plt.close(fig)


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "report"
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    simd_speedup(out, summary)


if __name__ == "__main__":
    main()
