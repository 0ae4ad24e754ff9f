"""Exploration learns the models in the physics that execution carries the plans out in.

Exploration's worlds once used DART's default boxed LCP (friction bounded
along world x and y) while execution used the Coulomb friction cone: a tall
crate's learned turn of 11.7 deg was 35 deg in execution, and turned crates
missed their goals by 2 cm (docs/physical_bench.md, "Three plans that broke
in DART"). Both now build their worlds with `vkgl.sim.world.new_world`, the contact solver's stop included (a
looser one in execution missed a turned crate's goal: `vkgl.sim.world.EXECUTION_SOLVER_TOLERANCE`).
"""

from __future__ import annotations

import json
from pathlib import Path

from vkgl.execute.scene_world import SceneWorld
from vkgl.formats.plan.reading import from_json
from vkgl.lang.compiler import compile_file
from vkgl.sim import world as sim_world
from vkgl.sim.explore import _PushTrial
from vkgl.sim.policy import plan_trials

REPO = Path(__file__).resolve().parents[2]


def _exploration_world(program) -> object:
    """The world of the Block's first push trial, as `vkgc learn` builds it (not run)."""
    spec = next(s for s in plan_trials(program.bodies["Block"]) if s.kind == "push")
    return _PushTrial(spec, 0).world


def _execution_world(program) -> object:
    """The world task a's plan is carried out in, with the golden plan's robot."""
    plan = from_json(json.loads((REPO / "tests" / "formats" / "golden" / "a_push.json").read_text()))
    return SceneWorld(program, program.scenes["tabletop"], plan.robot, record=False).world


def test_exploration_and_execution_simulate_with_the_same_settings() -> None:
    program = compile_file(str(REPO / "examples" / "tasks" / "a_push.vkg"))
    explored = sim_world.solver_settings(_exploration_world(program))
    executed = sim_world.solver_settings(_execution_world(program))
    assert explored == executed
    assert explored["friction"][2] == 1e-5  # DART's stop of the sweeps: what the stdlib was learned with
    assert explored["solver"] == "NsgsFrictionSolver"  # the friction cone, not the boxed LCP
    assert explored["friction"][0] == "Law.Coulomb"
    assert explored["collision_detector"] == "ode"


def test_grasp_trials_differ_from_the_shared_physics_in_the_contact_solver_alone() -> None:
    """The grasp trials keep DART's boxed LCP, whose finger contacts hold a tool (vkgl.sim.world.new_grasp_world);
    everything else is the shared physics."""
    shared = sim_world.solver_settings(sim_world.new_world())
    grasp = sim_world.solver_settings(sim_world.new_grasp_world())
    assert grasp["solver"] == "DantzigBoxedLcpSolver" and "friction" not in grasp
    assert {k: v for k, v in grasp.items() if k != "solver"} == {
        k: v for k, v in shared.items() if k not in ("solver", "friction")
    }
