"""Validation function (§4.1.2, Eq. 4.2-1 … 4.2-4), monitors (§4.1.3) and training sequences."""
import numpy as np
import pytest

from semantic_nav.instruction_classes import CLASS_IDS, MIRRORED_CLASS
from semnav_learning.training import (Episode, Monitor, TrainingConfig,
                                   ValidationThresholds, accumulated_errors, batch_rows,
                                   control_rate_sequence, decision_distance, decision_step,
                                   class_batch, class_hits_and_loss, make_batches,
                                   mirror_sequence,
                                   onset_verdict, step_errors, step_weights, turn_fit_by_class,
                                   turn_onset, validate_sequence, word_noise)
from tamp_resources import resource

T = ValidationThresholds(step_linear=0.1, step_angular=0.25, distance=1.0, angle=0.6)


def test_errors_and_accumulation():
    ref = np.array([[0.4, 0.0], [0.4, 0.5], [0.0, 0.0]])
    out = np.array([[0.3, 0.1], [0.4, 0.2], [0.1, -0.1]])
    d, e = step_errors(ref, out)
    np.testing.assert_allclose(d, [0.1, 0.0, -0.1])
    np.testing.assert_allclose(e, [-0.1, 0.3, 0.1])
    dist, angle = accumulated_errors(d, e, 10.0)
    np.testing.assert_allclose(dist, [0.01, 0.01, 0.0], atol=1e-12)
    np.testing.assert_allclose(angle, [-0.01, 0.02, 0.03])


def test_all_correct_reaches_the_destination():
    ref = np.tile([0.3, 0.2], (50, 1))
    assert validate_sequence(ref, ref + [0.005, -0.005], T, 10.0) == (50, True)


def test_one_wrong_step_counts_but_no_destination():
    ref = np.zeros((20, 2))
    out = np.zeros((20, 2))
    out[7, 1] = 0.3                     # |e_7| = 0.3 > 0.25
    assert validate_sequence(ref, out, T, 10.0) == (19, False)


def test_counting_stops_when_the_accumulated_error_is_too_large():
    ref = np.zeros((100, 2))
    out = np.full((100, 2), [0.09, 0.0])   # each step correct, D_i = 0.009 i: > 1 m at i = 112
    assert validate_sequence(ref, out, T, 10.0) == (100, True)
    out = np.full((100, 2), [0.0, 0.21])   # E = 0.021 (i + 1): 0.588 at index 27, 0.609 at 28
    assert validate_sequence(ref, out, T, 10.0) == (28, False)


def test_monitors():
    loss = Monitor("loss")
    assert [loss.update(v) for v in (0.5, 0.6, 0.4, 0.4)] == [True, False, True, False]
    valid = Monitor("validation")
    assert [valid.update(v) for v in ([514, 5], [495, 7], [629, 12], [631, 10], [617, 12],
                                      [640, 12])] == [True, True, True, False, False, True]
    assert valid.best == [640, 12]
    closed = Monitor("closed_loop")    # goals reached; a tie keeps the earlier model
    assert [closed.update(v) for v in (120, 118, 131, 131, 140)] == [True, False, True, False,
                                                                    True]
    assert closed.best == 140
    phrasing = Monitor("phrasing")     # (sentences right, cross-entropy); a tie by the entropy
    assert [phrasing.update(v) for v in ((931, 0.42), (931, 0.45), (931, 0.40), (978, 0.9),
                                        (970, 0.1))] == [True, False, True, True, False]
    assert phrasing.best == (978, 0.9)
    with pytest.raises(ValueError):
        Monitor("accuracy")


def test_class_hits_and_loss():
    probabilities = np.array([[0.7, 0.2, 0.1], [0.5, 0.25, 0.25], [0.0, 1.0, 0.0]])
    hits, loss = class_hits_and_loss(probabilities, np.array([0, 1, 1]))
    assert hits == 2                   # the second row's argmax is class 0
    assert loss == pytest.approx(-(np.log(0.7) + np.log(0.25) + np.log(1.0)) / 3)
    # a zero probability on the true class is a large but finite loss
    assert np.isfinite(class_hits_and_loss(probabilities[2:], np.array([0]))[1])


def test_control_rate_sequence_subsamples_and_holds_at_the_goal():
    scans = np.arange(12, dtype=np.float32)[:, None] * np.ones((1, 3), np.float32)
    commands = np.zeros((12, 2), np.float32)
    commands[:10] = [0.3, 0.1]
    episode = Episode(1, scans, commands, rate=40.0)
    config = TrainingConfig(hold_steps=5)
    s, c = control_rate_sequence(episode, 1, config)
    assert s[:3, 0].tolist() == [1, 5, 9]               # every 4th scan from phase 1
    assert s[3:, 0].tolist() == [10, 11, 10, 11, 10]    # the standing scans repeated
    assert c[3:].tolist() == [[0, 0]] * 5
    moving = Episode(1, scans, np.full((12, 2), 0.2, np.float32), rate=10.0)
    s, c = control_rate_sequence(moving, 0, config)     # ends moving: no hold appended
    assert len(s) == 12


def test_standing_tail_is_topped_up_not_doubled():
    """Records that already end standing for long enough (expert stop_duration) get no hold."""
    scans = np.arange(40, dtype=np.float32)[:, None] * np.ones((1, 3), np.float32)
    commands = np.zeros((40, 2), np.float32)
    commands[:8] = [0.3, 0.0]                   # moving up to index 7, then 32 standing samples
    episode = Episode(1, scans, commands, rate=40.0)
    s, c = control_rate_sequence(episode, 0, TrainingConfig(hold_steps=5))
    assert s[:, 0].tolist() == [0, 4, 8, 12, 16, 20, 24, 28, 32, 36]   # 8 standing steps >= 5
    s, c = control_rate_sequence(episode, 0, TrainingConfig(hold_steps=10))
    assert s[10:, 0].tolist() == [8, 9]        # 2 steps short of 10: first standing scans added
    assert np.all(c[2:] == 0.0) and len(c) == 12


def test_stop_targets_mark_the_standing_steps():
    scans = np.ones((12, 3), np.float32)
    commands = np.zeros((12, 2), np.float32)
    commands[:6] = [0.0, 0.5]                   # turning on the spot (v = 0, ω ≠ 0) is not a stop
    episode = Episode(4, scans, commands, rate=10.0)
    config = TrainingConfig(hold_steps=2, stop_targets=True, batch_size=2)

    class Words:
        dim = 2
    sentences = [np.ones((3, 2), np.float32)]
    (batch,) = make_batches([episode], None, Words(), np.random.default_rng(0), config,
                            phases=[0], sentences=sentences)
    inputs, targets, weights = batch
    assert targets["stop"][0, :, 0].tolist() == [0] * 6 + [1] * 6
    assert weights["stop"].tolist() == [[1.0] * 12]
    assert "stop" not in make_batches([episode], None, Words(), np.random.default_rng(0),
                                      TrainingConfig(hold_steps=2), phases=[0],
                                      sentences=sentences)[0][1]


def _corner_commands():
    """10 Hz: 0.5 s of steering (ω 0.2, too short for a turn), 1 s straight at 0.5 m/s, a
    2.5 s turn at 0.3 m/s, 0.5 s standing."""
    return np.array([[0.5, 0.2]] * 5 + [[0.5, 0.0]] * 10 + [[0.3, 0.3]] * 25
                    + [[0.0, 0.0]] * 5, np.float32)


def test_decision_step_skips_steering_and_falls_back_to_the_stop():
    config = TrainingConfig()                 # turn_threshold 0.15, turns of ≥ 2 s
    assert decision_step(_corner_commands(), 10.0, config) == 15
    straight = np.array([[0.5, 0.0]] * 20 + [[0.0, 0.0]] * 10, np.float32)
    assert decision_step(straight, 10.0, config) == 20
    assert decision_step(straight[:20], 10.0, config) is None


def test_decision_distance_counts_down_to_the_turn():
    config = TrainingConfig(decision_horizon=15.0)
    target = decision_distance(_corner_commands(), 10.0, config)
    # 15 steps of 0.05 m before the turn: 0.75 m at step 0, 0.25 m at step 10, then 0
    np.testing.assert_allclose(target[[0, 10, 14]], np.array([0.75, 0.25, 0.05]) / 15.0,
                               rtol=1e-6)
    assert not target[15:].any()
    clipped = decision_distance(_corner_commands(), 10.0, TrainingConfig(decision_horizon=0.5))
    np.testing.assert_allclose(clipped[[0, 10]], [1.0, 0.5], rtol=1e-6)
    endless = np.array([[0.5, 0.0]] * 20, np.float32)      # never turns nor stops: "far"
    assert decision_distance(endless, 10.0, config).tolist() == [1.0] * 20


def test_decision_targets_only_when_asked():
    episode = Episode(5, np.ones((45, 3), np.float32), _corner_commands(), rate=10.0)

    class Words:
        dim = 2
    sentences = [np.ones((3, 2), np.float32)]
    config = TrainingConfig(hold_steps=0, decision_targets=True)
    (batch,) = make_batches([episode], None, Words(), np.random.default_rng(0), config,
                            phases=[0], sentences=sentences)
    _, targets, weights = batch
    np.testing.assert_allclose(targets["decision"][0, :, 0],
                               decision_distance(_corner_commands(), 10.0, config))
    assert weights["decision"].tolist() == [[1.0] * 45]
    assert "decision" not in make_batches([episode], None, Words(), np.random.default_rng(0),
                                          TrainingConfig(hold_steps=0), phases=[0],
                                          sentences=sentences)[0][1]


def test_count_inputs_join_the_batches_and_survive_mirroring():
    sides = np.ones((45, 2), np.float32)
    sides[3:13, 1] = 4.0            # the right side open from 0.15 to 0.6 m of travel
    episode = Episode(5, np.ones((45, 3), np.float32), _corner_commands(), rate=10.0,
                      sides=sides)

    class Words:
        dim = 2
    config = TrainingConfig(hold_steps=0, count_inputs=True, mirror_probability=1.0)
    config.corners.min_width = 0.28
    # the opening began at 0.15 m (step 3): 0.25 m long at step 8, 0.3 m at step 9 (0.45 m)
    expected = np.eye(4)[[0] * 9 + [1] * 36]
    for phases in ([0], None):      # validation, and training (mirrored: the count is the same)
        (batch,) = make_batches([episode], None, Words(), np.random.default_rng(0), config,
                                phases=phases, sentences=[np.ones((3, 2), np.float32)])
        inputs, _, _ = batch
        assert inputs["counts"][0].tolist() == expected.tolist()
    with pytest.raises(ValueError, match="side ranges"):
        make_batches([Episode(5, episode.scans, episode.commands, rate=10.0)], None, Words(),
                     np.random.default_rng(0), config, phases=[0],
                     sentences=[np.ones((3, 2), np.float32)])


def test_count_targets_and_the_counting_input_follow_each_records_mode():
    """Learned counting: the count target is the counter over the record's side ranges in its
    own mode (a one-side count looks at the turning side only), the counting input one-hot that
    mode; mirrored, the turning side is the other column, the count the same."""
    sides = np.ones((45, 2), np.float32)
    sides[3:13, 1] = 4.0            # a right-hand opening from 0.15 to 0.6 m of travel
    sides[20:35, 0] = 4.0           # then a left-hand one from 0.9 m (0.03 m a step)
    commands = _corner_commands()

    class Words:
        dim = 2
    config = TrainingConfig(hold_steps=0, count_targets=True, counting_inputs=True,
                            mirror_probability=1.0)
    config.corners.min_width = 0.28
    both = [0] * 9 + [1] * 21 + [2] * 15      # each counted once 0.28 m long (steps 9, 30)
    right_only = [0] * 9 + [1] * 36           # class 5 turns right: the left one is not looked at
    for mode, expected, column in (("corners", both, 0), ("side", right_only, 1)):
        episode = Episode(5, np.ones((45, 3), np.float32), commands, rate=10.0, sides=sides,
                          counting=mode)
        for phases in ([0], None):  # validation, and training (mirrored)
            (batch,) = make_batches([episode], None, Words(), np.random.default_rng(0), config,
                                    phases=phases, sentences=[np.ones((3, 2), np.float32)])
            inputs, targets, weights = batch
            assert targets["count"][0].tolist() == expected
            assert inputs["counting"][0].tolist() == [[1.0 - column, float(column)]] * 45
            assert weights["count"].tolist() == [[1.0] * 45] and "counts" not in inputs


def test_record_countings_read_beside_the_records(tmp_path):
    from semnav_learning.training import record_countings
    records = tmp_path / "floor.records"
    assert record_countings(records, 2) == ["corners", "corners"]     # none written: corners
    records.with_suffix(".json").write_text('{"entry": {}, "countings": ["side", "corners"]}')
    assert record_countings(records, 2) == ["side", "corners"]
    with pytest.raises(ValueError, match="2 counting modes for 3 records"):
        record_countings(records, 3)


def test_step_weights_single_out_turning_and_standing_steps():
    commands = np.array([[0.5, 0.0], [0.5, 0.1], [0.3, 0.15], [0.2, -0.3], [0.0, 0.0]],
                        np.float32)
    config = TrainingConfig(stop_weight=0.5, turn_weight=3.0, turn_threshold=0.15)
    assert step_weights(commands, config).tolist() == [1.0, 1.0, 3.0, 3.0, 0.5]
    assert step_weights(commands, TrainingConfig()).tolist() == [1.0] * 5   # the seed's MSE


def test_turn_onset_compares_the_first_turning_steps():
    reference = np.zeros((30, 2))
    reference[12:20, 1] = 0.3                   # the expert turns left from step 12
    on_time, early, wrong_way = np.zeros((30, 2)), np.zeros((30, 2)), np.zeros((30, 2))
    on_time[14:22, 1] = 0.25
    early[3:6, 1] = 0.2                          # a left turn at an earlier corner
    wrong_way[12:20, 1] = -0.3                   # turns right instead: never turns left
    assert turn_onset(reference, on_time, 0.15) == (12, 14)
    assert onset_verdict(turn_onset(reference, on_time, 0.15), 2) == "on time"
    assert onset_verdict(turn_onset(reference, on_time, 0.15), 1) == "late"
    assert onset_verdict(turn_onset(reference, early, 0.15), 2) == "early"
    assert onset_verdict(turn_onset(reference, wrong_way, 0.15), 2) == "never"
    assert turn_onset(np.zeros((5, 2)), on_time[:5], 0.15) is None   # the expert never turns


def test_mirror_sequence_swaps_the_sides():
    scans = np.array([[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]], np.float32)   # beam 0 on the right
    commands = np.array([[0.5, 0.2], [0.3, -0.1]], np.float32)
    m_scans, m_commands, label = mirror_sequence(scans, commands, 6)
    assert m_scans.tolist() == [[3.0, 2.0, 1.0], [6.0, 5.0, 4.0]]
    np.testing.assert_allclose(m_commands, [[0.5, -0.2], [0.3, 0.1]])
    assert label == 5                            # left at the 2nd corner -> right at the 2nd
    assert all(MIRRORED_CLASS[MIRRORED_CLASS[c]] == c for c in CLASS_IDS)
    assert [c for c in CLASS_IDS if MIRRORED_CLASS[c] == c] == [1, 4]


def test_only_training_batches_are_mirrored():
    scans = np.arange(12, dtype=np.float32).reshape(4, 3)
    commands = np.tile(np.array([[0.4, 0.3]], np.float32), (4, 1))
    episode = Episode(3, scans, commands, rate=10.0)
    config = TrainingConfig(hold_steps=0, mirror_probability=1.0)

    class Words:
        dim = 2
    words = [np.ones((2, 2), np.float32)]
    fixed = make_batches([episode], None, Words(), np.random.default_rng(0), config,
                         phases=[0], sentences=words)
    assert fixed[0][1]["instruction_class"].tolist() == [2]          # validation: class 3
    assert np.all(fixed[0][1]["velocity"][0, :, 1] == 0.3)


def test_word_noise_has_the_asked_spread_and_none_at_zero():
    vectors = np.tile(np.array([[1.0, -2.0, 0.5]], np.float32), (20000, 1))
    rng = np.random.default_rng(3)
    assert word_noise(vectors, 0.0, rng) is vectors
    assert rng.integers(1 << 30) == np.random.default_rng(3).integers(1 << 30)   # no draw at 0
    noisy = word_noise(vectors, 0.3, np.random.default_rng(4))
    assert noisy.dtype == np.float32
    np.testing.assert_allclose(noisy.mean(axis=0), [1.0, -2.0, 0.5], atol=0.01)
    np.testing.assert_allclose(noisy.std(axis=0), [0.3] * 3, rtol=0.03)


@pytest.fixture(scope="module")
def phrase_words():
    """The real phrase sets and a random vector for every word they use."""

    from semantic_nav.instruction_layer import tokenise
    from semnav_learning.phrase_sets import load_phrase_sets
    from semantic_nav.word_vectors import WordVectors
    sets = load_phrase_sets(resource("config") / "semnav_phrases.yaml")
    vocabulary = sorted({t for phrases in sets.values() for p in phrases for t in tokenise(p.text)})
    matrix = np.random.default_rng(0).normal(size=(len(vocabulary), 4)).astype(np.float32)
    return sets, WordVectors(vocabulary, matrix, "random")


def test_word_noise_reaches_training_sentences_but_not_validation(phrase_words):
    sets, words = phrase_words
    episode = Episode(3, np.ones((4, 3), np.float32),
                      np.tile(np.array([[0.4, 0.3]], np.float32), (4, 1)), rate=10.0)

    def sentence(noise, phases):
        config = TrainingConfig(hold_steps=0, word_noise=noise)
        (batch,) = make_batches([episode], sets, words, np.random.default_rng(5), config,
                                phases=phases)
        return batch[0]["words"][0]
    assert np.array_equal(sentence(0.5, [0]), sentence(0.0, [0]))       # validation: clean
    clean, noisy = sentence(0.0, None), sentence(0.5, None)
    assert clean.shape == noisy.shape and not np.allclose(clean, noisy)
    rows = {tuple(v) for v in words.matrix.tolist()}
    assert all(tuple(v) in rows for v in clean.tolist())                # clean rows are words
    clean_batch, labels = class_batch(sets, words, np.random.default_rng(6), 8)
    noisy_batch, noisy_labels = class_batch(sets, words, np.random.default_rng(6), 8, noise=0.5)
    assert labels.tolist() == noisy_labels.tolist()
    # the first sentence is drawn before any noise: the same words, moved by the noise
    length = int(np.any(clean_batch[0] != 0, axis=1).sum())
    assert np.any(noisy_batch[0, length - 1] != 0)
    assert not np.allclose(clean_batch[0, :length], noisy_batch[0, :length])


def test_batch_rows_cut_the_padding_whatever_the_step_weights():
    """Two sequences of 3 and 5 steps in one batch; turning steps weigh 3 (--turn-weight)."""
    short = Episode(2, np.ones((3, 2), np.float32), np.array([[0.4, 0.3]] * 3, np.float32),
                    rate=10.0)
    long = Episode(5, np.ones((5, 2), np.float32), np.array([[0.4, 0.0]] * 5, np.float32),
                   rate=10.0)
    config = TrainingConfig(hold_steps=0, turn_weight=3.0, batch_size=2)

    class Words:
        dim = 2
    sentences = [np.ones((2, 2), np.float32)] * 2
    (batch,) = make_batches([short, long], None, Words(), np.random.default_rng(0), config,
                            phases=[0, 0], sentences=sentences)
    _, targets, weights = batch
    outputs = {"velocity": targets["velocity"] + 0.01}
    rows = list(batch_rows(targets, outputs, weights))
    assert [(label, len(ref), len(out)) for label, ref, out in rows] == [(2, 3, 3), (5, 5, 5)]
    np.testing.assert_allclose(rows[0][2], [[0.41, 0.31]] * 3, atol=1e-6)


def test_turn_fit_by_class_counts_verdicts_and_turning_error():
    reference = np.zeros((20, 2))
    reference[8:12, 1] = -0.3                    # a right turn from step 8
    late = reference.copy()
    late[:, 1] = np.roll(reference[:, 1], 5)     # the same turn 5 steps later
    rows = [(5, reference, reference), (5, reference, late), (1, np.zeros((20, 2)),
                                                             np.zeros((20, 2)))]
    fit = turn_fit_by_class(rows, 0.15, 2)
    assert list(fit) == [5]                      # class 1 never turns: left out
    records, mse, verdicts = fit[5]
    assert records == 2 and verdicts == {"on time": 1, "late": 1}
    # the late model still drives straight (ω = 0) on the expert's 4 turning steps (-0.3)
    assert mse == pytest.approx((0.0 + 0.3 ** 2) / 2)
