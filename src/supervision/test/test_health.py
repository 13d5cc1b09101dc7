"""supervision.health: the guard, the heartbeat and the report levels, on a fake clock."""
import pytest

from supervision.health import ERROR, OK, Health, HealthConfig, fatal_report


class Clock:
    def __init__(self):
        self.t = 100.0

    def __call__(self):
        return self.t


@pytest.fixture
def clock():
    return Clock()


@pytest.fixture
def logged():
    return []


@pytest.fixture
def health(clock, logged):
    return Health("node", HealthConfig(fault_hold_s=10.0, stale_periods=5.0, stale_min_s=2.0),
                  clock=clock, log=logged.append)


def boom(x):
    raise ValueError(f"bad {x}")


def test_run_returns_the_result_and_stays_ok(health):
    assert health.run("tick", "", lambda a, b: a + b, 2, 3) == 5
    level, message, values = health.report()
    assert level == OK and message == "all workers alive"
    assert ("tick runs/faults", "1/0") in values


def test_a_fault_is_caught_counted_and_turns_the_node_to_error(health, logged):
    assert health.run("tick", "instruction 7", boom, 1) is None
    level, message, _ = health.report()
    assert level == ERROR
    assert "tick: instruction 7: ValueError: bad 1" in message
    assert health.faults == 1
    assert len(logged) == 1 and "Traceback" in logged[0] and "instruction 7" in logged[0]


def test_the_same_fault_is_logged_once_and_counted_every_time(health, logged):
    for _ in range(5):
        health.run("tick", "", boom, 1)
    health.run("tick", "", boom, 2)
    assert health.faults == 6
    assert len(logged) == 2


def test_on_error_gets_the_exception_and_its_own_fault_is_caught(health):
    seen = []
    health.run("tick", "", boom, 1, on_error=seen.append)
    assert isinstance(seen[0], ValueError)
    health.run("tick", "", boom, 2, on_error=lambda exc: boom("again"))
    assert health.faults == 3  # two runs, one failing handler


def test_error_holds_after_recovery_then_clears(health, clock):
    health.run("cb", "", boom, 1)
    health.run("cb", "", lambda: None)
    clock.t += 9.0
    level, message, _ = health.report()
    assert level == ERROR and "fault 9.0 s ago" in message
    clock.t += 1.5
    assert health.report()[0] == OK


def test_error_stays_while_the_worker_keeps_failing(health, clock):
    health.run("cb", "", boom, 1)
    clock.t += 60.0
    level, message, _ = health.report()
    assert level == ERROR and message.startswith("degraded: failing: cb")


def test_a_periodic_worker_that_stops_beating_is_silent(health, clock):
    health.worker("tick", period_s=0.05)
    health.beat("tick")
    clock.t += 1.9
    assert health.report()[0] == OK  # 5 periods is 0.25 s, but never sooner than 2 s
    clock.t += 0.2
    level, message, _ = health.report()
    assert level == ERROR and "worker tick silent for 2.1 s (expected every 0.05 s)" in message
    health.beat("tick")
    assert health.report()[0] == OK


def test_a_slow_period_is_stale_after_its_periods(health, clock):
    health.worker("map", period_s=2.0)
    clock.t += 9.9
    assert health.report()[0] == OK
    clock.t += 0.2
    assert health.report()[0] == ERROR


def test_event_driven_workers_are_never_silent(health, clock):
    health.worker("/scan callback")
    clock.t += 3600.0
    assert health.report()[0] == OK


@pytest.mark.parametrize("field", ["fault_hold_s", "stale_periods", "stale_min_s"])
@pytest.mark.parametrize("value", [0.0, -1.0, float("nan"), float("inf")])
def test_config_refuses_non_positive_or_non_finite(field, value):
    with pytest.raises(ValueError, match=f"HealthConfig.{field} must be a positive finite"):
        HealthConfig(**{field: value})


def test_worker_refuses_a_bad_period(health):
    with pytest.raises(ValueError, match="worker 'tick': period_s must be positive"):
        health.worker("tick", period_s=0.0)


def test_the_last_words_of_a_dying_node_name_the_exception_where_and_why():
    def load():
        raise TypeError("'<' not supported between instances of 'str' and 'int'")
    try:
        load()
    except TypeError as exc:
        message, values = fatal_report(exc)
    assert message == ("not running: TypeError: '<' not supported between instances of 'str' "
                       "and 'int' (raised at test_health.py:" + str(load.__code__.co_firstlineno
                                                                   + 1) + " in load)")
    assert dict(values) == {"exception": "TypeError",
                            "reason": "'<' not supported between instances of 'str' and 'int'",
                            "raised at": f"test_health.py:{load.__code__.co_firstlineno + 1} "
                                         "in load"}
    assert fatal_report(ValueError("never raised")) == (
        "not running: ValueError: never raised",
        [("exception", "ValueError"), ("reason", "never raised"), ("raised at", "")])
