"""Benchmark: `vkgc learn` on the local process pool (1 and 2 workers) and on a local Ray instance.

    python bench/sim/bench_scale.py [BODYFILE_OR_FOLDER ...] [--cpus N] [--repeat R]

Learns the given bodies (default: all of stdlib/bodies/) into temporary
folders, once per mode, and prints one Markdown table: per mode the wall time
of the learning (explore + infer, best of R), the speed-up over 1 worker, and
whether the modules written are byte-identical to the 1-worker ones. The Ray
rows are measured with the instance already running; its start-up is printed
as a row of its own (it is paid once per `vkgc learn --ray` command, or never
when joining a running cluster).
"""

from __future__ import annotations

import argparse
import functools
import os
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def body_files(paths: list[str]) -> list[str]:
    """Files as given, folders as their *.vkg files."""
    found: list[str] = []
    for name in paths:
        path = Path(name)
        found += sorted(str(p) for p in path.glob("*.vkg")) if path.is_dir() else [name]
    return found


def learn_all(files: list[str], out: Path, **options: object) -> None:
    """`vkgc learn FILES -o OUT` with `options` passed to `vkgl.infer.library.learn`."""
    from vkgl.infer.library import learn

    for file in files:
        learn(file, out_dir=str(out), **options)  # type: ignore[arg-type]


def pool_learn(files: list[str], jobs: int, out: Path) -> None:
    """`vkgc learn FILES -o OUT --jobs JOBS`."""
    learn_all(files, out, jobs=jobs)


def best_of(repeat: int, run: Callable[[Path], None], keep: Path) -> float:
    """The best wall time of `repeat` runs of `run(folder)`; the last run's modules are left in `keep`."""
    best = float("inf")
    for _ in range(repeat):
        keep.mkdir(parents=True, exist_ok=True)
        for old in keep.iterdir():
            old.unlink()
        started = time.perf_counter()
        run(keep)
        best = min(best, time.perf_counter() - started)
    return best


def same(a: Path, b: Path) -> bool:
    """Whether two folders hold the same files with the same bytes."""
    names = sorted(p.name for p in a.iterdir())
    return names == sorted(p.name for p in b.iterdir()) and all(
        (a / n).read_bytes() == (b / n).read_bytes() for n in names
    )


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark and print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "bodies",
        nargs="*",
        default=[str(REPO / "stdlib" / "bodies")],
        help="body files or folders (default: stdlib/bodies/)",
    )
    parser.add_argument(
        "--cpus",
        type=int,
        default=2,
        help="workers of the pool and CPUs of Ray (default 2)",
    )
    parser.add_argument(
        "--repeat",
        type=int,
        default=1,
        help="runs per mode; the best is reported (default 1)",
    )
    args = parser.parse_args(argv)
    files = body_files(args.bodies)
    load_before = os.getloadavg()[0]

    from vkgl.sim.ray_runner import RayRunner

    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        rows: list[tuple[str, float, Path]] = []
        for jobs in sorted({1, args.cpus}):
            out = root / f"pool{jobs}"
            wall = best_of(args.repeat, functools.partial(pool_learn, files, jobs), out)
            rows.append((f"process pool, {jobs} worker{'s' if jobs > 1 else ''}", wall, out))
        started = time.perf_counter()
        with RayRunner(num_cpus=args.cpus) as runner:
            startup = time.perf_counter() - started
            out = root / "ray"
            wall = best_of(args.repeat, lambda o: learn_all(files, o, runner=runner), out)
            rows.append((f"local Ray instance, num_cpus={args.cpus}", wall, out))
        base_wall, base_out = rows[0][1], rows[0][2]
        print(
            f"bodies: {', '.join(Path(f).stem for f in files)}; {os.cpu_count()} cores; "
            f"load average {load_before:.1f} before, {os.getloadavg()[0]:.1f} after"
        )
        print()
        print("| mode | wall s | speed-up | modules identical to 1 worker |")
        print("|---|---:|---:|---|")
        for mode, wall, out in rows:
            print(f"| {mode} | {wall:.1f} | {base_wall / wall:.2f} | {'yes' if same(out, base_out) else 'NO'} |")
        print(f"| (Ray start-up, once per command) | {startup:.1f} | | |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
