"""The files a command reads and writes, checked before any work is done.

An input file that cannot be read (missing, not a regular file, too large) is
a diagnostic naming it (`path: error[E506]: ...`), exit 1, before any work.

An output is refused (exit 1, naming both) when it is one of the command's
inputs or another of its outputs, when it is a directory, or when its folder
is missing or not writable: minutes of exploration or simulation must never
end in a lost input or an unwritable result.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from vkgl.errors import InputError

# The options of each sub-command that name files to read, and those that name a file to write.
INPUT_FILES: dict[str, tuple[str, ...]] = {
    "explore": ("bodyfile",),
    "infer": ("trials",),
    "learn": ("bodyfiles",),
    "solve": ("taskfile",),
}
OUTPUT_FILES: dict[str, tuple[str, ...]] = {
    "explore": ("output", "plot"),
    "infer": ("output", "report", "plot"),
    "solve": ("json", "plot", "execution_json", "animate"),
}


def check_inputs(args: argparse.Namespace) -> None:
    """Raise CompileError (diagnostics naming each file, no position) for input files that cannot be read.

    Looks with `stat` before anything opens them: a missing file, a directory, a
    FIFO, a device or a symbolic-link loop, and a `.vkg` source over the size
    limit, are reported as `path: error[CODE]: message`, exit 1.
    """
    from vkgl.errors import CompileError
    from vkgl.lang.syntax.sources import file_problem

    problems = []
    for option, value in _values(args, INPUT_FILES):
        if option == "bodyfiles" and Path(value).is_dir():
            continue  # `vkgc learn FOLDER`: its *.vkg files are checked when they are compiled
        problem = file_problem(Path(value), value, limit=option != "trials")
        if problem is not None:
            problems.append(problem)
    if problems:
        raise CompileError(problems)


def check_paths(args: argparse.Namespace) -> None:
    """Raise InputError for an output that cannot be written or would replace an input or another output."""
    inputs = [(option, Path(value)) for option, value in _values(args, INPUT_FILES)]
    seen: list[tuple[str, Path]] = []
    for option, value in _values(args, OUTPUT_FILES):
        path = Path(value)
        flag = _flag(option)
        _check_writable(flag, path)
        for other_option, other in inputs + seen:
            if _same_file(path, other):
                what = "an input" if (other_option, other) in inputs else "another output"
                raise InputError(
                    f"{flag} {value}: is {what} of this command ({_flag(other_option)} {other}); "
                    "write to another file, so nothing is lost"
                )
        seen.append((option, path))


def _values(args: argparse.Namespace, table: dict[str, tuple[str, ...]]) -> list[tuple[str, str]]:
    out = []
    for option in table.get(args.command, ()):
        value = getattr(args, option, None)
        for item in value if isinstance(value, list) else [value]:
            if item:
                out.append((option, str(item)))
    return out


def _flag(option: str) -> str:
    positional = {"bodyfile": "BODYFILE", "bodyfiles": "BODYFILE", "trials": "TRIALS", "taskfile": "TASKFILE"}
    return positional.get(option, "--" + option.replace("_", "-"))


def _check_writable(flag: str, path: Path) -> None:
    if path.is_dir():
        raise InputError(f"{flag} {path}: is a directory; name a file in it")
    folder = path.parent
    if not folder.is_dir():
        raise InputError(f"{flag} {path}: there is no directory `{folder}`; create it first")
    if not os.access(folder, os.W_OK):
        raise InputError(f"{flag} {path}: the directory `{folder}` is not writable")


def _same_file(a: Path, b: Path) -> bool:
    """Whether two paths name one file (through links and `..` too), whether or not it exists yet."""
    try:
        if a.exists() and b.exists():
            return os.path.samefile(a, b)
        return a.resolve() == b.resolve()
    except (OSError, RuntimeError):  # a symlink loop names no file we could replace
        return False
