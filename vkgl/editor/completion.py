"""Completion candidates: keywords, units, body types, scene bodies, affordance names, frames.

After `Name.` only the members of that body type (frames and affordances)
are offered; after a number only units; after a motion's whole `range LO to
HI UNIT` only `open`; otherwise everything the program in scope declares plus
the grammar's keywords and units.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from vkgl.editor.symbols import all_instances
from vkgl.editor.vocabulary import NUMBER_PATTERN, keywords, units
from vkgl.lang.ir.program import Program
from vkgl.lang.ir.units import DIMENSION

_AFTER_NUMBER = re.compile(r"(?<![A-Za-z0-9_.])" + NUMBER_PATTERN + r"[ \t]*[A-Za-z]*$")
_AFTER_RANGE = re.compile(r"\brange\s+\S+(?:\s+\S+)?\s+to\s+" + NUMBER_PATTERN + r"\s*[A-Za-z]+[ \t]+[A-Za-z]*$")
_OPEN_DETAIL = "the body was still sliding when exploration ended: plans may slide it further"
_AFTER_DOT = re.compile(r"([A-Za-z_][A-Za-z0-9_]*)\.([A-Za-z_][A-Za-z0-9_]*)?$")


@dataclass(frozen=True)
class Candidate:
    """One completion: the text, its kind and a detail.

    Kinds: keyword, unit, body, robot, scene, instance, affordance, frame, region.
    """

    label: str
    kind: str
    detail: str = ""


def candidates(program: Program | None, before: str) -> list[Candidate]:
    """What may be written at the cursor, given the text of its line `before` the cursor."""
    dotted = _AFTER_DOT.search(before)
    if dotted is not None and program is not None:
        return _members(program, dotted.group(1))
    if _AFTER_NUMBER.search(before):
        return unit_candidates()
    if _AFTER_RANGE.search(before):
        return [Candidate("open", "keyword", _OPEN_DETAIL)]
    found = [Candidate(word, "keyword") for word in keywords()]
    found += unit_candidates()
    if program is not None:
        found += _declared(program)
    return found


def unit_candidates() -> list[Candidate]:
    """Every unit, with its dimension."""
    return [Candidate(unit, "unit", DIMENSION[unit]) for unit in sorted(units())]


def _declared(program: Program) -> list[Candidate]:
    found = [Candidate(name, "body", "body type") for name in sorted(program.bodies)]
    found += [Candidate(name, "robot", "robot type") for name in sorted(program.robots)]
    found += [Candidate(name, "scene", "scene") for name in sorted(program.scenes)]
    seen: set[str] = set()
    for scene, instance in all_instances(program):
        if instance.name not in seen:
            seen.add(instance.name)
            found.append(Candidate(instance.name, "instance", f"{instance.type.name} in scene {scene}"))
    for declared in program.scenes.values():  # for `goal B in R`, `keep out R`
        found += [Candidate(r.name, "region", f"region of scene {declared.name}") for r in declared.regions]
    for body, affordances in sorted(program.affordances.items()):
        found += [Candidate(a.name, "affordance", f"affordance of {body}") for a in affordances]
    return found


def _members(program: Program, qualifier: str) -> list[Candidate]:
    """Frames and affordances of a body type (or of a scene body's type)."""
    body_type = qualifier
    if qualifier not in program.bodies:
        body_type = next(
            (x.type.name for _, x in all_instances(program) if x.name == qualifier),
            qualifier,
        )
    found: list[Candidate] = []
    body = program.bodies.get(body_type)
    if body is not None:
        found += [Candidate(f.name, "frame", f"frame of {body_type}") for f in body.frames]
    found += [
        Candidate(a.name, "affordance", f"affordance of {body_type}") for a in program.affordances.get(body_type, [])
    ]
    return found
