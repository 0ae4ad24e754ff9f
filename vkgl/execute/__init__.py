"""Carrying a plan out in DART: the arm in the world, step replay, the closed loop, animation.

Calling the package, `vkgl.execute(program, task, plan, ...)`, calls the
driver's `vkgl.api.execute` (see `vkgl.callable_stage` for why).
"""

from vkgl.callable_stage import make_callable

make_callable(__name__)
