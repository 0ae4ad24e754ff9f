"""Benchmark: what the exploring fingertip does to a tall body (does it tip, slide, carry weight?).

    python bench/sim/bench_fingertip.py

Pushes a 6 x 6 x 12 cm, 200 g carton at the centre of its +x face with the
exploration's fingertip (`vkgl.sim.explore`, `force normal 1 N`, 2 s), at
several heights and table frictions, and prints one Markdown table: the
vertical force the fingertip puts on the body (from DART's contact forces,
mean and largest while it stands, + up), the slide, the largest tilt, and what
statics predicts (a push at height h tips the carton when mu h > w / 2 = 3 cm).
The fingertip is honest when the vertical force is about zero and the body
tips exactly where statics says (docs/exploration.md, "A pusher carries no
vertical load").

A second table measures the same for plan execution: the carton pushed 10 cm
by the Panda's pad (`vkgl.execute`, open loop) at 6 and at 2 cm over the
table, the pad's vertical force read from DART's contacts after every physics
step (the bench wraps `SceneWorld.advance` to see them).
"""

from __future__ import annotations

import sys

import numpy as np

HALF_WIDTH = 0.03  # m
TIPPED = 5.0  # deg: the load is measured while the carton stands (exploration's tipping threshold)
HEIGHT = 0.12  # m
CASES = [(0.4, 0.5), (0.8, 0.5), (0.8, 0.125), (1.0, 0.5)]  # (friction, push height as a fraction of the height)


def carton(friction: float, height_fraction: float):
    """The carton body, explored at one point of its +x face at the given fraction of its height."""
    from vkgl.lang.compiler import compile_source

    heights = {0.5: "", 0.125: "heights 4"}[height_fraction]  # heights 4: the lowest cell is centred at 1/8
    source = f"""
body Carton {{
    shape box (6, 6, 12) cm
    mass 0.2 kg
    friction {friction}
    explore pushes {{
        contacts on faces +x steps 1 {heights}
        force normal 1 N
        duration 2 s
    }}
}}
"""
    return compile_source(source).bodies["Carton"]


def push(friction: float, height_fraction: float) -> dict[str, float]:
    """Run the one trial at that height and measure it step by step."""
    from vkgl.sim import explore
    from vkgl.sim.policy import plan_trials

    specs = plan_trials(carton(friction, height_fraction))
    spec = min(specs, key=lambda s: abs(s.contact[2] + HEIGHT / 2 - height_fraction * HEIGHT))
    trial = explore._PushTrial(spec, 0)
    steps, _ = explore.step_counts(spec.duration)
    vertical, tilt = [], []
    for step in range(steps):
        if step % 5 == 0:
            trial.command()
        trial.drive()
        trial.world.step(False)
        pose = trial.node.getWorldTransform().matrix()
        tilt.append(float(np.degrees(np.arccos(np.clip(pose[2, 2], -1.0, 1.0)))))
        if tilt[-1] < TIPPED:  # once the carton falls, the fingertip's load says nothing about pushing
            vertical.append(_fingertip_force_on_body(trial.world)[2])
    start = np.array([0.0, 0.0])
    end = trial.node.getWorldTransform().matrix()[:2, 3]
    loaded = np.array(vertical[100:] or [0.0])  # after the first 0.1 s, once the push has started
    return {
        "h": float(spec.contact[2] + HEIGHT / 2),
        "mean": float(loaded.mean()),
        "peak": float(loaded[np.argmax(np.abs(loaded))]),
        "slide": float(np.linalg.norm(end - start)),
        "tilt": max(tilt),
    }


def _fingertip_force_on_body(world) -> np.ndarray:
    """The sum of the contact forces the fingertip exerts on the body now (world frame, N)."""
    total = np.zeros(3)
    result = world.getLastCollisionResult()
    for i in range(result.getNumContacts()):
        contact = result.getContact(i)
        first = contact.collisionObject1.getShapeFrame().getName()
        second = contact.collisionObject2.getShapeFrame().getName()
        force = np.asarray(contact.force, dtype=float)  # DART: the force on the first object
        if "fingertip" in second:
            total += force
        elif "fingertip" in first:
            total -= force
    return total


EXECUTED = """
use stdlib.robots.panda

body Carton {{
    shape box (6, 6, 12) cm
    mass 0.2 kg
    friction 0.8
}}

affordances Carton {{
    affordance push_px {{
        action fixed at (-3, 0, {z}) cm yaw 0deg
        motion prismatic along (1, 0, 0) from (0, 0, 0) cm range 0 to 20 cm
    }}
}}

scene carton_scene {{
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    carton : Carton on table at (0.45, 0.05) m yaw 0deg
}}

task push_carton {{
    scene carton_scene
    goal carton at (0.55, 0.05) m yaw 0deg within 1 cm, 3deg
}}
"""


def executed(height: float) -> dict[str, float]:
    """Plan and execute the carton's push at `height` (m over the table); the pad's vertical load on it."""
    import vkgl
    from vkgl.execute import scene_world
    from vkgl.formats.trials import tilt_deg
    from vkgl.lang.compiler import compile_source

    program = compile_source(EXECUTED.format(z=round(100 * (height - HEIGHT / 2), 3)), "carton.vkg")
    plan = vkgl.solve(program, "push_carton")
    loads: list[float] = []
    advance = scene_world.SceneWorld.advance

    def watched(self, n: int) -> None:  # the same steps, one at a time, reading the contacts after each
        for _ in range(n):
            advance(self, 1)
            force = _fingertip_force_on_body(self.world)
            if np.any(force):
                loads.append(float(force[2]))

    scene_world.SceneWorld.advance = watched
    try:
        report = vkgl.execute(program, "push_carton", plan.document())
    finally:
        scene_world.SceneWorld.advance = advance
    load = np.array(loads or [0.0])
    return {
        "status": report.status,
        "mean": float(load.mean()),
        "low": float(load.min()),
        "high": float(load.max()),
        "tilt": float(tilt_deg(report.final["carton"])),
    }


def main() -> int:
    """Print the tables."""
    print("| friction | push height | statics says | vertical force on body, mean (peak) | moved | largest tilt |")
    print("|---|---|---|---|---|---|")
    for friction, fraction in CASES:
        m = push(friction, fraction)
        says = "tips" if friction * m["h"] > HALF_WIDTH else "slides"
        print(
            f"| {friction} | {100 * m['h']:.1f} cm | {says} | {m['mean']:+.3f} N ({m['peak']:+.3f} N) "
            f"| {100 * m['slide']:.1f} cm | {m['tilt']:.1f} deg |"
        )
    print("\nthe carton weighs 1.962 N; + is up\n")
    print("| executed, friction 0.8 | pad's vertical force on the body: mean (range) | status | final tilt |")
    print("|---|---|---|---|")
    for height in (0.06, 0.02):
        m = executed(height)
        print(
            f"| pushed at {100 * height:.0f} cm | {m['mean']:+.3f} N ({m['low']:+.3f} to {m['high']:+.3f} N) "
            f"| {m['status']} | {m['tilt']:.3f} deg |"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
