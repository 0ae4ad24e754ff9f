"""The result of a solve: `Plan` (text, `vkg-plan/8` document) and its picture."""
