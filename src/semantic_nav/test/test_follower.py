"""DirectionFollower: simple instructions in order, halting advance, bad input."""
import math

import numpy as np
import pytest

from semantic_nav.follower import (ROOT, DirectionFollower, FollowerCommand, FollowerConfig,
                                   ModelMissingError, UnknownInstructionError)
from semantic_nav.collision_guard import GuardConfig
from supervision.config_file import ConfigError
from semantic_nav.doorways import DoorConfig
from semantic_nav.laser_layer import model_from_scan
from semantic_nav.postprocess import PostprocessConfig
from semantic_nav.word_vectors import WordVectors

WORDS = ["go", "straight", "to", "the", "end", "turn", "left", "right"]


class ScriptedPolicy:
    """Stands in for the network: Z_w from the first word vector, commands from a script."""

    def __init__(self, commands):
        self.commands, self.steps, self.resets, self.scans = list(commands), 0, 0, []

    def classify(self, vectors):
        z = np.zeros(10)
        z[int(vectors[-1][0])] = 1.0          # class index taken from the last word's vector
        return z

    def reset(self):
        self.resets += 1

    def step(self, z_w, scan):
        self.scans.append(scan)
        self.steps += 1
        return self.commands.pop(0) if self.commands else (0.0, 0.0)


@pytest.fixture
def words():
    matrix = np.zeros((len(WORDS), 3), np.float32)
    matrix[WORDS.index("end"), 0] = 0        # "... to the end" -> class 1
    matrix[WORDS.index("left"), 0] = 2       # "turn left" -> class 3
    matrix[WORDS.index("right"), 0] = 1      # "turn right" -> class 2
    return WordVectors(WORDS, matrix, "tiny")


def urg(beams=683):
    inc = math.radians(360 / 1024) * 682 / (beams - 1)
    return model_from_scan("urg", -inc * (beams - 1) / 2, inc, beams, 0.02, 5.6)


def test_start_splits_and_classifies(words):
    follower = DirectionFollower(ScriptedPolicy([]), words)
    assert follower.start("go straight to the end, then turn left") == [1, 3]
    assert follower.control_period == pytest.approx(0.1)


class UnsurePolicy(ScriptedPolicy):
    """Z_w 0.7 on class 3 and 0.3 on class 2; records the Z_w each step gets."""

    def classify(self, vectors):
        z = np.zeros(10)
        z[1], z[2] = 0.3, 0.7
        return z

    def step(self, z_w, scan):
        self.z_seen = np.array(z_w)
        return super().step(z_w, scan)


def test_lstm_fused_gets_the_class_one_hot_unless_configured_otherwise(words):
    scan = np.full(683, 3.0)
    for one_hot, expected in ((True, [0, 0, 1.0]), (False, [0, 0.3, 0.7])):
        policy = UnsurePolicy([(0.2, 0.0)])
        follower = DirectionFollower(policy, words, FollowerConfig(one_hot_class=one_hot))
        assert follower.start("turn left") == [3]
        follower.step(scan, urg())
        np.testing.assert_allclose(policy.z_seen, expected + [0] * 7)


def test_halting_counter_advances_to_the_next_instruction(words):
    policy = ScriptedPolicy([(0.3, 0.0), (0.0005, -0.0004), (0.01, 0.0)] + [(0.0, 0.0)] * 49)
    follower = DirectionFollower(policy, words)
    follower.start("go straight to the end then turn right")
    laser = urg()
    ranges = np.full(683, 2.0)
    first = [follower.step(ranges, laser) for _ in range(3)]
    assert (first[0].v, first[0].w) == (0.3, 0.0)
    assert (first[1].v, first[1].w) == (0.0, 0.0)       # Eq. 2.2-12: both below v_min
    assert (first[2].v, first[2].w) == (0.02, 0.0)      # pulled up to v_move
    resets = policy.resets
    commands = [follower.step(ranges, laser) for _ in range(50)]
    assert all(c.index == 0 and c.predicted_class == 1 for c in commands[:49])
    assert commands[49] == FollowerCommand(0.0, 0.0, 1, 2, False)   # 50th zero: next one
    assert policy.resets == resets + 1                   # memory cleared
    more = [follower.step(ranges, laser) for _ in range(50)]
    assert more[-1].done and not more[-2].done
    steps = policy.steps
    assert follower.step(ranges, laser).done and policy.steps == steps


@pytest.mark.parametrize("beams", [683, 500, 1081])
def test_any_beam_count_is_interpolated(words, beams):
    policy = ScriptedPolicy([(0.2, 0.1)])
    follower = DirectionFollower(policy, words)
    follower.start("turn left")
    if beams == 1081:
        laser = model_from_scan("utm", math.radians(-135), math.radians(0.25), 1081, 0.02, 30)
    else:
        laser = urg(beams)
    follower.step(np.full(beams, 3.0), laser)
    assert policy.scans[0].shape == (881,)
    assert np.linalg.norm(policy.scans[0]) == pytest.approx(1.0, abs=1e-6)


def test_unknown_words_are_named(words):
    seed = DirectionFollower(ScriptedPolicy([]), words, FollowerConfig(splitting="seed"))
    with pytest.raises(UnknownInstructionError, match="blorp"):
        seed.start("turn left, blorp zindle")       # a simple instruction of unknown words
    spoken = DirectionFollower(ScriptedPolicy([]), words)
    spoken.start("turn left, then blorp zindle")   # names no motion: joined, its words skipped
    assert spoken.instructions == ["turn left blorp zindle"]
    assert spoken.unknown_words == ["blorp", "zindle"]
    with pytest.raises(UnknownInstructionError):
        spoken.start("  ,  ")


class SpreadPolicy(ScriptedPolicy):
    """Z_w of ScriptedPolicy, spread to `confidence` on its class."""

    def __init__(self, confidence):
        super().__init__([])
        self.confidence = confidence

    def classify(self, vectors):
        z = super().classify(vectors)
        return z * self.confidence + (1.0 - z) * (1.0 - self.confidence) / 9.0


def test_unknown_words_are_skipped_only_when_the_rest_reads_with_confidence(words):
    sure = DirectionFollower(SpreadPolicy(0.95), words)
    assert sure.start("turn blorp left") == [3] and sure.unknown_words == ["blorp"]
    unsure = DirectionFollower(SpreadPolicy(0.6), words)
    assert unsure.start("turn left") == [3]               # every word known: followed
    with pytest.raises(UnknownInstructionError, match="only 0.60 confidence") as refused:
        unsure.start("turn blorp left")
    assert refused.value.words == ["blorp"]


def test_step_before_start_is_an_error(words):
    with pytest.raises(RuntimeError, match="start"):
        DirectionFollower(ScriptedPolicy([]), words).step(np.ones(683), urg())


def test_missing_model_names_make_train(tmp_path):
    with pytest.raises(ModelMissingError, match="make train"):
        DirectionFollower.from_files(tmp_path / "none.keras")


class StopHeadPolicy(ScriptedPolicy):
    """A network with a stop head: creeps at 0.04 m/s while saying "standing at the goal"."""

    def __init__(self, moving_steps):
        super().__init__([(0.3, 0.0)] * moving_steps)
        self.moving_steps, self.stop_probability = moving_steps, None

    def step(self, z_w, scan):
        command = super().step(z_w, scan)
        self.stop_probability = 0.1 if self.steps <= self.moving_steps else 0.9
        return command if self.steps <= self.moving_steps else (0.04, 0.01)


def test_stop_head_output_halts_the_instruction(words):
    """Beyond the seed: the raw (0.04, 0.01) would never halt; the stop head makes it (0, 0)."""
    follower = DirectionFollower(StopHeadPolicy(3), words)
    follower.start("go straight to the end")
    commands = [follower.step(np.full(683, 2.0), urg()) for _ in range(53)]
    assert [(c.v, c.w) for c in commands[:3]] == [(0.3, 0.0)] * 3
    assert all((c.v, c.w) == (0.0, 0.0) for c in commands[3:])
    assert not commands[-2].done and commands[-1].done      # the 50th stop output halts


def wall_ahead_ranges(laser, distance):
    """Ranges of `laser` facing a wall `distance` ahead, open (5.6 m) elsewhere."""
    angles = laser.angle_min + laser.angle_increment * np.arange(laser.beams)
    with np.errstate(divide="ignore"):
        ranges = np.where(np.cos(angles) > 1e-9, distance / np.cos(angles), 5.6)
    return np.minimum(ranges, 5.6)


def test_collision_guard_stops_v_keeps_omega_and_a_held_robot_halts(words):
    """Beyond the seed, steering off: a wall 0.36 m ahead (gap 0.06 m to the footprint) leaves
    less free path than v_move can drive, so v becomes 0; ω passes; 50 held steps end the
    instruction."""
    laser = urg()
    ranges = wall_ahead_ranges(laser, 0.36)
    policy = ScriptedPolicy([(0.3, 0.2)] + [(0.3, 0.0)] * 50)
    config = FollowerConfig(guard=GuardConfig(steer=False))
    follower = DirectionFollower(policy, words, config)
    follower.start("go straight to the end")
    turning = follower.step(ranges, laser)
    assert (turning.v, turning.w) == (0.0, 0.2)
    held = [follower.step(ranges, laser) for _ in range(50)]
    assert all((c.v, c.w) == (0.0, 0.0) for c in held)
    assert held[-1].done and not held[-2].done
    assert follower.guard_actions == {"slowed": 0, "held": 51, "steered": 0, "turned": 0}
    open_space = DirectionFollower(ScriptedPolicy([(0.3, 0.2)]), words)
    open_space.start("go straight to the end")
    assert (open_space.step(np.full(683, 5.0), laser).v) == 0.3


def test_steering_guard_turns_a_blocked_robot_instead_of_halting_it(words):
    """Default guard: the same wall blocks every arc, so the follower turns in place at
    steer_turn (0.5 rad/s), to the network's side, and the halting counter never runs."""
    laser = urg()
    ranges = wall_ahead_ranges(laser, 0.36)
    follower = DirectionFollower(ScriptedPolicy([(0.3, -0.2)] * 60), words)
    follower.start("go straight to the end")
    commands = [follower.step(ranges, laser) for _ in range(60)]
    assert all((c.v, c.w) == (0.0, -0.5) for c in commands)
    assert not commands[-1].done
    assert follower.guard_actions == {"slowed": 0, "held": 0, "steered": 0, "turned": 60}
    follower.start("go straight to the end")          # counted per sentence
    assert sum(follower.guard_actions.values()) == 0


def test_guard_actions_are_counted_per_kind(words):
    """A wall 0.6 m ahead slows 0.3 m/s; a wall 0.33 m to the left (inside the margin) makes
    the guard steer a left turn (ω 0.5) to ω = 0, along the wall (test_collision_guard)."""
    laser = urg()
    angles = laser.angle_min + laser.angle_increment * np.arange(laser.beams)
    with np.errstate(divide="ignore"):
        left_wall = np.minimum(np.where(np.sin(angles) > 1e-9, 0.33 / np.sin(angles), 5.6), 5.6)
    follower = DirectionFollower(ScriptedPolicy([(0.3, 0.0), (0.1, 0.5)]), words)
    follower.start("go straight to the end")
    slowed = follower.step(wall_ahead_ranges(laser, 0.6), laser)
    steered = follower.step(left_wall, laser)
    assert 0.0 < slowed.v < 0.3 and (steered.v, steered.w) == (0.1, 0.0)
    assert follower.guard_actions == {"slowed": 1, "held": 0, "steered": 1, "turned": 0}


def test_follower_config_file(tmp_path):
    from semantic_nav.follower import load_follower_config
    shipped = load_follower_config(ROOT / "config" / "semnav_follower.yaml")
    assert shipped == FollowerConfig(laser_config=str(ROOT / "config" / "semnav_laser.yaml"))
    no_guard = load_follower_config(ROOT / "config" / "semnav_follower_no_guard.yaml")
    assert not no_guard.guard.enabled and no_guard.postprocess == PostprocessConfig()
    assert shipped.doors.width == 1.4 and no_guard.doors.width == 0.0
    assert shipped.ask.enabled and not no_guard.ask.enabled    # the seed drives on what it read
    assert shipped.one_hot_class and not no_guard.one_hot_class     # the seed feeds the softmax
    assert (shipped.splitting, no_guard.splitting) == ("spoken", "seed")
    no_doors = load_follower_config(ROOT / "config" / "semnav_follower_no_doors.yaml")
    assert no_doors == FollowerConfig(doors=DoorConfig(width=0.0), one_hot_class=False)
    bad = tmp_path / "bad.yaml"
    bad.write_text("guard:\n  radius: 0.3\n  margn: 0.1\n")
    with pytest.raises(ValueError, match="margn"):
        load_follower_config(bad)
    bad.write_text("splitting: words\n")
    with pytest.raises(ValueError, match="splitting: one of seed, spoken"):
        load_follower_config(bad)
    bad.write_text("postprocess:\n  halt_steps: many\n")
    with pytest.raises(ValueError, match="halt_steps"):
        load_follower_config(bad)
    bad.write_text("doors:\n  wide: 1.0\n")
    with pytest.raises(ConfigError,
                       match="doors: unknown key 'wide' \\(did you mean 'width'\\?\\)"):
        load_follower_config(bad)
    bad.write_text("guard:\n  enabled: 1\n")
    with pytest.raises(ValueError, match="enabled"):
        load_follower_config(bad)
    with pytest.raises(ConfigError, match="none.yaml: no such follower config"):
        load_follower_config(tmp_path / "none.yaml")


class CountingPolicy(ScriptedPolicy):
    """A network with the corner-count input: drives at 0.5 m/s and keeps the counts it gets."""

    class config:
        count_input = True

    def __init__(self, steps):
        super().__init__([(0.5, 0.0)] * steps)
        self.counts = []

    def step(self, z_w, scan, counts=None):
        self.counts.append(int(np.argmax(counts)))
        return super().step(z_w, scan)


def test_count_input_network_gets_the_corners_counted_from_the_live_scans(words):
    """Beyond the seed: the left side reads open (4 m) from step 10 to 39; at 0.05 m a step the
    opening is 1 m long at step 30, where the count becomes 1; the next simple instruction
    starts counting afresh. The opening is only the counter's window wide (0.35 m at 2 m), a
    door to semantic_nav.doorways, so doorways stay open here."""
    policy = CountingPolicy(60)
    follower = DirectionFollower(policy, words, FollowerConfig(doors=DoorConfig(width=0.0)))
    follower.start("go straight to the end then turn left")
    laser = urg()
    angles = laser.angle_min + laser.angle_increment * np.arange(laser.beams)
    left = np.abs(angles - math.pi / 2) <= math.radians(5)
    commands = []
    for step in range(60):
        ranges = np.full(laser.beams, 2.0)
        ranges[left] = 4.0 if 10 <= step < 40 else 2.0
        commands.append(follower.step(ranges, laser))
    assert policy.counts[:30] == [0] * 30 and policy.counts[30:] == [1] * 30
    assert [c.corners for c in commands[29:31]] == [0, 1]
    # 50 zero commands end "go straight to the end": the command that starts "turn left"
    # reports its count, 0, and the network gets 0 from then on
    policy.commands = [(0.0, 0.0)] * 50
    stops = [follower.step(np.full(laser.beams, 2.0), laser) for _ in range(51)]
    assert [c.index for c in stops[47:50]] == [0, 0, 1]
    assert [c.corners for c in stops[47:50]] == [1, 1, 0] and policy.counts[-1] == 0


class SelfCountingPolicy(ScriptedPolicy):
    """A network that counts itself: it gets the counting mode, never a count."""

    class config:
        count_input = False
        counting_input = True

    def __init__(self, steps):
        super().__init__([(0.5, 0.0)] * steps)
        self.modes, self.z_ws = [], []
        self.counted = 2

    def classify(self, vectors):
        return np.eye(10)[4]                  # class 5: turn right at the second corner

    def step(self, z_w, scan, counts=None, counting=None):
        assert counts is None
        self.modes.append(counting.tolist())
        self.z_ws.append(z_w)
        return super().step(z_w, scan)


@pytest.mark.parametrize("sentence, mode", [
    ("turn right at the second corner", [1.0, 0.0]),    # corners over both sides
    ("take the second right", [0.0, 1.0]),              # that side's branches
])
def test_a_network_that_counts_itself_gets_the_counting_mode_and_no_rule(words, sentence, mode):
    """Learned counting: no corner counter and no pass-then-turn class 1 at run time; the
    network gets the class Z_w read and the counting mode, and the command reports what its
    count output says."""
    policy = SelfCountingPolicy(5)
    follower = DirectionFollower(policy, words, FollowerConfig(doors=DoorConfig(width=0.0)))
    follower.start(sentence)
    assert follower.counter is None and follower.classes == [5]
    laser = urg()
    commands = [follower.step(np.full(laser.beams, 2.0), laser) for _ in range(3)]
    assert policy.modes == [mode] * 3 and [c.corners for c in commands] == [2] * 3
    assert all(np.argmax(z) == 4 for z in policy.z_ws)


def door_ahead_ranges(laser, door):
    """Ranges of `laser` facing a wall 2 m ahead; door=(y0, y1): an open door in it (no return
    through it), None: no door."""
    angles = laser.angle_min + laser.angle_increment * np.arange(laser.beams)
    ranges = wall_ahead_ranges(laser, 2.0)
    if door is not None:
        y = 2.0 * np.tan(angles)
        ranges[(np.cos(angles) > 0) & (y > door[0]) & (y < door[1])] = 5.6
    return ranges


@pytest.mark.parametrize("width, closed", [(1.4, True), (0.0, False)])
def test_the_network_sees_a_door_ahead_as_the_wall(words, width, closed):
    """Beyond the seed: with doorways closed the network's scan of a wall with a 1 m door is
    the scan of the plain wall (the jamb beams aside), and the cut beams end on the wall line,
    where the node draws them."""
    laser = urg()
    scans = {}
    for door in ((-0.5, 0.5), None):
        policy = ScriptedPolicy([(0.0, 0.0)])
        follower = DirectionFollower(policy, words, FollowerConfig(doors=DoorConfig(width=width)))
        follower.start("go straight to the end")
        follower.step(door_ahead_ranges(laser, door), laser)
        scans[door] = (policy.scans[0], follower.doorway_points)
    (with_door, points), (plain, _) = scans[(-0.5, 0.5)], scans[None]
    differs = np.abs(with_door - plain) > 0.1 * np.abs(plain).max()
    if closed:
        assert differs.sum() <= 4 and len(points) > 20
        np.testing.assert_allclose(points[:, 0], 2.0, atol=1e-6)
        assert np.all(np.abs(points[:, 1]) < 0.5)
    else:
        assert differs.sum() > 20 and len(points) == 0


def test_default_model_counts_corners_in_words_and_numerals():
    """The committed default with Stanford's vectors: the counting phrasings of the phrase sets
    and numerals written as digits ("2nd" is read as "second")."""
    from semantic_nav.word_vectors import WordVectorsError
    try:
        follower = DirectionFollower.from_files()
    except (ModelMissingError, WordVectorsError) as error:
        pytest.skip(str(error))
    assert follower.start("turn left at the 2nd corner") == [6]
    assert follower.start("make a right two corners down") == [5]
    assert follower.start("will you go ahead and turn left to corners down") == [6]
    assert follower.start("take a left turn at corner number three") == [8]
    assert follower.start("go straight to the end, then turn right at the 3rd corner") == [1, 7]


def test_the_second_right_counts_the_right_side_only():
    """The default model reads both as class 5; "the second right" counts the right-hand
    branches only (a left opening leaves the count alone), "the second corner" every corner.
    Without side counting (the seed's follower) both count corners; without the corner count
    the network gets 0 throughout."""
    from semantic_nav.word_vectors import WordVectorsError
    try:
        follower = DirectionFollower.from_files()
    except (ModelMissingError, WordVectorsError) as error:
        pytest.skip(str(error))
    laser = urg()
    angles = laser.angle_min + laser.angle_increment * np.arange(laser.beams)
    left = np.abs(angles - math.pi / 2) <= math.radians(40)    # a branch 1.7 m wide at 1 m
    ahead = np.abs(angles) <= math.radians(60)

    def counts_past_a_left_opening(sentence):
        """Corridor walls 1 m to each side, open ahead; the left side open from step 5 to 64."""
        assert follower.start(sentence) == [5]
        counted = []
        for step in range(70):
            ranges = np.full(laser.beams, 1.0)
            ranges[ahead] = 5.6
            ranges[left] = 4.0 if 5 <= step < 65 else 1.0
            counted.append(follower.step(ranges, laser).corners)
        return follower.countings, max(counted)

    assert counts_past_a_left_opening("take the second right") == (["side"], 0)
    assert counts_past_a_left_opening("turn right at the second corner") == (["corners"], 1)
    follower.config = FollowerConfig(side_counting=False)
    assert counts_past_a_left_opening("take the second right") == (["corners"], 1)


def test_without_the_corner_count_the_network_gets_zero(words):
    policy = CountingPolicy(40)
    follower = DirectionFollower(policy, words, FollowerConfig(corner_count=False,
                                                               doors=DoorConfig(width=0.0)))
    follower.start("go straight to the end")
    laser = urg()
    angles = laser.angle_min + laser.angle_increment * np.arange(laser.beams)
    left = np.abs(angles - math.pi / 2) <= math.radians(5)
    for step in range(40):
        ranges = np.full(laser.beams, 2.0)
        ranges[left] = 4.0 if 5 <= step < 35 else 2.0
        command = follower.step(ranges, laser)
    assert command.corners == 1 and set(policy.counts) == {0}   # counted, not given


class ClassRecordingPolicy(CountingPolicy):
    """Reads every sentence as class 5; keeps the class LSTM_fused gets at each step."""

    def __init__(self, steps):
        super().__init__(steps)
        self.classes = []

    def classify(self, vectors):
        return np.eye(10)[4]

    def step(self, z_w, scan, counts=None):
        self.classes.append(int(np.argmax(z_w)) + 1)
        return super().step(z_w, scan, counts)


@pytest.mark.parametrize("sentence, counting, opening_side, pass_then_turn", [
    ("take the second right", "side", -1, True),
    ("take the second right", "side", -1, False),
    ("turn right at the second corner", "corners", 1, True),   # a left corner counts too
    ("turn right at the second corner", "corners", 1, False),
])
def test_a_count_is_passed_then_the_turn_taken(words, sentence, counting, opening_side,
                                               pass_then_turn):
    """Beyond the seed: a class 5 instruction is driven as class 1 until one branch is counted
    (one side: a right one; over both sides: any) after its opening has run 1 m (step 25 at
    0.05 m a step) and it is behind the robot (step 35), then as class 2 with the count afresh
    and the memory kept; without the rule the network gets class 5 and the count throughout."""
    policy = ClassRecordingPolicy(50)
    follower = DirectionFollower(policy, words, FollowerConfig(
        doors=DoorConfig(width=0.0), side_pass_then_turn=pass_then_turn,
        corner_pass_then_turn=pass_then_turn))
    assert follower.start(sentence) == [5]
    assert follower.countings == [counting]
    laser = urg()
    angles = laser.angle_min + laser.angle_increment * np.arange(laser.beams)
    opening = np.abs(angles - opening_side * math.pi / 2) <= math.radians(5)
    for step in range(50):
        ranges = np.full(laser.beams, 2.0)
        ranges[opening] = 4.0 if 5 <= step < 35 else 2.0
        follower.step(ranges, laser)
    if pass_then_turn:
        assert policy.classes == [1] * 35 + [2] * 15
        assert policy.counts == [0] * 25 + [1] * 10 + [0] * 15
    else:
        assert policy.classes == [5] * 50
        assert policy.counts == [0] * 25 + [1] * 25
    assert policy.resets == 1                                  # start() only


@pytest.fixture
def phrases(tmp_path):
    path = tmp_path / "phrases.yaml"
    path.write_text('sets: ["turn {dir}", "go straight to the end"]\n')
    return str(path)


def test_a_misheard_side_is_read_as_the_side_it_sounds_like(words, phrases):
    """"lift" is outside the phrase sets; skipped, "turn" alone would read (scripted) as class 1
    with confidence, but it sounds like "left": the follower turns left and says so."""
    follower = DirectionFollower(SpreadPolicy(0.95), words,
                                 FollowerConfig(phrase_vocabulary=phrases))
    assert follower.start("turn lift") == [3]
    assert follower.corrections == [("lift", "left")] and follower.unknown_words == []
    assert follower.start("turn left") == [3] and follower.corrections == []
    never = DirectionFollower(SpreadPolicy(0.95), words,
                              FollowerConfig(phrase_vocabulary=phrases, misheard_edits=0))
    assert never.start("turn lift") == [1] and never.unknown_words == ["lift"]


def test_readings_that_disagree_are_not_followed(words, phrases):
    """"lend" is one edit from "end" (class 1 here) and two from "left" (class 3): with two
    edits allowed the readings disagree, so the word is only skipped, and the rest decides."""
    config = FollowerConfig(phrase_vocabulary=phrases, misheard_edits=2)
    sure = DirectionFollower(SpreadPolicy(0.95), words, config)
    assert sure.start("turn lend") == [1]
    assert sure.corrections == [] and sure.unknown_words == ["lend"]
    unsure = DirectionFollower(SpreadPolicy(0.6), words, config)
    with pytest.raises(UnknownInstructionError, match="lend"):
        unsure.start("turn lend")
    one_edit = DirectionFollower(SpreadPolicy(0.95), words,
                                 FollowerConfig(phrase_vocabulary=phrases))
    assert one_edit.start("turn lend") == [1] and one_edit.corrections == [("lend", "end")]


def test_a_homophone_reading_comes_before_readings_a_letter_edit_away(words, tmp_path,
                                                                      monkeypatch):
    """Whisper writes "ride" for "right"; "ride" is also one edit from "side" (read here as
    class 1): the readings disagree, but the homophone's is weighed first."""
    path = tmp_path / "phrases.yaml"
    path.write_text('sets: ["turn {dir}", "go to the side"]\n')
    follower = DirectionFollower(SpreadPolicy(0.95), words,
                                 FollowerConfig(phrase_vocabulary=str(path)))
    assert follower.start("turn ride") == [2]
    assert follower.corrections == [("ride", "right")]
    monkeypatch.setattr("semantic_nav.misheard.HOMOPHONES", {})
    assert follower.start("turn ride") == [1]       # "right" is 3 edits away: "side" alone
    assert follower.corrections == [("ride", "side")]


def test_a_reading_without_confidence_is_not_followed(words, phrases):
    unsure = DirectionFollower(SpreadPolicy(0.6), words, FollowerConfig(phrase_vocabulary=phrases))
    with pytest.raises(UnknownInstructionError, match="lift"):
        unsure.start("turn lift")
