"""The arm's reach in task space: workspace checks, and proofs that a hand pose is out of reach before optimising."""
