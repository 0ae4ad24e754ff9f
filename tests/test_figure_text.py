"""Titles that fit (`vkgl.figure_text`): no line wider than its room, nothing of the text lost."""

from __future__ import annotations

import re

from hypothesis import given, settings
from hypothesis import strategies as st

from vkgl.figure_text import fit_lines, text_width

_STEP = "G2: add Block.turn_px_right_family_member@+2.63cm/over+20deg+1.00cm on block\nwith stick.tip: slide 25.0 cm"


def test_a_short_title_is_left_as_it_is() -> None:
    assert fit_lines("G0: start", 240.0, 9) == "G0: start"


def test_a_long_step_title_is_broken_between_words_and_after_punctuation_within_its_column() -> None:
    fitted = fit_lines(_STEP, 240.0, 9)
    lines = fitted.split("\n")
    assert all(text_width(line, 9) <= 240.0 for line in lines)
    assert "with stick.tip: slide 25.0 cm" in lines  # the break it had is kept
    assert any(line.endswith("2.63cm/") for line in lines)  # a word too long for a line breaks after its `/`
    assert fitted.replace("\n", "").replace(" ", "") == _STEP.replace("\n", "").replace(" ", "")


@settings(max_examples=25, deadline=None)
@given(
    st.text(alphabet=st.sampled_from("abcXYZ_.@/+ 0123456789"), min_size=1, max_size=120),
    st.floats(min_value=20.0, max_value=400.0),
)
def test_every_line_fits_and_no_character_is_lost(text: str, width: float) -> None:
    fitted = fit_lines(text, width, 9)
    assert all(text_width(line, 9) <= width for line in fitted.split("\n") if len(line) > 1)
    assert fitted.replace("\n", "").replace(" ", "") == text.replace(" ", "")


def test_a_number_keeps_its_unit_on_its_line() -> None:
    """The last frame of task q's animation: its status broke as `drawer open 10.2` / `cm (goal 10.0 cm)`."""
    text = (
        "q_drawer_and_door   t = 19.12 s   end settle   hand  47 cm up  —  reached, drawer open 10.2 cm "
        "(goal 10.0 cm), door open 30.4 deg (goal 30.0 deg)"
    )
    for width in (0.95 * 7 * 72, 150.0, 200.0, 260.0, 320.0):
        lines = fit_lines(text, width, 10).split("\n")
        assert not any(re.match(r"\s*(cm|s|deg)\b", line) for line in lines), lines
