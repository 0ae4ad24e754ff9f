"""Exploration: run a body's grid-search policies in DART and record what happened.

`explore(body)` unrolls the body's `explore` blocks into trials
(`vkgl.sim.policy`), runs each trial in its own fresh DART world
(`vkgl.sim.world`) with a simulated effector (`vkgl.sim.fingertip`), and
returns a `vkg-trials/1` dataset (`vkgl.formats.trials.Trials`).

A trial depends only on the body, its grid point and the seed, never on which
process runs it or when: the output is byte-identical whatever `jobs` is.

What is recorded, at SAMPLE_PERIOD (50 Hz) from t = 0 to the duration:
`T_ow` (body frame in the world), `T_ro` (effector frame in the body frame,
both measured from the simulated poses), and per trial the action: the contact
point and the force (body frame, declared magnitude). A trial whose simulation
fails (NaN, body leaves the table, deep penetration) keeps its samples up to
the failure, is marked `ok = False` and says why in `reason`. So does a trial
whose lying body tips over (tilts more than TIP_ANGLE, 5 deg): it ends there,
`reason` starting with TIPPED, and inference records the contact's height.

The force of a push (docs/exploration.md, "Force"): `force normal F` is the
push beyond what friction can hold. The fingertip's force limit is F + mu m g
for a body lying on the table (mu, m as declared), F plus the joint's Coulomb
friction at the contact for a body on a joint (its `friction`, a torque
divided by the contact's distance from a hinge's axis), F for a tool held by
a hand.
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterator
from concurrent.futures import Future, ProcessPoolExecutor
from concurrent.futures import TimeoutError as FuturesTimeout
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from typing import Any, Literal

import dartpy as dart
import numpy as np

from vkgl.errors import SimulationError
from vkgl.formats.trials import TIP_ANGLE, TIPPED, Trials, tilt_deg
from vkgl.lang.ir.geometry import body_mesh, resting_height
from vkgl.lang.ir.nodes import Body
from vkgl.sim import world as sim_world
from vkgl.sim.fingertip import Hand, Pusher, frame_facing
from vkgl.sim.policy import TrialSpec, plan_trials

SAMPLE_PERIOD = 0.02  # s (50 Hz)
CONTROL_PERIOD = 0.005  # s between two commands of the effector (200 Hz)
START_GAP = 0.001  # m between fingertip and face at the start, jittered by +-50 % with the seed
FLOAT_HEIGHT = 0.5  # m above the table where a held tool starts
LIFT_LIMIT = 0.01  # m the lowest point of a lying body may rise above (or sink below) the table top
MAX_SPEED = 10.0  # m/s: nothing explored at 10 cm/s gets near this unless the simulation diverges
MAX_TURN_RATE = 100.0  # rad/s
PENETRATION_LIMIT = 0.005  # m of contact penetration beyond which the simulation is not trusted
MIN_LEVER = 0.01  # m: a hinge's friction torque is covered as if no push were closer to its axis
G = -sim_world.GRAVITY[2]  # m/s^2


@dataclass
class TrialResult:
    """What one trial recorded (samples until the end or the failure)."""

    t: np.ndarray  # (n,)
    T_ro: np.ndarray  # (n, 4, 4)
    T_ow: np.ndarray  # (n, 4, 4)
    ok: bool
    reason: str


# Runs trials elsewhere than the local pool: `runner(specs, seed)` must return
# `run_trial(spec, seed)` for every spec, in order (e.g. `vkgl.sim.ray_runner.RayRunner`).
Runner = Callable[[list[TrialSpec], int], list[TrialResult]]


ProgressMode = bool | Literal["lines"]
"""How exploration shows its progress on stderr: not at all (False), a live bar (True: for a terminal), or a line
every tenth of the trials ("lines": for a pipe or a log)."""


def explore(
    body: Body, *, seed: int = 0, jobs: int | None = None, progress: ProgressMode = False, runner: Runner | None = None
) -> Trials:
    """Run every trial of the body's `explore` blocks and return the dataset.

    `jobs`: parallel processes (default: all cores). `progress`: show a
    progress bar on stderr (`ProgressMode`: "lines" prints a line every
    tenth of the trials instead). `runner`: run the trials with it instead of the
    local process pool. Raises InputError for a body without an `explore`
    block and SimulationError when DART cannot build the body.
    """
    specs = plan_trials(body)
    preflight(body)
    if runner is not None:
        return assemble(body.name, specs, runner(specs, seed))
    results = _run_all(specs, seed, _job_count(jobs, len(specs)), progress)
    return assemble(body.name, specs, results)


def preflight(body: Body) -> None:
    """Build the body once in this process so that a mesh DART rejects fails here, with its file name."""
    world = sim_world.new_world()
    sim_world.add_body(world, body.name, body, np.eye(4))


def _job_count(jobs: int | None, n_trials: int) -> int:
    if jobs is None:
        jobs = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    return max(1, min(int(jobs), n_trials))


def _run_all(specs: list[TrialSpec], seed: int, jobs: int, progress: ProgressMode) -> list[TrialResult]:
    """Run the trials in `jobs` worker processes; results in grid order.

    Workers are processes even for one job: a simulator that aborts (ODE
    asserts on a blown-up world) takes down its worker, not the caller. The
    trials that a broken pool leaves without result are run again one per
    process, so that the one that aborts is found and marked failed.
    Ctrl-C ends the workers at once (they ignore SIGINT themselves, so none
    prints a traceback) and is raised again here.
    """
    results: list[TrialResult | None] = [None] * len(specs)
    context = multiprocessing.get_context("fork" if "fork" in multiprocessing.get_all_start_methods() else "spawn")
    try:
        # Submitting forks the workers and starts the pool's threads: do it with SIGINT blocked, so that
        # they inherit the block (a Ctrl-C is then always delivered to this thread, which can act on it)
        # and no worker can take a Ctrl-C before it has set itself to ignore it. Before the progress bar
        # starts its thread, too.
        with _sigint_blocked():
            pool = ProcessPoolExecutor(max_workers=jobs, mp_context=context, initializer=_worker_signals)
            futures = [pool.submit(run_trial, spec, seed) for spec in specs]
        try:
            advance = (
                _progress_lines(len(specs)) if progress == "lines" else _progress_bar(len(specs)) if progress else None
            )
            try:
                for i, future in enumerate(futures):
                    results[i] = _result(future)
                    if advance:
                        advance()
            finally:
                if advance:
                    advance(stop=True)
        except BaseException:
            _stop_now(pool)
            raise
        pool.shutdown()
    except BrokenProcessPool:
        pass
    for i, spec in enumerate(specs):
        if results[i] is None:
            results[i] = _run_isolated(spec, seed, context)
    return [r for r in results if r is not None]


def _worker_signals() -> None:
    """In a worker: Ctrl-C is the parent's to handle (it ends the workers), and SIGTERM, with which the parent ends
    them, ends a worker at once: a forked worker inherits the parent's handlers (`vkgc` handles SIGTERM as it
    handles Ctrl-C, for the whole process tree), and a Python handler runs only between two simulation steps."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})


@contextlib.contextmanager
def _sigint_blocked() -> Iterator[None]:
    if threading.current_thread() is not threading.main_thread():
        yield  # only the main thread receives Python's signals; nothing to arrange elsewhere
        return
    signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})


def _result(future: Future[TrialResult]) -> TrialResult:
    """`future.result()`, waking up often so that a pending Ctrl-C is raised here without delay."""
    while True:
        try:
            return future.result(timeout=0.1)
        except FuturesTimeout:
            continue


def _stop_now(pool: ProcessPoolExecutor) -> None:
    """End a pool without waiting for its running trials (Ctrl-C, or an error in the parent)."""
    # The executor has no public way to kill busy workers; shutdown() alone would wait for them.
    processes = list(getattr(pool, "_processes", {}).values())
    for process in processes:
        process.terminate()
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        process.join(timeout=1.0)
        if process.is_alive():
            process.kill()
            process.join(timeout=1.0)  # reaped, not left a zombie


def _run_isolated(spec: TrialSpec, seed: int, context: Any) -> TrialResult:
    with _sigint_blocked():
        pool = ProcessPoolExecutor(max_workers=1, mp_context=context, initializer=_worker_signals)
        future = pool.submit(run_trial, spec, seed)
    try:
        result = _result(future)
    except BrokenProcessPool:
        pool.shutdown()
        return TrialResult(
            np.zeros(0),
            np.zeros((0, 4, 4)),
            np.zeros((0, 4, 4)),
            False,
            "the simulator aborted (a numerical blow-up took down its process)",
        )
    except BaseException:
        _stop_now(pool)
        raise
    pool.shutdown()
    return result


def _progress_lines(total: int) -> Callable[..., None]:
    """A line on stderr every tenth of `total` trials (and at the last): what a pipe or a log can show."""
    done, started, every = 0, time.monotonic(), max(1, total // 10)

    def advance(stop: bool = False) -> None:
        nonlocal done
        if stop:
            return
        done += 1
        if done % every == 0 or done == total:
            print(f"exploring: {done}/{total} trials ({time.monotonic() - started:.0f} s)", file=sys.stderr, flush=True)

    return advance


def _progress_bar(total: int) -> Callable[..., None]:
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    bar = Progress(
        TextColumn("exploring"),
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
        console=Console(stderr=True),
        transient=True,
    )
    task = bar.add_task("trials", total=total)
    bar.start()

    def advance(stop: bool = False) -> None:
        if stop:
            bar.stop()
        else:
            bar.advance(task)

    return advance


def run_trial(spec: TrialSpec, seed: int = 0) -> TrialResult:
    """Run one trial in a fresh world. Never raises for a simulation that goes wrong: that is `ok = False`."""
    try:
        if spec.kind == "push":
            return _PushTrial(spec, seed).run()
        return _GraspTrial(spec).run()
    except SimulationError:
        raise
    except Exception as exc:  # DART or numpy failing mid-trial must not end the whole exploration
        return TrialResult(
            np.zeros(0),
            np.zeros((0, 4, 4)),
            np.zeros((0, 4, 4)),
            False,
            f"the simulation failed: {type(exc).__name__}: {exc}",
        )


class _Trial:
    """The loop shared by all trials: command the effector, step, sample, check."""

    def __init__(self, spec: TrialSpec) -> None:
        self.spec = spec
        self.world = sim_world.new_world()
        self.table = sim_world.add_table(self.world)[1]
        self.node: Any = None  # the explored body's DART node, set by subclasses
        self.lying = False  # True when the body lies on the table (its lowest point is watched)
        self.hull = body_mesh(spec.body).convex_hull.vertices

    def command(self) -> None:
        """Once per control period: decide what the effector does (where it pushes)."""

    def drive(self) -> None:
        """Every physics step: the effector's drive forces."""
        raise NotImplementedError

    def effector_pose(self) -> np.ndarray:
        raise NotImplementedError

    def effector_node(self) -> Any:
        raise NotImplementedError

    def run(self) -> TrialResult:
        steps, per_sample = step_counts(self.spec.duration)
        per_control = max(1, round(CONTROL_PERIOD / sim_world.TIME_STEP))
        t, T_ro, T_ow = [], [], []

        def sample() -> str:
            body = self.node.getWorldTransform().matrix()
            effector = self.effector_pose()
            t.append(self.world.getTime())
            T_ow.append(body.copy())
            T_ro.append(np.linalg.solve(body, effector))
            return self.failure(body, effector)

        reason = sample()
        for step in range(steps):
            if reason:
                break
            if step % per_control == 0:
                reason = self.runaway()
                if reason:
                    break
                self.command()
            self.drive()
            self.world.step(False)  # step(True) would zero the drive's forces
            if (step + 1) % per_sample == 0:
                reason = sample()
        return TrialResult(np.array(t), np.array(T_ro), np.array(T_ow), not reason, reason)

    def runaway(self) -> str:
        """'' unless a body moves absurdly fast: stop before the numbers overflow (ODE aborts then)."""
        for node in (self.node, self.effector_node()):
            linear = np.asarray(node.getLinearVelocity(), dtype=np.float64)
            angular = np.asarray(node.getAngularVelocity(), dtype=np.float64)
            if not (np.all(np.isfinite(linear)) and np.all(np.isfinite(angular))):
                return "the simulation diverged (NaN in a velocity)"
            if np.linalg.norm(linear) > MAX_SPEED or np.linalg.norm(angular) > MAX_TURN_RATE:
                return "the simulation diverged (a body reached an absurd speed)"
        return ""

    def failure(self, body: np.ndarray, effector: np.ndarray) -> str:
        """Why the simulation can no longer be trusted, or ''."""
        if not (np.all(np.isfinite(body)) and np.all(np.isfinite(effector))):
            return "the simulation diverged (NaN in a pose)"
        if self.lying:
            lowest = float((self.hull @ body[:3, :3].T + body[:3, 3])[:, 2].min())
            if lowest > LIFT_LIMIT:
                return f"the body left the table (its lowest point rose {100 * lowest:.1f} cm)"
            if lowest < -LIFT_LIMIT:
                return f"the body left the table (its lowest point fell to {100 * lowest:.1f} cm)"
            tilt = float(tilt_deg(body))
            if tilt > TIP_ANGLE:  # a falling body is no motion to learn; inference records where it tipped
                return f"{TIPPED} (tilted {tilt:.1f} deg, more than {TIP_ANGLE:g} deg)"
        result = self.world.getLastCollisionResult()
        depth = max((result.getContact(i).penetrationDepth for i in range(result.getNumContacts())), default=0.0)
        if depth > PENETRATION_LIMIT:
            return f"bodies interpenetrate by {1000 * depth:.1f} mm (more than {1000 * PENETRATION_LIMIT:.0f} mm)"
        return ""


class _PushTrial(_Trial):
    """`contacts ... force normal`: the fingertip starts just outside the face and pushes along its normal."""

    def __init__(self, spec: TrialSpec, seed: int) -> None:
        super().__init__(spec)
        body = spec.body
        pose = sim_world.translation(np.array([0.0, 0.0, resting_height(body, 0.0, 0.0)]))
        _, self.node = sim_world.add_body(self.world, body.name, body, pose, spec.joint_start)
        self.lying = body.joint is None
        start_body = self.node.getWorldTransform().matrix()
        rng = np.random.default_rng(np.random.SeedSequence([seed, spec.index]))
        gap = START_GAP * (0.5 + float(rng.random()))
        direction = start_body[:3, :3] @ spec.direction
        effector = np.eye(4)
        effector[:3, :3] = frame_facing(direction, start_body[:3, :3] @ spec.line_axis)
        effector[:3, 3] = (start_body @ np.append(spec.contact, 1.0))[:3] - gap * direction
        self.pusher = Pusher(self.world, effector, push_force_limit(body, spec.magnitude, spec.contact))
        table_filter = dart.collision.BodyNodeCollisionFilter()
        table_filter.addBodyNodePairToBlackList(self.pusher.node, self.table)  # the robot hovers, never rubs the table
        self.world.getConstraintSolver().getCollisionOption().collisionFilter = table_filter

    def command(self) -> None:
        body = self.node.getWorldTransform().matrix()
        self.pusher.aim(body[:3, :3] @ self.spec.direction)  # "force normal": follow the face as it turns

    def drive(self) -> None:
        self.pusher.drive()

    def effector_pose(self) -> np.ndarray:
        return self.pusher.effector_pose()

    def effector_node(self) -> Any:
        return self.pusher.node


class _GraspTrial(_Trial):
    """`grasp FRAME ... force directions`: the hand holds the body at FRAME and drives it along a direction."""

    def __init__(self, spec: TrialSpec) -> None:
        super().__init__(spec)
        body = spec.body
        assert spec.grasp is not None
        rest = resting_height(body, 0.0, 0.0)
        if body.joint is None:  # a tool: the robot holds it up, above the table
            start = sim_world.translation(np.array([0.0, 0.0, rest + FLOAT_HEIGHT]))
            self.hand = Hand(self.world, start @ spec.grasp, start[:3, :3] @ spec.direction, spec.magnitude)
            self.node = self.hand.carry(body, spec.grasp)
        else:  # a body on its own joint (a door by its handle): held where it stands
            _, self.node = sim_world.add_body(
                self.world, body.name, body, sim_world.translation(np.array([0.0, 0.0, rest])), spec.joint_start
            )
            start = self.node.getWorldTransform().matrix()
            self.hand = Hand(self.world, start @ spec.grasp, start[:3, :3] @ spec.direction, spec.magnitude)
            self.hand.hold(self.node)

    def drive(self) -> None:
        self.hand.drive()

    def effector_pose(self) -> np.ndarray:
        return self.hand.effector_pose()

    def effector_node(self) -> Any:
        return self.hand.node


def step_counts(duration: float) -> tuple[int, int]:
    """(physics steps of a trial, physics steps between two samples)."""
    return round(duration / sim_world.TIME_STEP), max(1, round(SAMPLE_PERIOD / sim_world.TIME_STEP))


def push_force_limit(body: Body, force: float, contact: np.ndarray | None = None) -> float:
    """The fingertip's force limit: the declared push beyond what friction holds.

    A lying body: beyond the table's friction, mu m g. A body on a joint (the
    table does not hold it): beyond the joint's Coulomb `friction` at the
    contact (`contact`, body frame): a slide's force as it is, a hinge's
    torque over the contact's distance from the axis (at least 1 cm, so that a
    push on the axis itself stays finite).
    """
    joint = body.joint
    if joint is None:
        friction = body.friction if body.friction is not None else sim_world.DEFAULT_FRICTION
        return force + friction * body.mass.value * G
    if joint.friction is None or joint.friction.value <= 0.0:
        return force
    if joint.type == "prismatic":
        return force + float(joint.friction.value)
    axis = joint.axis.array() / np.linalg.norm(joint.axis.array())
    through = joint.through.array() if joint.through is not None else np.zeros(3)
    offset = (np.zeros(3) if contact is None else np.asarray(contact, dtype=float)) - through
    lever = float(np.linalg.norm(offset - (offset @ axis) * axis))
    return force + float(joint.friction.value) / max(lever, MIN_LEVER)


def assemble(body: str, specs: list[TrialSpec], results: list[TrialResult]) -> Trials:
    """Pack trial results into a `vkg-trials/1` dataset (NaN-padded to the longest trial)."""
    n = len(specs)
    longest = max(steps // per_sample + 1 for steps, per_sample in (step_counts(s.duration) for s in specs))
    t = np.full((n, longest), np.nan)
    T_ro = np.full((n, longest, 4, 4), np.nan)
    T_ow = np.full((n, longest, 4, 4), np.nan)
    for i, r in enumerate(results):
        k = len(r.t)
        t[i, :k], T_ro[i, :k], T_ow[i, :k] = r.t, r.T_ro, r.T_ow
    return Trials(
        body=body,
        t=t,
        T_ro=T_ro,
        T_ow=T_ow,
        contact=np.array([s.contact for s in specs], dtype=float).reshape(n, 3),
        force=np.array([s.magnitude * s.direction for s in specs], dtype=float).reshape(n, 3),
        ok=np.array([r.ok for r in results], dtype=bool),
        reason=np.array([r.reason for r in results], dtype=str),
    )
