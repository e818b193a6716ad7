#!/usr/bin/env python3
"""Checks frnn's layering (docs/ARCHITECTURE.md): each folder includes only the headers of the
layers below it. Prints every include that breaks a rule, with file and line, and exits 1 if any.

    scripts/check_includes.py [SOURCE_DIR]
    scripts/check_includes.py --self-test   # the checker finds a planted violation
"""
import re
import sys
import tempfile
from pathlib import Path

# The public headers of the core layer (include/frnn/*.hpp without vulkan.hpp, and detail/).
CORE = r"frnn/(?!vulkan\.hpp|io/|sim/|bench/|mpi/)[a-z_]+(\.hpp|/[a-z_]+\.hpp)"
VULKAN = r"frnn/vulkan\.hpp|frnn/grid\.glsl"
MPI = r"frnn/mpi/[a-z_]+\.hpp"
LOCAL = r'[a-z0-9_]+\.(hpp|glsl)'  # a header beside the file (quoted includes search there first)
# frnn::io's file utilities (not its point readers and writers): atomic files, child programs, plots.
IO_FILES = r"frnn/io/(atomic_file|child_process|gnuplot)\.hpp"

# Folder -> what its quoted includes may name. Tests and examples may use everything.
RULES = {
    "include/frnn": [CORE],
    "include/frnn/mpi": [CORE, MPI],
    "src/cpu": [CORE, r"cpu/.*"],
    "src/core": [CORE, r"cpu/.*", r"core/.*"],
    "src/io": [CORE, r"frnn/io/.*", LOCAL],
    "src/mpi": [CORE, MPI, r"mpi/.*"],
    # The Vulkan grid shares the CPU grid's policies: kind choice and cell rules.
    "src/vulkan": [CORE, VULKAN, r"core/(kind_policy|cell_rules)\.hpp", LOCAL],
    "sim": [CORE, r"frnn/sim/.*", IO_FILES, LOCAL],
    "python/src": [CORE, VULKAN, LOCAL],
    "bench": [CORE, VULKAN, MPI, r"frnn/bench/.*", IO_FILES, r"frnn/sim/.*"],
    "apps": [CORE, VULKAN, MPI, r"frnn/(io|sim|bench)/.*", LOCAL],
}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')


def check(root: Path) -> list[str]:
    problems = []
    for folder, allowed in RULES.items():
        pattern = re.compile("|".join(f"(?:{a})" for a in allowed))
        # A subfolder with rules of its own (include/frnn/mpi) follows those.
        nested = [root / f for f in RULES if f.startswith(folder + "/")]
        for path in sorted((root / folder).rglob("*")):
            if path.suffix not in (".hpp", ".cpp", ".h", ".glsl", ".comp") or any(n in path.parents for n in nested):
                continue
            for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
                m = INCLUDE.match(line)
                if m and not pattern.fullmatch(m.group(1)):
                    problems.append(f"{path.relative_to(root)}:{number}: {folder} may not include \"{m.group(1)}\"")
    return problems


def self_test() -> int:
    """Plants one allowed and one forbidden include in a scratch tree: only the second is reported."""
    with tempfile.TemporaryDirectory() as scratch:
        root = Path(scratch)
        for folder in RULES:
            (root / folder).mkdir(parents=True)
        (root / "src/core/ok.cpp").write_text('#include "frnn/grid.hpp"\n#include "cpu/parallel.hpp"\n')
        (root / "src/core/bad.cpp").write_text('#include <vector>\n#include "frnn/sim/scene.hpp"\n')
        found = check(root)
    expected = ['src/core/bad.cpp:2: src/core may not include "frnn/sim/scene.hpp"']
    if found != expected:
        print(f"check_includes self-test: found {found}, expected {expected}", file=sys.stderr)
        return 1
    return 0


def main() -> int:
    if sys.argv[1:] == ["--self-test"]:
        return self_test()
    root = Path(sys.argv[1] if len(sys.argv) > 1 else Path(__file__).resolve().parent.parent)
    missing = [f for f in RULES if not (root / f).is_dir()]
    if missing:
        print(f"check_includes: no folder {', '.join(missing)} under {root}", file=sys.stderr)
        return 2
    problems = check(root)
    for p in problems:
        print(p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
