"""`vkgc` arguments: usage errors are input errors (exit 1), numbers are checked before any work."""

from __future__ import annotations

import pytest
from conftest import EXAMPLES

from vkgl.cli import main

A_PUSH = str(EXAMPLES / "tasks" / "a_push.vkg")


@pytest.mark.parametrize(
    ("argv", "says"),
    [
        (["solve", A_PUSH, "--max-depth", "abc"], "--max-depth: expected a whole number from 1 to 12"),
        (["solve", A_PUSH, "--max-depth", "0"], "--max-depth: expected a whole number from 1 to 12"),
        (["solve", A_PUSH, "--max-depth", "9" * 5000], "--max-depth: expected a whole number"),
        (["solve", A_PUSH, "--timeout", "inf"], "--timeout: expected seconds"),
        (["solve", A_PUSH, "--timeout", "1e308"], "--timeout: expected seconds"),
        (["solve", A_PUSH, "--timeout", "-1"], "--timeout: expected seconds"),
        (["solve", A_PUSH, "--max-replans", "-1"], "--max-replans: expected a whole number from 0"),
        (["explore", A_PUSH, "-o", "t.npz", "--jobs", "0"], "--jobs: expected a whole number from 1"),
        (["explore", A_PUSH, "-o", "t.npz", "--jobs", "-3"], "--jobs: expected a whole number from 1"),
        (["learn", A_PUSH, "--seed", "１"], "--seed: expected a whole number"),  # fullwidth digit
        (["solve"], "the following arguments are required: TASKFILE"),
        (["solve", A_PUSH, "--no-such-option"], "unrecognized arguments: --no-such-option"),
        (["frobnicate"], "invalid choice: 'frobnicate'"),
    ],
)
def test_a_usage_error_exits_1_and_names_the_option(argv, says, capsys) -> None:
    with pytest.raises(SystemExit) as stop:
        main(argv)
    assert stop.value.code == 1
    err = capsys.readouterr().err
    assert says in err
    assert "Traceback" not in err


def test_every_argument_has_help() -> None:
    import argparse

    from vkgl.cli.arguments import build_parser

    parser = build_parser()
    subparsers = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    for name, sub in subparsers.choices.items():
        for action in sub._actions:
            if action.help is argparse.SUPPRESS or isinstance(action, argparse._HelpAction):
                continue
            assert action.help, f"vkgc {name} {action.option_strings or action.dest}: no help text"


def test_a_file_with_several_tasks_needs_task(tmp_path, capsys) -> None:
    text = (EXAMPLES / "tasks" / "a_push.vkg").read_text(encoding="utf-8")
    second = text.replace("task a_push", "task a_push_again").split("task a_push_again", 1)[1]
    both = tmp_path / "both.vkg"
    both.write_text(text.replace('"../scenes/', f'"{EXAMPLES}/scenes/') + "\ntask a_push_again" + second)
    assert main(["solve", str(both)]) == 1
    err = capsys.readouterr().err
    assert "a_push" in err and "a_push_again" in err and "--task" in err
    assert main(["solve", str(both), "--task", "a_push_again"]) == 0
    assert "task a_push_again: solved" in capsys.readouterr().out


def test_verbose_prints_the_joint_configurations(capsys) -> None:
    assert main(["solve", A_PUSH, "-v"]) == 0
    out = capsys.readouterr().out
    assert "joints (rad; panda_joint1" in out
    assert "step 1 start [" in out and "step 1 end   [" in out


def test_version_prints_the_installed_version(capsys) -> None:
    """`--version` looks the version up only when asked (importlib.metadata is slow to import)."""
    import vkgl

    with pytest.raises(SystemExit) as stop:
        main(["--version"])
    assert stop.value.code == 0
    assert capsys.readouterr().out == f"vkgc {vkgl.__version__}\n"
