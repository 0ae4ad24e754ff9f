"""Tasks and worlds made for the tests and the benches: generated bodies and tasks, the far block, the joint tasks."""
