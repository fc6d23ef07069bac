#!/usr/bin/python3
"""The chart of `raybench history --metric NAME --plot OUT.png`: one metric across the stored runs.

Usage: /usr/bin/python3 tools/history_plot.py SERIES.json OUT.png
       (SERIES.json "-": read from standard input; OUT.png "-": the PNG to standard output, which is
       how raybench calls it, writing the image itself by its one output rule)

SERIES.json is what `raybench history --metric NAME --json` writes: the runs in the order they
were stored (id, time, git revision, dirty flag) and one series of values per figure (null where
a run has no such figure). Up to eight figures get a line each; more are drawn as their geometric
mean per run with the range of the figures shaded, so that a regression across many benchmarks
shows as one step.
"""
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import atomic_save  # noqa: E402

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    if sys.argv[1] == "-":
        doc = json.load(sys.stdin)
    else:
        with open(sys.argv[1]) as f:
            doc = json.load(f)
    runs, series = doc["runs"], doc["series"]
    if not runs or not series:
        sys.exit("history_plot.py: nothing to draw")
    labels = [f"{r['git_revision']}{'*' if r['git_dirty'] else ''}\n{r['time'][:10]}\nrun {r['id']}" for r in runs]
    x = list(range(len(runs)))
    direction = {1: "higher is better", -1: "lower is better"}.get(doc.get("direction"), "")
    fig, ax = plt.subplots(figsize=(max(6.0, 1.1 * len(runs) + 3), 4.5))
    if len(series) <= 8:
        for s in series:
            pts = [(i, v) for i, v in zip(x, s["values"]) if v is not None]
            ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", label=s["name"])
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
        title = f"{doc['metric']} across runs"
    else:
        gm, lo, hi = [], [], []
        for i in x:
            v = [s["values"][i] for s in series if s["values"][i] is not None and s["values"][i] > 0]
            gm.append(math.exp(sum(math.log(a) for a in v) / len(v)) if v else float("nan"))
            lo.append(min(v) if v else float("nan"))
            hi.append(max(v) if v else float("nan"))
        ax.fill_between(x, lo, hi, alpha=0.2, label=f"range over {len(series)} figures")
        ax.plot(x, gm, "o-", label="geometric mean")
        ax.set_yscale("log")
        ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
        title = f"{doc['metric']} across runs: {len(series)} figures"
    if doc.get("filter"):
        title += f" matching '{doc['filter']}'"
    ax.set_title(title, fontsize=10)
    ax.set_xticks(x)
    ax.set_xticklabels(labels, fontsize=7)
    ax.set_xlabel("run (git revision at build time; * dirty)")
    ax.set_ylabel(f"{doc['metric']} ({doc['unit']}{', ' + direction if direction else ''})")
    ax.grid(True, lw=0.3)
    fig.tight_layout()
    if sys.argv[2] == "-":
        fig.savefig(sys.stdout.buffer, format="png", dpi=100)
        sys.stdout.buffer.flush()
    else:
        atomic_save.savefig(fig, sys.argv[2], dpi=100)
    plt.close(fig)


if __name__ == "__main__":
    main()
