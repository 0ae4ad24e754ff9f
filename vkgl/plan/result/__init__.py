"""The result of a solve: `Plan` (text, `vkg-plan/4` document) and its picture."""
