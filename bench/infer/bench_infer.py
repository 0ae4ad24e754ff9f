"""Benchmark: constraint inference on synthetic ground truth, on real tracks, and its speed.

    python bench/infer/bench_infer.py [--per-type N] [--seed S]

1. Synthetic trials (synthetic): every motion type (fixed, prismatic,
   revolute, free) with fixed and free actions, random axes and centres, 2 %
   outliers, per noise level: type accuracy of the motion and of the action,
   median axis error (deg) and median revolute centre error (cm, distance to
   the true axis line), CPU time per 100-sample trial. Targets: accuracy >=
   95 % up to 5 mm / 2 deg, median axis error < 2 deg, centre error < 1 cm,
   < 10 ms per trial.
2. Real tracks (Sturm et al.'s, not in the repository: `sturm_tracks.npz` and
   `labels.json` read in place from the folder `$VKGL_ARTICULATION_DATA` names; skipped, saying
   where it looked, when absent): the confusion table by mechanism; target >=
   95 % correct.

`--trials F.npz` (repeatable) also times inference on recorded datasets.
Prints Markdown tables.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from collections import Counter, defaultdict
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(REPO), str(REPO / "tests" / "support")]  # the test suite's synthetic ground truth

from synthetic import score, synthetic_trials  # noqa: E402

from vkgl.formats.trials import Trials  # noqa: E402
from vkgl.infer.trial import infer_trial, infer_trials  # noqa: E402

REAL = Path(os.environ.get("VKGL_ARTICULATION_DATA", "")) if os.environ.get("VKGL_ARTICULATION_DATA") else None
NOISE_LEVELS = [(0.0, 0.0), (0.001, 0.5), (0.002, 1.0), (0.005, 2.0), (0.01, 3.0)]


def synthetic_table(per_type: int, seed: int) -> list[str]:
    rows = [
        "| noise | trials | motion type | action type | axis err (median) | centre err (median) | ms / trial |",
        "|---|---|---|---|---|---|---|",
    ]
    for noise_p, noise_deg in NOISE_LEVELS:
        trials, truths = synthetic_trials(seed, per_type, noise_p=noise_p, noise_r=np.deg2rad(noise_deg))
        started = time.process_time()
        results = infer_trials(trials)
        per_trial = (time.process_time() - started) / len(trials) * 1000
        found = score(results, truths)
        rows.append(
            f"| {noise_p * 1000:g} mm / {noise_deg:g} deg | {len(trials)} | {found.motion_accuracy:.1%} "
            f"| {found.action_accuracy:.1%} | {found.axis_error_deg:.2f} deg | {found.center_error * 100:.2f} cm "
            f"| {per_trial:.1f} |"
        )
    return rows


def confusion_rows(per_type: int, seed: int) -> list[str]:
    """Which motion types are confused with which, over all noise levels."""
    counts: Counter[tuple[str, str]] = Counter()
    for noise_p, noise_deg in NOISE_LEVELS:
        trials, truths = synthetic_trials(seed + 1, per_type, noise_p=noise_p, noise_r=np.deg2rad(noise_deg))
        for i, truth in enumerate(truths):
            counts[(truth.motion, infer_trial(trials, i).motion.type)] += 1
    kinds = ["fixed", "prismatic", "revolute", "free"]
    rows = ["| true \\ inferred | " + " | ".join(kinds) + " |", "|---" * (len(kinds) + 1) + "|"]
    for truth in kinds:
        rows.append(f"| {truth} | " + " | ".join(str(counts[(truth, k)]) for k in kinds) + " |")
    return rows


def real_table() -> list[str]:
    if REAL is None or not (REAL / "sturm_tracks.npz").is_file():
        where = f"no sturm_tracks.npz in {REAL}" if REAL else "VKGL_ARTICULATION_DATA is not set"
        return [f"(real tracks not found: {where}; set VKGL_ARTICULATION_DATA to their folder: skipped)"]
    trials = Trials.load(REAL / "sturm_tracks.npz")
    labels = json.loads((REAL / "labels.json").read_text())
    started = time.process_time()
    results = infer_trials(trials)
    elapsed = time.process_time() - started
    by_mechanism: dict[str, Counter[str]] = defaultdict(Counter)
    truth_of = {}
    wrong = []
    for label, result in zip(labels, results):
        inferred = result.motion.type if result.motion is not None else "skipped"
        by_mechanism[label["mechanism"]][inferred] += 1
        truth_of[label["mechanism"]] = label["motion"]
        if inferred != label["motion"]:
            wrong.append(f"{label['index']} ({label['mechanism']}: {inferred})")
    kinds = ["fixed", "prismatic", "revolute", "free"]
    rows = ["| mechanism | true | tracks | " + " | ".join(kinds) + " | correct |", "|---" * (len(kinds) + 4) + "|"]
    total = correct = 0
    for mechanism in sorted(by_mechanism):
        counts = by_mechanism[mechanism]
        n = sum(counts.values())
        ok = counts[truth_of[mechanism]]
        total, correct = total + n, correct + ok
        cells = " | ".join(str(counts[k]) for k in kinds)
        rows.append(f"| {mechanism} | {truth_of[mechanism]} | {n} | {cells} | {ok}/{n} |")
    samples = sum(r.samples for r in results)
    blanks = " | ".join("" for _ in kinds)
    rows.append(f"| **all** | | {total} | {blanks} | **{correct}/{total} = {correct / total:.1%}** |")
    rows.append("")
    rows.append(f"misclassified: {', '.join(wrong) or 'none'}")
    rows.append(f"CPU time: {elapsed / samples * 100 * 1000:.1f} ms per 100 samples ({samples} samples)")
    return rows


def dataset_rows(path: Path) -> list[str]:
    """Inference time on a recorded dataset (e.g. `vkgc explore` output)."""
    trials = Trials.load(path)
    started = time.process_time()
    results = infer_trials(trials)
    elapsed = time.process_time() - started
    samples = sum(r.samples for r in results)
    kinds = Counter(r.motion.type if r.motion is not None else "skipped" for r in results)
    return [
        f"{path.name}: {len(trials)} trials of {trials.body}, {samples} samples, motions {dict(sorted(kinds.items()))}",
        f"CPU time: {elapsed / len(trials) * 1000:.1f} ms per trial, "
        f"{elapsed / samples * 100 * 1000:.1f} ms per 100 samples",
    ]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--per-type", type=int, default=25, help="trials per (motion, action) pair and noise level")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--trials", type=Path, action="append", default=[], help="also time a recorded dataset")
    args = parser.parse_args()
    print(f"## Synthetic ground truth ({args.per_type} trials per motion x action pair, 2 % outliers)\n")
    print("\n".join(synthetic_table(args.per_type, args.seed)))
    print("\nMotion confusion over all noise levels:\n")
    print("\n".join(confusion_rows(max(2, args.per_type // 5), args.seed)))
    print("\n## Real tracks (Sturm et al., positions only)\n")
    print("\n".join(real_table()))
    for path in args.trials:
        print(f"\n## {path}\n")
        print("\n".join(dataset_rows(path)))


if __name__ == "__main__":
    main()
