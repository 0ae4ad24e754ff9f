"""Record every plan of the examples and of generated tasks, or compare plans against such a recording.

    python bench/physical/plan_snapshot.py record before.json [--seed 1] [--count 50] [--timeout 60] [--only 3,7-9]
                                  [--cpu-clock]
    python bench/physical/plan_snapshot.py compare before.json after.json [--rtol 0]

For a refactoring that must not change any plan: record on the old code, record on the new, compare. Each task
is solved with `vkgl.solve` (two worker processes); a plan's document is kept without its timings and the URDF's
path. `compare` prints each task whose status or plan differs (numbers within `--rtol`, 0 by default: the same
machine gives the same floats) and exits 1 if any does. A task that timed out in either recording is compared by
status only, and reported apart: a timeout depends on the machine's load, not on the code. `--cpu-clock` counts
each timeout in CPU seconds of its worker (`time.process_time`), as `bench_physical.py --cpu-clock` does: under
load a task then ends the same way as on an idle machine, and fewer are compared by status only.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from multiprocessing import get_context
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(REPO), str(REPO / "tests" / "support")]


def task_files(
    seed: int, count: int, scratch: Path, only: list[int] | None = None
) -> list[tuple[str, str, str | None]]:
    """(key, task file, task name) of every example and of `count` generated tasks of `seed` (`only`: those
    generated tasks alone, no example)."""
    from task_makers import generated_tasks

    jobs: list[tuple[str, str, str | None]] = [
        (f"example:{f.stem}", str(f), None) for f in sorted((REPO / "examples" / "tasks").glob("*.vkg"))
    ]
    if only is not None:
        jobs = []
    library = generated_tasks.fixture_library()
    for index in range(count) if only is None else only:
        spec = generated_tasks.task_spec(seed, index)
        path = generated_tasks.write_task(spec, scratch / spec.name, library)
        jobs.append((f"generated:{spec.name}", str(path), spec.name))
    return jobs


def solve_one(job: tuple[str, str, str | None, float, bool]) -> dict[str, Any]:
    """The plans of one task file (every task it declares when no name is given); with `cpu_clock` the solve's
    deadlines count this worker's CPU seconds."""
    import vkgl

    key, path, name, timeout, cpu_clock = job
    if cpu_clock:
        time.perf_counter = time.process_time  # every deadline (`time.perf_counter() > deadline`) then counts CPU
    program = vkgl.compile(path)
    names = [name] if name else [d.name for d in program.root.decls if type(d).__name__ == "Task"]
    out = {}
    for task in names:
        plan = vkgl.solve(program, task, timeout=timeout)
        doc = plan.to_json()
        doc.pop("stats", None)
        doc.get("robot", {}).pop("urdf", None)
        out[f"{key}:{task}"] = {"status": plan.status, "doc": doc}
    return out


def record(
    out: Path, seed: int, count: int, timeout: float, only: list[int] | None = None, cpu_clock: bool = False
) -> int:
    """Solve every task (`only`: those generated tasks; `cpu_clock`: timeouts in CPU seconds) and write the
    recording."""
    results: dict[str, Any] = {}
    with tempfile.TemporaryDirectory() as scratch:
        jobs = [(*job, timeout, cpu_clock) for job in task_files(seed, count, Path(scratch), only)]
        with ProcessPoolExecutor(2, mp_context=get_context("spawn")) as pool:
            for done in pool.map(solve_one, jobs):
                results.update(done)
                for key, value in done.items():
                    print(f"{key}: {value['status']}", file=sys.stderr, flush=True)
    out.write_text(json.dumps(results, indent=1, sort_keys=True) + "\n", encoding="utf-8")
    return 0


def differences(a: Any, b: Any, rtol: float, where: str = "") -> list[str]:
    """Where two JSON values differ (numbers within `rtol`)."""
    if isinstance(a, dict) and isinstance(b, dict):
        if set(a) != set(b):
            return [f"{where}: keys {sorted(set(a) ^ set(b))}"]
        return [d for k in a for d in differences(a[k], b[k], rtol, f"{where}.{k}")]
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return [f"{where}: {len(a)} vs {len(b)} entries"]
        return [d for i, (x, y) in enumerate(zip(a, b, strict=True)) for d in differences(x, y, rtol, f"{where}[{i}]")]
    numbers = (int, float)
    if isinstance(a, numbers) and isinstance(b, numbers) and not isinstance(a, bool):
        return [] if math.isclose(a, b, rel_tol=rtol, abs_tol=rtol * 1e-6) else [f"{where}: {a!r} vs {b!r}"]
    return [] if a == b else [f"{where}: {a!r} vs {b!r}"]


def compare(before: Path, after: Path, rtol: float) -> int:
    """Print what differs between two recordings; 1 if a plan differs."""
    a = json.loads(before.read_text(encoding="utf-8"))
    b = json.loads(after.read_text(encoding="utf-8"))
    changed, timed_out, same = [], [], 0
    for key in sorted(set(a) | set(b)):
        x, y = a.get(key), b.get(key)
        if x is None or y is None:
            changed.append(f"{key}: only in {'after' if x is None else 'before'}")
        elif "timeout" in (x["status"], y["status"]):
            timed_out.append(f"{key}: {x['status']} -> {y['status']}")
        elif found := differences(x, y, rtol):
            changed.append(f"{key}: {found[0]}" + (f" (+{len(found) - 1} more)" if len(found) > 1 else ""))
        else:
            same += 1
    print(f"{same} identical, {len(changed)} changed, {len(timed_out)} timed out in either (not compared)")
    for line in changed + timed_out:
        print(f"  {line}")
    return 1 if changed else 0


def _indices(text: str) -> list[int]:
    """`3,7-9` -> [3, 7, 8, 9]."""
    out: list[int] = []
    for part in text.split(","):
        low, _, high = part.partition("-")
        out += range(int(low), int(high or low) + 1)
    return out


def main(argv: list[str] | None = None) -> int:
    """Record or compare."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    rec = sub.add_parser("record", help="solve every task and write the plans")
    rec.add_argument("out", type=Path)
    rec.add_argument("--seed", type=int, default=1)
    rec.add_argument("--count", type=int, default=50)
    rec.add_argument("--timeout", type=float, default=60.0, help="per task, s (default 60)")
    rec.add_argument("--only", help="these generated tasks alone, no example (indices: 3,7-9)")
    rec.add_argument("--cpu-clock", action="store_true", help="count timeouts in each worker's CPU seconds")
    cmp_ = sub.add_parser("compare", help="compare two recordings")
    cmp_.add_argument("before", type=Path)
    cmp_.add_argument("after", type=Path)
    cmp_.add_argument("--rtol", type=float, default=0.0)
    args = parser.parse_args(argv)
    if args.command == "record":
        only = None if args.only is None else _indices(args.only)
        return record(args.out, args.seed, args.count, args.timeout, only, args.cpu_clock)
    return compare(args.before, args.after, args.rtol)


if __name__ == "__main__":
    sys.exit(main())
