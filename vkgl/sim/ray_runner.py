"""Exploration trials on a Ray cluster: `vkgc learn --ray [ADDRESS]`.

`RayRunner` is a `vkgl.sim.explore.Runner`: it runs `run_trial(spec, seed)`,
the very function the local process pool runs, as one Ray task per trial, and
returns the results in grid order. A trial depends only on its spec and the
seed, so the dataset, and the module `vkgc learn` writes, are byte-identical
to the process pool's.

    with RayRunner(address=None, num_cpus=2) as runner:   # a local Ray instance
        explore(body, runner=runner)

`address`: None starts a local instance (with `num_cpus` CPUs, default all);
`"auto"` joins the cluster started on this machine with `ray start --head`;
`"HOST:6379"` or `"ray://HOST:10001"` a remote one. Every node needs `vkgl`
(same version) installed: `pip install 'vkgl[ray]'`. If Ray is already
initialised in this process, that connection is used and left open.

A task whose worker dies (the simulator aborting on a blown-up world) is not
retried: the trial is marked failed, with the process pool's reason.
"""

from __future__ import annotations

import logging
from types import TracebackType
from typing import Any, Self

from vkgl.errors import InputError
from vkgl.sim.explore import TrialResult, _progress_bar, run_trial
from vkgl.sim.policy import TrialSpec

# The process pool's words for a trial whose process died (vkgl.sim.explore._run_isolated).
ABORTED = "the simulator aborted (a numerical blow-up took down its process)"


def _ray() -> Any:
    try:
        import ray
    except ImportError as exc:
        raise InputError(
            f"--ray needs Ray, which is not installed ({exc}); install it with `pip install 'vkgl[ray]'`"
        ) from exc
    return ray


class RayRunner:
    """Runs exploration trials as Ray tasks; a context manager that connects to (or starts) Ray."""

    def __init__(
        self,
        address: str | None = None,
        num_cpus: int | None = None,
        progress: bool = False,
    ) -> None:
        self.address = address or None
        self.num_cpus = num_cpus
        self.progress = progress
        self._started = False

    def __enter__(self) -> Self:
        ray = _ray()
        if not ray.is_initialized():
            options: dict[str, Any] = {
                "include_dashboard": False,
                "logging_level": logging.WARNING,
                "log_to_driver": False,
            }
            if self.address is None:
                options["num_cpus"] = self.num_cpus
            try:
                ray.init(address=self.address, **options)
            except (ConnectionError, RuntimeError, ValueError) as exc:
                where = self.address or "a local instance"
                raise InputError(f"--ray: cannot connect to Ray at {where}: {exc}") from exc
            self._started = True
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        if self._started:
            _ray().shutdown()
            self._started = False

    def __call__(self, specs: list[TrialSpec], seed: int) -> list[TrialResult]:
        """`run_trial(spec, seed)` for every spec, on the cluster; results in grid order."""
        ray = _ray()
        if not ray.is_initialized():
            raise RuntimeError("RayRunner is used outside its `with` block")
        task = ray.remote(max_retries=0)(run_trial)
        refs = [task.remote(spec, seed) for spec in specs]
        advance = _progress_bar(len(refs)) if self.progress else None
        try:
            if advance is not None:
                pending = list(refs)
                while pending:
                    _, pending = ray.wait(pending, num_returns=1)
                    advance()
            return [self._result(ray, ref) for ref in refs]
        finally:
            if advance is not None:
                advance(stop=True)

    @staticmethod
    def _result(ray: Any, ref: Any) -> TrialResult:
        from ray import exceptions

        try:
            result: TrialResult = ray.get(ref)
            return result
        except exceptions.RayTaskError as exc:  # the trial raised (SimulationError): raise it here, as itself
            raise exc.as_instanceof_cause() from None
        except (exceptions.WorkerCrashedError, exceptions.NodeDiedError):
            import numpy as np

            return TrialResult(np.zeros(0), np.zeros((0, 4, 4)), np.zeros((0, 4, 4)), False, ABORTED)
