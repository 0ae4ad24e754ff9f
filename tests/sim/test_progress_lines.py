"""Exploration's progress on a pipe (`vkgl.sim.explore`, `progress="lines"`): a line every tenth of the trials."""

from __future__ import annotations

import pytest

from vkgl.sim.explore import _progress_lines


@pytest.mark.parametrize("total", [1, 7, 30, 95])
def test_a_line_every_tenth_of_the_trials_and_at_the_last(total: int, capsys: pytest.CaptureFixture[str]) -> None:
    advance = _progress_lines(total)
    for _ in range(total):
        advance()
    advance(stop=True)
    lines = capsys.readouterr().err.splitlines()
    assert 1 <= len(lines) <= 11
    assert lines[-1].startswith(f"exploring: {total}/{total} trials")
    counts = [int(line.split()[1].split("/")[0]) for line in lines]
    assert counts == sorted(set(counts))  # each line later than the one before, none twice
