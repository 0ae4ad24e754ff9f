"""How the hand holds a tool in execution: its fingers, the grip's strength, the load it carries, and the slip.

- `fingers`: the hand's finger joints in the world (`Fingers`), opened before a
  grasp, closed onto the tool's faces, opened to let go;
- `model`: the grip of the two fingers on a tool (`Grip`): how much force and
  torque the pads' friction carries, and how much of that a load uses;
- `watch`: `GripWatch`, which measures every control period the load on the
  grip and how far the tool has slipped in the hand, breaks the grip when the
  load exceeds what friction carries, and fails the step (`GripSlipped`) when
  the slip goes past the tolerance.
"""
