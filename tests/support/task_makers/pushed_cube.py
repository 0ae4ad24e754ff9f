"""An 8 cm cube that slides 40 cm when pushed at its -x face: the `.vkg` source of the body and its one affordance,
shared by the tests that push it past (or clear a blocker for) it."""

CUBE_SOURCE = """
body Cube {
    shape box (8, 8, 8) cm
    mass 0.256 kg
    friction 0.5
}

affordances Cube {
    affordance push_center_px {
        action fixed at (-4, 0, 0) cm yaw 0deg
        motion prismatic along (1, 0, 0) from (0, 0, 0) cm range 0 to 40 cm
    }
}
"""
