"""How a motion ended: a drawer at its stop is a bound, a block still sliding when its push ended is open."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import trials_of

from vkgl.infer.ending import END_WINDOW, MOVING_RATIO, motion_ending
from vkgl.infer.library import infer_library
from vkgl.lang.compiler import compile_file
from vkgl.lang.ir.nodes import PrismaticC, RevoluteC
from vkgl.sim.explore import assemble, run_trial
from vkgl.sim.policy import plan_trials

BODIES = Path(__file__).resolve().parents[2] / "stdlib" / "bodies"
T = np.arange(0.0, 10.0 + 1e-9, 0.02)  # 50 Hz, 10 s


def test_a_motion_that_stops_before_the_end_is_not_moving() -> None:
    states = np.minimum(0.035 * T, 0.30)  # 3.5 cm/s until a stop at 30 cm (8.6 s), then still
    ending = motion_ending(T, states)
    assert ending is not None and not ending.moving
    assert ending.end_speed == pytest.approx(0.0, abs=1e-9) and ending.peak_speed == pytest.approx(0.035)


def test_a_motion_at_its_steady_speed_at_the_end_is_moving() -> None:
    states = 0.029 * T + 0.0005 * np.random.default_rng(0).standard_normal(T.size)  # tracking noise
    ending = motion_ending(T, states)
    assert ending is not None and ending.moving and ending.ratio > 0.8  # the peak of noisy windows is a bit high


def test_a_motion_slowing_below_half_its_peak_speed_has_stopped() -> None:
    speed = np.where(T < 9.0, 0.03, 0.03 * (MOVING_RATIO - 0.1))  # a stall: well under half speed at the end
    states = np.concatenate([[0.0], np.cumsum(speed[1:] * np.diff(T))])
    ending = motion_ending(T, states)
    assert ending is not None and not ending.moving


def test_a_trial_too_short_to_tell_has_no_ending() -> None:
    t = np.arange(0.0, 2 * END_WINDOW - 0.02, 0.02)
    assert motion_ending(t, 0.03 * t) is None


def _learned(stem: str, keep, stdlib_explored) -> dict:
    """The stdlib body's trials that `keep` selects, of its exploration as `vkgc learn` explores it (in DART, once
    per run: `stdlib_explored`, tests/conftest.py), inferred: its affordances by name."""
    body = compile_file(str(BODIES / f"{stem}.vkg")).body()
    trials = trials_of(stdlib_explored(stem), [s.index for s in plan_trials(body) if keep(s)])
    return _by_name(infer_library(trials, body_use=f"stdlib.bodies.{stem}", header="test"))


def _by_name(result) -> dict:
    """An inference's groups and affordances by the affordance's name."""
    return {g.name: (g, a) for g, a in zip(result.groups, result.module.decls[0].affordances)}  # type: ignore[union-attr]


def test_a_drawer_pulled_to_its_stop_gives_a_bounded_range(stdlib_explored) -> None:
    # the pull at the handle from the closed end: 30 cm in 8.6 s, then 1.4 s against the stop
    found = _learned(
        "drawer",
        lambda s: s.policy == "pull" and s.joint_start == 0.0 and s.label.startswith("pull at handle"),
        stdlib_explored,
    )
    group, affordance = found["pull_center_px"]
    assert isinstance(affordance.motion, PrismaticC) and not affordance.motion.range.open
    assert affordance.motion.range.upper.value == pytest.approx(0.30, abs=0.002)
    assert not group.still_moving


def test_a_block_still_sliding_when_its_push_ended_gives_an_open_range_and_its_turns_stay_closed(block_pushes) -> None:
    # the 2 s pushes toward +x only (its -x face; `block_pushes`, tests/conftest.py, shared with
    # tests/sim/test_explore.py): the centre ones slide it 5.7 cm, still sliding; the end ones turn it
    found = _by_name(infer_library(block_pushes, body_use="stdlib.bodies.block", header="test"))
    group, affordance = found["push_center_px"]
    assert isinstance(affordance.motion, PrismaticC) and affordance.motion.range.open
    assert affordance.motion.range.upper.value == pytest.approx(0.057, abs=0.002)
    assert group.still_moving
    turn_group, turn = found["turn_px_left"]
    assert isinstance(turn.motion, RevoluteC) and not turn.motion.range.open
    assert turn_group.still_moving  # it was still turning, but a turn's range stays closed (docs/inference.md)


def test_a_heavy_slab_pushed_at_its_centre_for_three_seconds_gives_an_open_slide(tmp_path) -> None:
    # a generated body of the physical bench (tests/support/task_makers/generated_tasks.py, SlabW) and its short
    # push grid:
    # the centre push slides it 3.6 cm in 3 s, still sliding; inference once called that trial `fixed`
    source = (
        "body SlabW {\n    shape box (16, 30, 6) cm\n    mass 1.44 kg\n    friction 0.5\n"
        "    explore pushes {\n        contacts on faces +x steps 3\n        force normal 1 N\n"
        "        duration 3 s\n    }\n}\n"
    )
    (tmp_path / "slabw.vkg").write_text(source, encoding="utf-8")
    body = compile_file(str(tmp_path / "slabw.vkg")).bodies["SlabW"]
    specs = [s for s in plan_trials(body) if abs(s.contact[1]) < 1e-9]
    trials = assemble(body.name, specs, [run_trial(s, 0) for s in specs])
    result = infer_library(trials, body_use="body.vkg", header="test")
    found = {g.name: (g, a) for g, a in zip(result.groups, result.module.decls[0].affordances)}  # type: ignore[union-attr]
    group, affordance = found["push_center_nx"]  # the +x face's push goes along -x
    assert isinstance(affordance.motion, PrismaticC) and affordance.motion.range.open
    assert 0.03 < affordance.motion.range.upper.value < 0.045
    assert group.still_moving
