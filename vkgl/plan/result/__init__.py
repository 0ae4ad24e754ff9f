"""The result of a solve: `Plan` (text, `vkg-plan/3` document) and its picture."""
