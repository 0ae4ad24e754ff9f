"""Benchmark: how fast `vkgc` starts, as whole processes, against the targets of issue 22.

    python bench/lang/bench_startup.py [--runs N] [--instructions]

Prints two Markdown tables. The first: wall time (median of `--runs` runs,
default 7) and CPU time (user + system, median) of `python -c pass` for scale,
`vkgc --help`, `vkgc check` and `vkgc fmt --check` of an example, `vkgc check`
of tasks a, g (a drawer) and k (a region goal) and `vkgc solve` of tasks a and
b, with the targets:

- `vkgc check` on an example: at most 0.2 s wall;
- `vkgc solve` of a paper task (a_push, b_stick_push): at most 0.5 s wall.

With `--instructions` (needs valgrind) each command also runs once under
`valgrind --tool=callgrind`: the instructions it executed (billions), which the
load of a shared machine does not change, and the seconds they project to at
`--rate` billion instructions per second (default 3.5: what this machine ran
`vkgc check` at under a load of 14, CPU time over instructions; idle it runs
faster, so the projection errs long. Measure the rate on an idle machine as
the `vkgc check` row's instructions over its CPU time).

The second: where `vkgc check`'s imports go, from `python -X importtime`
(each module's own time, summed by top-level package), and which of SciPy,
DART, NLopt and OMPL it loaded (none, since docs/internals.md "Start-up time").

Every process runs as an installed `vkgc` would: bytecode is written and
reused (PYTHONDONTWRITEBYTECODE is dropped), and the cache folder (the
grammar's tables, the parses of module files, DART's verdicts on URDFs, the
bodies' hulls, the arm's reach) is a fresh one that one untimed run of each
command fills first. The first line of the
table is that cold first `check`. On a busy machine wall times grow with the
load and CPU times much less: compare the CPU column with `python -c pass`'s
when the wall times look wrong.
"""

from __future__ import annotations

import argparse
import os
import re
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
CHECKED = "examples/tasks/b_stick_push.vkg"
ALSO_CHECKED = ("examples/tasks/g_open_drawer.vkg", "examples/tasks/k_region_goal.vkg")
"""A drawer (its contact points and frames on a union's surface) and a region goal (its fit): `check`s that
once imported trimesh and SciPy."""
HEAVY = ("scipy", "dartpy", "nlopt", "ompl")


def environment(cache: str) -> dict[str, str]:
    """The environment of a `vkgc` as installed: this checkout first, bytecode kept, its own cache folder."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    env["PYTHONPATH"] = str(REPO)
    env["VKGL_CACHE_DIR"] = cache
    return env


def run_once(argv: list[str], env: dict[str, str]) -> tuple[float, float]:
    """Wall and CPU (user + system) seconds of one process."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run(argv, env=env, cwd=REPO, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def medians(argv: list[str], env: dict[str, str], runs: int) -> tuple[float, float]:
    """Median wall and median CPU seconds of `runs` processes."""
    times = [run_once(argv, env) for _ in range(runs)]
    return statistics.median(t[0] for t in times), statistics.median(t[1] for t in times)


def instructions(argv: list[str], env: dict[str, str]) -> float:
    """Billions of instructions one process executes, counted by callgrind (the load does not change them)."""
    with tempfile.TemporaryDirectory(prefix="vkgl-bench-callgrind-") as folder:
        out = Path(folder) / "callgrind.out"
        result = subprocess.run(
            ["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", *argv],
            env=env,
            cwd=REPO,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.PIPE,
            text=True,
            check=True,
        )
    found = re.search(r"Collected\s*:\s*(\d+)", result.stderr)
    if found is None:
        raise RuntimeError(f"callgrind printed no count: {result.stderr[-500:]}")
    return int(found.group(1)) / 1e9


def row(what: str, wall: float, cpu: float, target: float | None = None, counted: str = "") -> str:
    shown_target = "" if target is None else f"<= {target * 1000:.0f} ms"
    verdict = "" if target is None else ("ok" if wall <= target else "SLOW")
    return f"| {what} | {wall * 1000:.0f} ms | {cpu * 1000:.0f} ms |{counted} {shown_target} | {verdict} |"


def counted_cells(argv: list[str], env: dict[str, str], rate: float, target: float | None) -> str:
    """The instructions and projected-seconds cells of a row (with the projection's verdict against `target`)."""
    billions = instructions(argv, env)
    projected = billions / rate
    verdict = "" if target is None else (" ok" if projected <= target else " SLOW")
    return f" {billions:.3f} G | {projected * 1000:.0f} ms{verdict} |"


def import_breakdown(env: dict[str, str]) -> tuple[dict[str, float], set[str]]:
    """Seconds of `vkgc check`'s imports by top-level package (own times), and which heavy packages it loaded."""
    argv = [sys.executable, "-X", "importtime", "-m", "vkgl.cli", "check", CHECKED]
    result = subprocess.run(argv, env=env, cwd=REPO, capture_output=True, text=True, check=True)
    totals: dict[str, float] = defaultdict(float)
    for line in result.stderr.splitlines():
        match = re.match(r"import time:\s+(\d+) \|\s+\d+ \| (\s*)(\S+)", line)
        if match:
            totals[match.group(3).split(".")[0]] += int(match.group(1)) / 1e6
    return dict(totals), set(totals) & set(HEAVY)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--runs", type=int, default=7)
    parser.add_argument("--instructions", action="store_true", help="also count instructions with callgrind")
    parser.add_argument("--rate", type=float, default=3.5, help="billion instructions per second")
    args = parser.parse_args()
    runs = max(1, args.runs)
    if args.instructions and shutil.which("valgrind") is None:
        parser.error("--instructions needs valgrind on the PATH")

    python = [sys.executable]
    vkgc = [sys.executable, "-m", "vkgl.cli"]
    commands = [
        ("`python -c pass` (for scale)", [*python, "-c", "pass"], None),
        ("`vkgc --help`", [*vkgc, "--help"], None),
        (f"`vkgc check {CHECKED}`", [*vkgc, "check", CHECKED], 0.2),
        (f"`vkgc fmt --check {CHECKED}`", [*vkgc, "fmt", "--check", CHECKED], None),
        ("`vkgc check examples/tasks/a_push.vkg`", [*vkgc, "check", "examples/tasks/a_push.vkg"], 0.2),
        *((f"`vkgc check {path}`", [*vkgc, "check", path], 0.2) for path in ALSO_CHECKED),
        ("`vkgc solve examples/tasks/a_push.vkg`", [*vkgc, "solve", "examples/tasks/a_push.vkg"], 0.5),
        (f"`vkgc solve {CHECKED}`", [*vkgc, "solve", CHECKED], 0.5),
    ]
    with tempfile.TemporaryDirectory(prefix="vkgl-bench-cache-") as cache:
        env = environment(cache)
        cold = run_once([*vkgc, "check", CHECKED], env)  # writes bytecode, the grammar's tables, DART's verdict
        for _, argv, _ in commands:
            run_once(argv, env)  # the solve's reach cache too
        counted_head = f" instructions | projected at {args.rate:g} G/s |" if args.instructions else ""
        print(f"| command ({runs} runs) | wall (median) | CPU (median) |{counted_head} target | |")
        print("|---|---|---|" + ("---|---|" if args.instructions else "") + "---|---|")
        blank = " | |" if args.instructions else ""
        print(row(f"first `vkgc check {CHECKED}` (cold cache folder)", *cold, counted=blank))
        for what, argv, target in commands:
            counted = counted_cells(argv, env, args.rate, target) if args.instructions else ""
            print(row(what, *medians(argv, env, runs), target, counted))
        print()

        totals, heavy = import_breakdown(env)
    print("| `vkgc check`'s imports by package (own time, -X importtime) | time |")
    print("|---|---|")
    for name, seconds in sorted(totals.items(), key=lambda item: -item[1])[:12]:
        print(f"| {name} | {seconds * 1000:.1f} ms |")
    print(f"| all imports | {sum(totals.values()) * 1000:.1f} ms |")
    print()
    print(f"heavy packages `vkgc check` imported: {', '.join(sorted(heavy)) or 'none'}")


if __name__ == "__main__":
    main()
