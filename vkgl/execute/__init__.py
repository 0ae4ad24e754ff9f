"""Carrying a plan out in DART: the arm in the world, step replay, the closed loop, animation.

`vkgl.execute` is two things by design: this package (the stage) and the
driver's function `vkgl.execute(program, task, plan, ...)` (`vkgl.api.execute`).
Python binds a package's name on its parent once any of its modules is
imported, which would hide the function; so the package object itself is
callable and calls the driver. `vkgl.execute(...)` works whichever of the two
`vkgl.execute` currently is.
"""

from __future__ import annotations

import sys
import types
from typing import Any


class _CallableStage(types.ModuleType):
    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        from vkgl.api import execute

        return execute(*args, **kwargs)


sys.modules[__name__].__class__ = _CallableStage
