"""Hypothesis strategies that generate valid IR scenes, tasks and whole modules (as the parser would build
them), from the parts `strategies` draws: the same rules (see its docstring)."""

from __future__ import annotations

import functools
import string

from hypothesis import strategies as st
from strategies import (
    PATH,
    affordance_sets,
    bodies,
    correspondence_blocks,
    counts,
    file_paths,
    names,
    poses,
    quantities,
    refs,
    robots,
    vectors,
)

from vkgl.lang.ir import nodes as ir
from vkgl.lang.ir.regions import KeepOut, Region


@functools.cache
def scenes() -> st.SearchStrategy[ir.Scene]:
    table = st.builds(ir.Table, size=vectors("length", 2), position=vectors("length", 3))
    robot = st.builds(ir.SceneRobot, name=names(), type=refs(), pose=poses())
    origin = ir.Pose(position=ir.Vector(values=(0.0, 0.0, 0.0), unit="m"))  # what the builder puts before checks
    relative = st.one_of(
        st.builds(
            lambda b: ir.Placement(
                on_table=False, pose=origin, relative_to=ir.FrameRef(body=b, frame="slot"), inside=True
            ),
            names(),
        ),
        st.builds(
            lambda b, f: ir.Placement(on_table=False, pose=origin, relative_to=ir.FrameRef(body=b, frame=f)),
            names(),
            names(),
        ),
    )
    placement = st.one_of(
        st.builds(ir.Placement, on_table=st.just(True), pose=poses(n=2, rpy=False)),
        st.builds(ir.Placement, on_table=st.just(False), pose=poses()),
        relative,
    )
    opening = st.none() | st.sampled_from(["length", "angle"]).flatmap(quantities)  # `open Q`: a joint's start
    body = st.builds(ir.SceneBody, name=names(), type=refs(), placement=placement, opening=opening)
    return st.builds(
        ir.Scene,
        name=names(),
        table=st.none() | table,
        robots=st.lists(robot, max_size=2),
        bodies=st.lists(body, max_size=3),
        regions=st.lists(st.builds(lambda r, n: r.model_copy(update={"name": n}), regions(), names()), max_size=2),
    )


@functools.cache
def regions() -> st.SearchStrategy[Region]:
    """Boxes (two corners) and polygons (three to five vertices), each corner a 2-vector of lengths."""
    corner = vectors("length", 2)
    return st.one_of(
        st.builds(lambda cs: Region(kind="box", corners=cs), st.lists(corner, min_size=2, max_size=2)),
        st.builds(lambda cs: Region(kind="polygon", corners=cs), st.lists(corner, min_size=3, max_size=5)),
    )


@functools.cache
def goals() -> st.SearchStrategy[ir.Goal]:
    """Position goals (2- or 3-vectors, with or without yaw), heading-only goals and joint goals.

    Tolerances as the syntax can say them: `within L`, `within L, A`, nothing,
    `within A` for a heading-only goal, and one of the opening's kind for a joint goal.
    """
    position_goal = st.builds(
        ir.Goal,
        body=refs(),
        position=st.one_of(vectors("length", 2), vectors("length", 3)),
        yaw=st.none() | quantities("angle"),
        tol_position=st.none() | quantities("length"),
    ).flatmap(
        lambda g: (
            st.just(g)
            if g.tol_position is None
            else st.builds(lambda a: g.model_copy(update={"tol_yaw": a}), st.none() | quantities("angle"))
        )
    )
    yaw_goal = st.builds(ir.Goal, body=refs(), yaw=quantities("angle"), tol_yaw=st.none() | quantities("angle"))
    joint_goal = st.sampled_from(["length", "angle"]).flatmap(
        lambda kind: st.builds(ir.Goal, body=refs(), opening=quantities(kind), tol_opening=st.none() | quantities(kind))
    )
    moved_goal = st.builds(
        ir.Goal,
        body=refs(),
        moved_by=st.one_of(vectors("length", 2), vectors("length", 3)),
        moved_in=st.none() | refs(),
        turned_by=st.none() | quantities("angle"),
        tol_position=st.none() | quantities("length"),
    )
    turned_goal = st.builds(
        ir.Goal, body=refs(), turned_by=quantities("angle"), tol_yaw=st.none() | quantities("angle")
    )
    region_goal = st.builds(
        ir.Goal,
        body=refs(),
        region=regions(),
        yaw=st.none() | quantities("angle"),
        tol_position=st.none() | quantities("length"),
    ) | st.builds(ir.Goal, body=refs(), region_ref=refs(), tol_position=st.none() | quantities("length"))
    return st.one_of(position_goal, yaw_goal, joint_goal, moved_goal, turned_goal, region_goal)


@functools.cache
def tasks() -> st.SearchStrategy[ir.Task]:
    search = st.builds(ir.SearchSpec, max_depth=st.none() | counts(0, 20), timeout=st.none() | quantities("time"))
    keep = st.builds(KeepOut, body=st.none() | refs(), region=regions()) | st.builds(
        KeepOut, body=st.none() | refs(), region_ref=refs()
    )
    return st.builds(
        ir.Task,
        name=names(),
        scene=refs(),
        goals=st.lists(goals(), min_size=1, max_size=3),
        search=st.none() | search,
        keep_out=st.lists(keep, max_size=2),
    )


# ---------------------------------------------------------------- modules


@functools.cache
def docs() -> st.SearchStrategy[str | None]:
    """Doc comments: lines without surrounding spaces; inner lines may be empty (paragraphs)."""
    line = (
        st.text(alphabet=string.ascii_letters + string.digits + " .,:;()`'#-*", min_size=1, max_size=30)
        .map(str.strip)
        .filter(bool)
    )
    inner = st.one_of(line, st.just(""))
    return st.none() | st.builds(
        lambda first, middle, last: "\n".join([first, *middle, *last]),
        line,
        st.lists(inner, max_size=3),
        st.lists(line, max_size=1),
    )


@functools.cache
def uses() -> st.SearchStrategy[ir.Use]:
    dotted = st.lists(names(), min_size=1, max_size=3).map(".".join)
    return st.one_of(
        st.builds(ir.Use, target=dotted, by_path=st.just(False)),
        st.builds(ir.Use, target=file_paths(".vkg"), by_path=st.just(True)),
    )


@functools.cache
def declarations() -> st.SearchStrategy[ir.Decl]:
    return st.one_of(bodies(), robots(), affordance_sets(), correspondence_blocks(), scenes(), tasks())


@functools.cache
def modules() -> st.SearchStrategy[ir.Module]:
    """Whole modules: a doc comment, uses and declarations of every kind."""
    return st.builds(
        ir.Module,
        path=st.just(PATH),
        doc=docs(),
        uses=st.lists(uses(), max_size=3),
        decls=st.lists(declarations(), max_size=4),
    )
