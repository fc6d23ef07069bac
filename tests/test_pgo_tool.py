#!/usr/bin/python3
"""tools/pgo.py on made-up rounds: the ratios, their intervals and verdicts, the families' geometric
means and the section it writes. Run by ctest (test `pgo_tool`); exits non-zero on a failure."""
import json
import os
import random
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
TOOL = os.path.join(HERE, "..", "tools", "pgo.py")
sys.path.insert(0, os.path.join(HERE, "..", "tools"))
import pgo  # noqa: E402

failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAILED:", what, file=sys.stderr)


# The sign test's interval: 9 rounds leave out the lowest and the highest ratio (k = 2, 96.1 %);
# 6 rounds keep the whole range (k = 1, 96.9 %); 5 rounds cannot reach 95 % (the range, 93.75 %).
iv = pgo.sign_interval([1.09, 1.01, 1.02, 1.03, 1.04, 1.05, 1.06, 1.07, 0.5])
check((iv["ratio"], iv["lo"], iv["hi"], iv["rounds"]) == (1.04, 1.01, 1.07, 9), f"9 rounds: {iv}")
check(abs(iv["coverage"] - (1 - 2 * 10 / 512)) < 1e-12, f"9 rounds' coverage: {iv}")
iv = pgo.sign_interval([1, 2, 3, 4, 5, 6])
check((iv["lo"], iv["hi"]) == (1, 6) and abs(iv["coverage"] - (1 - 2 / 64)) < 1e-12, f"6 rounds: {iv}")
iv = pgo.sign_interval([1, 2, 3, 4, 5])
check((iv["lo"], iv["hi"]) == (1, 5) and abs(iv["coverage"] - 0.9375) < 1e-12, f"5 rounds: {iv}")
check(pgo.verdict({"ratio": 1.1, "lo": 1.05, "hi": 1.2}) == "faster", "faster")
check(pgo.verdict({"ratio": 0.9, "lo": 0.85, "hi": 0.95}) == "slower", "slower")
check(pgo.verdict({"ratio": 1.0, "lo": 0.97, "hi": 1.02}) == "within the noise", "within the noise")
check(pgo.short_name("void rb::bvh::walk<8, rb::A>(rb::Bvh const&, int) [clone .cold]") == "void rb::bvh::walk<8, rb::A> [clone .cold]",
      "short name")

# Made-up rounds: PGO makes family "fast" 20 % faster, "slow" 20 % slower and leaves "same" alone;
# the trace of scene "s" is 10 % faster. Every round multiplies both builds by the same load factor
# and each measurement by its own noise of at most 1 %.
rng = random.Random(5)
truth = {"fast/a/scalar/half": 1.2, "fast/b/scalar/half": 1.2, "slow/a/scalar/half": 1 / 1.2, "same/a/scalar/half": 1.0}
with tempfile.TemporaryDirectory() as d:
    res, out = os.path.join(d, "results"), os.path.join(d, "out")
    for b in ("normal", "pgo"):
        os.makedirs(os.path.join(res, b))
    for rnd in range(1, 10):
        load = rng.uniform(0.7, 1.0)
        for b in ("normal", "pgo"):
            rows = [{"run_name": n, "run_type": "iteration",
                     "tests_per_s": 1e8 * load * (f if b == "pgo" else 1) * rng.uniform(0.99, 1.01)} for n, f in truth.items()]
            with open(os.path.join(res, b, f"bench-{rnd}.json"), "w") as f:
                json.dump({"context": {"raybench_git": "abc1234", "raybench_build_flags": f"-O3 {b}"}, "benchmarks": rows}, f)
            secs = 0.01 / (load * (1.1 if b == "pgo" else 1) * rng.uniform(0.99, 1.01))
            with open(os.path.join(res, b, f"trace-s-diffuse-8-r{rnd}.json"), "w") as f:
                json.dump({"scene": "s", "ray_set": "diffuse", "packet": 8, "rays": 100000, "seconds": [secs]}, f)
    r = subprocess.run([sys.executable, TOOL, res, out, "--honest", "made-up training", "--rounds", "9"],
                       capture_output=True, text=True)
    check(r.returncode == 0, f"the tool ran: {r.stderr}")
    j = json.load(open(os.path.join(out, "pgo.json")))
    fams = {f["kernel"]: f for f in j["families"]}
    for fam, want, word in (("fast", 1.2, "faster"), ("slow", 1 / 1.2, "slower"), ("same", 1.0, "within the noise")):
        p = fams[fam]["pgo"]
        check(p["lo"] <= want <= p["hi"] and abs(p["ratio"] / want - 1) < 0.02, f"{fam}: {p} holds {want}")
        check(pgo.verdict(p) == word, f"{fam}: {pgo.verdict(p)}, not {word}")
        check(p["rounds"] == 9, f"{fam}: 9 rounds")
    check(fams["fast"]["benchmarks"] == 2, "two benchmarks in family fast")
    allk = j["all_kernels"]["pgo"]
    check(abs(allk["ratio"] / 1.2 ** 0.25 - 1) < 0.02, f"all kernels: the geometric mean of the rows' ratios: {allk}")
    t = j["traces"][0]["pgo"]
    check(t["lo"] <= 1.1 <= t["hi"] and pgo.verdict(t) == "faster", f"trace: {t}")
    md = open(os.path.join(out, "pgo.md")).read()
    # Without binaries nothing is profiled: the verdict says so instead of a reason.
    check("| slow | 1 | 0.8" in md and "| slower (not profiled) | 0 / 1 |" in md, "the slow family's row in the section")
    check("| s | diffuse | 8 |" in md and "| faster |" in md, "the trace's row in the section")
    check("Revision measured: `abc1234`" in md, "the revision in the section")
    check(os.path.exists(os.path.join(out, "pgo_kernels.png")) and os.path.exists(os.path.join(out, "pgo_traces.png")), "charts")
    check("tuned" not in md, "no tuned column without a tuned build")
    # A tuned build (here the PGO build's rounds again) gets a column of its own in both tables.
    shutil.copytree(os.path.join(res, "pgo"), os.path.join(res, "tuned"))
    r = subprocess.run([sys.executable, TOOL, res, out, "--honest", "made-up training", "--tuned", "itself"],
                       capture_output=True, text=True)
    md = open(os.path.join(out, "pgo.md")).read()
    check(r.returncode == 0 and md.count("tuned / normal [95 %] |") == 2, f"the tuned columns: {r.stderr}")
    check("- Tuned training workload: itself." in md, "the tuned training named")

# Why a row is slower: the rules on the code of its hottest function in the two builds.
def mix(size=1000, instructions=300, jumps=30, min_max=10, compares=10):
    return {"size": size, "instructions": instructions, "jumps": jumps, "min_max": min_max, "compares": compares}


def why(a, b, hot_a="_ZN2rb1fEv", hot_b="_ZN2rb1fEv", cold_a=0.0, cold_b=0.0):
    return pgo.why_slower({"normal": {"hot": hot_a, "mix": a, "cold_share": cold_a},
                           "pgo": {"hot": hot_b, "mix": b, "cold_share": cold_b}})


check(why(mix(), mix(min_max=2, compares=16, jumps=38))[0] == "min/max became jumps", "min/max compiled as jumps")
check(why(mix(), mix(min_max=14, jumps=20))[0] == "jumps became min/max", "jumps turned into min/max")
check(why(mix(), mix(size=1200))[0] == "grew", "code grown by a fifth")
check(why(mix(), mix(), cold_b=5.0)[0] == "time in .cold code", "time in the .cold part")
check(why(mix(), mix(min_max=2, compares=16, size=1200))[0] == "min/max became jumps; grew", "two rules at once")
check(why(mix(), mix(jumps=20))[0] == "code changed, no rule", "a change no rule names")
check(why(mix(), mix(jumps=32, min_max=9, compares=12, size=1050))[0] == "same code, slower",
      "differences below the thresholds (3 and 10 % of a count or of the size)")
check(why(mix(), mix(), hot_b="_ZN2rb1gEv")[0] == "another hottest function", "another hottest function")
check(pgo.why_slower({"normal": {"hot": "_ZN2rb1fEv", "mix": mix()}, "pgo": None}) is None, "no reason without both profiles")

print(f"pgo_tool: {len(failures)} failures")
sys.exit(1 if failures else 0)
