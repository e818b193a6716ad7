#!/usr/bin/python3
"""Runs the shell and Python blocks of frnn's Markdown docs, and checks their figures tables.

    run_doc_blocks.py --source DIR --build DIR FILE.md      run FILE's blocks in order
    run_doc_blocks.py --source DIR --check-figures FILE.md ...   figures and references only
    run_doc_blocks.py --self-test                            the checks find planted faults

Blocks: a fence tagged sh or bash runs with `bash -e -o pipefail`, one tagged python with
Debian's /usr/bin/python3; other tags (text, cpp, json, ...) are shown, not run, and a fence
without a tag is an error, so that no command hides in an untagged block. The last non-blank
line before a fence may be

    <!-- not run: REASON -->            the block is skipped (the reason is required), or
    <!-- test with: "A" -> "B" -->      A is replaced by B in the test only (one line each;
                                        A must occur in the block): small sizes for long runs.

All blocks of one file run in one fresh scratch folder, as a user in one terminal would, with
the project's top-level entries linked into it (so `build/release/apps/frnn/frnn` and
`sim/scenes/...` work as written) and the files they write landing in it; the folder is removed
afterwards, also on failure. `frnn`, `frnn-view` and `frnn_mpi_bench` are on PATH (as after
`cmake --install`), before a fresh Debian's PATH; `import frnn` finds the build's module; and
OpenMPI may run as root and start more ranks than cores (its environment variables,
docs/TROUBLESHOOTING.md).

Links: a relative link must name an existing file and, with #anchor, one of its headings.
Figures: every Markdown table with numeric cells needs a line `Measured: COMMIT, DATE, MACHINE,
N cores` in its section or a section above it, unless the line before it says
`<!-- not figures: REASON -->` (a table of definitions or settings, not of measurements). No
file may send the reader to a guide of figures outside the repository (OUTSIDE_GUIDE).
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

RUN_TAGS = {"sh": "bash", "bash": "bash", "python": "python"}
BLOCK_TIMEOUT = 150  # seconds; the whole `docs` label stays under 3 minutes
FENCE = re.compile(r"^(\s*)(```+)\s*([^\s`]*)\s*$")
NOT_RUN = re.compile(r"^<!--\s*not run:\s*(.*?)\s*-->$")
NOT_FIGURES = re.compile(r"^<!--\s*not figures:\s*\S.*-->$")
TEST_WITH = re.compile(r'^<!--\s*test with:\s*"(.*)"\s*->\s*"(.*)"\s*-->$')
MEASURED = re.compile(r"^Measured:\s.*\b[0-9a-f]{7,40}\b.*\b\d{4}-\d{2}-\d{2}\b.*\b\d+ cores?\b")
HEADING = re.compile(r"^(#{1,6})\s")
# A cell holding a measured number: digits with an optional unit or ratio sign, possibly bold.
NUMBER = re.compile(r"^[~<>≈+-]?\**\s*[\d,]*\.?\d+(e[-+]?\d+)?\s*(x|×|%|ns|µs|us|ms|s|MB|GB|MiB|GiB)?\**$")
# Built from parts so that this file does not match the check itself.
OUTSIDE_GUIDE = re.compile("bench" + "mark guide|BENCH" + "MARKS\\.md", re.IGNORECASE)
TEXT_SUFFIXES = {".md", ".cpp", ".hpp", ".h", ".py", ".sh", ".cmake", ".json", ".toml", ".txt", ".glsl", ".comp", ".in"}


class Block:
    def __init__(self, line, tag, text, not_run, replacements):
        self.line, self.tag, self.text = line, tag, text
        self.not_run, self.replacements = not_run, replacements


def parse_blocks(path: Path) -> tuple[list[Block], list[str]]:
    """The fenced blocks of a Markdown file with their markers, and the problems found."""
    lines = path.read_text(encoding="utf-8").splitlines()
    blocks, problems = [], []
    i = 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        indent, ticks, tag = m.group(1), m.group(2), m.group(3).lower()
        start = i + 1
        j = start
        while j < len(lines) and not re.match(rf"^\s*{ticks}\s*$", lines[j]):
            j += 1
        if j == len(lines):
            problems.append(f"{path}:{i + 1}: a fence that is never closed")
            break
        body = [line[len(indent):] if line.startswith(indent) else line.lstrip() for line in lines[start:j]]
        if not tag:
            problems.append(f"{path}:{i + 1}: a fence without a language tag (```sh, ```python, ```text, ...)")
        # The markers: the non-blank lines right before the fence that are marker comments.
        not_run, replacements = None, []
        k = i - 1
        while k >= 0 and not lines[k].strip():
            k -= 1
        while k >= 0:
            text = lines[k].strip()
            if (n := NOT_RUN.match(text)) is not None:
                not_run = n.group(1)
                if not not_run:
                    problems.append(f"{path}:{k + 1}: 'not run' without a reason")
            elif (t := TEST_WITH.match(text)) is not None:
                replacements.insert(0, (t.group(1), t.group(2)))
            else:
                break
            k -= 1
        block = Block(start, tag, "\n".join(body) + "\n", not_run, replacements)
        for old, _ in replacements:
            if old not in block.text:
                problems.append(f'{path}:{start}: test-with marker "{old}" does not occur in the block')
        if (not_run is not None or replacements) and tag not in RUN_TAGS:
            problems.append(f"{path}:{start}: a marker before a ```{tag} block, which is never run")
        blocks.append(block)
        i = j + 1
    return blocks, problems


def check_figures(path: Path) -> list[str]:
    """Tables of numbers without a Measured line in their section (or one above it)."""
    lines = path.read_text(encoding="utf-8").splitlines()
    problems = []
    # measured[level] is true when the current section at that heading level has a Measured line.
    measured = [False] * 7
    level = 0
    in_fence = False
    pending = []  # tables of the current section not yet covered: (line number, level)

    def close_section(down_to):
        nonlocal pending
        still = []
        for number, lvl in pending:
            if any(measured[: lvl + 1]):
                continue
            if lvl >= down_to:
                problems.append(f"{path}:{number}: a table of figures without a 'Measured: COMMIT, DATE, "
                                "MACHINE, N cores' line in its section")
            else:
                still.append((number, lvl))
        pending = still

    i = 0
    while i < len(lines):
        line = lines[i]
        if FENCE.match(line):
            in_fence = not in_fence
            i += 1
            continue
        if in_fence:
            i += 1
            continue
        if (h := HEADING.match(line)) is not None:
            new = len(h.group(1))
            close_section(new)
            for lvl in range(new, 7):
                measured[lvl] = False
            level = new
        elif MEASURED.match(line.strip()):
            measured[level] = True
        elif line.lstrip().startswith("Measured:"):
            problems.append(f"{path}:{i + 1}: a Measured line needs a commit, a date (YYYY-MM-DD), "
                            "the machine and its cores: " + line.strip())
        elif line.lstrip().startswith("|") and i + 1 < len(lines) and re.match(r"^\s*\|[\s:|-]+\|\s*$", lines[i + 1]):
            start = i
            i += 2
            numbers = 0
            while i < len(lines) and lines[i].lstrip().startswith("|"):
                cells = [c.strip() for c in lines[i].strip().strip("|").split("|")]
                numbers += sum(1 for c in cells[1:] if NUMBER.match(c))
                i += 1
            before = start - 1
            while before >= 0 and not lines[before].strip():
                before -= 1
            exempt = before >= 0 and NOT_FIGURES.match(lines[before].strip())
            if numbers >= 2 and not exempt:
                pending.append((start + 1, level))
            continue
        i += 1
    close_section(0)
    return problems


LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)\)")


def heading_anchors(path: Path) -> set[str]:
    """GitHub's anchors of a Markdown file's headings: lower case, punctuation dropped, spaces
    to hyphens, repeats numbered."""
    anchors, seen = set(), {}
    in_fence = False
    for line in path.read_text(encoding="utf-8").splitlines():
        if FENCE.match(line):
            in_fence = not in_fence
        if in_fence or not HEADING.match(line):
            continue
        slug = re.sub(r"[^\w\- ]", "", line.lstrip("#").strip().lower().replace("`", "")).replace(" ", "-")
        count = seen.get(slug, 0)
        seen[slug] = count + 1
        anchors.add(slug if count == 0 else f"{slug}-{count}")
    return anchors


def check_links(path: Path) -> list[str]:
    """Relative links whose file, or whose heading anchor, does not exist."""
    problems = []
    in_fence = False
    for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        if FENCE.match(line):
            in_fence = not in_fence
        if in_fence:
            continue
        for target in LINK.findall(line):
            if re.match(r"^[a-z]+:", target):
                continue
            file, _, anchor = target.partition("#")
            linked = (path.parent / file).resolve() if file else path
            if not linked.exists():
                problems.append(f"{path}:{number}: a link to {file}, which does not exist")
            elif anchor and linked.suffix == ".md" and anchor not in heading_anchors(linked):
                problems.append(f"{path}:{number}: a link to {target}: {linked.name} has no heading '#{anchor}'")
    return problems


def check_references(path: Path) -> list[str]:
    return [f"{path}:{n}: refers to a guide outside the repository: {line.strip()}"
            for n, line in enumerate(path.read_text(encoding="utf-8", errors="replace").splitlines(), 1)
            if OUTSIDE_GUIDE.search(line)]


def tree_references(source: Path) -> list[str]:
    """References to an outside guide in any text file of the source tree (not build trees)."""
    problems = []
    for folder, dirs, names in os.walk(source):
        dirs[:] = [d for d in dirs if d not in (".git", "build") and not d.startswith("build-")]
        for name in names:
            path = Path(folder) / name
            if path.suffix in TEXT_SUFFIXES or name in ("CMakeLists.txt", "LICENSE"):
                problems += check_references(path)
    return problems


def environment(build: Path) -> dict:
    env = dict(os.environ)
    # A fresh Debian 12's PATH after the install (a pyenv or conda python3 first on the
    # machine's PATH is not the README's set-up: docs/TROUBLESHOOTING.md covers it).
    paths = [build / "apps" / "frnn", build / "bench", "/usr/local/sbin", "/usr/local/bin", "/usr/sbin",
             "/usr/bin", "/sbin", "/bin"]
    env["PATH"] = os.pathsep.join(str(p) for p in paths)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(build / "python"), env.get("PYTHONPATH")]))
    # OpenMPI refuses root and more ranks than slots unless told (docs/TROUBLESHOOTING.md).
    env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1", PRTE_MCA_rmaps_default_mapping_policy=":oversubscribe")
    env.pop("DISPLAY", None)
    return env


def lay_out_scratch(scratch: Path, source: Path, build: Path) -> None:
    """Links the project's top-level entries into the scratch folder; build/release is the build."""
    for entry in source.iterdir():
        if entry.name in (".git", "build"):
            continue
        (scratch / entry.name).symlink_to(entry)
    (scratch / "build").mkdir()
    (scratch / "build" / "release").symlink_to(build)


def run_file(path: Path, source: Path, build: Path) -> int:
    blocks, problems = parse_blocks(path)
    for p in problems:
        print(p, file=sys.stderr)
    if problems:
        return 1
    env = environment(build)
    failures = 0
    with tempfile.TemporaryDirectory(prefix="frnn-docs-") as scratch:
        lay_out_scratch(Path(scratch), source, build)
        for block in blocks:
            where = f"{path.relative_to(source)}:{block.line}"
            if block.tag not in RUN_TAGS:
                continue
            if block.not_run is not None:
                print(f"{where}: not run: {block.not_run}")
                continue
            text = block.text
            for old, new in block.replacements:
                text = text.replace(old, new)
            command = (["bash", "-e", "-o", "pipefail", "-c", text] if RUN_TAGS[block.tag] == "bash"
                       else ["/usr/bin/python3", "-c", text])
            began = time.monotonic()
            try:
                done = subprocess.run(command, cwd=scratch, env=env, capture_output=True, text=True,
                                      timeout=BLOCK_TIMEOUT, stdin=subprocess.DEVNULL)
                status = done.returncode
                output = done.stdout + done.stderr
            except subprocess.TimeoutExpired as e:
                status = f"timed out after {BLOCK_TIMEOUT} s"
                output = (e.stdout or b"").decode(errors="replace") + (e.stderr or b"").decode(errors="replace")
            seconds = time.monotonic() - began
            if status == 0:
                print(f"{where}: ran ({block.tag}, {seconds:.1f} s)")
                continue
            failures += 1
            print(f"{where}: FAILED ({status}) after {seconds:.1f} s. The block as run:\n{text}"
                  f"Its output (last 40 lines):\n" + "\n".join(output.splitlines()[-40:]), file=sys.stderr)
    return 1 if failures else 0


def self_test() -> int:
    """Plants each fault the checks look for in a scratch file: every one must be reported."""
    cases = {
        "untagged": ("```\nls\n```\n", "without a language tag"),
        "reasonless": ("<!-- not run: -->\n```sh\nls\n```\n", "without a reason"),
        "stale": ('<!-- test with: "lattice:100" -> "lattice:8" -->\n```sh\nls\n```\n', "does not occur"),
        "unmeasured": ("## Speed\n| a | ms |\n|---|---:|\n| x | 1.5 |\n| y | 2.5 ms |\n", "without a 'Measured"),
        "definitions": ("## W\n<!-- not figures: -->\n| a | n |\n|---|---:|\n| x | 1 |\n| y | 2 |\n", "without a 'Measured"),
        "incomplete": ("## Speed\nMeasured: 2026-12-01, 2 cores.\n", "needs a commit"),
        "guide": ("see the " + "bench" + "mark guide\n", "outside the repository"),
        "dead link": ("see [there](nowhere.md)\n", "does not exist"),
        "dead anchor": ("# Top\nsee [here](#bottom)\n", "has no heading"),
    }
    good = ("# T `x`, y\n[up](#t-x-y)\nMeasured: 1234abc, 2026-12-01, Some CPU, 2 cores.\n## Sub\n| a | ms |\n|---|---:|\n"
            "| x | 1.5 |\n| y | 2 |\n## Defs\n<!-- not figures: definitions -->\n| a | n |\n|---|---:|\n| x | 1 |\n| y | 2 |\n"
            "\n<!-- not run: needs a window -->\n```sh\nfrnn view\n```\n")
    failures = 0
    with tempfile.TemporaryDirectory() as scratch:
        for name, (text, expected) in {**cases, "good": (good, None)}.items():
            path = Path(scratch) / f"{name}.md"
            path.write_text(text)
            found = parse_blocks(path)[1] + check_figures(path) + check_references(path) + check_links(path)
            ok = (not found) if expected is None else any(expected in p for p in found)
            if not ok:
                print(f"self-test {name}: found {found}, expected {expected or 'nothing'}", file=sys.stderr)
                failures += 1
    return 1 if failures else 0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--source", type=Path)
    parser.add_argument("--build", type=Path)
    parser.add_argument("--check-figures", action="store_true")
    parser.add_argument("--self-test", action="store_true")
    parser.add_argument("files", nargs="*", type=Path)
    args = parser.parse_args()
    if args.self_test:
        return self_test()
    if not args.source or not args.files:
        parser.error("--source and at least one FILE.md are needed")
    source = args.source.resolve()
    files = [f if f.is_absolute() else source / f for f in args.files]
    if args.check_figures:
        problems = [p for f in files for p in check_figures(f) + parse_blocks(f)[1] + check_links(f)]
        problems += tree_references(source)
        for p in problems:
            print(p, file=sys.stderr)
        print(f"{len(files)} files checked, {len(problems)} problems")
        return 1 if problems else 0
    if not args.build:
        parser.error("--build is needed to run blocks")
    return max(run_file(f, source, args.build.resolve()) for f in files)


if __name__ == "__main__":
    sys.exit(main())
