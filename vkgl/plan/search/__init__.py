"""The search over graph sequences (paper, Algorithm 1) and the exclusions a re-solve adds."""
