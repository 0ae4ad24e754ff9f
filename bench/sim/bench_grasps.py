"""What learning grasps adds to `vkgc learn`, per body: candidates, trials, grasps kept, seconds.

Run on demand: `PYTHONPATH=. python bench/sim/bench_grasps.py [--repeat N]`. For every stdlib body and three
graspable bodies (a 6 cm cube, a 6 x 6 x 12 cm carton, a 4 cm cylinder), `vkgl.api.learn_grasps` runs the
body's grasp candidates in DART (docs/inference.md, "Grasps") and the table prints the seconds it took (the
best of N runs: the machine may be shared, the minimum is the cost), the candidates found from the
geometry, how many the open hand had room for, the trials run and the grasps kept with their largest slip.
The target: at most 10 s per body.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from vkgl.api import learn_grasps
from vkgl.lang.ir.nodes import Body
from vkgl.lang.syntax.parser import parse_module

REPO = Path(__file__).resolve().parents[2]
EXTRA = {
    "cube 6 cm": "body Cube { shape box (6, 6, 6) cm mass 0.3 kg }",
    "carton 6x6x12 cm": "body Carton { shape box (6, 6, 12) cm mass 0.3 kg }",
    "can r 2 cm": "body Can { shape cylinder radius 2 cm height 10 cm mass 0.35 kg }",
}
TARGET = 10.0  # s per body


def bodies() -> dict[str, Body]:
    """The stdlib's bodies and the extra graspable ones, by a short name."""
    found: dict[str, Body] = {}
    for path in sorted((REPO / "stdlib" / "bodies").glob("*.vkg")):
        for decl in parse_module(path.read_text(encoding="utf-8"), str(path)).decls:
            if isinstance(decl, Body):
                found[path.stem] = decl
    for name, text in EXTRA.items():
        (body,) = parse_module(text, name).decls
        assert isinstance(body, Body)
        found[name] = body
    return found


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=1, help="runs per body; the best is printed")
    args = parser.parse_args()
    print(f"{'body':18s} {'seconds':>8s} {'candidates':>10s} {'room':>5s} {'trials':>6s} {'kept':>5s} {'max slip':>9s}")
    worst = 0.0
    learn_grasps(bodies()["block"])  # once, untimed: DART's import and the URDF's parse are paid per process
    for name, body in bodies().items():
        best = float("inf")
        for _ in range(max(1, args.repeat)):
            start = time.perf_counter()
            trials, kept = learn_grasps(body)
            best = min(best, time.perf_counter() - start)
        worst = max(worst, best)
        ran = [t for t in trials.trials if not t.blocked]
        room = len({t.candidate for t in ran})
        slips = [a.evidence.slip for a in kept if a.evidence is not None and a.evidence.slip is not None]
        slip = f"{1000 * max(slips):.1f} mm" if slips else "-"
        print(f"{name:18s} {best:8.2f} {len(trials.candidates):10d} {room:5d} {len(ran):6d} {len(kept):5d} {slip:>9s}")
    verdict = "within" if worst <= TARGET else "OVER"
    print(f"slowest body: {worst:.2f} s ({verdict} the {TARGET:.0f} s target)")


if __name__ == "__main__":
    main()
