"""Grasps: which of a body's tried grasps are kept, as affordances (`kept`). The trials are `vkgl.sim.grasp`'s."""
