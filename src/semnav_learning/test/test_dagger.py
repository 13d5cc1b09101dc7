"""DAgger's on-route truncation: states after the policy strays from the expert's route."""
import numpy as np

from semnav_learning.dagger import on_route_steps, route_distances

# An L route: 10 m east, then 5 m north (a left turn at (10, 0)).
ROUTE = np.array([[0.0, 0.0], [10.0, 0.0], [10.0, 5.0]])


def test_route_distances_to_the_nearest_segment():
    points = [[5.0, 0.5], [12.0, 0.0], [10.0, 6.0], [11.0, 3.0], [-3.0, 4.0]]
    np.testing.assert_allclose(route_distances(points, ROUTE), [0.5, 2.0, 1.0, 1.0, 5.0])
    np.testing.assert_allclose(route_distances([[3.0, 4.0]], ROUTE[:1]), [5.0])


def test_states_end_where_the_policy_drives_past_the_corner():
    # The policy drives straight on past the corner at x = 10 (0.5 m per step).
    path = np.column_stack([np.arange(0.0, 15.0, 0.5), np.full(30, 0.2), np.zeros(30)])
    # x = 11.5 is the first pose more than 1 m from the route (1.5 m past the corner's leg).
    assert on_route_steps(path, [ROUTE], 1.0) == 23
    assert path[23, 0] == 11.5
    # The robot that turns at the corner never leaves the route.
    turned = np.array([[x, 0.1, 0.0] for x in np.arange(0.0, 10.0, 0.5)]
                      + [[9.9, y, 1.57] for y in np.arange(0.0, 5.0, 0.5)])
    assert on_route_steps(turned, [ROUTE], 1.0) == len(turned)
    # With a second part's route the union counts: the east leg continued is on route.
    assert on_route_steps(path, [ROUTE, np.array([[10.0, 0.0], [20.0, 0.0]])], 1.0) == 30


def test_a_round_keeps_each_sequence_counting_mode_for_training(tmp_path):
    from penguin_base.record_format import RecordSequence, Sample, read_records
    from semantic_nav.instruction_classes import COUNT_CORNERS, COUNT_SIDE
    from semnav_learning.dagger import write_round
    from semnav_learning.training import record_countings
    ranges = (1.0, 2.0, 3.0)
    sequences = [RecordSequence(8, [Sample(0.3, 0.0, ranges)] * 3),
                 RecordSequence(5, [Sample(0.2, 0.5, ranges)] * 2)]
    path = tmp_path / "round.records"
    write_round(path, sequences, [COUNT_SIDE, COUNT_CORNERS])
    assert [s.instruction_class for s in read_records(path)] == [8, 5]
    # training reads the modes beside the records, as for a dataset build's floor
    assert record_countings(path, 2) == [COUNT_SIDE, COUNT_CORNERS]
