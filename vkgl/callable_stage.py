"""Stage packages that can be called as the driver's function of the same name.

`vkgl.execute` and `vkgl.infer` are both a stage's package and a function of
the driver (`vkgl.api.execute`, `vkgl.api.infer`, exported by `vkgl`). Python
binds a package's name on its parent as soon as any of its modules is
imported, which would hide the function: so such a package's module object is
made callable, and calls the driver. `vkgl.execute(...)` and `vkgl.infer(...)`
then work whichever of the two the name is bound to.
"""

from __future__ import annotations

import importlib
import sys
import types
from typing import Any


class _CallableStage(types.ModuleType):
    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        api = importlib.import_module("vkgl.api")  # at call time: the driver sits above every stage
        return getattr(api, self.__name__.rsplit(".", 1)[-1])(*args, **kwargs)


def make_callable(package: str) -> None:
    """Make the already imported `package` (e.g. "vkgl.execute") callable as `vkgl.api.<its last name>`."""
    sys.modules[package].__class__ = _CallableStage
