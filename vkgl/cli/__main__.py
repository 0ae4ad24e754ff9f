"""`python -m vkgl.cli` is `vkgc`."""

import sys

from vkgl.cli import main

sys.exit(main())
