#!/usr/bin/env python3
"""The AVX-512 translation units (bench/simd16_*.cpp, tracer/traverse_mesh16.cpp) must not define a
function that another translation unit may also define: the linker keeps one copy of such a
(weak) function, and if it kept the AVX-512 one, the binary would fault on a CPU without AVX-512.
Run by the build on the object file: every externally visible function in it that uses an AVX-512
register or encoding (an EVEX prefix: also the AVX-512 VL instructions on ymm0-15) must be one of its
own (its name mentions run_simd16, simd16 or xsimd's avx512 architecture, so no AVX2 file can define it).

Usage: check_simd16.py OBJDUMP OBJECT...
"""
import re
import subprocess
import sys

OWN = re.compile(r"simd16|avx512")
# AVX-512 only: zmm registers, mask registers k1-k7, xmm/ymm 16-31, embedded broadcast or masking.
AVX512 = re.compile(r"%zmm|%k[1-7]\b|%[xy]mm(1[6-9]|2[0-9]|3[01])\b|\{1to\d+\}|\{%k")
# Segment and address-size prefixes may precede an EVEX prefix (0x62, in 64-bit mode always EVEX).
LEGACY_PREFIXES = {"26", "2e", "36", "3e", "64", "65", "67"}


def main() -> int:
    objdump, objects = sys.argv[1], sys.argv[2:]
    problems = []
    for obj in objects:
        syms = subprocess.run([objdump, "-t", obj], capture_output=True, text=True, check=True).stdout
        visible = set()
        for line in syms.splitlines():
            # "ADDR FLAGS SECTION SIZE NAME", FLAGS seven columns: global (g) or unique (u) in the
            # first, weak (w) in the second, F (function) in the last.
            flags = line[17:24]
            if len(flags) == 7 and flags[6] == "F" and (flags[0] in "gu" or flags[1] == "w"):
                visible.add(line.split()[-1])
        dis = subprocess.run([objdump, "-d", obj], capture_output=True, text=True, check=True).stdout
        current = None
        flagged = set()
        for line in dis.splitlines():
            m = re.match(r"^[0-9a-f]+ <(.+)>:$", line)
            if m:
                current = m.group(1)
                continue
            if not current or current not in visible or current in flagged or OWN.search(current):
                continue
            # "ADDR:\tBYTES\tINSTRUCTION"; a long instruction's remaining bytes follow on a line without one.
            parts = line.split("\t")
            if len(parts) < 3:
                continue
            raw = parts[1].split()
            while raw and raw[0] in LEGACY_PREFIXES:
                raw = raw[1:]
            if (raw and raw[0] == "62") or AVX512.search(parts[2]):
                flagged.add(current)
                problems.append(f"{obj}: {current} is visible to other files and holds AVX-512 code ({line.strip()})")
    for p in problems:
        print(p, file=sys.stderr)
    if problems:
        print("the AVX-512 files (targets rb_simd16, rb_simd16_ops, rb_tracer_simd16) must define only their own functions (bench/simd16.hpp and tracer/traverse_mesh16.cpp explain why)", file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
