#!/usr/bin/env python3
"""The engine's layers, checked: a file may include the headers of its own folder and of the
folders below it, never of one above. Run by the build (target rb_layers, before any compile), so
that an include that climbs a layer fails the build with the file, the line and the layers it may use.

    core <- soa <- kernels <- bvh            (the number layer, SoA containers, kernels, the BVH)
    core <- kernels <- scene                 (scenes beside them: loaders, generators, CSG trees)
    tracer: bvh, kernels, scene and below    (a scene ready to trace)
    accuracy, render: tracer and below       (the lab; the recursive renderer)
    bench: tracer, accuracy, render and below
    apps: everything; fuzz and tests: everything
    within apps: results/ uses neither report/ nor cli/; report/ does not use cli/

Usage: check_layers.py SOURCE_DIR      check every include
       check_layers.py --cmake          print the table for CMake, one "layer=below,below" a line
                                        (each layer's include folder: CMakeLists.txt, rb_layer)
"""
import pathlib
import re
import sys

BELOW = {
    "core": set(),
    "soa": {"core"},
    "kernels": {"core", "soa"},
    "bvh": {"core", "soa", "kernels"},
    "scene": {"core", "soa", "kernels"},
    "tracer": {"core", "soa", "kernels", "bvh", "scene"},
    "accuracy": {"core", "soa", "kernels", "bvh", "scene", "tracer"},
    "render": {"core", "soa", "kernels", "bvh", "scene", "tracer"},
    "bench": {"core", "soa", "kernels", "bvh", "scene", "tracer", "accuracy", "render"},
    "apps": {"core", "soa", "kernels", "bvh", "scene", "tracer", "accuracy", "render", "bench"},
}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([a-z_]+)/')
# Folders inside a layer that must not use some of their siblings.
NOT_WITHIN = {
    "apps/results": {"apps/report", "apps/cli"},
    "apps/report": {"apps/cli"},
}
SUB_INCLUDE = re.compile(r'^\s*#\s*include\s+"([a-z_]+/[a-z_]+)/')


def main() -> int:
    if sys.argv[1:] == ["--cmake"]:
        for layer, allowed in BELOW.items():
            print(f"{layer}={','.join(sorted(allowed))}")
        return 0
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
    problems = []
    for layer, allowed in BELOW.items():
        for path in sorted((root / layer).rglob("*")):
            if path.suffix not in {".hpp", ".cpp", ".h", ".in"}:
                continue
            for number, line in enumerate(path.read_text(encoding="utf-8", errors="replace").splitlines(), 1):
                m = INCLUDE.match(line)
                if not m or m.group(1) == layer or m.group(1) in allowed or m.group(1) not in BELOW:
                    continue
                problems.append(f"{path.relative_to(root)}:{number}: includes {m.group(1)}/, a layer above {layer}/ "
                                f"({layer}/ may use {', '.join(sorted(allowed)) or 'nothing else'})")
    for folder, banned in NOT_WITHIN.items():
        for path in sorted((root / folder).rglob("*")):
            if path.suffix not in {".hpp", ".cpp", ".h"}:
                continue
            for number, line in enumerate(path.read_text(encoding="utf-8", errors="replace").splitlines(), 1):
                m = SUB_INCLUDE.match(line)
                if m and m.group(1) in banned:
                    problems.append(f"{path.relative_to(root)}:{number}: includes {m.group(1)}/, which {folder}/ may not use "
                                    f"({folder}/ may not use {', '.join(sorted(banned))})")
    for p in problems:
        print(p, file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
