"""Carrying a plan out in DART: the arm in the world, step replay, the closed loop, animation."""
