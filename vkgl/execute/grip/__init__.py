"""How the hand holds a tool in execution: the grip's strength, the load it carries, and the slip.

- `model`: the grip of the Panda's two fingers on a tool (`Grip`): how much
  force and torque the pads' friction carries, and the load it must carry;
- `watch`: `GripWatch`, which measures every control period how much of that
  the held tool's load uses and how far the tool has slipped in the hand, breaks
  the grip when the load exceeds what friction carries, and fails the step
  (`GripSlipped`) when the slip goes past the tolerance.
"""
