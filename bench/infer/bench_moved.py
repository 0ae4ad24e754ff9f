"""Benchmark: did the body move? Per trial, the statistic inference tests before it may call a motion `fixed`.

    python bench/infer/bench_moved.py [--generated SlabW CrateM CrateT] [--body-file F.vkg ...] [--jobs N] [--seed S]

Explores each body's `explore` blocks in DART (`vkgl.sim.explore`; the
generated types of the physical bench, `tests/support/task_makers/generated_tasks.py`,
with their short push grid only, as `bench_physical.py --short-pushes`
explores them; or any body file) and prints, per trial: the MAP motion, how
far its pose ended from its start (`vkgl.infer.select.end_offset`: medians
over the last `END_WINDOW` of the distance and the angle), the thresholds
beyond which the body moved (`AT_REST_TOLERANCES` x `sigma_p`, x `sigma_r`),
the measurement noise the data show (`noise_p`), and the end ratio of the MAP
motion (`vkgl.infer.ending`: still moving at the end, or stopped). These are
the measurements behind docs/inference.md, "Did the body move?".
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from dataclasses import replace
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(REPO), str(REPO / "tests" / "support")]

from task_makers import generated_tasks  # noqa: E402

from vkgl.formats.trials import Trials  # noqa: E402
from vkgl.infer.data import SkipTrial, trial_edges  # noqa: E402
from vkgl.infer.select import AT_REST_TOLERANCES, end_offset  # noqa: E402
from vkgl.infer.trial import infer_trial  # noqa: E402
from vkgl.lang.compiler import compile_file  # noqa: E402
from vkgl.sim.explore import explore  # noqa: E402
from vkgl.sim.policy import plan_trials  # noqa: E402

HEADER = (
    "| body | trial | MAP motion | end offset cm | threshold cm | end angle deg | threshold deg | noise mm "
    "| end ratio |\n|---|---|---|---:|---:|---:|---:|---:|---:|"
)


def generated_body_file(name: str, folder: Path) -> Path:
    """A body file of the generated type `name` with its short push grid only."""
    types = {t.name: t for t in generated_tasks.GENERATED_TYPES}
    if name not in types:
        raise SystemExit(f"no generated type {name!r}; the types are {', '.join(types)}")
    path = folder / f"{name.lower()}.vkg"
    path.write_text(replace(types[name], long_slides=False).source(), encoding="utf-8")
    return path


def trial_rows(path: Path, *, seed: int, jobs: int | None) -> list[str]:
    """One table row per trial of every body the file declares."""
    rows = []
    for name, body in compile_file(str(path)).bodies.items():
        if not body.explores:
            continue
        labels = [spec.label for spec in plan_trials(body)]  # the order `explore` runs them in
        trials = explore(body, seed=seed, jobs=jobs)
        rows += [_row(name, label, trials, i) for i, label in enumerate(labels)]
    return rows


def _row(name: str, label: str, trials: Trials, i: int) -> str:
    result = infer_trial(trials, i)
    try:
        edges = trial_edges(trials, i)
    except SkipTrial as exc:
        return f"| {name} | {label} | skipped: {exc} | | | | | | |"
    data = edges.motion
    offset = end_offset(data, edges.t)
    distance, angle = offset if offset is not None else (float("nan"), float("nan"))
    motion = result.motion.type if result.motion is not None else "-"
    ratio = f"{result.ending.ratio:.2f}" if result.ending is not None else "-"
    return (
        f"| {name} | {label} | {motion} | {distance * 100:.2f} | {AT_REST_TOLERANCES * data.sigma_p * 100:.2f} "
        f"| {np.degrees(angle):.2f} | {np.degrees(AT_REST_TOLERANCES * data.sigma_r):.2f} "
        f"| {data.noise_p * 1000:.2f} | {ratio} |"
    )


def main(argv: list[str] | None = None) -> int:
    """Explore, infer, print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--generated", nargs="*", default=None, help="generated types (default: SlabW CrateM CrateT)")
    parser.add_argument("--body-file", type=Path, action="append", default=[], help="a body file (repeatable)")
    parser.add_argument("--jobs", type=int, default=None, help="parallel processes (default: all cores)")
    parser.add_argument("--seed", type=int, default=0, help="the exploration's seed (default 0)")
    args = parser.parse_args(argv)
    names = args.generated if args.generated is not None else ([] if args.body_file else ["SlabW", "CrateM", "CrateT"])
    with tempfile.TemporaryDirectory() as scratch:
        files = [generated_body_file(n, Path(scratch)) for n in names] + list(args.body_file)
        print(f"## bench_moved: seed {args.seed}\n")
        print(HEADER)
        for path in files:
            for row in trial_rows(path, seed=args.seed, jobs=args.jobs):
                print(row, flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
