#!/usr/bin/python3
"""Counts the skipped tests of one test tree and names the instruction-set levels that ran.

It also names the tests that tests/mpi/retry_lsan_tracer.cmake ran twice, after LeakSanitizer's
tracer crashed at exit with every test passed.

    scripts/test_summary.py TREE JUNIT.xml [--allowed tests/skips.txt] [--strict]
    scripts/test_summary.py --self-test

JUNIT.xml is ctest's report (`ctest --output-junit`, with `--test-output-size-passed` large enough
to keep the whole output of the mpirun suites). A skip is a test ctest reports as skipped
(GoogleTest's GTEST_SKIP, through the discovered tests' skip expression) or, inside a test that
passed, a GoogleTest "[  SKIPPED ]" line: the suites that mpirun runs whole report their
skips only there, named TEST/Suite.Case. Every skip must match a line of the allowed list,
`TREE NAME-REGEX REASON` (TREE release, asan or *; the regex matches the whole name); with
--strict (scripts/test under FRNN_STRICT=1) any other skip fails the run.

The oracle tests print "frnn oracle tests at instruction-set level: L" once per run; the summary
lists the levels seen and says "L: not run" for each of base, avx2 and avx512 that did not run.
"""
import argparse
import contextlib
import io
import re
import sys
import tempfile
import xml.etree.ElementTree as ElementTree
from pathlib import Path

LEVELS = ("base", "avx2", "avx512")
LEVEL_LINE = re.compile(r"frnn oracle tests at instruction-set level: (\w+)")
GTEST_SKIPPED = re.compile(r"^\[  SKIPPED \] ([\w/.]+\.[\w/]+)", re.MULTILINE)
# tests/mpi/retry_lsan_tracer.cmake's line when it ran a suite twice.
RETRIED = "retry_lsan_tracer: running the suite once more"
# Terminal colours, as GoogleTest prints them under mpirun, and as ctest's report escapes them.
COLOUR = re.compile(r"(\x1b|\[NON-XML-CHAR-0x1B\])\[[0-9;]*m")


def read_allowed(path: Path) -> list[tuple[str, re.Pattern, str]]:
    allowed = []
    for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        parts = line.split(None, 2)
        if len(parts) < 3:
            raise SystemExit(f"{path}:{number}: expected 'TREE NAME-REGEX REASON', got: {line}")
        allowed.append((parts[0], re.compile(parts[1]), parts[2]))
    return allowed


def skips_and_levels(junit: Path) -> tuple[list[str], set[str], int, int]:
    """The skipped test names, the oracle levels that ran, the tests that passed and failed."""
    root = ElementTree.parse(junit).getroot()
    skipped, levels, passed, failed = [], set(), 0, 0
    for case in root.iter("testcase"):
        name = case.get("name", "")
        out = COLOUR.sub("", case.findtext("system-out") or "")
        if case.find("skipped") is not None:
            skipped.append(name)
        elif case.find("failure") is not None or case.get("status") != "run":
            failed += 1
        else:
            passed += 1
            # A test whose own status is "run" but that ran a whole GoogleTest program (mpirun).
            skipped += [f"{name}/{inner}" for inner in dict.fromkeys(GTEST_SKIPPED.findall(out))]
        levels.update(LEVEL_LINE.findall(out))
    return skipped, levels, passed, failed


def retried(junit: Path) -> list[str]:
    """The tests run twice because LeakSanitizer's tracer crashed at exit (retry_lsan_tracer.cmake)."""
    root = ElementTree.parse(junit).getroot()
    return [case.get("name", "") for case in root.iter("testcase") if RETRIED in (case.findtext("system-out") or "")]


def summarize(tree: str, junit: Path, allowed_file: Path, strict: bool) -> int:
    allowed = read_allowed(allowed_file)
    skipped, levels, passed, failed = skips_and_levels(junit)
    listed, unlisted = [], []
    for name in skipped:
        reason = next((r for t, pattern, r in allowed if t in (tree, "*") and pattern.fullmatch(name)), None)
        (listed if reason else unlisted).append((name, reason))
    print(f"{tree}: {passed} passed, {failed} failed, {len(skipped)} skipped")
    print(f"{tree} tree: {len(skipped)} skipped, {len(listed)} of them listed in {allowed_file.name}, "
          f"{len(unlisted)} not listed")
    for name, reason in listed:
        print(f"  skipped {name}: {reason}")
    for name, _ in unlisted:
        print(f"  SKIPPED, NOT LISTED: {name}")
    again = retried(junit)
    if again:
        print(f"{tree} tree: {len(again)} run twice after LeakSanitizer's tracer crashed at exit: {', '.join(again)}")
    ran = [level for level in LEVELS if level in levels]
    print(f"{tree} tree: oracle tests ran at " + (", ".join(ran) if ran else "no instruction-set level"))
    for level in LEVELS:
        if level not in levels:
            print(f"  {level}: not run")
    if unlisted and strict:
        print(f"{tree} tree: {len(unlisted)} skips are not listed in {allowed_file} (FRNN_STRICT=1): "
              "a test that did not run must say why there, or run", file=sys.stderr)
        return 1
    return 0


def self_test() -> int:
    report = """<testsuite>
  <testcase name="a" status="notrun"><skipped message="x"/><system-out>[  SKIPPED ] A.b</system-out></testcase>
  <testcase name="mpi" status="run"><system-out>[NON-XML-CHAR-0x1B][0;32m[  SKIPPED ] [NON-XML-CHAR-0x1B][mM.one (0 ms)
[  SKIPPED ] M.one (0 ms)
frnn oracle tests at instruction-set level: avx2</system-out></testcase>
  <testcase name="c" status="run"><system-out>frnn oracle tests at instruction-set level: base
retry_lsan_tracer: running the suite once more</system-out></testcase>
</testsuite>"""
    with tempfile.TemporaryDirectory() as scratch, contextlib.redirect_stdout(io.StringIO()), \
            contextlib.redirect_stderr(io.StringIO()):
        junit, allowed = Path(scratch) / "r.xml", Path(scratch) / "skips.txt"
        junit.write_text(report)
        skipped, levels, passed, failed = skips_and_levels(junit)
        ok = skipped == ["a", "mpi/M.one"] and levels == {"avx2", "base"} and (passed, failed) == (2, 0)
        ok = ok and retried(junit) == ["c"]
        allowed.write_text("release a listed on purpose\n* mpi/M\\.one needs two ranks\n")
        ok = ok and summarize("release", junit, allowed, True) == 0
        allowed.write_text("asan a only in the other tree\n")
        ok = ok and summarize("release", junit, allowed, True) == 1 and summarize("release", junit, allowed, False) == 0
    if not ok:
        print("test_summary self-test failed", file=sys.stderr)
    return 0 if ok else 1


def main() -> int:
    if sys.argv[1:] == ["--self-test"]:
        return self_test()
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("tree")
    parser.add_argument("junit", type=Path)
    parser.add_argument("--allowed", type=Path, default=Path(__file__).resolve().parent.parent / "tests" / "skips.txt")
    parser.add_argument("--strict", action="store_true")
    args = parser.parse_args()
    return summarize(args.tree, args.junit, args.allowed, args.strict)


if __name__ == "__main__":
    sys.exit(main())
