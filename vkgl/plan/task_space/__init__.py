"""Task-space feasibility: exact geometric reasoning, the optimisation of motion values, the arm's workspace,
and the inverse-kinematics check of the hand poses."""
