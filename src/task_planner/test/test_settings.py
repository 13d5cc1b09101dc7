"""config/task_planner.yaml: read and checked at start, every error naming the file and key."""
import math

import pytest
import yaml

from task_planner.settings import BATTERY, REQUIRED, SettingsError, load_settings
from tamp_resources import resource

SHIPPED = resource("config") / "task_planner.yaml"


def write(tmp_path, text):
    path = tmp_path / "task_planner.yaml"
    path.write_text(text)
    return path


def shipped_with(tmp_path, **changes):
    settings = yaml.safe_load(SHIPPED.read_text())
    settings.update(changes)
    return write(tmp_path, yaml.safe_dump(settings))


def test_the_shipped_settings_load_with_the_battery():
    settings = load_settings(SHIPPED, REQUIRED + BATTERY)
    assert settings["speed_mps"] == 0.5 and settings["battery_low_fraction"] == 0.2


@pytest.mark.parametrize("value, shown", [(0, "0"), (-0.5, "-0.5"), (math.inf, "inf"),
                                          (math.nan, "nan"), ("fast", "'fast'"),
                                          (True, "True")])
def test_a_speed_that_is_not_positive_is_refused_naming_file_key_and_value(tmp_path, value,
                                                                             shown):
    path = shipped_with(tmp_path, speed_mps=value)
    with pytest.raises(SettingsError) as caught:
        load_settings(path)
    assert str(caught.value) == (f"{path}: speed_mps must be a finite number > 0 [m/s], "
                                 f"got {shown}")


@pytest.mark.parametrize("changes, message", [
    ({"step_s": 0}, r"step_s must be a finite number > 0 \[s\], got 0"),
    ({"robot_radius_m": -0.1}, r"robot_radius_m must be a finite number >= 0 \[m\]"),
    ({"rollout_horizon": 2.5}, r"rollout_horizon must be an integer >= 1, got 2.5"),
    ({"rollout_priority_first_at_node": "yes"},
     r"rollout_priority_first_at_node must be true or false, got 'yes'"),
    ({"battery_low_fraction": 1.5},
     r"battery_low_fraction must be a finite number >= 0 and <= 1, got 1.5"),
    ({"speed_mp": 0.5}, r"unknown key 'speed_mp' \(did you mean 'speed_mps'\?\)"),
])
def test_bad_values_and_unknown_keys_are_named(tmp_path, changes, message):
    path = shipped_with(tmp_path, **changes)
    with pytest.raises(SettingsError, match=rf"^{path}: {message}"):
        load_settings(path)


def test_missing_keys_are_named_and_battery_keys_only_when_used(tmp_path):
    path = write(tmp_path, "speed_mps: 0.5\n")
    with pytest.raises(SettingsError, match=rf"^{path}: missing key\(s\) robot_radius_m$"):
        load_settings(path)
    path = write(tmp_path, "speed_mps: 0.5\nrobot_radius_m: 0.25\n")
    assert load_settings(path)["speed_mps"] == 0.5
    with pytest.raises(SettingsError, match=r"missing key\(s\) battery_capacity_wh, "):
        load_settings(path, REQUIRED + BATTERY)


@pytest.mark.parametrize("text, message", [
    ("speed_mps: [0.5\n", r"not valid YAML \(line 2, column 1: "),
    ("- 0.5\n", r"expected a mapping of settings, got \[0.5\]"),
    ("", r"expected a mapping of settings, got None"),
])
def test_a_malformed_file_is_named(tmp_path, text, message):
    path = write(tmp_path, text)
    with pytest.raises(SettingsError, match=rf"^{path}: {message}"):
        load_settings(path)


def test_a_missing_file_is_named(tmp_path):
    with pytest.raises(SettingsError, match=rf"^{tmp_path}/nope.yaml: no such settings file$"):
        load_settings(tmp_path / "nope.yaml")
