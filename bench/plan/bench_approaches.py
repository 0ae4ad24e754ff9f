"""Benchmark: what the search of ways into a contact costs, beyond the three rules.

    PYTHONPATH=. python bench/plan/bench_approaches.py [--repeat 5]

Three contacts of the stdlib Hook pulling the stdlib Drawer at its bar's
overhang (`Drawer.pull_px_left`, the scene of `tests/scenarios/tools/test_side_approach.py`):

- `no ledge`: the first rule works (along the push is blocked, from above works: 2 ways);
- `ledge`: a ledge over the hook's shaft blocks the rules and the cone; the 20th way (from the side along
  the bar) works;
- `wide ledge`: nothing works: the 3 rules and all 28 searched ways fail.

Each contact is captured from a real solve (`StraightMoves.into_contact` as the search calls it), then
`into_contact` is timed `--repeat` times. Prints a Markdown table: ways tried, wall time per call (median)
and per way.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(REPO), str(REPO / "tests" / "scenarios" / "tools"), str(REPO / "tests" / "support")]

CASES = (
    ("no ledge", {"width": 1.0, "y": 0.5}),  # far away on the table's side: in nobody's way
    ("ledge", {"width": 3.9, "y": -0.0725}),
    ("wide ledge", {"width": 8.0, "y": -0.093}),
)


def captured(source: Path) -> tuple[Any, Any, Any, str]:
    """The (moves, step, state, label) of the first `Drawer.pull_px_left` contact the search approaches."""
    import vkgl
    from vkgl.plan.arm import straight_moves

    found: list[tuple[Any, Any, Any, str]] = []
    original = straight_moves.StraightMoves.into_contact

    def spy(self: Any, step: Any, state: Any, label: str) -> Any:
        if step.affordance == "Drawer.pull_px_left" and not found:
            found.append((self, step, state.copy(), label))
        return original(self, step, state, label)

    straight_moves.StraightMoves.into_contact = spy  # type: ignore[method-assign]
    try:
        vkgl.solve(vkgl.compile(source), "hook_drawer_ledge")
    finally:
        straight_moves.StraightMoves.into_contact = original  # type: ignore[method-assign]
    if not found:
        raise SystemExit(f"{source}: the search never approached Drawer.pull_px_left")
    return found[0]


def ways_tried(moves: Any, step: Any, state: Any, label: str) -> tuple[int, str]:
    """How many ways `into_contact` tried, and what it returned, counted by wrapping `_approach`."""
    count = [0]
    original = moves._approach

    def counting(*args: Any) -> Any:
        count[0] += 1
        return original(*args)

    moves._approach = counting
    try:
        result = moves.into_contact(step, state.copy(), label)
    finally:
        del moves._approach
    return count[0], "clear" if not hasattr(result, "why") else "none works"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeat", type=int, default=5, help="timed calls per contact (default 5)")
    args = parser.parse_args()
    from test_side_approach import SOURCE

    print("| contact | ways tried | result | ms per call (median) | ms per way |")
    print("|---|---:|---|---:|---:|")
    with tempfile.TemporaryDirectory() as folder:
        for name, ledge in CASES:
            path = Path(folder) / f"{name.replace(' ', '_')}.vkg"
            path.write_text(SOURCE.format(**ledge), encoding="utf-8")
            moves, step, state, label = captured(path)
            count, result = ways_tried(moves, step, state, label)
            times = []
            for _ in range(args.repeat):
                began = time.perf_counter()
                moves.into_contact(step, state.copy(), label)
                times.append(time.perf_counter() - began)
            median = statistics.median(times) * 1000
            print(f"| {name} | {count} | {result} | {median:.1f} | {median / count:.1f} |")


if __name__ == "__main__":
    main()
