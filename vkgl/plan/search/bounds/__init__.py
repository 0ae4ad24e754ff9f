"""Lower bounds on the graphs a sequence still needs (what makes the best-first search admissible)."""
