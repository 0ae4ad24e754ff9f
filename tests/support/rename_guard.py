"""An autouse fixture for tests of writers: any rename outside the temporary folder fails the test.

Run as root, a writer with the old bug renamed over /dev/stdout; with this guard such a test fails instead of
replacing a system file. Import the fixture into a test module to use it.
"""

from __future__ import annotations

import os

import pytest


@pytest.fixture(autouse=True)
def no_rename_outside_the_temporary_folder(
    monkeypatch: pytest.MonkeyPatch, tmp_path_factory: pytest.TempPathFactory
) -> None:
    """A writer with the old bug would rename over /dev/stdout (run as root): refuse any rename outside /tmp, the
    run's `tmp_path` folders and vkgl's cache folder (the run's own, in memory: tests/conftest.py)."""
    import tempfile

    from vkgl.resources import cache_folder

    folders = [tempfile.gettempdir(), tmp_path_factory.getbasetemp(), cache_folder()]
    allowed = tuple(os.path.realpath(folder) for folder in folders if folder is not None)
    real_replace, real_rename = os.replace, os.rename

    def guarded(real):  # type: ignore[no-untyped-def]
        def rename(source, destination, *args, **kwargs):  # type: ignore[no-untyped-def]
            if not os.path.realpath(os.path.dirname(os.path.abspath(destination))).startswith(allowed):
                raise AssertionError(f"a test renamed over {destination}")
            return real(source, destination, *args, **kwargs)

        return rename

    monkeypatch.setattr(os, "replace", guarded(real_replace))
    monkeypatch.setattr(os, "rename", guarded(real_rename))
