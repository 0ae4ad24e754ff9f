"""Inference: from recorded trials to kinematic constraints and a body's affordances.

Along the pipeline: `data` (trials -> edges) -> `models`, `revolute`,
`likelihood` (fit and score fixed / prismatic / revolute / free) -> `select`
(posterior, MAP type per edge) -> `trial` (MAP graph per trial) ->
`affordances` (grouping, names, IR) -> `library` (`infer_library`, `learn`,
the report); `plot` draws the posteriors, `synthetic` makes ground truth.
See docs/inference.md.
"""
