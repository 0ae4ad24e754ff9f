"""Clutter handled on purpose: a body in the way cleared first, bodies in no one's way kept still."""
