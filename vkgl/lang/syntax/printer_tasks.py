"""How the printer writes the statements of tasks: goals (pose, joint, relative and region goals), regions,
keep-out regions and the search block. `vkgl.lang.syntax.printer` re-exports these functions.
"""

from __future__ import annotations

from vkgl.lang.ir.nodes import Goal, SearchSpec
from vkgl.lang.ir.regions import KeepOut, Region
from vkgl.lang.syntax.quantities import quantity_text, vector_text


def goal_text(g: Goal) -> str:
    """`B at (x, y) m [yaw Q] [within L[, A]]`, `B yaw Q [within A]`, `B open Q [within Q]` or a relative goal,
    `B moved by V [in F] [turned by Q] [within L[, A]]`, `B turned by Q [within A]` (as written, never the pose
    the checker filled in)."""
    text = g.body.name
    if g.relative:
        if g.moved_by is not None:
            text += " moved by " + vector_text(g.moved_by)
            if g.moved_in is not None:
                text += " in " + g.moved_in.name
        if g.turned_by is not None:
            text += " turned by " + quantity_text(g.turned_by)
        tolerances = [quantity_text(q) for q in (g.tol_position, g.tol_yaw) if q is not None]
        return text + (" within " + ", ".join(tolerances) if tolerances else "")
    if g.region_ref is not None:
        text += " in " + g.region_ref.name
    elif g.region is not None:
        text += " in region " + region_text(g.region)
    if g.opening is not None:
        text += " open " + quantity_text(g.opening)
        return text + (" within " + quantity_text(g.tol_opening) if g.tol_opening is not None else "")
    if g.position is not None:
        text += " at " + vector_text(g.position)
    if g.yaw is not None:
        text += " yaw " + quantity_text(g.yaw)
    tolerances = [quantity_text(q) for q in (g.tol_position, g.tol_yaw) if q is not None]
    if tolerances:
        text += " within " + ", ".join(tolerances)
    return text


def region_text(r: Region) -> str:
    """`(0.6, -0.1) to (0.8, 0.1) m` or `polygon (0.6, 0), (0.8, 0), (0.7, 0.2) m`: one unit after the last
    corner when all share it."""
    texts = [vector_text(c) for c in r.corners]
    units = {t[t.rindex(")") + 1 :] for t in texts}
    if len(units) == 1:
        texts = [t[: t.rindex(")") + 1] for t in texts[:-1]] + texts[-1:]
    return " to ".join(texts) if r.kind == "box" else "polygon " + ", ".join(texts)


def keep_out_text(keep: KeepOut) -> str:
    """`keep out R` or `keep B out of R`, R a scene region's name or `region ...` written in place."""
    place = keep.region_ref.name if keep.region_ref is not None else "region " + region_text(keep.region)  # type: ignore[arg-type]
    return f"keep {keep.body.name} out of {place}" if keep.body is not None else f"keep out {place}"


def search_text(s: SearchSpec) -> str:
    """`search { max_depth 6  timeout 30 s }` on one line, as docs/language.md writes it."""
    items = []
    if s.max_depth is not None:
        items.append(f"max_depth {s.max_depth}")
    if s.timeout is not None:
        items.append("timeout " + quantity_text(s.timeout))
    return "search { " + "  ".join(items) + " }" if items else "search { }"
