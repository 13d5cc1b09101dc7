"""Closed loop in sim2d: "take the second right" stops at the second right-hand branch of a
corridor whose branches alternate left and right; "turn right at the second corner" keeps
counting the corners over both sides (the default model and follower)."""
import pytest
from semnav_alternating_floor import START, alternating_floor_world

from semantic_nav.instruction_classes import COUNT_CORNERS, COUNT_SIDE
from semnav_learning.episodes import REACHED, chain_goals, run_episode


@pytest.fixture(scope="module")
def floor(tmp_path_factory):
    return alternating_floor_world(tmp_path_factory.mktemp("alternating"))


@pytest.fixture(scope="module")
def follower():
    from semantic_nav.follower import DirectionFollower, ModelMissingError
    from semantic_nav.word_vectors import WordVectorsError
    try:
        return DirectionFollower.from_files()
    except (ModelMissingError, WordVectorsError) as error:
        pytest.skip(str(error))


@pytest.mark.parametrize("sentence, counting, branch_x", [
    ("take the second right", COUNT_SIDE, 24.0),                # 4th corner, 2nd right
    ("turn right at the second corner", COUNT_CORNERS, 12.0),   # 2nd corner, 1st right
])
@pytest.mark.long      # two drives of 12 m and 24 m with the URG-04LX's rays marched: ~6 s
def test_the_robot_turns_into_the_branch_its_counting_names(floor, follower, sentence,
                                                            counting, branch_x):
    world, oracle = floor
    parts = chain_goals(oracle, START, (5,), (counting,))
    assert parts[0].goal.pose[0] == pytest.approx(branch_x, abs=0.1)
    result = run_episode(world, "penguin", follower, START, sentence, parts, noise_seed=1)
    assert result.predicted == [5] and follower.countings == [counting]
    assert result.success and result.reason == REACHED, result.reason
    assert result.path[-1][0] == pytest.approx(branch_x, abs=0.9)       # inside that branch
    assert result.path[-1][1] < 5.0                                     # south: the right side
