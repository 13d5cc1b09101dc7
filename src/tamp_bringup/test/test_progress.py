"""tamp_bringup.progress: durations, the simulated-time rate, the ETA of a scenario run and the
requests its launch log shows as sent."""
import pytest

from tamp_bringup import progress


@pytest.mark.parametrize("seconds, text", [(0, "0 s"), (44.6, "45 s"), (185, "3 min 05 s"),
                                           (3720, "1 h 02 min"), (-3, "0 s")])
def test_duration_text(seconds, text):
    assert progress.duration_text(seconds) == text


def test_sim_rate_falls_back_until_a_second_has_passed():
    rate = progress.SimRate(5.0)
    assert rate.update(10.0, 0.0) == 5.0
    assert rate.update(10.5, 2.0) == 5.0
    assert rate.update(20.0, 30.0) == pytest.approx(3.0)


def test_remaining_wall_time():
    assert progress.remaining_wall_s(100.0, 400.0, 3.0) == pytest.approx(100.0)
    assert progress.remaining_wall_s(500.0, 400.0, 3.0) == 0.0
    assert progress.remaining_wall_s(0.0, 400.0, 0.0) == float("inf")


def test_sent_requests_are_counted_from_the_launch_log():
    log = ('[INFO] [1.2, 70.1]: scenario 70.1 s: Bob (phone 192.168.1.101) sends: "Chat"\n'
           '[INFO] [1.3, 74.0]: scenario 74.0 s: David (phone 192.168.1.102) speaks: "I have" '
           '(audio -> STT)\n'
           '[INFO] [1.4, 105.0]: scenario 105.0 s: Carol sets off to the dining room\n')
    assert progress.count_sent_requests(log) == 2


def test_scenario_lines_before_the_start_before_and_after_the_last_request():
    assert "starting" in progress.scenario_line(12.0, None, 5.0, 200.0, 900.0, 7, 0)
    assert "stopping the launch" in progress.scenario_line(300.0, None, 5.0, 200.0, 900.0, 7, 7,
                                                           started=True)
    before = progress.scenario_line(40.0, 120.0, 3.0, 200.0, 900.0, 7, 3)
    assert before.startswith("[scenario] 40 s: simulated 120 s at 3.0x, requests sent 3 of 7")
    assert "last request in 27 s" in before and "at most 5 min 27 s left" in before
    after = progress.scenario_line(100.0, 500.0, 5.0, 200.0, 900.0, 7, 7)
    assert "waiting for the open requests" in after and "at most 2 min 00 s left" in after
    assert "gives up at 1100 s simulated" in after
