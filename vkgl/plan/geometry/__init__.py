"""Collision geometry in feasibility: bodies swept along their motions against the bodies that stay still."""
