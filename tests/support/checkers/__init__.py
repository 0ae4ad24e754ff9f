"""Checks that judge the planner's outputs independently of it: plan geometry, contact chains, replays, JSON
closeness."""
