"""Which parts of the DART world touch a body while a plan is carried out: who disturbed a bystander.

    python bench/physical/touches.py TASK.vkg PLAN.json BODY [--every 0.1]

Carries out the `vkg-plan/7` plan (`vkgc solve TASK.vkg --json PLAN.json`) step by step in the world execution
uses (`vkgl.execute.replay.Replay`, open loop) and prints, once per control period at most every `--every`
simulated seconds per pair, each contact of BODY with anything but the table: when, what the arm was doing,
the two body nodes (`skeleton:node`: `arm:panda_hand`, `stick:stick` for a held tool), the contact point,
DART's penetration depth, and how far BODY has moved from where it started. gen3_017 of the physical bench
(`--seed 3 --only 17`): the Hook was touched by the held Stick only, from t = 23.3 s of step 4 (the Stick's
underside on the Hook's top), and dragged 9.8 cm (docs/planning.md, "A tool at its contact and the bodies it
does not act on").
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

import numpy as np

REPO = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(REPO)]


def _node(collision_object: Any) -> str:
    """`skeleton:body node` of a DART collision object."""
    node = collision_object.getShapeFrame().asShapeNode().getBodyNodePtr()
    return f"{node.getSkeleton().getName()}:{node.getName()}"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("task", type=Path, help="the .vkg file of the task")
    parser.add_argument("plan", type=Path, help="its plan, vkg-plan/7 JSON")
    parser.add_argument("body", help="the scene body whose contacts are printed")
    parser.add_argument("--every", type=float, default=0.1, help="s of simulated time between lines of one pair")
    args = parser.parse_args()

    import vkgl
    from vkgl.execute.replay import Replay
    from vkgl.formats.plan.reading import read

    program = vkgl.compile(args.task)
    plan = read(args.plan)
    scene = program.scenes[program.tasks[plan.task].scene.name]
    replay = Replay(program, scene, plan.robot, record=False)
    if args.body not in replay.types:
        parser.error(f"no body `{args.body}` in scene {scene.name}")
    world = replay.sim.world
    start = replay.poses()[args.body][:3, 3].copy()
    last: dict[tuple[str, str], float] = {}

    def look() -> None:
        result = world.getLastCollisionResult()
        for i in range(result.getNumContacts()):
            contact = result.getContact(i)
            a, b = _node(contact.collisionObject1), _node(contact.collisionObject2)
            if args.body not in (a.split(":")[0], b.split(":")[0]) or "table" in (a + b):
                continue
            key = (a, b)
            if replay.time < last.get(key, -np.inf) + args.every - 1e-9:
                continue
            last[key] = replay.time
            moved = np.linalg.norm(replay.poses()[args.body][:2, 3] - start[:2]) * 100
            p = np.asarray(contact.point)
            print(
                f"t = {replay.time:6.2f} s  {replay.label:<22} {a:>20} - {b:<20} at ({p[0]:.3f}, {p[1]:.3f}, "
                f"{p[2]:.3f}) m  {contact.penetrationDepth * 1000:.2f} mm deep  {args.body} moved {moved:.2f} cm"
            )

    replay.watch(look)
    for index, step in enumerate(plan.steps, 1):
        replay.run_step(index, step)
    replay.let_go()
    replay.settle(0.5)
    moved = np.linalg.norm(replay.poses()[args.body][:2, 3] - start[:2]) * 100
    print(f"{args.body} ended {moved:.2f} cm from where it started")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
