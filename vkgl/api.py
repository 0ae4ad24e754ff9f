"""The driver: compile once, then learn, solve and execute on typed objects.

The stages never compile files and never call one another sideways; this
module composes them, and the CLI and notebooks call it:

    import vkgl
    program = vkgl.compile("examples/tasks/a_push.vkg")
    plan = vkgl.solve(program)                       # the file's only task
    report = vkgl.execute(program, plan.task, plan)  # carry it out in DART
    print(report.text())

Heavy back ends (DART, NLopt) are imported inside the functions, so that
`import vkgl` and `vkgc --help` stay fast.
"""

from __future__ import annotations

import os
import re
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Union

from vkgl.errors import InputError

if TYPE_CHECKING:
    from vkgl.execute.progress import Progress
    from vkgl.execute.resolving import Attempts
    from vkgl.formats.execution_report import ExecutionReport, Resolve, StepReport
    from vkgl.formats.grasp_trials import GraspTrials
    from vkgl.formats.plan import PlanDocument
    from vkgl.formats.trials import Trials
    from vkgl.infer.library import InferenceResult
    from vkgl.lang.ir.nodes import Affordance, Body, Task
    from vkgl.lang.ir.program import Program
    from vkgl.plan.problem.avoid import Avoid
    from vkgl.plan.result.plan import Plan
    from vkgl.sim.explore import ProgressMode, Runner

ProgramLike = Union["Program", str, os.PathLike[str]]
"""A compiled Program, or the path of a `.vkg` file to compile."""

__all__ = [
    "compile",
    "compile_source",
    "execute",
    "explore",
    "infer",
    "learn",
    "learn_grasps",
    "solve",
]


def compile(path: str | os.PathLike[str]) -> Program:
    """Parse, resolve and check a `.vkg` file and everything it uses.

    Raises `vkgl.errors.CompileError` (carrying every diagnostic) when the
    file has errors; warnings are kept in `program.warnings`.
    """
    from vkgl.lang.compiler import compile_file

    return compile_file(Path(path))


def compile_source(text: str, name: str = "<string>", *, base_dir: str | os.PathLike[str] | None = None) -> Program:
    """Compile `.vkg` source given as a string.

    `name` is the path diagnostics show; `use "file.vkg"` is resolved relative
    to `base_dir` (default: the current directory).
    """
    from vkgl.lang.compiler import compile_source as compile_text

    return compile_text(text, name, base_dir=None if base_dir is None else Path(base_dir))


def _program(program: ProgramLike) -> Program:
    from vkgl.lang.ir.program import Program

    return program if isinstance(program, Program) else compile(program)


def solve(
    program: ProgramLike,
    task: str | Task | None = None,
    *,
    max_depth: int | None = None,
    timeout: float | None = None,
    progress: bool = False,
    avoid: Avoid | None = None,
    arm_start: Sequence[float] | None = None,
) -> Plan:
    """Plan for `task` of `program` (its only task when None); return a Plan.

    `max_depth` and `timeout` override the task's `search` block. `avoid`
    (`vkgl.plan.problem.avoid.Avoid`) names plans already tried and steps that failed
    in execution, which the plan must not repeat. `arm_start` are the arm's
    joints where its first path starts (default: its home configuration,
    where execution starts it). A goal that
    no plan reaches, or a search that runs out of time, is a result, not an
    error: `plan.status` is "infeasible" or "timeout" and `plan.reason` says
    why. Input errors raise `vkgl.errors.InputError`.
    """
    from vkgl.plan.solve import solve as solve_task

    compiled = _program(program)
    return solve_task(
        compiled,
        _task(compiled, task),
        max_depth=max_depth,
        timeout=timeout,
        progress=progress,
        avoid=avoid,
        arm_start=arm_start,
    )


def execute(
    program: ProgramLike,
    task: str | Task | None,
    plan: Plan | PlanDocument,
    *,
    replan: bool = False,
    max_replans: int = 3,
    record: bool = False,
    on_step: Callable[[StepReport], None] | None = None,
    on_progress: Callable[[Progress], None] | None = None,
    on_resolve: Callable[[Resolve], None] | None = None,
) -> ExecutionReport:
    """Carry `plan` out in DART physics and report how close the bodies came to the goal.

    With `replan`, the loop re-solves (with `solve`) from the observed scene
    whenever a body strays from the plan or a step fails, at most
    `max_replans` times, never repeating a plan tried nor a step that failed
    where it failed. With `record`, the report keeps frames for
    `vkgl.execute.animate.animate`. `on_step` is told of every step as it
    ends (the CLI prints a line each), `on_progress` where the execution is
    while it runs (`vkgl.execute.progress.Progress`: the CLI's live bar),
    `on_resolve` of every re-solve (the CLI prints what it excluded and found).
    """
    from vkgl.execute.closed_loop import execute as execute_plan
    from vkgl.formats.plan import PlanDocument

    if max_replans < 0:
        raise InputError(f"max_replans must be 0 or more, not {max_replans}")
    compiled = _program(program)
    document = plan if isinstance(plan, PlanDocument) else plan.document()
    return execute_plan(
        compiled,
        _task(compiled, task if task is not None else document.task),
        document,
        replan=replan,
        max_replans=max_replans,
        record=record,
        resolve=resolver,
        on_step=on_step,
        on_progress=on_progress,
        on_resolve=on_resolve,
    )


def resolver(program: Program, task: str, attempts: Attempts) -> PlanDocument:
    """How the closed loop re-solves: the planner, on the program it observed, avoiding what was tried.

    The plans tried and the steps that failed (`attempts`) become the
    planner's `vkgl.plan.problem.avoid.Avoid`; the new plan's arm paths start where
    the arm stands (`attempts.arm`).
    """
    from vkgl.plan.problem.avoid import Avoid

    avoid = Avoid.of(attempts.plans, attempts.failed_steps)
    return solve(program, task, avoid=avoid, arm_start=attempts.arm).document()


def explore(
    body: Body, *, seed: int = 0, jobs: int | None = None, progress: ProgressMode = False, runner: Runner | None = None
) -> Trials:
    """Run the body's exploration grid in DART; return the `vkg-trials/1` dataset.

    The trials run on a local process pool of `jobs` workers, or with `runner`
    (e.g. `vkgl.sim.ray_runner.RayRunner`, on a Ray cluster); the dataset is
    the same either way.
    """
    from vkgl.sim.explore import explore as explore_body

    return explore_body(body, seed=seed, jobs=jobs, progress=progress, runner=runner)


def infer(
    trials: Trials,
    *,
    body_use: str | None = None,
    header: str | None = None,
    path: str = "<inferred>",
    grasps: Sequence[Affordance] = (),
    check_from: str | os.PathLike[str] | None = None,
) -> InferenceResult:
    """Infer the affordances of the explored body; the result holds the module's IR and source.

    `body_use` is what the generated module imports to know the body
    (default `stdlib.bodies.<body>`); `header` its leading comment; `grasps`
    (the kept grasps, `learn_grasps`) are added after the inferred affordances.
    `check_from`: where the module will be written; the module `body_use` names
    must then be found from there and declare the body, or InputError before
    anything is inferred (an output that is not a file, `/dev/stdout`, is
    checked as if saved in the working directory).
    """
    from vkgl.infer.library import infer_library

    use = body_use or f"stdlib.bodies.{trials.body.lower()}"
    _check_use(use)
    if check_from is not None:
        _check_body_found(use, trials.body, Path(check_from), given=body_use is not None)
    text = header or f"Inferred from {len(trials)} trials. Do not edit."
    return infer_library(trials, body_use=use, header=text, path=path, grasps=grasps)


def learn_grasps(body: Body, *, seed: int = 0) -> tuple[GraspTrials, list[Affordance]]:
    """Try `body`'s grasp candidates in DART and keep those that held (docs/inference.md, "Grasps").

    Returns the trials and the kept grasps' affordances (none for `explore grasps { approach none }`).
    """
    from vkgl.infer.grasps.kept import kept_grasps
    from vkgl.sim.grasp.run import try_grasps

    trials = try_grasps(body, seed=seed)
    return trials, kept_grasps(body, trials)


def _check_body_found(use: str, body: str, destination: Path, *, given: bool) -> None:
    from vkgl.atomic import Way, decide
    from vkgl.lang.body_use import check_body_use

    if decide(destination)[0] is not Way.REPLACE:  # a stream or a device: no folder the module will be read from
        destination = Path.cwd() / f"{body.lower()}.vkg"
    check_body_use(use, body, destination, given=given)


_MODULE_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)*")
_MODULE_PATH = re.compile(r"[^\x00-\x1f\x7f\"\\]+\.vkg")


def _check_use(use: str) -> None:
    """What a generated module imports is a dotted module name or a `.vkg` path: nothing else gets pasted."""
    if not (_MODULE_NAME.fullmatch(use) or _MODULE_PATH.fullmatch(use)):
        raise InputError(
            f"--use {use[:60]!r}: not a module (write a dotted name such as `mylib.bodies.crate`, "
            "or the path of a .vkg file without quotes)"
        )


def learn(
    body_files: Sequence[str | os.PathLike[str]] | str | os.PathLike[str],
    *,
    body: str | None = None,
    out_dir: str | os.PathLike[str] | None = None,
    seed: int = 0,
    jobs: int | None = None,
    progress: ProgressMode = False,
    force: bool = False,
    runner: Runner | None = None,
) -> list[Path]:
    """Explore and infer each body file's body, and try its grasps; write `<body>.vkg` per body; return the paths.

    A body without an `explore` block is learned for its grasps alone (an
    InputError when none held).

    `body_files` are files or folders (each folder stands for its `*.vkg`
    files, in name order). `runner` runs the trials elsewhere (see `explore`).

    The output folder defaults to the `affordances/` folder beside a
    `bodies/` folder (the stdlib layout), else to an `affordances/` folder
    in the body file's folder, so it is never the body file itself. The
    same input writes the same bytes. An existing file is replaced only when
    it is a module `vkgc learn` generated (its first line says so), or with
    `force`; a file any of the compilations read (a body file, a module it
    uses) is never replaced. Two bodies that would write one module, and a
    folder that cannot be written, are refused before anything is explored.
    """
    from vkgl.atomic import write_text
    from vkgl.infer.library import body_import

    files = _body_files([body_files] if isinstance(body_files, str | os.PathLike) else list(body_files))
    if body is not None and len(files) > 1:
        raise InputError(f"--body {body}: names a body of one file, but {len(files)} files were given")
    programs = [compile(f) for f in files]  # every file is checked before any exploration starts
    jobs_to_run = _learning_jobs(files, programs, body, None if out_dir is None else Path(out_dir), force)
    written = []
    for source, target, destination in jobs_to_run:
        destination.parent.mkdir(parents=True, exist_ok=True)
        if progress == "lines":
            print(f"{target.name}: learning into {destination}", file=sys.stderr, flush=True)
        # a body without an `explore` block is learned for its grasps alone (a carton to pick up)
        trials = explore(target, seed=seed, jobs=jobs, progress=progress, runner=runner) if target.explores else None
        grasp_trials, grasps = learn_grasps(target, seed=seed)
        body_use, shown = body_import(source, destination)
        ran = sum(not t.blocked for t in grasp_trials.trials)
        header = _learn_header(body_use, shown, 0 if trials is None else len(trials), ran)
        if trials is None:
            from vkgl.infer.library import grasp_library

            _check_use(body_use)
            result = grasp_library(grasp_trials, grasps, body_use=body_use, header=header, path=str(destination))
        else:
            result = infer(trials, body_use=body_use, header=header, path=str(destination), grasps=grasps)
        write_text(destination, result.source)
        written.append(destination)
    return written


def _learn_header(body_use: str, shown: str, trials: int, grasp_trials: int = 0) -> str:
    """The generated module's first line, naming the body file as a user can find it from anywhere.

    A stdlib body is named as `vkgc learn` is run on it from the repository root; any other body file by
    its path relative to the generated module, said as such (not as a command line nobody typed). The
    grasp trials that ran are counted apart (none: the line reads as before grasps were learned).
    """
    parts = [f"{trials} trials"] if trials or not grasp_trials else []  # a body learned for its grasps alone: none
    parts += [f"{grasp_trials} grasp trials"] if grasp_trials else []
    counted = " and ".join(parts)
    if not body_use.endswith(".vkg"):  # a stdlib body, imported by dotted name
        return f"Generated by `vkgc learn {shown}` from {counted}. Do not edit."
    return f"Generated by `vkgc learn` from {counted} of the body file {shown} (relative to this file). Do not edit."


def _body_files(paths: Sequence[str | os.PathLike[str]]) -> list[Path]:
    """Files as given; a folder as its `*.vkg` files, sorted by name, less the modules `vkgc` generated.

    A file named twice is learned once. Generated modules in a folder are not
    body files: `vkgc learn lib -o lib` run twice learns the same bodies.
    """
    files: list[Path] = []
    for name in paths:
        path = Path(name)
        if path.is_dir():
            found = [f for f in sorted(path.glob("*.vkg")) if not is_generated(f)]
            if not found:
                raise InputError(f"{path}: a folder without .vkg body files")
            files.extend(found)
        else:
            files.append(path)
    unique: dict[Path, Path] = {}
    for file in files:
        unique.setdefault(file.resolve(), file)
    return list(unique.values())


GENERATED_MARK = "# Generated by `vkgc learn"
"""How a module `vkgc learn` wrote begins; only such a file is replaced without `force`."""
GENERATED_PREFIX = "# Generated by `vkgc "
"""How every module `vkgc` generated begins (`learn` and `infer`)."""


def is_generated(path: Path, mark: str = GENERATED_PREFIX) -> bool:
    """Whether the regular file `path` begins with `mark` (a module `vkgc` generated); False if it cannot be read."""
    from vkgl.lang.checks.learn_hint import file_begins_with

    return file_begins_with(path, mark)


def _learning_jobs(
    files: list[Path], programs: list[Program], body: str | None, out_dir: Path | None, force: bool
) -> list[tuple[Path, Body, Path]]:
    """(body file, body, module to write) per file, every destination checked before anything is explored.

    Refused: two bodies learned into one module (`Crate` and `CRATE`, or one
    body in two files, into one folder), a destination that is a file any of
    the compilations read (a body file, a module it uses, a mesh), a
    hand-written module (unless `force`), and a folder that cannot be written.
    """
    from vkgl.atomic import decide

    read: dict[Path, tuple[Path, str]] = {}
    for source, program in zip(files, programs, strict=True):
        for real, what in program.files().items():
            read.setdefault(real, (source, what))
    planned: list[tuple[Path, Body, Path]] = []
    claimed: dict[Path, tuple[Path, str]] = {}
    for source, program in zip(files, programs, strict=True):
        target = program.body(body)
        destination = (out_dir or _default_out_dir(source)) / f"{target.name.lower()}.vkg"
        real = destination.resolve()
        if real in claimed:
            first, name = claimed[real]
            raise InputError(
                f"{destination}: body `{name}` of {first} and body `{target.name}` of {source} would both be "
                "learned into this one module; learn them into different folders (-o DIR) or rename one body"
            )
        claimed[real] = (source, target.name)
        _refuse_to_replace(destination, source, read, force)
        _check_out_folder(destination.parent)
        decide(destination)  # a directory or a socket in its place: refused now
        planned.append((source, target, destination))
    return planned


def _refuse_to_replace(destination: Path, source: Path, read: dict[Path, tuple[Path, str]], force: bool) -> None:
    real = destination.resolve()
    if real == source.resolve():
        raise InputError(
            f"{source}: learning {destination.name} here would replace the body file itself; "
            "name an output folder with -o DIR"
        )
    if real in read:
        user, what = read[real]
        raise InputError(
            f"{destination}: is {what}, which {user} reads; learning here would replace it; "
            "name another output folder with -o DIR"
        )
    if force or not destination.exists():
        return
    if not is_generated(destination, GENERATED_MARK):
        raise InputError(
            f"{destination}: exists and was not generated by `vkgc learn`; "
            "name another output folder with -o DIR, or replace it with --force"
        )


def _check_out_folder(folder: Path) -> None:
    """Raise InputError unless `folder` is, or can be made as, a writable directory."""
    existing = folder
    while not existing.exists() and existing != existing.parent:
        existing = existing.parent
    if not existing.is_dir():
        raise InputError(f"{folder}: cannot be made an output folder: `{existing}` is not a directory")
    if not os.access(existing, os.W_OK | os.X_OK):
        raise InputError(f"{folder}: the output folder is not writable (`{existing}`); name another with -o DIR")


def _default_out_dir(body_file: Path) -> Path:
    """`affordances/` beside a `bodies/` folder (the stdlib layout), else inside the body file's folder."""
    from vkgl.lang.checks.learn_hint import default_learn_folder

    return default_learn_folder(body_file)


def _task(program: Program, task: str | Task | None) -> Task:
    from vkgl.lang.ir.nodes import Task

    if isinstance(task, Task):
        return task
    return program.task(task)
