"""Every diagnostic code of the front end, with its one-line meaning.

Codes are stable: tools and users grep for them. docs/errors.md shows an
example of each; tests/lang/golden/ holds a golden test for each.
"""

from __future__ import annotations

CODES: dict[str, str] = {
    # syntax (vkgl/lang/parser.py)
    "E101": "unexpected token",
    "E102": "unexpected character or unterminated string",
    "E103": "unexpected end of file",
    "E104": "nesting too deep",
    "E105": "unknown unit",
    # units and values as written (vkgl/lang/parser.py)
    "E201": "wrong dimension of a unit",
    "E202": "missing unit",
    "E203": "unit on a plain number",
    "E204": "wrong number of components",
    "E205": "unit both after the vector and on its components",
    "E206": "not a whole number",
    "E207": "rpy on a body placed on the table",
    "E208": "number too large",
    # names (vkgl/lang/checks.py)
    "E301": "unknown name",
    "E302": "duplicate name",
    "E303": "unknown frame on a body",
    "E304": "unknown effector",
    "E305": "name of the wrong kind",
    "E306": "goal on a body not in the task's scene",
    "E307": "unknown link in the robot's URDF",
    # values (vkgl/lang/checks.py)
    "E401": "non-positive mass",
    "E402": "non-positive size",
    "E403": "negative friction",
    "E404": "zero direction vector",
    "E405": "joint limits lower > upper",
    "E406": "statement given twice",
    "E407": "required statement missing",
    "E408": "scene without a table",
    "E409": "scene without a robot",
    "E410": "task without a goal",
    "E411": "non-positive count, duration, force, timeout or tolerance",
    "E412": "posterior outside [0, 1]",
    # modules and files (vkgl/lang/resolve.py, checks.py)
    "E501": "missing module",
    "E502": "import cycle",
    "E503": "mesh file missing or unreadable",
    "E504": "URDF file missing or unreadable",
    "E505": "source file missing or unreadable",
    # warnings
    "W601": "a goal body that no imported affordance can move",
    "W602": "a tool frame with no correspondence in a task's scene",
}
