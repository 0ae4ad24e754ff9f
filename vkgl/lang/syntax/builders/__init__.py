"""Parse tree to IR: the builder and its parts (tasks, regions, grasps, families)."""
