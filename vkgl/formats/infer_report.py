"""`vkg-infer-report/2`: per trial, the posterior over constraint types, the MAP parameters of both edges and
how the motion ended (/2: `ending` per motion, `still_moving` and `open` per affordance).

`vkgl.infer.library.build_report` fills it; this module is its only writer
(docs/formats.md documents the fields).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from vkgl.atomic import write_text

INFER_REPORT_FORMAT = "vkg-infer-report/2"


def write_infer_report(path: str | Path, report: dict[str, Any]) -> None:
    """Write the report as indented JSON, atomically."""
    if report.get("format") != INFER_REPORT_FORMAT:
        raise ValueError(f"not a {INFER_REPORT_FORMAT} report: format {report.get('format')!r}")
    write_text(path, json.dumps(report, indent=1) + "\n")
