"""The sub-commands of `vkgc`: each calls the driver (`vkgl.api`) and prints what it did.

Heavy modules are imported inside the commands so that `vkgc --help` starts fast.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from vkgl.cli.exit_codes import EXIT_INPUT, EXIT_NO_PLAN, EXIT_NOT_REACHED, EXIT_OK, EXIT_TIMEOUT

Command = Callable[[argparse.Namespace], int]
COMMANDS: dict[str, Command] = {}
"""The sub-commands by name."""


def _command(name: str) -> Callable[[Command], Command]:
    def register(fn: Command) -> Command:
        COMMANDS[name] = fn
        return fn

    return register


def _is_terminal(stream: Any) -> bool:
    return bool(getattr(stream, "isatty", lambda: False)())


def print_diagnostics(diagnostics: Sequence[Any], sources: dict[str, str], stream: Any) -> None:
    from vkgl.lang.diagnostics.diagnostic import render

    for diag in diagnostics:
        source = sources.get(diag.span.file) if diag.span is not None else None
        print(render(diag, source), file=stream)


def _text_out(args: argparse.Namespace) -> Any:
    """Where the command's text goes: stdout, unless one of its outputs is stdout itself (`--json -`,
    `-o /dev/stdout`): then stderr, so that stdout holds that output alone (`vkgc solve t.vkg --json - | jq`)."""
    from vkgl.atomic import stream_descriptor
    from vkgl.cli.paths import OUTPUT_FILES

    named = [getattr(args, option, None) for option in OUTPUT_FILES.get(args.command, ())]
    return sys.stderr if any(value and stream_descriptor(value) == 1 for value in named) else sys.stdout


def _written(path: str, what: str, out: Any) -> None:
    """Say that `path` was written (`plan.json: plan as vkg-plan/8`) on `out` (`_text_out`)."""
    print(f"{path}: {what}", file=out)


def _summary(n_errors: int, n_warnings: int, n_files: int) -> str:
    files = f"{n_files} file{'s' if n_files != 1 else ''}"
    if not n_errors and not n_warnings:
        return f"checked {files}: no errors"
    parts = []
    if n_errors:
        parts.append(f"{n_errors} error{'s' if n_errors != 1 else ''}")
    if n_warnings:
        parts.append(f"{n_warnings} warning{'s' if n_warnings != 1 else ''}")
    return f"{', '.join(parts)} in {files}"


# ---------------------------------------------------------------- commands


@_command("check")
def cmd_check(args: argparse.Namespace) -> int:
    """Parse and check files; print every diagnostic and a summary line."""
    from vkgl.lang.compiler import check_files

    diagnostics, sources = check_files(list(args.files))
    print_diagnostics(diagnostics, sources, sys.stdout)
    errors = sum(1 for d in diagnostics if d.is_error)
    print(_summary(errors, len(diagnostics) - errors, len(args.files)))
    return EXIT_INPUT if errors else EXIT_OK


@_command("fmt")
def cmd_fmt(args: argparse.Namespace) -> int:
    """Rewrite files in canonical form, or with --check list those that would change."""
    from vkgl.atomic import write_text
    from vkgl.errors import CompileError
    from vkgl.lang.syntax.printer import format_source
    from vkgl.lang.syntax.sources import read_source

    status = EXIT_OK
    for name in args.files:
        path = Path(name)
        text = read_source(path, name)
        if not isinstance(text, str):  # missing, not a regular file, too large, not UTF-8: a diagnostic
            print_diagnostics([text], {}, sys.stderr)
            status = EXIT_INPUT
            continue
        try:
            formatted = format_source(text, str(path))
        except CompileError as exc:
            print_diagnostics(exc.diagnostics, {str(path): text}, sys.stderr)
            status = EXIT_INPUT
            continue
        if formatted == text:
            continue
        if args.check:
            print(f"{name}: would reformat")
            status = EXIT_INPUT
        else:
            write_text(path, formatted)
            print(f"{name}: reformatted")
    return status


@_command("explore")
def cmd_explore(args: argparse.Namespace) -> int:
    """Run a body's exploration grid in DART and write a `vkg-trials/1` dataset."""
    from vkgl import api
    from vkgl.cli.paths import check_outputs_against

    program = api.compile(args.bodyfile)
    print_diagnostics(program.warnings, program.sources, sys.stderr)  # what `vkgc check` would warn about
    check_outputs_against(args, program.files(), f"read by the compilation of {args.bodyfile}")
    body = program.body(args.body)
    trials = api.explore(body, seed=args.seed, jobs=args.jobs, progress=_is_terminal(sys.stderr) or "lines")
    trials.save(args.output)
    out = _text_out(args)
    failed = int((~trials.ok).sum())
    _written(args.output, f"{len(trials)} trials of {body.name}" + (f", {failed} failed" if failed else ""), out)
    if args.plot:
        from vkgl.sim.plot import plot_trials

        plot_trials(trials, args.plot)
        _written(args.plot, "picture of the trials", out)
    return EXIT_OK


@_command("infer")
def cmd_infer(args: argparse.Namespace) -> int:
    """Infer affordances from a trials dataset and write a library module."""
    from vkgl import api
    from vkgl.atomic import write_text
    from vkgl.formats.infer_report import write_infer_report
    from vkgl.formats.trials import Trials

    trials = Trials.load(args.trials)
    # the dataset by its file name: the folder it was read from says nothing to a reader of the module
    header = f"Generated by `vkgc infer` from {len(trials)} trials ({Path(args.trials).name}). Do not edit."
    result = api.infer(trials, body_use=args.use, header=header, check_from=args.output)
    write_text(args.output, result.source)
    out = _text_out(args)
    _written(args.output, f"affordances of {trials.body}", out)
    if args.report:
        write_infer_report(args.report, result.report)
        _written(args.report, "per-trial report", out)
    if args.plot:
        from vkgl.infer.plot import plot_posteriors

        plot_posteriors(result, args.plot)
        _written(args.plot, "posterior over types by contact", out)
    return EXIT_OK


@_command("learn")
def cmd_learn(args: argparse.Namespace) -> int:
    """Explore bodies and infer their affordances in one go (trials on the local pool, or on Ray with --ray)."""
    import contextlib

    from vkgl import api

    if args.ray and Path(args.ray).exists():  # `learn --ray FILE`: the file is not an address
        args.bodyfiles, args.ray = [args.ray, *args.bodyfiles], ""
    runner: Any = contextlib.nullcontext(None)
    if args.ray is not None:
        from vkgl.sim.ray_runner import RayRunner

        runner = RayRunner(address=args.ray or None, num_cpus=args.jobs, progress=_is_terminal(sys.stderr))
    with runner as run:
        for out in api.learn(
            args.bodyfiles,
            body=args.body,
            out_dir=args.output,
            seed=args.seed,
            jobs=args.jobs,
            progress=_is_terminal(sys.stderr) or "lines",
            force=args.force,
            runner=run,
        ):
            print(f"{out}: generated")
    return EXIT_OK


@_command("lsp")
def cmd_lsp(args: argparse.Namespace) -> int:
    """Serve the language server over stdin/stdout (for editors)."""
    from vkgl.editor.server import main as serve

    return serve()


@_command("solve")
def cmd_solve(args: argparse.Namespace) -> int:
    """Plan for a task; print the graph sequence; optionally write JSON and a picture."""
    import json

    from vkgl import api
    from vkgl.atomic import write_text
    from vkgl.cli.paths import check_outputs_against

    if args.animate:  # refuse a file it cannot write before seconds of planning and minutes of simulation
        from vkgl.execute.animate import check_animation_path

        check_animation_path(args.animate)
    program = api.compile(args.taskfile)
    # the warnings `vkgc check` prints: a tool no correspondence names is why a far goal is "infeasible"
    print_diagnostics(program.warnings, program.sources, sys.stderr)
    check_outputs_against(args, program.files(), f"read by the compilation of {args.taskfile}")
    plan = api.solve(
        program,
        args.task,
        max_depth=args.max_depth,
        timeout=args.timeout,
        progress=_is_terminal(sys.stderr),
    )
    out = _text_out(args)
    print(plan.text(), file=out)
    if args.verbose:
        print(_joint_details(plan), file=out)
        print(_search_details(plan.details), file=out)
    if args.json:
        write_text(args.json, json.dumps(plan.to_json(), indent=1) + "\n")
        _written(args.json, "plan as vkg-plan/8", out)
    if args.plot and plan.status == "solved":
        from vkgl.plan.result.picture import plot_plan

        plot_plan(plan, args.plot)
        _written(args.plot, "picture of the plan", out)
    elif args.plot:  # said, so that a missing picture is no surprise (nothing is written, nothing replaced)
        print(f"{args.plot}: not written (no plan to draw)", file=sys.stderr)
    executes = args.execute or args.replan or args.animate or args.execution_json
    if plan.status == "solved" and executes and not _execute(args, program, plan):
        return EXIT_NOT_REACHED
    return {"solved": EXIT_OK, "infeasible": EXIT_NO_PLAN, "timeout": EXIT_TIMEOUT}[plan.status]


def _search_details(details: dict[str, Any]) -> str:
    """`solve -v`: the search's counters, one per line."""
    lines = ["search:"]
    for key, value in details.items():
        if isinstance(value, dict):
            lines.append(f"  {key}:")
            lines.extend(f"    {k}: {v}" for k, v in value.items())
        else:
            lines.append(f"  {key}: {value}")
    return "\n".join(lines)


def _joint_details(plan: Any) -> str:
    """`solve -v`: the arm's joint configuration at the start and end of every step (radians)."""
    if not plan.steps:
        return "joints: none (no plan)"
    names = plan.robot.joints
    lines = [f"joints (rad; {', '.join(names)}):"]
    for k, step in enumerate(plan.steps, start=1):
        for when, q in (("start", step.q_start), ("end", step.q_end)):
            lines.append(f"  step {k} {when:<5} [" + ", ".join(f"{v:+.4f}" for v in q) + "]")
    return "\n".join(lines)


def _execute(args: argparse.Namespace, program: Any, plan: Any) -> bool:
    """`solve --execute`: replay the plan in DART, print the report, write what was asked for.

    Returns whether the execution reached every goal.
    """
    import json

    from vkgl import api
    from vkgl.atomic import write_text
    from vkgl.cli.progress import ExecutionProgress

    # a line per step (and per re-solve) as it happens, on a terminal or piped; a live bar on a terminal
    with ExecutionProgress(sys.stderr, live=_is_terminal(sys.stderr)) as shown:
        report = api.execute(
            program,
            plan.task,
            plan,
            replan=args.replan,
            max_replans=args.max_replans,
            record=bool(args.animate),
            on_step=shown.step_done,
            on_progress=shown.progress,
            on_resolve=shown.resolved,
        )
    out = _text_out(args)
    print(report.text(), file=out)
    if args.execution_json:
        write_text(args.execution_json, json.dumps(report.to_json(), indent=1) + "\n")
        _written(args.execution_json, "execution as vkg-execution/5", out)
    if args.animate:
        from vkgl.execute.animate import animate

        animate(report, args.animate)
        _written(args.animate, "animation of the execution", out)
    return report.status == "reached"


# ---------------------------------------------------------------- arguments
