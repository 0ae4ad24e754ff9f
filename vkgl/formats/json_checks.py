"""Field checks of the JSON formats: each raises `PlanFormatError` with the JSON path of the bad field.

Shared by the readers in `vkgl.formats` (the plan and its arm paths); the
messages say what was expected and show what was found.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from vkgl.errors import PlanFormatError

_ROTATION_TOL = 1e-6  # how far from orthonormal a pose's rotation block may be


def show(value: Any) -> str:
    """`value` as JSON writes it (NaN as NaN), cut to 40 characters."""
    try:
        text = json.dumps(value)
    except (TypeError, ValueError):
        text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


def expect_object(data: Any, path: str, keys: Sequence[str], optional: Sequence[str] = ()) -> dict[str, Any]:
    where = path or "the plan"
    if not isinstance(data, dict):
        raise PlanFormatError(path, f"expected a JSON object, found {show(data)}" + (f" ({where})" if not path else ""))
    for key in keys:
        if key not in data:
            raise PlanFormatError(join_path(path, key), "missing")
    unknown = [k for k in data if k not in keys and k not in optional]
    if unknown:
        raise PlanFormatError(join_path(path, str(unknown[0])), f"unknown key (expected {', '.join(keys)})")
    return data


def join_path(path: str, key: str) -> str:
    return f"{path}.{key}" if path else key


def expect_list(data: Any, path: str) -> list[Any]:
    if not isinstance(data, list):
        raise PlanFormatError(path, f"expected a list, found {show(data)}")
    return data


def expect_text(data: Any, path: str) -> str:
    if not isinstance(data, str):
        raise PlanFormatError(path, f"expected a string, found {show(data)}")
    return data


def expect_name(data: Any, path: str) -> str:
    if not isinstance(data, str) or not data:
        raise PlanFormatError(path, f"expected a non-empty string, found {show(data)}")
    return data


def expect_dotted(data: Any, path: str, form: str) -> str:
    text = expect_name(data, path)
    head, dot, tail = text.partition(".")
    if not (head and dot and tail):
        raise PlanFormatError(path, f"expected `{form}`, found {show(text)}")
    return text


def expect_choice(data: Any, path: str, choices: Sequence[str]) -> str:
    if data not in choices or not isinstance(data, str):
        raise PlanFormatError(path, f"expected one of {', '.join(choices)}, found {show(data)}")
    return data


def is_int(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def expect_number(data: Any, path: str) -> float:
    if not is_number(data):
        raise PlanFormatError(path, f"expected a finite number, found {show(data)}")
    return data  # type: ignore[no-any-return]


def expect_joints(data: Any, path: str, count: int) -> np.ndarray:
    if not isinstance(data, list) or not all(is_number(v) for v in data):
        raise PlanFormatError(path, f"expected a list of finite numbers (joint positions, rad), found {show(data)}")
    if len(data) != count:
        raise PlanFormatError(path, f"expected {count} joint positions (one per robot.joints), found {len(data)}")
    return frozen(np.asarray(data, dtype=float))


def expect_pose(data: Any, path: str) -> np.ndarray:
    shaped = isinstance(data, list) and len(data) == 4 and all(isinstance(r, list) and len(r) == 4 for r in data)
    if not shaped or not all(is_number(v) for row in data for v in row):
        raise PlanFormatError(path, "expected a 4x4 matrix of finite numbers")
    pose = np.asarray(data, dtype=float)
    if np.abs(pose[3] - (0.0, 0.0, 0.0, 1.0)).max() > 1e-9:
        raise PlanFormatError(path, "expected a homogeneous transform (last row 0 0 0 1)")
    rotation = pose[:3, :3]
    if np.abs(rotation.T @ rotation - np.eye(3)).max() > _ROTATION_TOL or np.linalg.det(rotation) < 0:
        raise PlanFormatError(path, "expected a rotation in the upper-left 3x3 block (orthonormal, det +1)")
    return frozen(pose)


def expect_poses(data: Any, path: str) -> dict[str, np.ndarray]:
    if not isinstance(data, dict):
        raise PlanFormatError(path, f"expected an object of body name -> 4x4 pose, found {show(data)}")
    return {expect_name(name, path): expect_pose(pose, f"{path}.{name}") for name, pose in data.items()}


def frozen(array: np.ndarray) -> np.ndarray:
    array.flags.writeable = False
    return array
