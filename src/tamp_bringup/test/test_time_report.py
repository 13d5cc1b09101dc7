"""tamp_bringup.time_report: the report's "where the time went" table and plot."""
from tamp_bringup.time_report import plot_time, robot_shares, time_markdown


def test_the_table_gives_seconds_and_shares_per_activity(tmp_path):
    record = dict(sim_s=100.0, activities={"": [[0.0, "travel"], [30.0, "function"],
                                                [80.0, "searching"]]})
    shares = robot_shares(record)
    assert shares == {"": {"travel": 30.0, "function": 50.0, "searching": 20.0}}
    lines = time_markdown(shares, "time.png")
    assert "| travel | 30 s (30 %) |" in lines
    assert "| searching | 20 s (20 %) |" in lines
    assert "| function | 50 s (50 %) |" in lines
    assert not any(line.startswith("| idle") for line in lines)   # nothing idle: no row
    assert lines[-2] == "![time](time.png)"
    plot_time(tmp_path / "time.png", shares, "test")
    assert (tmp_path / "time.png").read_bytes()[:4] == b"\x89PNG"


def test_a_fleet_gets_a_column_per_robot_and_an_old_record_no_section():
    record = dict(sim_s=10.0, activities={"robot1": [[0.0, "idle"]],
                                          "robot2": [[0.0, "travel"], [5.0, "idle"]]})
    lines = time_markdown(robot_shares(record), "time.png")
    assert "| activity | robot1 | robot2 |" in lines
    assert "| idle | 10 s (100 %) | 5 s (50 %) |" in lines
    assert time_markdown(robot_shares(dict(sim_s=10.0)), "time.png") == []
