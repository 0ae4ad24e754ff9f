"""Arm motion that the planner and the executor share, below both: the collision worlds of the arm and the
bodies, straight Cartesian moves, transits (OMPL), timing, the standoffs, and how arm paths are drawn."""
