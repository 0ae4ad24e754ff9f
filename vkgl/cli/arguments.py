"""The arguments of `vkgc`: one parser, every argument with its help and its range.

A usage error (unknown option, missing argument, a number out of range) is an
input error: exit 1 with a message that names the option, never exit 2, which
means "no plan" to scripts.
"""

from __future__ import annotations

import argparse
import math
import re
import sys
from collections.abc import Callable, Sequence
from typing import Any, NoReturn

from vkgl.cli.exit_codes import EXIT_INPUT

MAX_DEPTH_LIMIT = 12
"""Graphs in a sequence at most: deeper searches grow exponentially where the bound prunes little."""

TIMEOUT_LIMIT = 3600.0
"""s: a search longer than an hour is a mistake, not a plan."""

MAX_REPLANS_LIMIT = 100
MAX_JOBS = 256


class _Parser(argparse.ArgumentParser):
    """argparse, but usage errors exit with 1 (input error), not 2, and suggest the name meant."""

    argv: list[str] | None = None  # what `main` parses (sys.argv[1:] when None), to know the sub-command

    def error(self, message: str) -> NoReturn:
        self.print_usage(sys.stderr)
        hints = _suggestions(self, message)
        self.exit(EXIT_INPUT, f"{self.prog}: error: {message}\n" + "".join(f"{self.prog}: {h}\n" for h in hints))


def _suggestions(parser: _Parser, message: str) -> list[str]:
    """ "did you mean" for each misspelled option (`--exectue`) or sub-command (`slove`) a usage error names."""
    from vkgl.errors import did_you_mean

    hints = []
    if message.startswith("unrecognized arguments: "):
        options = _option_strings(parser, _command_in(parser, sys.argv[1:] if parser.argv is None else parser.argv))
        for word in message.removeprefix("unrecognized arguments: ").split():
            if word.startswith("-") and (hint := did_you_mean(word.split("=", 1)[0], options)):
                hints.append(f"{word}: {hint}")
    elif (choice := re.match(r"argument (\S+): invalid choice: '([^']*)' \(choose from (.*)\)$", message)) is not None:
        choices = re.findall(r"'([^']*)'", choice.group(3))
        if hint := did_you_mean(choice.group(2), choices):
            hints.append(f"{choice.group(2)}: {hint}")
    return hints


def _option_strings(parser: argparse.ArgumentParser, command: str | None) -> list[str]:
    """The options of `parser` and of its sub-command `command` (all of them when None): an unknown option
    is reported by the top parser, and only the command's own options are worth suggesting."""
    options = []
    for action in parser._actions:
        options += [o for o in action.option_strings if o.startswith("--")]
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                if command is None or name == command:
                    options += _option_strings(sub, None)
    return options


def _command_in(parser: argparse.ArgumentParser, argv: list[str]) -> str | None:
    """The sub-command named in `argv`, if any."""
    names = {n for a in parser._actions if isinstance(a, argparse._SubParsersAction) for n in a.choices}
    return next((word for word in argv if word in names), None)


def _bounded_int(low: int, high: int) -> Callable[[str], int]:
    def parse(text: str) -> int:
        try:
            value = int(text.strip(), 10) if text.strip().lstrip("+-").isascii() and len(text) <= 20 else None
        except ValueError:
            value = None
        if value is None or not low <= value <= high:
            raise argparse.ArgumentTypeError(f"expected a whole number from {low} to {high}, got {text!r}")
        return value

    parse.__name__ = "whole number"  # what argparse names in its message
    return parse


def _seconds(text: str) -> float:
    try:
        value = float(text) if text.strip().isascii() else math.nan
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and 0 < value <= TIMEOUT_LIMIT):
        raise argparse.ArgumentTypeError(f"expected seconds, more than 0 and at most {TIMEOUT_LIMIT:g}, got {text!r}")
    return value


class _Version(argparse.Action):
    """`--version`: print `vkgc VERSION` and exit; the version is looked up only then (importlib.metadata is slow)."""

    def __init__(self, option_strings: list[str], dest: str = argparse.SUPPRESS, help: str | None = None) -> None:
        super().__init__(option_strings=option_strings, dest=dest, default=argparse.SUPPRESS, nargs=0, help=help)

    def __call__(self, parser: argparse.ArgumentParser, *args: Any) -> NoReturn:
        from vkgl import __version__

        print(f"vkgc {__version__}")
        parser.exit()


def build_parser(argv: Sequence[str] | None = None) -> argparse.ArgumentParser:
    """The argument parser of `vkgc`: of all sub-commands, or, given the `argv` it will parse and when that
    starts with a sub-command, of that one alone (argparse makes each sub-command a parser of its own, and
    making the six others was a fortieth of a `vkgc check`; nothing parsed after the sub-command's name
    reaches them)."""
    parser = _Parser(
        prog="vkgc",
        description="Compile, explore, infer and plan with VKG (virtual kinematic graph) programs.",
        epilog="exit codes: 0 ok, 1 input errors (usage errors too), 2 no plan, 3 timeout, 4 internal error, "
        "5 plan executed in physics but the goal was not reached (solve --execute), 130 interrupted, "
        "141 the output's reader went away (| head) after a success",
    )
    parser.add_argument("--version", action=_Version, help="print the version")
    parser.add_argument("--debug", action="store_true", help="show the traceback of internal errors")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    named = [argv[0]] if argv and argv[0] in SUBCOMMANDS else list(SUBCOMMANDS)
    for name in named:
        helped, add_arguments = SUBCOMMANDS[name]
        add_arguments(_subcommand(sub, name, help=helped))
    return parser


def _check_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("files", nargs="+", metavar="FILE", help=".vkg files to check (each with what it uses)")


def _fmt_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("files", nargs="+", metavar="FILE", help=".vkg files to rewrite in place")
    p.add_argument("--check", action="store_true", help="only report files that would change (exit 1)")


def _explore_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("bodyfile", metavar="BODYFILE", help=".vkg file that declares the body")
    p.add_argument("--body", metavar="NAME", help="the body to explore (default: the file's only body)")
    p.add_argument("-o", "--output", required=True, metavar="TRIALS.npz", help="where to write the vkg-trials/1 data")
    p.add_argument("--plot", metavar="F.png", help="also draw the trials (top view)")
    _add_run_options(p)


def _infer_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("trials", metavar="TRIALS.npz", help="a vkg-trials/1 dataset (from `vkgc explore`)")
    p.add_argument("-o", "--output", required=True, metavar="MODULE.vkg", help="where to write the affordance module")
    p.add_argument("--report", metavar="R.json", help="also write the per-trial report (vkg-infer-report/2)")
    p.add_argument("--plot", metavar="F.png", help="also draw the posterior over types by contact")
    p.add_argument(
        "--use",
        metavar="MODULE",
        help="module that declares the body, as the output will find it: a dotted name or a path from the output's "
        "folder, e.g. ../bodies/crate.vkg (default stdlib.bodies.<body>; looked up before inferring)",
    )


def _learn_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "bodyfiles",
        nargs="+",
        metavar="BODYFILE",
        help="body files, or folders of them (every *.vkg inside, in name order)",
    )
    p.add_argument("--body", metavar="NAME", help="with one BODYFILE: the body to learn when it declares several")
    p.add_argument(
        "-o",
        "--output",
        metavar="DIR",
        help="where to write <body>.vkg (default: affordances/ beside the body file's bodies/ folder, "
        "else affordances/ in the body file's folder)",
    )
    p.add_argument("--force", action="store_true", help="replace an existing <body>.vkg that learn did not generate")
    p.add_argument(
        "--ray",
        nargs="?",
        const="",
        default=None,
        metavar="ADDRESS",
        help="run the trials on Ray (pip install 'vkgl[ray]'): the cluster at ADDRESS (auto, HOST:6379 or "
        "ray://HOST:10001), or without ADDRESS a local Ray instance with --jobs CPUs; the modules written are "
        "the same as without --ray (put --ray after the files)",
    )
    _add_run_options(p)


def _lsp_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--stdio",
        action="store_true",
        help="talk over stdin/stdout (the default and only transport; accepted because clients pass it)",
    )


def _solve_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("taskfile", metavar="TASKFILE", help=".vkg file that declares the task")
    p.add_argument("--task", metavar="NAME", help="the task to solve (needed when the file declares several)")
    p.add_argument("--json", metavar="F", help="write the plan as vkg-plan/8 JSON (-: stdout, the text to stderr)")
    p.add_argument("--plot", metavar="F.png", help="draw the plan (one panel per mode)")
    p.add_argument(
        "--max-depth",
        type=_bounded_int(1, MAX_DEPTH_LIMIT),
        metavar="N",
        help=f"override the task's search max_depth (1 to {MAX_DEPTH_LIMIT})",
    )
    p.add_argument(
        "--timeout",
        type=_seconds,
        metavar="S",
        help=f"override the task's search timeout (s, more than 0, at most {TIMEOUT_LIMIT:g})",
    )
    p.add_argument(
        "-v", "--verbose", action="store_true", help="also print the joint configurations and the search's counters"
    )
    p.add_argument("--execute", action="store_true", help="replay the plan in DART physics and report the goal error")
    p.add_argument(
        "--replan",
        action="store_true",
        help="closed loop: re-solve from the observed scene when a body strays (implies --execute)",
    )
    p.add_argument(
        "--max-replans",
        type=_bounded_int(0, MAX_REPLANS_LIMIT),
        default=3,
        metavar="N",
        help=f"give up after N re-solves (default 3, at most {MAX_REPLANS_LIMIT})",
    )
    p.add_argument("--animate", metavar="F.gif", help="write a top-view animation of the execution (implies --execute)")
    p.add_argument(
        "--execution-json", metavar="F", help="write the execution report as vkg-execution/5 JSON (implies --execute)"
    )


SUBCOMMANDS: dict[str, tuple[str, Callable[[argparse.ArgumentParser], None]]] = {
    "check": ("parse and check .vkg files", _check_arguments),
    "fmt": ("rewrite .vkg files in canonical form", _fmt_arguments),
    "explore": ("run a body's exploration grid in DART", _explore_arguments),
    "infer": ("infer affordances from a trials dataset", _infer_arguments),
    "learn": ("explore + infer: generate the affordance modules of bodies", _learn_arguments),
    "lsp": ("run the language server for editors (LSP over stdio)", _lsp_arguments),
    "solve": ("plan for a task", _solve_arguments),
}
"""The sub-commands in the order `vkgc --help` lists them: their help and what adds their arguments."""


def _subcommand(sub: Any, name: str, **kwargs: Any) -> argparse.ArgumentParser:
    parser: argparse.ArgumentParser = sub.add_parser(name, **kwargs)
    # `--debug` is accepted after the sub-command too (`vkgc solve T --debug`).
    parser.add_argument("--debug", action="store_true", default=argparse.SUPPRESS, help=argparse.SUPPRESS)
    return parser


def _add_run_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--seed", type=_bounded_int(0, 2**32 - 1), default=0, help="random seed (default 0)")
    p.add_argument(
        "--jobs",
        type=_bounded_int(1, MAX_JOBS),
        default=None,
        metavar="N",
        help=f"parallel processes (default: all cores; 1 to {MAX_JOBS})",
    )
