"""Kinematic graphs, graph sequences and their rollout in task space."""
