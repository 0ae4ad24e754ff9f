"""`vkgl.execute.progress`: the world's ticks become reports of the step, the arm's phase and the simulated time."""

from __future__ import annotations

from vkgl.execute.progress import PERIOD, Progress, ProgressFeed


class _World:
    """A stand-in for the world's label and clock (what `SceneWorld` exposes to the feed)."""

    def __init__(self) -> None:
        self.label = "start"
        self.time = 0.0


def _feed() -> tuple[_World, list[Progress], ProgressFeed]:
    world, seen = _World(), []
    return world, seen, ProgressFeed(seen.append, lambda: world.label, lambda: world.time)


def test_a_step_is_reported_when_it_begins_then_by_phase():
    world, seen, feed = _feed()
    world.label = "step 1 settle"
    feed.begin(0, 2, 3, "add Block.push_center_px on block with arm.fingertip: slide 10.0 cm")
    assert seen[-1].phase == ""  # still the label of step 1: step 2 has not moved yet
    assert seen[-1].text().startswith("step 2/3 add Block.push_center_px")
    for label in ("step 2 transit", "step 2 approach", "step 2 motion"):
        world.label = label
        world.time += 0.02
        feed.tick()
    assert [p.phase for p in seen[1:]] == ["transit", "approach", "motion"]


def test_the_same_phase_is_reported_at_most_every_period():
    world, seen, feed = _feed()
    feed.begin(1, 1, 1, "add Block.push_center_px on block with arm.fingertip: slide 10.0 cm")
    world.label = "step 1 motion"
    for _ in range(100):  # 2 s of simulated time in 20 ms control periods
        world.time += 0.02
        feed.tick()
    motion = [p for p in seen if p.phase == "motion"]
    assert 2 / PERIOD - 2 <= len(motion) <= 2 / PERIOD + 2
    assert world.time - motion[-1].sim_time <= PERIOD + 1e-9  # never more than a period behind
    assert "[replan 1]" in motion[-1].text() and "motion, t = " in motion[-1].text()


def test_between_steps_the_phase_is_the_labels_last_word():
    world, seen, feed = _feed()
    feed.begin(0, 0, 2, "putting things down to re-solve")
    world.label = "replan retreat"
    feed.tick()
    feed.phase("re-solving")
    assert [p.phase for p in seen] == ["start", "retreat", "re-solving"]
    assert seen[-1].text() == "putting things down to re-solve: re-solving, t = 0.0 s"


def test_no_callback_no_work():
    world = _World()
    feed = ProgressFeed(None, lambda: world.label, lambda: world.time)
    feed.begin(0, 1, 1, "x")
    feed.tick()
    feed.phase("re-solving")  # nothing to call: nothing happens
