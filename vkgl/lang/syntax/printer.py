"""The printer: IR -> canonical VKG source, and `vkgc fmt`.

`print_module` writes the one canonical text of a module: the doc comment, the
`use` lines, then the declarations separated by one blank line; 4-space
indentation, one statement per line, body items in a fixed order. It is exact:
`parse_module(print_module(ir), ir.path) == ir` (numbers are printed with the
shortest text that converts back to the very same SI float in the unit the
user wrote, see `format_scaled`).

`format_source` is `print_module` of the parsed text plus the comments and the
single blank lines the user put between statements, which the IR does not keep.
"""

from __future__ import annotations

import functools
import re
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field

from vkgl.lang.ir.nodes import (
    Affordance,
    AffordanceSet,
    Body,
    BoxShape,
    Constraint,
    Correspondences,
    CylinderShape,
    Explore,
    FixedC,
    FreeC,
    GraspC,
    GraspPolicy,
    MeshShape,
    Module,
    Placement,
    PrismaticC,
    Quantity,
    RevoluteC,
    Robot,
    Scene,
    Shape,
    Span,
    Task,
    UnionShape,
    Use,
)
from vkgl.lang.syntax.printer_tasks import goal_text, keep_out_text, region_text, search_text
from vkgl.lang.syntax.quantities import (
    family_text,
    format_number,
    joint_text,
    pose_text,
    quantity_text,
    range_text,
    string_text,
    vector_text,
)

INDENT = "    "

# ---------------------------------------------------------------- layout


@dataclass
class Line:
    """One output line and where the construct it prints came from.

    `anchor` is the source line the construct starts on (None: unknown; then
    `keyword` + `within` let `format_source` find it); `closes` marks a `}` whose
    anchor is the end line of its block. `leading` holds the full-line comments
    printed above the line as (blank line before it, text), `trailing` those at
    its end; `gap` asks for a blank line above the comments, `gap_before_code`
    for one between the comments and the line.
    """

    depth: int
    text: str
    anchor: int | None = None
    closes: bool = False
    keyword: str | None = None
    within: Span | None = None
    leading: list[tuple[bool, str]] = field(default_factory=list)
    trailing: list[str] = field(default_factory=list)
    gap: bool = False
    gap_before_code: bool = False
    first_comment_line: int | None = None

    @property
    def blank(self) -> bool:
        """True for an empty line."""
        return not self.text


def _line_of(span: Span | None) -> int | None:
    return span.line if span is not None else None


def _end_of(span: Span | None) -> int | None:
    return span.end_line if span is not None else None


class _Layout:
    """Builds the list of `Line`s of a module."""

    def __init__(self) -> None:
        self.lines: list[Line] = []

    def add(self, depth: int, text: str, anchor: int | None = None, **kw: object) -> None:
        self.lines.append(Line(depth, text, anchor, **kw))  # type: ignore[arg-type]

    def blank(self) -> None:
        if self.lines and not self.lines[-1].blank:
            self.lines.append(Line(0, ""))

    def block(self, depth: int, header: str, node_span: Span | None, fill: Callable[[int], None]) -> None:
        self.add(depth, header + " {", _line_of(node_span))
        fill(depth + 1)
        self.add(depth, "}", _end_of(node_span), closes=True)

    # ------------------------------------------------------------ module

    def module(self, m: Module) -> None:
        if m.doc is not None:
            for text in m.doc.split("\n"):
                self.add(0, "# " + text if text else "#")
            self.blank()
        for use in m.uses:
            self.add(0, "use " + _use_target(use), _line_of(use.span))
        for decl in m.decls:
            self.blank()
            self.decl(decl)

    def decl(self, d: object) -> None:
        if isinstance(d, Body):
            self.block(0, f"body {d.name}", d.span, lambda k: self.body_items(k, d))
        elif isinstance(d, Robot):
            self.block(0, f"robot {d.name}", d.span, lambda k: self.robot_items(k, d))
        elif isinstance(d, AffordanceSet):
            self.block(0, f"affordances {d.body.name}", d.span, lambda k: self.affordances(k, d))
        elif isinstance(d, Correspondences):
            self.block(0, "correspondences", d.span, lambda k: self.correspondences(k, d))
        elif isinstance(d, Scene):
            self.block(0, f"scene {d.name}", d.span, lambda k: self.scene_items(k, d))
        elif isinstance(d, Task):
            self.block(0, f"task {d.name}", d.span, lambda k: self.task_items(k, d))
        else:
            raise TypeError(f"not a declaration: {type(d).__name__}")

    # ------------------------------------------------------------ bodies

    def body_items(self, k: int, b: Body) -> None:
        self.shape(k, "shape ", b.shape)
        self.add(k, "mass " + quantity_text(b.mass), _line_of(b.mass.span))
        if b.friction is not None:
            self.add(k, "friction " + format_number(b.friction), keyword="friction", within=b.span)
        for f in b.frames:
            self.add(k, f"frame {f.name} = {pose_text(f.pose)}", _line_of(f.span))
        if b.joint is not None:
            self.add(k, "joint " + joint_text(b.joint), _line_of(b.joint.span))
        for e in b.explores:
            self.block(k, f"explore {e.name}", e.span, functools.partial(self.explore_items, e=e))
        if b.grasps is not None:
            self.block(k, "explore grasps", b.grasps.span, functools.partial(self.grasp_policy_items, g=b.grasps))

    def grasp_policy_items(self, k: int, g: GraspPolicy) -> None:
        if g.approaches is not None:
            self.add(k, "approach " + ", ".join(g.approaches), keyword="approach", within=g.span)
        for word, q in (("max_width", g.max_width), ("force", g.force), ("lift", g.lift), ("slip", g.slip)):
            if q is not None:
                self.add(k, f"{word} {quantity_text(q)}", _line_of(q.span))
        if g.trials is not None:
            self.add(k, f"trials {g.trials}", _line_of(g.trials_span))

    def shape(self, k: int, prefix: str, s: Shape, suffix: str = "", span: Span | None = None) -> None:
        anchor = _line_of(span if span is not None else s.span)
        if isinstance(s, UnionShape):
            self.add(k, prefix + "union {", anchor)
            for part in s.parts:
                self.shape(k + 1, "", part.shape, " at " + pose_text(part.pose), part.span)
            self.add(k, "}" + suffix, _end_of(s.span), closes=True)
        else:
            self.add(k, prefix + _simple_shape_text(s) + suffix, anchor)

    def explore_items(self, k: int, e: Explore) -> None:
        if e.contacts is not None:
            c = e.contacts
            if c.frames:
                self.add(k, f"contacts at {', '.join(f.name for f in c.frames)}", _line_of(c.span))
            else:
                heights = f" heights {c.heights}" if c.heights != 1 else ""  # mid-height only: as before heights
                self.add(k, f"contacts on faces {', '.join(c.faces)} steps {c.steps}{heights}", _line_of(c.span))
        if e.grasp is not None:
            self.add(k, f"grasp {e.grasp.name}", _line_of(e.grasp.span))
        if e.force is not None:
            f = e.force
            if f.mode == "normal":
                text = "force normal " + quantity_text(f.magnitude)
            else:
                nx, ny, nz = f.grid or (0, 0, 0)
                text = f"force directions {nx} x {ny} x {nz}  {quantity_text(f.magnitude)}"
            self.add(k, text, _line_of(f.span))
        if e.duration is not None:
            self.add(k, "duration " + quantity_text(e.duration), _line_of(e.duration.span))

    # ------------------------------------------------------------ robots, affordances

    def robot_items(self, k: int, r: Robot) -> None:
        self.add(k, "urdf " + string_text(r.urdf), keyword="urdf", within=r.span)
        for e in r.effectors:
            self.add(k, f"effector {e.name} = link {e.link} offset {pose_text(e.offset)}", _line_of(e.span))

    def affordances(self, k: int, s: AffordanceSet) -> None:
        for t in s.tipping:
            faces = f" on faces {', '.join(t.faces)}" if t.faces else ""
            self.add(k, f"tips above {quantity_text(t.height)}{faces}", _line_of(t.span))
        for a in s.affordances:
            self.block(k, f"affordance {a.name}", a.span, functools.partial(self.affordance_items, a=a))

    def affordance_items(self, k: int, a: Affordance) -> None:
        self.add(k, "action " + constraint_text(a.action), _line_of(a.action.span))
        self.add(k, "motion " + constraint_text(a.motion), _line_of(a.motion.span))
        if a.family is not None:
            self.add(k, family_text(a.family), _line_of(a.family.span))
        if a.evidence is not None:
            ev = a.evidence
            text = (
                f"evidence trials {ev.trials} loglik {format_number(ev.loglik)} posterior {format_number(ev.posterior)}"
            )
            if ev.slip is not None:
                text += " slip " + quantity_text(Quantity(value=ev.slip, unit=ev.slip_unit))
            self.add(k, text, _line_of(ev.span))

    def correspondences(self, k: int, c: Correspondences) -> None:
        for item in c.items:
            self.add(k, f"{item.frame.body}.{item.frame.frame} ~ {item.effector.name}", _line_of(item.span))

    # ------------------------------------------------------------ scenes, tasks

    def scene_items(self, k: int, s: Scene) -> None:
        if s.table is not None:
            t = s.table
            self.add(k, f"table size {vector_text(t.size)} at {vector_text(t.position)}", _line_of(t.span))
        for r in s.robots:
            self.add(k, f"robot {r.name} : {r.type.name} at {pose_text(r.pose)}", _line_of(r.span))
        for b in s.bodies:
            opening = f" open {quantity_text(b.opening)}" if b.opening is not None else ""
            self.add(k, f"{b.name} : {b.type.name}{opening} {placement_text(b.placement)}", _line_of(b.span))
        for region in s.regions:
            self.add(k, f"region {region.name} = {region_text(region)}", _line_of(region.span))

    def task_items(self, k: int, t: Task) -> None:
        self.add(k, "scene " + t.scene.name, _line_of(t.scene.span))
        for i, g in enumerate(t.goals):
            if i == 0:
                self.add(k, "goal " + goal_text(g), _line_of(g.span))
            else:
                self.add(k + 1, "and " + goal_text(g), _line_of(g.span))
        for keep in t.keep_out:
            self.add(k, keep_out_text(keep), _line_of(keep.span))
        if t.search is not None:
            self.add(k, search_text(t.search), _line_of(t.search.span))


def placement_text(p: Placement) -> str:
    """`on table at (x, y) m [yaw Q]`, `at POSE`, `in B` or `at B.F`, as written."""
    if p.relative_to is not None:
        ref = p.relative_to
        return f"in {ref.body}" if p.inside else f"at {ref.body}.{ref.frame}"
    return ("on table at " if p.on_table else "at ") + pose_text(p.pose)


def _use_target(u: Use) -> str:
    return string_text(u.target) if u.by_path else u.target


def _simple_shape_text(s: Shape) -> str:
    if isinstance(s, BoxShape):
        return "box " + vector_text(s.size)
    if isinstance(s, CylinderShape):
        return f"cylinder radius {quantity_text(s.radius)} height {quantity_text(s.height)}"
    if isinstance(s, MeshShape):
        scale = "" if s.scale == 1.0 else " scale " + format_number(s.scale)
        return "mesh " + string_text(s.path) + scale
    raise TypeError(f"not a shape: {type(s).__name__}")


def constraint_text(c: Constraint) -> str:
    """`fixed [at POSE]`, `prismatic along V [from P]`, `revolute about P axis V`, `free` or `grasp at POSE ...`."""
    if isinstance(c, FixedC):
        return "fixed" if c.pose is None else "fixed at " + pose_text(c.pose)
    if isinstance(c, GraspC):
        width = quantity_text(Quantity(value=c.width, unit=c.width_unit))
        force = quantity_text(Quantity(value=c.force, unit=c.force_unit))
        return f"grasp at {pose_text(c.pose)} width {width} force {force}"
    if isinstance(c, PrismaticC):
        text = "prismatic along " + vector_text(c.axis)
        text = text if c.origin is None else text + " from " + vector_text(c.origin)
        return text + range_text(c.range)
    if isinstance(c, RevoluteC):
        return f"revolute about {vector_text(c.center)} axis {vector_text(c.axis)}" + range_text(c.range)
    if isinstance(c, FreeC):
        return "free"
    raise TypeError(f"not a constraint: {type(c).__name__}")


def layout(module: Module) -> list[Line]:
    """The lines of the canonical text of `module`, each with the source line it came from."""
    out = _Layout()
    out.module(module)
    while out.lines and out.lines[-1].blank:
        out.lines.pop()
    return out.lines


def render(lines: Iterable[Line], tail: Iterable[tuple[bool, str]] = ()) -> str:
    """The text of laid-out lines with the comments attached to them; `tail` ends the file."""
    lines = list(lines)
    code = [INDENT * ln.depth + ln.text if ln.text else "" for ln in lines]
    columns = _trailing_columns(lines, code)
    out: list[str] = []

    def gap() -> None:
        if out and out[-1]:
            out.append("")

    for ln, text, column in zip(lines, code, columns):
        if ln.gap:
            gap()
        comment_indent = INDENT * (ln.depth + 1 if ln.closes else ln.depth)
        for i, (blank_before, comment) in enumerate(ln.leading):
            if i > 0 and blank_before:
                gap()
            out.append(comment_indent + comment)
        if ln.leading and ln.gap_before_code:
            gap()
        if ln.trailing:
            text = text.ljust(column) + " ".join(ln.trailing)
        out.append(text)
    for blank_before, comment in tail:
        if blank_before:
            gap()
        out.append(comment)
    while out and not out[-1]:
        out.pop()
    return "\n".join(out) + "\n"


def _trailing_columns(lines: list[Line], code: list[str]) -> list[int]:
    """Where trailing comments start: aligned over each run of consecutive commented lines."""
    columns = [0] * len(lines)
    i = 0
    while i < len(lines):
        if not lines[i].trailing:
            i += 1
            continue
        j = i
        while j + 1 < len(lines) and lines[j + 1].trailing and not lines[j + 1].leading:
            j += 1
        column = max(len(code[n]) for n in range(i, j + 1)) + 2
        for n in range(i, j + 1):
            columns[n] = column
        i = j + 1
    return columns


def print_module(module: Module) -> str:
    """The canonical source of `module`; `parse_module(print_module(m), m.path) == m`."""
    return render(layout(module))


# ---------------------------------------------------------------- fmt


def format_source(text: str, path: str) -> str:
    """`text` in canonical form, keeping its comments and the blank lines between statements.

    Raises CompileError (with the parser's diagnostics) if `text` does not parse.
    Idempotent: `format_source(format_source(t, p), p) == format_source(t, p)`.
    """
    from vkgl.lang.syntax.parser import parse_module_with_comments

    module, comments = parse_module_with_comments(text, path)
    source = text.split("\n")  # lines as Lark counts them (never `str.splitlines()`)
    lines = layout(module)
    _resolve_keyword_anchors(lines, source)
    doc_lines = _doc_line_count(module, source)
    tail = _attach_comments(lines, [c for c in comments if c.line > doc_lines], source)
    _keep_blank_lines(lines, source)
    return render(lines, tail)


_STRING = re.compile(r'"[^"\n]*"')


def _doc_line_count(module: Module, source: list[str]) -> int:
    """How many source lines at the top of the file the doc comment spans (0 if none)."""
    from vkgl.lang.syntax.parser import doc_line_count

    return doc_line_count("\n".join(source)) if module.doc is not None else 0


def _resolve_keyword_anchors(lines: list[Line], source: list[str]) -> None:
    """Anchor lines whose IR value has no span (friction, urdf) at their keyword's line."""
    for ln in lines:
        if ln.anchor is not None or ln.keyword is None or ln.within is None:
            continue
        pattern = re.compile(rf"(^|[^A-Za-z0-9_]){ln.keyword}([^A-Za-z0-9_]|$)")
        for number in range(ln.within.line, min(ln.within.end_line, len(source)) + 1):
            code = _STRING.sub('""', source[number - 1]).split("#", 1)[0]
            if pattern.search(code):
                ln.anchor = number
                break


def _attach_comments(lines: list[Line], comments: list, source: list[str]) -> list[tuple[bool, str]]:
    """Attach each comment to its line: a trailing comment to the statement it ends, a
    full-line one above the statement that follows it. Returns those after the last statement."""
    anchored = [(i, ln) for i, ln in enumerate(lines) if ln.anchor is not None and not ln.blank]
    tail: list[tuple[bool, str]] = []
    for comment in sorted(comments, key=lambda c: (c.line, c.col)):
        text = comment.text.rstrip()
        before = source[comment.line - 1][: comment.col - 1] if comment.line <= len(source) else ""
        if before.strip():
            _attach_trailing(anchored, comment.line, text)
            continue
        entry = (_blank(source, comment.line - 1), text)
        following = [(ln.anchor, i, ln) for i, ln in anchored if ln.anchor > comment.line]  # type: ignore[operator]
        if following:
            target = min(following, key=lambda t: (t[0], t[1]))[2]
            if not target.leading:
                target.first_comment_line = comment.line
            target.leading.append(entry)
        else:
            tail.append(entry)
    return tail


def _attach_trailing(anchored: list[tuple[int, Line]], line: int, text: str) -> None:
    exact = [ln for _, ln in anchored if ln.anchor == line]
    if exact:
        exact[-1].trailing.append(text)
        return
    earlier = [(ln.anchor, i, ln) for i, ln in anchored if ln.anchor < line]  # type: ignore[operator]
    if earlier:
        max(earlier, key=lambda t: (t[0], t[1]))[2].trailing.append(text)
    elif anchored:
        anchored[0][1].leading.insert(0, (False, text))


def _keep_blank_lines(lines: list[Line], source: list[str]) -> None:
    """Keep one blank line where the source had one above a statement or its comments.

    Declarations are always separated by exactly one blank line (the layout
    has it), and a block never starts with one.
    """
    previous: Line | None = None
    for ln in lines:
        if ln.blank:
            previous = ln
            continue
        first_line = ln.first_comment_line if ln.leading else None if ln.closes else ln.anchor
        opens_block = previous is not None and previous.text.endswith("{")
        if first_line is not None and previous is not None and not opens_block:
            ln.gap = _blank(source, first_line - 1)
        if ln.leading and ln.anchor is not None and not ln.closes:
            ln.gap_before_code = _blank(source, ln.anchor - 1)
        previous = ln


def _blank(source: list[str], number: int) -> bool:
    return 1 <= number <= len(source) and not source[number - 1].strip()
