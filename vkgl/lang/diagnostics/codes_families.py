"""Diagnostic codes of contact families (E47x): `family along DIR from LO to HI UNIT [drift VEC] [arc ...] [sigma Q]`.

`vkgl.lang.diagnostics.codes` re-exports them; they are registered after the physical codes, in this order.
The checks are in vkgl/lang/checks/families.py; the meaning in docs/language.md, "Families".
"""

from __future__ import annotations

from vkgl.lang.diagnostics.registry import register as _code

FAMILY_WITHOUT_CONTACT = _code(
    "E470",
    "a family on an affordance that has no contact to move",
    (
        "A `family` moves an affordance's contact along its face, so the affordance needs a contact pose "
        "(`action fixed at POSE`) and a motion that a push at a point makes: a slide (`prismatic`) or a turn "
        "(`revolute`). A grasp that frees the body (`motion free`) or an action without a pose has no contact "
        "to move along a face: remove the `family` line."
    ),
)
FAMILY_OFF_THE_FACE = _code(
    "E471",
    "a family's direction that leaves the face",
    (
        "A family's `along` direction is the line on the face along which the contact may move: it lies across "
        "the push, at right angles to a slide's direction and to a turn's axis (within 1 deg). Write the "
        "face's direction, e.g. `along (0, 1, 0)` for a push along x."
    ),
)
FAMILY_WITHOUT_ITS_CONTACT = _code(
    "E472",
    "a family's offsets that leave out the action's contact",
    (
        "`family along DIR from LO to HI UNIT` gives the offsets of the contact from the action's pose, lower "
        "first; the action's own contact (offset 0) is where the `motion` line was measured, so LO <= 0 <= HI. "
        "Swap swapped bounds; move the action's pose into the band (or widen the band to reach it)."
    ),
)
FAMILY_WRONG_SPREAD = _code(
    "E473",
    "a family's drift or sigma that does not fit its motion",
    (
        "A turn's pivot may drift with the offset (`drift (x, y, z)`, metres of pivot per metre of offset); a "
        "slide has no pivot, so no drift. `sigma` is how far what the explored contacts did spreads about the "
        "family: for a turn a length (the pivot's spread), for a slide an angle (the direction's spread), never "
        "negative."
    ),
)
FAMILY_BAD_ARC = _code(
    "E474",
    "an arc that is not a slide's, or whose pivot would not lie beyond the centre line",
    (
        "`arc lever L bias B ahead A` says how a slide pushed off its centre turns the body: at offset s the pivot "
        "lies A ahead of the contact and L^2/|s| + B across the push, on the far side of the centre line. Only a "
        "slide (`prismatic`) has a centre to be pushed off, and a turn's family moves its pivot with `drift` "
        "instead: write `arc` only in a slide's family, without `drift`. The lever is more than 0 and the pivot "
        "stays beyond the centre line over the whole band (L^2/|s| + B > 0 at the band's ends): widen the lever, "
        "raise the bias or narrow the band. With an `arc`, sigma is the law's error in the turn over 10 cm of push "
        "(an angle)."
    ),
)
