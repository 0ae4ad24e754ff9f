"""`vkgc`: the command line. Thin: parse arguments, call the driver (`vkgl.api`), print.

Exit codes (all sub-commands, `vkgl.cli.exit_codes`): 0 success; 1 errors in
the input, usage errors included; 2 no plan within the search limits; 3
timeout; 4 internal error (`--debug` shows the traceback); 5 a plan carried
out in physics missed its goal (`solve --execute`); 130 interrupted; 141 the
reader of the output went away (`| head -1`) and the command otherwise
succeeded (`vkgl.cli.pipes`).
"""

from __future__ import annotations

import argparse
import sys
import traceback
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from vkgl.cli.arguments import build_parser
from vkgl.cli.commands import COMMANDS, Command, print_diagnostics
from vkgl.cli.exit_codes import EXIT_INPUT, EXIT_INTERNAL, EXIT_INTERRUPTED, EXIT_OK, EXIT_PIPE_CLOSED
from vkgl.cli.paths import check_inputs, check_paths, dash_means_stdout

__all__ = ["build_parser", "main", "run"]


def run() -> None:
    """The `vkgc` console script: Ctrl-C ends it at once (`vkgl.cli.interrupt`); exit with `main()`'s code.

    A closed pipe (`vkgc solve t.vkg | head -1`) silences the output and the
    command runs on to write its files (`vkgl.cli.pipes`); a success is then
    exit 141, as a shell reports for Unix tools.
    """
    from vkgl.cli import interrupt, pipes

    interrupt.install()
    pipes.install()
    try:
        code = main()
    except SystemExit as exc:  # argparse's --help and usage errors
        code = EXIT_OK if exc.code is None else exc.code if isinstance(exc.code, int) else EXIT_INPUT
    sys.exit(EXIT_PIPE_CLOSED if pipes.closed_by_reader() and code == EXIT_OK else code)


def main(argv: Sequence[str] | None = None) -> int:
    """Run `vkgc` with `argv` (default sys.argv[1:]); return the exit code."""
    try:
        parser = build_parser(sys.argv[1:] if argv is None else argv)
        parser.argv = None if argv is None else list(argv)  # type: ignore[attr-defined]  # for "did you mean"
        args = parser.parse_args(argv)
        if args.command is None:
            parser.print_help()
            return EXIT_INPUT
        return _run(COMMANDS[args.command], args)
    except KeyboardInterrupt:  # before or after a command ran (a command's own Ctrl-C is handled in _run)
        print("vkgc: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED


def _run(command: Command, args: argparse.Namespace) -> int:
    from vkgl.errors import CompileError, VkgError

    try:
        dash_means_stdout(args)
        check_paths(args)
        check_inputs(args)
        return command(args)
    except CompileError as exc:
        print_diagnostics(exc.diagnostics, _sources_of(exc), sys.stderr)
        return EXIT_INPUT
    except VkgError as exc:
        print(f"vkgc: error: {exc}", file=sys.stderr)
        return exc.exit_code
    except KeyboardInterrupt:
        print("vkgc: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except OSError as exc:  # a file that vanished or became unwritable while we worked
        where = exc.filename if exc.filename is not None else "a file"
        print(f"vkgc: error: cannot access {where}: {exc.strerror or exc}", file=sys.stderr)
        return EXIT_INPUT
    except Exception as exc:  # the last line of defence: never a bare traceback for users
        if args.debug:
            traceback.print_exc()
        print(
            f"vkgc: internal error: {type(exc).__name__}: {exc} (run with --debug for the traceback)", file=sys.stderr
        )
        return EXIT_INTERNAL


def _sources_of(exc: Any) -> dict[str, str]:
    from vkgl.lang.syntax.sources import read_source

    sources: dict[str, str] = dict(getattr(exc, "sources", {}) or {})
    for diag in exc.diagnostics:
        if diag.span is not None and diag.span.file not in sources:
            text = read_source(Path(diag.span.file), diag.span.file)  # regular, bounded, UTF-8, or not shown
            if isinstance(text, str):
                sources[diag.span.file] = text
    return sources
