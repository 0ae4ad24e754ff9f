"""The result of a solve: `Plan` (text, `vkg-plan/5` document) and its picture."""
