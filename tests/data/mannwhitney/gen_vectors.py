#!/usr/bin/python3
"""Test vectors for raybench's Mann-Whitney U test (apps/results/stats.cpp), from SciPy.

Run: /usr/bin/python3 tests/data/mannwhitney/gen_vectors.py > tests/data/mannwhitney/vectors.json

Each vector is two samples and what scipy.stats.mannwhitneyu(a, b, alternative="two-sided")
returns with its defaults (method "auto", continuity correction), which is what Google
Benchmark's compare.py reports: exact p for samples of at most 8 without ties, the normal
approximation with tie and continuity correction otherwise. The samples are seeded and cover both
methods, ties, all-equal samples, single values, unequal sizes and timing-like data.
"""
import json
import random

import scipy
from scipy.stats import mannwhitneyu


def main():
    rng = random.Random(20)
    cases = []

    def add(a, b, what):
        r = mannwhitneyu(a, b, alternative="two-sided")
        cases.append({"what": what, "a": a, "b": b, "u1": float(r.statistic), "p": float(r.pvalue)})

    add([1.0, 2.0, 3.0], [4.0, 5.0, 6.0], "3 vs 3 separated (exact, smallest p)")
    add([1.0, 2.0], [3.0, 4.0], "2 vs 2 separated (exact)")
    add([1.0], [2.0], "1 vs 1 (exact)")
    add([1.0, 3.0, 5.0, 7.0, 9.0], [2.0, 4.0, 6.0, 8.0, 10.0], "5 vs 5 interleaved (exact)")
    add([5.0, 5.0, 5.0], [5.0, 5.0, 5.0], "all equal (asymptotic, zero variance)")
    add([1.0, 2.0, 2.0, 3.0], [2.0, 3.0, 4.0, 4.0], "ties, small (asymptotic)")
    add([float(i) for i in range(9)], [float(i) + 0.5 for i in range(9)], "9 vs 9 (asymptotic)")
    add([float(i) for i in range(8)], [float(i) + 100 for i in range(30)], "8 vs 30 separated (exact, one sample <= 8)")
    for k in range(40):
        n1 = rng.randint(2, 14)
        n2 = rng.randint(2, 14)
        shift = rng.choice([0.0, 0.01, 0.03, 0.1])
        a = [round(1.0 + rng.gauss(0, 0.02), 6) for _ in range(n1)]
        b = [round(1.0 + shift + rng.gauss(0, 0.02), 6) for _ in range(n2)]
        if k % 5 == 0:  # coarse values: ties
            a = [round(x, 2) for x in a]
            b = [round(x, 2) for x in b]
        add(a, b, f"random {n1} vs {n2}, shift {shift}{', rounded (ties)' if k % 5 == 0 else ''}")
    add([rng.gauss(10, 1) for _ in range(60)], [rng.gauss(10.3, 1) for _ in range(45)], "60 vs 45 (asymptotic)")
    head = json.dumps("scipy.stats.mannwhitneyu(a, b, alternative='two-sided'), scipy " + scipy.__version__)
    print('{"generator": ' + head + ',\n "cases": [')
    print(",\n".join("  " + json.dumps(c) for c in cases))
    print(" ]}")


if __name__ == "__main__":
    main()
