"""The result of a solve: `Plan` (text, `vkg-plan/7` document) and its picture."""
