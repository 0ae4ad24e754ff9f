"""Diagnostic codes of what is physically possible: scene geometry (E42x), motion ranges (E43x), joints (E44x).

`vkgl.lang.diagnostics.codes` re-exports them; they are registered after its own codes, in this order.
"""

from __future__ import annotations

from vkgl.lang.diagnostics.registry import register as _code

# scene geometry (checks_scene.py): tolerances TOUCH, EDGE and REST there, definitions in docs/language.md
BODIES_OVERLAP = _code(
    "E420",
    "bodies overlap at the start",
    (
        "Two bodies of a scene, or a body and a robot's base, interpenetrate at the start by more than 1 mm "
        "(touching is fine). Shapes are exact: boxes, cylinders, the parts of unions, the convex hulls of "
        "meshes. Move one of them; the message says by how much they overlap."
    ),
)
OFF_TABLE = _code(
    "E421",
    "body off the table or overhanging its edge",
    (
        "A body without a physical `joint` must lie on the table: the shadow of its shape on the table may "
        "pass the table's rectangle by at most 1 mm. The message gives the body's extent and the table's. Any "
        "body farther than 1 km from the table's centre (`-1e308`) is far off the table. Move the body onto "
        "the table, or make the table larger. A position more than three table diagonals away that a smaller "
        "length unit would put on the table (`(45, 10) m` for centimetres) gets a note saying so."
    ),
)
FLOATING_BODY = _code(
    "E422",
    "body neither resting on the table nor on another body",
    (
        "A body placed `at (x, y, z)` without a physical `joint` must rest: its lowest point within 1 mm of "
        "the table top, or of the top of another body under it (whose shadow on the table overlaps its own). "
        "It floats, or sinks into the table. Place it `on table at (x, y) m`, or give the height the message "
        "suggests."
    ),
)
GOAL_OFF_TABLE = _code(
    "E423",
    "goal off the table",
    (
        "At its goal (at the goal's yaw, or at the best heading when the yaw is free, within the goal's "
        "tolerances) the body would pass the table's edge by more than 1 mm plus the position tolerance. Move "
        "the goal onto the table. As for E421, a note names the smaller length unit that would put a far goal "
        "on the table (`(600, 100) m` for millimetres). A region goal is E423 when its body fits in the region "
        "but not in the part of it that lies on the table."
    ),
)
GOAL_IN_ROBOT_BASE = _code(
    "E424",
    "goal inside a robot's base",
    (
        "At its goal the body would overlap a robot's base by more than 1 mm plus the position tolerance. The"
        " base is the collision geometry of the first link of the robot's URDF (else a cylinder of radius 10 "
        "cm around the robot's position). Move the goal away from the robot."
    ),
)
GOAL_IN_FIXED_BODY = _code(
    "E425",
    "goal inside a body that nothing can move",
    (
        "At its goal the body would overlap, by more than 1 mm plus the position tolerance, a body of the "
        "scene that no affordance of the compilation moves and that has no physical joint: it stays where it"
        " is. Move the goal, or `use` an affordance module for that body."
    ),
)
JOINT_BODY_TOUCHES = _code(
    "E426",
    "a body on a joint touches another body",
    (
        "A body on a physical joint hangs 1 mm above where the scene places it (so that it does not rub on "
        "the table: the simulator anchors its joint there, and the planner's geometry knows it). There it is "
        "less than 0.5 mm from another body (or overlaps it by at most 1 mm, E420 reports more): when it "
        "moves on its joint it rubs on that body and drags it along (a drawer touching its cabinet's top "
        "dragged the cabinet 20 cm in DART). Move it so that it has room on every side, e.g. a drawer "
        "placed lower in its cabinet."
    ),
)
CONTRADICTORY_GOALS = _code(
    "E427",
    "goals of one body that cannot both hold",
    (
        "Two goals of a task name the same body, and no pose meets both: their positions lie farther apart "
        "than the sum of their position tolerances, their headings farther than the sum of their heading "
        "tolerances, or their joint openings farther than the sum of theirs (relative goals compared as the "
        "poses they stand for; a region goal is not compared). Keep one of them, or widen the tolerances."
    ),
)

# motion ranges (builder.py, checks.py)
RANGE_WITHOUT_STATE = _code(
    "E430",
    "a range on a motion that has no state",
    (
        "`range LO to HI UNIT` bounds the displacement of a `prismatic` motion or the angle of a `revolute` "
        "one; a `fixed` or `free` motion has no single value to bound. Remove the range, or give the motion "
        "its type."
    ),
)
REVERSED_RANGE = _code(
    "E431",
    "a motion range with lower > upper",
    ("A motion's range is written `range LOWER to UPPER UNIT`, lower first: swap them."),
)
NEGATIVE_RANGE = _code(
    "E432",
    "a motion range below zero",
    (
        "Motion values are never negative: the positive sense of a motion is the one the exploring force "
        "produced, and plans use only that sense (no pulling). A range that starts below zero is an error, "
        "not clipped: write `range 0 to HI UNIT` (and, for the other sense, an affordance whose axis points "
        "the other way)."
    ),
)
OPEN_TURN = _code(
    "E433",
    "an open range on a turn",
    (
        "`open` after a range says the body was still sliding when its exploration ended, so plans may slide "
        "it further (a free slide on its support). A turn is not extended that way: a push near a body's end "
        "turns it about a pivot that drifts as it turns (docs/inference.md), so a revolute motion is known "
        "only over the angles it was explored over. Remove `open`, or explore the turn further."
    ),
)

# physical joints and joint goals (builder.py, checks_joints.py)
NEGATIVE_JOINT_DYNAMICS = _code(
    "E440",
    "negative joint damping or friction",
    (
        "A joint's `damping` and `friction` resist its motion; they are zero or positive (0 means none, as "
        "leaving them out does). A negative value would push the joint along, which no real slide or hinge "
        "does."
    ),
)
NO_JOINT_TO_OPEN = _code(
    "E441",
    "an opening for a body without a physical joint",
    (
        "`goal B open Q` sets the coordinate of B's physical joint (its slide or hinge), and `B : T at POSE "
        "open Q` in a scene starts it there, so B's type must declare a `joint prismatic|revolute ...`. A body "
        "without one has no opening: give it a pose goal (`goal B at (x, y) m`) or leave out the scene's "
        "`open Q`, or name the body that has the joint."
    ),
)
START_PAST_JOINT_LIMIT = _code(
    "E442",
    "a body that starts past its joint's limits",
    (
        "`B : T at POSE open Q` starts B's physical joint at Q, measured from where B is placed (0) as the "
        "joint's `limits` are; without `open Q` it starts at 0. A joint cannot start past its stops: give a Q "
        "within the limits (also when the limits exclude 0, e.g. `limits (10, 20) cm`), or widen them if the "
        "real joint goes further."
    ),
)

# regions of the table's plane (checks_regions.py): region goals and keep-out regions, docs/language.md
REGION_CORNERS_SWAPPED = _code(
    "E450",
    "a region's corners swapped",
    (
        "`region (x0, y0) to (x1, y1) UNIT` is the axis-aligned box from its lower-left corner to its upper-right "
        "one: x0 <= x1 and y0 <= y1. The message says which coordinates are swapped and the note gives the "
        "region as it was probably meant."
    ),
)
REGION_NOT_CONVEX = _code(
    "E451",
    "a region that is not a convex polygon",
    (
        "A region is a box at least 1 mm wide along both axes, or a `polygon` of at least three vertices, in "
        "order around it, that is convex and encloses some area. A concave outline can be split into convex "
        "regions (several `keep out` statements, or the convex part a goal needs)."
    ),
)
KEEP_OUT_AT_START = _code(
    "E452",
    "a keep-out region that a body starts in",
    (
        "`keep out R` keeps every body of the task's scene out of region R (`keep B out of R` only B): no body's "
        "footprint may enter it while the plan moves it. A body whose footprint is already inside R by more "
        "than 1 mm at the start could never satisfy that. The message says which body and how deep; move the "
        "region, or name the bodies it is meant for (`keep block out of R`)."
    ),
)
REGION_TOO_SMALL = _code(
    "E453",
    "a region goal the body cannot fit in",
    (
        "`goal B in R` asks for B's whole footprint (the shadow of its shape on the table) inside region R, "
        "passing its edges by at most the position tolerance. At no heading the goal allows (every 5 deg when "
        "its yaw is free) does the footprint fit: no plan can reach the goal. The message gives the region's and "
        "the footprint's extents; make the region larger, or allow other headings."
    ),
)
