"""`python -m vkgl.cli` is `vkgc`."""

from vkgl.cli import run

run()
