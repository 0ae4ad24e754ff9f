"""The registry behind `codes`: what a diagnostic code is, and the ordered table of all of them."""

from __future__ import annotations

from dataclasses import dataclass

from vkgl.lang.diagnostics.diagnostic import Diagnostic
from vkgl.lang.ir.nodes import Span


@dataclass(frozen=True)
class Code:
    """One diagnostic code: `code` ("E301"), its one-line `meaning`, and the `explanation` docs/errors.md shows."""

    code: str
    meaning: str
    explanation: str

    @property
    def severity(self) -> str:
        """ "error" for E codes, "warning" for W codes."""
        return "warning" if self.code.startswith("W") else "error"

    def diagnostic(self, message: str, span: Span | None, *notes: str) -> Diagnostic:
        """A diagnostic of this code (error or warning by the code's letter); empty notes are dropped."""
        kept = tuple(n for n in notes if n)
        if self.code.startswith("W"):
            return Diagnostic(self.code, message, span, "warning", kept)
        return Diagnostic(self.code, message, span, notes=kept)

    def __str__(self) -> str:
        return self.code


CODES: dict[str, Code] = {}


def register(code: str, meaning: str, explanation: str) -> Code:
    entry = Code(code, meaning, explanation)
    assert code not in CODES, code
    CODES[code] = entry
    return entry
