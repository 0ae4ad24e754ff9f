"""Diagnostics: the `Diagnostic` type, the registry of codes, and docs/errors.md generated from it."""
