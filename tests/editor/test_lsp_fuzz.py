"""A few hundred random messages to `vkgc lsp` (tests/editor/lsp_fuzz.py; its 10,000-message run is on demand).

Random edits, positions (negative, past the end, not numbers) and URIs (not
open, `/dev/zero`, a FIFO, percent-encoded, `untitled:`, other schemes): every
request answered within the bound with a result or an allowed error, no error
shown to the user, memory under the bound, and a clean shutdown.
"""

from __future__ import annotations

from pathlib import Path

from lsp_fuzz import fuzz


def test_a_short_fuzz_run_finds_no_crash_hang_or_leak(tmp_path: Path) -> None:
    report = fuzz(messages=300, seed=7, reply_bound=30.0, memory_bound=1000.0, folder=tmp_path)
    assert report.failures == []
    assert report.messages >= 300 and report.requests > 50
    assert report.answered_with_error.get(-32602, 0) > 0  # invalid positions were sent, and answered
