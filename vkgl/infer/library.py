"""The affordance library of a body: `vkgc infer` and `vkgc learn`.

`infer_library(trials, ...)` turns a `vkg-trials/1` dataset into an
`affordances BODY { ... }` module (IR and canonical source, through the
printer) and the per-trial `vkg-infer-report/2` (`vkgl.formats.infer_report`).
`body_import` says how a generated module imports its body. The driver
(`vkgl.api.learn`) composes exploration and this stage.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from vkgl.errors import InputError
from vkgl.formats.grasp_trials import GraspTrials
from vkgl.formats.infer_report import INFER_REPORT_FORMAT
from vkgl.formats.trials import Trials
from vkgl.infer.affordances import Group, affordance_ir, group_trials
from vkgl.infer.faces.tipping import tipped, tipping_ir
from vkgl.infer.select import EdgeInference
from vkgl.infer.trial import TrialInference, infer_trials
from vkgl.lang.ir.nodes import Affordance, AffordanceSet, Module, Ref, Use
from vkgl.lang.syntax.printer import print_module

INFERENCE_REVISION = 3
"""Bumped when inference writes other affordances from the same trials, so that caches of learned modules keyed
on it are learned again (2: a body whose pose ended off its start is not `fixed`, docs/inference.md; 3: an arc law
whose pushes never showed its pivot come in holds `beyond` its innermost push, `vkgl.infer.faces.arc`). Not bumped
when only noisy trials can come out otherwise: on a simulated trial, the only kind learned modules come from, the
end window's median position and mean orientation (`select.end_offset`) give the distance the median of its samples'
distances gave, and the angle to 0.02 deg (docs/inference.md, "Did the body move?")."""


@dataclass
class InferenceResult:
    """What inference made of a dataset.

    `module` (IR) and `source` (its canonical text) hold the affordances;
    `report` is the `vkg-infer-report/2` dict; `trials` and `groups` are the
    per-trial graphs and the affordance groups (for pictures and tests).
    """

    body: str
    module: Module
    source: str
    report: dict[str, Any]
    trials: list[TrialInference]
    groups: list[Group]


def infer_library(
    trials: Trials,
    *,
    body_use: str,
    header: str,
    path: str = "<inferred>",
    grasps: Sequence[Affordance] = (),
) -> InferenceResult:
    """Infer the affordances of `trials.body` and print them as a module.

    `body_use` is what the module imports to know the body (`stdlib.bodies.block`,
    or a path ending in `.vkg`); `header` becomes its leading comment; `path` is
    the module's path in the IR; `grasps` (`vkgl.infer.grasps.kept.kept_grasps`) follow
    the inferred affordances. Raises InputError when no trial can be used or
    when the body never moved.
    """
    results = infer_trials(trials)
    _require_usable(trials, results)
    groups = group_trials(trials, results)
    if not groups:
        raise InputError(
            f"{trials.body}: the body did not move in any of the {len(trials)} trials (every motion came out "
            "`fixed`), so there is no affordance to learn; check the exploration's force and duration"
        )
    module = Module(
        path=path,
        doc=header,
        uses=[Use(target=body_use, by_path=body_use.endswith(".vkg"))],
        decls=[
            AffordanceSet(
                body=Ref(name=trials.body),
                affordances=[*(affordance_ir(g) for g in groups), *grasps],
                tipping=tipping_ir(trials),
            )
        ],
    )
    report = build_report(trials, results, groups)
    return InferenceResult(
        body=trials.body, module=module, source=print_module(module), report=report, trials=results, groups=groups
    )


def grasp_library(
    trials: GraspTrials, grasps: Sequence[Affordance], *, body_use: str, header: str, path: str = "<inferred>"
) -> InferenceResult:
    """The module of a body learned for its grasps alone (it has no `explore` block): `grasps` as its affordances.

    Raises InputError when no grasp held, saying what became of the candidates.
    """
    if not grasps:
        blocked = len({t.candidate for t in trials.trials if t.blocked})
        raise InputError(
            f"{trials.body}: has no `explore` block and none of its {len(trials.candidates)} grasp candidates held "
            f"({blocked} left the open hand no room; wider than the hand's opening is no candidate): add an "
            "`explore` block to learn how it moves when pushed, or an `explore grasps` block with another force"
        )
    module = Module(
        path=path,
        doc=header,
        uses=[Use(target=body_use, by_path=body_use.endswith(".vkg"))],
        decls=[AffordanceSet(body=Ref(name=trials.body), affordances=list(grasps))],
    )
    report = {"format": INFER_REPORT_FORMAT, "body": trials.body, "trials": [], "affordances": []}
    return InferenceResult(
        body=trials.body, module=module, source=print_module(module), report=report, trials=[], groups=[]
    )


# ---------------------------------------------------------------- the generated module's import


def body_import(body_file: Path, destination: Path) -> tuple[str, str]:
    """How the generated module imports the body, and how its header names the body file.

    A stdlib body is imported by dotted name (`stdlib.bodies.block`) and shown
    as `stdlib/bodies/block.vkg`; any other by its path relative to the
    generated file, so the header does not depend on the current directory.
    """
    body_path = body_file.resolve()
    relative = _stdlib_relative(body_path)
    if relative is not None:
        return ".".join(relative.with_suffix("").parts), relative.as_posix()
    relative_text = Path(os.path.relpath(body_path, destination.resolve().parent)).as_posix()
    return relative_text, relative_text


def _stdlib_relative(body_path: Path) -> Path | None:
    """`stdlib/bodies/block.vkg` when `body_path` is a stdlib body, else None.

    A stdlib body is one of the installed stdlib, or of a source checkout's
    `stdlib/` (the repository, whether or not it is installed editable) that
    the installed stdlib also has: both are imported as `stdlib.bodies.NAME`.
    """
    from vkgl.resources import stdlib_dir

    installed = stdlib_dir().resolve()
    if body_path.is_relative_to(installed):
        return body_path.relative_to(installed.parent)
    for folder in body_path.parents:
        if folder.name == "stdlib":
            inside = body_path.relative_to(folder)
            return Path("stdlib") / inside if (installed / inside).is_file() else None
    return None


# ---------------------------------------------------------------- checks and report


def _require_usable(trials: Trials, results: list[TrialInference]) -> None:
    if len(trials) == 0:
        raise InputError(f"{trials.body}: the dataset has no trials")
    skipped = [r for r in results if r.skipped is not None]
    if len(skipped) == len(results) and all(tipped(trials, i) for i in range(len(trials))):
        raise InputError(
            f"{trials.body}: every one of the {len(trials)} pushes tipped it over, so there is no affordance to "
            "learn; push it lower: `contacts on faces ... heights H` explores H heights up each face"
        )
    if len(skipped) == len(results):
        reasons = sorted({r.skipped for r in skipped if r.skipped})
        shown = "; ".join(reasons[:3]) + (f"; and {len(reasons) - 3} more" if len(reasons) > 3 else "")
        raise InputError(f"{trials.body}: none of the {len(trials)} trials can be used ({shown})")


def build_report(trials: Trials, results: list[TrialInference], groups: list[Group]) -> dict[str, Any]:
    """The `vkg-infer-report/2` dict: per trial the posterior and MAP parameters of both edges, how it ended."""
    name_of = {i: g.name for g in groups for i in g.members}
    entries = []
    for r in results:
        entry: dict[str, Any] = {"index": r.index, "contact": _floats(r.contact), "force": _floats(r.force)}
        if r.skipped is not None:
            entry["skipped"] = r.skipped
        else:
            entry["samples"] = r.samples
            entry["action"] = _edge_report(r.action)
            entry["motion"] = _edge_report(r.motion)
            if r.ending is not None:
                entry["motion"]["ending"] = {
                    "end_speed": _number(r.ending.end_speed),
                    "peak_speed": _number(r.ending.peak_speed),
                    "ratio": _number(r.ending.ratio),
                    "moving": r.ending.moving,
                }
            entry["loglik"] = _number(r.loglik)
            entry["affordance"] = name_of.get(r.index)
        entries.append(entry)
    return {
        "format": INFER_REPORT_FORMAT,
        "body": trials.body,
        "trials": entries,
        "affordances": [
            {
                "name": g.name,
                "trials": g.members,
                "kept": g.kept,
                "loglik": _number(g.loglik),
                "posterior": _number(g.posterior),
                "still_moving": g.still_moving,
                "open": g.open_range,
            }
            for g in groups
        ],
    }


def _edge_report(edge: EdgeInference | None) -> dict[str, Any]:
    if edge is None:
        return {"type": None, "posterior": None, "params": None}
    params = {k: _floats(np.asarray(v)) for k, v in edge.params.items() if k != "radius"}
    best = edge.best
    out: dict[str, Any] = {
        "type": edge.type,
        "posterior": {k: _number(v) for k, v in edge.posterior.items()},
        "params": params,
        "loglik": _number(edge.loglik),
    }
    if best.states.size:
        out["range"] = [_number(float(best.states.min())), _number(float(best.states.max()))]
    return out


def _number(x: float) -> float | None:
    """A JSON-safe float (None for NaN or infinity), rounded to 1e-6 so reports diff cleanly."""
    x = float(x)
    if not np.isfinite(x):
        return None
    value = round(x, 6)
    return 0.0 if value == 0.0 else value


def _floats(a: np.ndarray) -> Any:
    a = np.asarray(a, dtype=float)
    if a.ndim == 0:
        return _number(float(a))
    return [_floats(x) for x in a]
