"""`vkgc`: the command line. Thin: parse arguments, call the library, print.

Exit codes (all sub-commands): 0 success; 1 errors in the input; 2 no plan
within the search limits; 3 timeout; 4 internal error (`--debug` shows the
traceback). Heavy modules are imported inside the commands so that
`vkgc --help` starts fast.
"""

from __future__ import annotations

import argparse
import sys
import traceback
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

EXIT_OK, EXIT_INPUT, EXIT_NO_PLAN, EXIT_TIMEOUT, EXIT_INTERNAL = 0, 1, 2, 3, 4
# `solve --execute` only: a plan was found, but carried out in physics it did not reach the goal.
EXIT_NOT_REACHED = 5

Command = Callable[[argparse.Namespace], int]
_COMMANDS: dict[str, Command] = {}


def _command(name: str) -> Callable[[Command], Command]:
    def register(fn: Command) -> Command:
        _COMMANDS[name] = fn
        return fn

    return register


def _is_terminal(stream: Any) -> bool:
    return bool(getattr(stream, "isatty", lambda: False)())


def _print_diagnostics(diagnostics: Sequence[Any], sources: dict[str, str], stream: Any) -> None:
    from vkgl.lang.diagnostics import render

    for diag in diagnostics:
        source = sources.get(diag.span.file) if diag.span is not None else None
        print(render(diag, source), file=stream)


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
    _print_diagnostics(diagnostics, sources, sys.stdout)
    errors = sum(1 for d in diagnostics if d.is_error)
    print(_summary(errors, len(diagnostics) - errors, len(args.files)))
    return EXIT_INPUT if errors else EXIT_OK


@_command("fmt")
def cmd_fmt(args: argparse.Namespace) -> int:
    """Rewrite files in canonical form, or with --check list those that would change."""
    from vkgl.errors import CompileError
    from vkgl.lang.printer import format_source

    status = EXIT_OK
    for name in args.files:
        path = Path(name)
        try:
            text = path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as exc:
            print(f"{name}: error: cannot read: {exc}", file=sys.stderr)
            status = EXIT_INPUT
            continue
        try:
            formatted = format_source(text, str(path))
        except CompileError as exc:
            _print_diagnostics(exc.diagnostics, {str(path): text}, sys.stderr)
            status = EXIT_INPUT
            continue
        if formatted == text:
            continue
        if args.check:
            print(f"{name}: would reformat")
            status = EXIT_INPUT
        else:
            path.write_text(formatted, encoding="utf-8")
            print(f"{name}: reformatted")
    return status


def _load_body(path: str, name: str | None) -> Any:
    from vkgl.errors import InputError
    from vkgl.lang.compiler import compile_file

    program = compile_file(path)
    own = [d for d in program.root.decls if getattr(d, "kind", None) == "body"]
    if name is not None:
        if name not in program.bodies:
            known = ", ".join(sorted(program.bodies)) or "none"
            raise InputError(f"{path}: no body named `{name}` (bodies in scope: {known})")
        return program.bodies[name]
    if len(own) != 1:
        names = ", ".join(b.name for b in own) or "none"
        raise InputError(f"{path}: declares {len(own)} bodies ({names}); say which with --body NAME")
    return own[0]


@_command("explore")
def cmd_explore(args: argparse.Namespace) -> int:
    """Run a body's exploration grid in DART and write a `vkg-trials/1` dataset."""
    from vkgl.sim.explore import explore

    body = _load_body(args.bodyfile, args.body)
    trials = explore(body, seed=args.seed, jobs=args.jobs, progress=_is_terminal(sys.stderr))
    trials.save(args.output)
    failed = int((~trials.ok).sum())
    print(f"{args.output}: {len(trials)} trials of {body.name}" + (f", {failed} failed" if failed else ""))
    if args.plot:
        from vkgl.sim.plot import plot_trials

        plot_trials(trials, args.plot)
        print(f"{args.plot}: picture of the trials")
    return EXIT_OK


@_command("infer")
def cmd_infer(args: argparse.Namespace) -> int:
    """Infer affordances from a trials dataset and write a library module."""
    import json

    from vkgl.infer.library import infer_library
    from vkgl.sim.trials import Trials

    trials = Trials.load(args.trials)
    body_use = args.use or f"stdlib.bodies.{trials.body.lower()}"
    header = f"Generated by `vkgc infer {Path(args.trials).name}` from {len(trials)} trials. Do not edit."
    result = infer_library(trials, body_use=body_use, header=header)
    Path(args.output).write_text(result.source, encoding="utf-8")
    print(f"{args.output}: affordances of {trials.body}")
    if args.report:
        Path(args.report).write_text(json.dumps(result.report, indent=1) + "\n", encoding="utf-8")
        print(f"{args.report}: per-trial report")
    if args.plot:
        from vkgl.infer.plot import plot_posteriors

        plot_posteriors(result, args.plot)
        print(f"{args.plot}: posterior over types by contact")
    return EXIT_OK


@_command("learn")
def cmd_learn(args: argparse.Namespace) -> int:
    """Explore a body and infer its affordances in one go."""
    from vkgl.infer.library import learn

    out = learn(
        args.bodyfile,
        body=args.body,
        out_dir=args.output,
        seed=args.seed,
        jobs=args.jobs,
        progress=_is_terminal(sys.stderr),
    )
    print(f"{out}: generated")
    return EXIT_OK


@_command("solve")
def cmd_solve(args: argparse.Namespace) -> int:
    """Plan for a task; print the graph sequence; optionally write JSON and a picture."""
    import json

    from vkgl.plan.solve import solve

    plan = solve(
        args.taskfile,
        max_depth=args.max_depth,
        timeout=args.timeout,
        progress=_is_terminal(sys.stderr),
    )
    print(plan.text())
    if args.verbose:
        print(_search_details(plan.details))
    if args.json:
        Path(args.json).write_text(json.dumps(plan.to_json(), indent=1) + "\n", encoding="utf-8")
        print(f"{args.json}: plan as vkg-plan/1")
    if args.plot and plan.status == "solved":
        from vkgl.viz import plot_plan

        plot_plan(plan, args.plot)
        print(f"{args.plot}: picture of the plan")
    if plan.status == "solved" and (args.execute or args.replan or args.animate or args.execution_json):
        if not _execute(args, plan.to_json()):
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


def _execute(args: argparse.Namespace, plan_json: dict[str, Any]) -> bool:
    """`solve --execute`: replay the plan in DART, print the report, write what was asked for.

    Returns whether the execution reached every goal.
    """
    import json

    from vkgl.sim.execute import execute_file

    if args.animate:
        from vkgl.sim.animate import check_animation_path

        check_animation_path(args.animate)  # refuse a bad file name before minutes of simulation
    report = execute_file(args.taskfile, plan_json, replan=args.replan, max_replans=args.max_replans,
                          record=bool(args.animate))
    print(report.text())
    if args.execution_json:
        Path(args.execution_json).write_text(json.dumps(report.to_json(), indent=1) + "\n", encoding="utf-8")
        print(f"{args.execution_json}: execution as vkg-execution/1")
    if args.animate:
        from vkgl.sim.animate import animate

        animate(report, args.animate)
        print(f"{args.animate}: animation of the execution")
    return report.status == "reached"


# ---------------------------------------------------------------- arguments


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of `vkgc` (all sub-commands)."""
    parser = argparse.ArgumentParser(
        prog="vkgc",
        description="Compile, explore, infer and plan with VKG (virtual kinematic graph) programs.",
        epilog="exit codes: 0 ok, 1 input errors, 2 no plan, 3 timeout, 4 internal error, "
        "5 plan executed in physics but the goal was not reached (solve --execute)",
    )
    parser.add_argument("--version", action="version", version="vkgc 0.1.0")
    parser.add_argument("--debug", action="store_true", help="show the traceback of internal errors")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    _add_sub = sub.add_parser

    def add_parser(name: str, **kwargs: Any) -> argparse.ArgumentParser:
        # `--debug` is accepted after the sub-command too (`vkgc solve T --debug`).
        p = _add_sub(name, **kwargs)
        p.add_argument("--debug", action="store_true", default=argparse.SUPPRESS, help=argparse.SUPPRESS)
        return p

    sub.add_parser = add_parser  # type: ignore[method-assign]

    p = sub.add_parser("check", help="parse and check .vkg files")
    p.add_argument("files", nargs="+", metavar="FILE")

    p = sub.add_parser("fmt", help="rewrite .vkg files in canonical form")
    p.add_argument("files", nargs="+", metavar="FILE")
    p.add_argument("--check", action="store_true", help="only report files that would change (exit 1)")

    p = sub.add_parser("explore", help="run a body's exploration grid in DART")
    p.add_argument("bodyfile", metavar="BODYFILE")
    p.add_argument("--body", metavar="NAME", help="the body to explore (default: the file's only body)")
    p.add_argument("-o", "--output", required=True, metavar="TRIALS.npz")
    p.add_argument("--plot", metavar="F.png", help="also draw the trials (top view)")
    _add_run_options(p)

    p = sub.add_parser("infer", help="infer affordances from a trials dataset")
    p.add_argument("trials", metavar="TRIALS.npz")
    p.add_argument("-o", "--output", required=True, metavar="MODULE.vkg")
    p.add_argument("--report", metavar="R.json", help="also write the per-trial report (vkg-infer-report/1)")
    p.add_argument("--plot", metavar="F.png", help="also draw the posterior over types by contact")
    p.add_argument("--use", metavar="MODULE", help="module that declares the body (default stdlib.bodies.<body>)")

    p = sub.add_parser("learn", help="explore + infer: generate a body's affordance module")
    p.add_argument("bodyfile", metavar="BODYFILE")
    p.add_argument("--body", metavar="NAME")
    p.add_argument("-o", "--output", metavar="DIR", help="where to write <body>.vkg")
    _add_run_options(p)

    p = sub.add_parser("solve", help="plan for a task")
    p.add_argument("taskfile", metavar="TASKFILE")
    p.add_argument("--json", metavar="F", help="write the plan as vkg-plan/1 JSON")
    p.add_argument("--plot", metavar="F.png", help="draw the plan (one panel per mode)")
    p.add_argument("--max-depth", type=int, metavar="N", help="override the task's search max_depth")
    p.add_argument("--timeout", type=float, metavar="S", help="override the task's search timeout (s)")
    p.add_argument("-v", "--verbose", action="store_true", help="say more about the search")
    p.add_argument("--execute", action="store_true", help="replay the plan in DART physics and report the goal error")
    p.add_argument("--replan", action="store_true",
                   help="closed loop: re-solve from the observed scene when a body strays (implies --execute)")
    p.add_argument("--max-replans", type=int, default=3, metavar="N", help="give up after N re-solves (default 3)")
    p.add_argument("--animate", metavar="F.gif", help="write a top-view animation of the execution (implies --execute)")
    p.add_argument("--execution-json", metavar="F",
                   help="write the execution report as vkg-execution/1 JSON (implies --execute)")
    return parser


def _add_run_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument("--jobs", type=int, default=None, metavar="N", help="parallel processes (default: all cores)")


def main(argv: Sequence[str] | None = None) -> int:
    """Run `vkgc` with `argv` (default sys.argv[1:]); return the exit code."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return EXIT_INPUT
    return _run(_COMMANDS[args.command], args)


def _run(command: Command, args: argparse.Namespace) -> int:
    from vkgl.errors import CompileError, VkgError

    try:
        return command(args)
    except CompileError as exc:
        _print_diagnostics(exc.diagnostics, _sources_of(exc), sys.stderr)
        return EXIT_INPUT
    except VkgError as exc:
        print(f"vkgc: error: {exc}", file=sys.stderr)
        return exc.exit_code
    except KeyboardInterrupt:
        print("vkgc: interrupted", file=sys.stderr)
        return 130
    except Exception as exc:  # the last line of defence: never a bare traceback for users
        if args.debug:
            traceback.print_exc()
        print(f"vkgc: internal error: {type(exc).__name__}: {exc} (run with --debug for the traceback)",
              file=sys.stderr)
        return EXIT_INTERNAL


def _sources_of(exc: Any) -> dict[str, str]:
    sources: dict[str, str] = dict(getattr(exc, "sources", {}) or {})
    for diag in exc.diagnostics:
        if diag.span is not None and diag.span.file not in sources:
            try:
                sources[diag.span.file] = Path(diag.span.file).read_text(encoding="utf-8")
            except (OSError, UnicodeDecodeError):
                pass
    return sources


if __name__ == "__main__":
    sys.exit(main())
