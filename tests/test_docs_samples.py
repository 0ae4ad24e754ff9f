"""The sample outputs of the docs are what the commands print: each is run here and compared.

A sample is a fenced block right after a `<!-- sample: NAME ... -->` line in docs/*.md. `SAMPLES` says how
each output sample is produced (the command, and the folder it runs in); a `...-task` sample is a `.vkg`
file another sample runs. The comparison is exact for the words; numbers may differ by two units of their
last printed digit (floating point differs between CPUs), or by a sample's `noise` (what a simulation makes
of that rounding), timings (a number before ` s`) are not compared, the search's counters may differ by a
quarter (they follow the floating point too), and runs of spaces count as one.

To update a sample after an intended change of a message, run the command the sample names and paste its
output (`VKG_SHOW_SAMPLES=1` prints every sample's output as it is now).
"""

from __future__ import annotations

import os
import re
import shutil
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import pytest

from vkgl.cli import main

REPO = Path(__file__).resolve().parents[1]
DOCS = REPO / "docs"
MARK = re.compile(r"^<!-- sample: ([\w-]+)[^\n]*-->\n```[\w]*\n(.*?)^```", re.S | re.M)


def samples() -> dict[str, tuple[Path, str]]:
    """Every sample of the docs by name: the file it is in and its text."""
    found: dict[str, tuple[Path, str]] = {}
    for doc in sorted(DOCS.glob("*.md")):
        for name, text in MARK.findall(doc.read_text(encoding="utf-8")):
            assert name not in found, f"sample {name} is named twice ({found[name][0].name}, {doc.name})"
            found[name] = (doc, text)
    return found


@dataclass(frozen=True)
class Sample:
    """How an output sample is produced: `vkgc` with `argv`, in a folder prepared by `setup`."""

    argv: list[str]
    setup: Callable[[Path], None] | None = None  # writes the files the command reads into the folder
    start: str = ""  # the sample shows the output from the first line that starts with this
    noise: float = 0.0  # how far a number may differ at least (what physics makes of a CPU's rounding)
    ran: str = ""  # a session fixture that ran this very command once for several files (tests/conftest.py)


def _user_folder(file_name: str, text: Callable[[], str]) -> Callable[[Path], None]:
    """A folder like the repository root after `pip install .`: `examples/scenes` and `stdlib/` copied (the
    installed stdlib is another copy), and a task sample saved as a file."""

    def setup(folder: Path) -> None:
        shutil.copytree(REPO / "examples" / "scenes", folder / "examples" / "scenes")
        shutil.copytree(REPO / "stdlib", folder / "stdlib")
        (folder / file_name).write_text(text(), encoding="utf-8")

    return setup


def _task(name: str) -> str:
    return samples()[name][1]


def _with_bad_goal() -> str:
    """The quickstart's task with the mistake its error sample shows."""
    return _task("quickstart-task").replace("goal block at (0.60, 0.05) m", "goal block at (0.60, 90deg) m")


SAMPLES: dict[str, Sample] = {
    "quickstart-solve": Sample(
        ["solve", "examples/tasks/b_stick_push.vkg", "--plot", "{tmp}/plan.png", "--json", "{tmp}/plan.json"]
    ),
    "quickstart-check-error": Sample(["check", "my_task.vkg"], _user_folder("my_task.vkg", _with_bad_goal)),
    "planning-read": Sample(["solve", "examples/tasks/d_rotate_push.vkg"]),
    "execution-report": Sample(
        ["solve", "examples/tasks/a_push.vkg", "--execute"],
        start="execution of a_push",
        noise=0.05,
        ran="a_push_executed",  # its stderr taken for a terminal: the sample is stdout, the same on a pipe
    ),
    "planning-no-plan": Sample(
        ["solve", "no_tools.vkg"], _user_folder("no_tools.vkg", lambda: _task("planning-no-plan-task"))
    ),
    "planning-grip": Sample(
        ["solve", "heavy_bar.vkg"], _user_folder("heavy_bar.vkg", lambda: _task("planning-grip-task"))
    ),
}
TASKS = {"quickstart-task", "planning-no-plan-task", "planning-grip-task"}


def _run(sample: Sample, tmp: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch) -> str:
    """What the terminal shows: stderr (warnings come first) then stdout; the output files' folder as typed."""
    folder = tmp / "user"
    folder.mkdir()
    if sample.setup is not None:
        sample.setup(folder)
        monkeypatch.chdir(folder)
    else:
        monkeypatch.chdir(REPO)
    out_dir = tmp / "out"
    out_dir.mkdir()
    main([arg.replace("{tmp}", str(out_dir)) for arg in sample.argv])
    captured = capsys.readouterr()
    return _from_start((captured.err + captured.out).replace(f"{out_dir}/", ""), sample.start)


def _from_start(shown: str, start: str) -> str:
    """The output from its first line that starts with `start` (all of it without one)."""
    if not start:
        return shown
    lines = shown.splitlines(keepends=True)
    return "".join(lines[next(k for k, line in enumerate(lines) if line.startswith(start)) :])


_NUMBER = re.compile(r"-?\d+(?:\.\d+)?")
_TIMING = re.compile(r"^ s(?![a-z])")
_COUNTER = re.compile(r"^ (graphs? expanded|task-space checks?|joint-space checks?|sequences)")


def differences(shown: str, real: str, noise: float = 0.0) -> list[str]:
    """Where `real` differs from the doc's `shown` beyond the tolerances of the module docstring (numbers at
    least `noise` apart); runs of spaces count as one (columns move with a number's sign)."""
    words_shown, words_real = _NUMBER.split(shown), _NUMBER.split(real)
    if [_spaced(w) for w in words_shown] != [_spaced(w) for w in words_real]:
        return [f"the words differ:\n--- doc\n{shown}\n--- real\n{real}"]
    problems = []
    numbers = zip(_NUMBER.findall(shown), _NUMBER.findall(real), words_shown[1:], strict=True)
    for doc_number, real_number, after in numbers:
        a, b = float(doc_number), float(real_number)
        if _TIMING.match(after):
            continue
        decimals = len(doc_number.partition(".")[2])
        if _COUNTER.match(after):
            ok = abs(a - b) <= 0.25 * max(a, b, 4)
        elif decimals == 0:
            ok = a == b  # a count of steps, a line number
        else:
            ok = abs(a - b) <= max(2 * 10.0**-decimals, noise) + 1e-12
        if not ok:
            problems.append(f"{doc_number} in the doc, {real_number} now (before `{after[:30]}`)")
    return problems


def _spaced(words: str) -> str:
    return re.sub(" +", " ", words)


def test_every_sample_of_the_docs_is_produced_here() -> None:
    assert set(samples()) == set(SAMPLES) | TASKS


@pytest.mark.parametrize("name", sorted(SAMPLES))
def test_a_docs_sample_is_what_the_command_prints(
    name: str,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
    request: pytest.FixtureRequest,
) -> None:
    monkeypatch.delenv("VKG_PATH", raising=False)
    doc, shown = samples()[name]
    sample = SAMPLES[name]
    if sample.ran:  # run once for this test and others, from the repository root, without VKG_PATH
        _, out, err = request.getfixturevalue(sample.ran)
        real = _from_start(err + out, sample.start)
    else:
        real = _run(sample, tmp_path, capsys, monkeypatch)
    if os.environ.get("VKG_SHOW_SAMPLES"):
        print(f"--- {name}\n{real}")
    problems = differences(shown, real, sample.noise)
    assert not problems, f"{doc.relative_to(REPO)}, sample {name}:\n" + "\n".join(problems)


def test_the_quickstart_task_checks_clean_where_a_user_saves_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """At the repository root: its `use "examples/..."` is found, and `use stdlib.tools` has no W603."""
    real = _run(
        Sample(["check", "my_task.vkg"], _user_folder("my_task.vkg", lambda: _task("quickstart-task"))),
        tmp_path,
        capsys,
        monkeypatch,
    )
    assert real == "checked 1 file: no errors\n"


def test_the_tolerance_takes_cpu_noise_and_catches_a_change() -> None:
    doc = "task t: solved in 2 steps (depth 3; 0.231 s; 8 graphs expanded)\nfinal: block at (0.950, 0.000) m"
    assert differences(doc, doc.replace("0.231 s", "9.5 s").replace("0.950", "0.951")) == []
    assert differences(doc, doc.replace("8 graphs", "9 graphs")) == []
    assert differences(doc, doc.replace("0.950", "0.960"))
    assert differences(doc, doc.replace("2 steps", "3 steps"))
    assert differences(doc, doc.replace("block at", "stick at"))
