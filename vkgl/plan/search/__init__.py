"""The search over graph sequences (paper, Algorithm 1) and the exclusions a re-solve adds.

Rooms: `bounds` (lower bounds on the graphs still needed, below the search), `clutter` (clearing a body in the
way and keeping bodies still, above the search: they call it).
"""
