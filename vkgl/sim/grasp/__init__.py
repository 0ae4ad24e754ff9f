"""Grasp trials in DART: `candidates` (from the shape), `hand` (the URDF's gripper, simulated), `trial` (one
grasp, lift or pull, slip) and `run` (all of a body's). docs/inference.md, "Grasps", explains them."""
