"""The result of a solve: `Plan` (text, `vkg-plan/6` document) and its picture."""
