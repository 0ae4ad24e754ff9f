"""Inference: from recorded trials to kinematic constraints and a body's affordances.

Along the pipeline: `data` (trials -> edges) -> `models`, `revolute`,
`likelihood` (fit and score fixed / prismatic / revolute / free) -> `select`
(posterior, MAP type per edge) -> `trial` (MAP graph per trial) ->
`affordances` (grouping, names, IR) -> `library` (`infer_library`, the
report, how a generated module imports its body); `plot` draws the
posteriors. See docs/inference.md.

Calling the package, `vkgl.infer(trials)`, calls the driver's
`vkgl.api.infer` (see `vkgl.callable_stage` for why).
"""

from vkgl.callable_stage import make_callable

make_callable(__name__)
