"""The task-space problem's inequality constraints: the moved bodies' limits and their values at one rollout."""
