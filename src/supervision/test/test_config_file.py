"""The shared loader of user-written YAML files: one-line errors naming the file and the key."""
import pytest

from supervision.config_file import ConfigError, check_keys, find_file, read_yaml


class OwnError(ConfigError):
    pass


def test_a_missing_file_and_broken_yaml_are_one_line_naming_the_file(tmp_path):
    with pytest.raises(ConfigError, match=rf"^{tmp_path}/none.yaml: no such world file$"):
        read_yaml(tmp_path / "none.yaml", what="world file")
    broken = tmp_path / "broken.yaml"
    broken.write_text("a: 1\nb: [2\n")
    with pytest.raises(OwnError) as raised:
        read_yaml(broken, OwnError)
    assert str(raised.value).startswith(f"{broken}: not valid YAML (line 3, column 1: ")
    assert "\n" not in str(raised.value)
    (tmp_path / "fine.yaml").write_text("a: [1, 2]\n")
    assert read_yaml(tmp_path / "fine.yaml") == {"a": [1, 2]}


def test_an_unknown_key_names_the_nearest_known_one_or_lists_them():
    with pytest.raises(ConfigError, match=r"^s.yaml: unknown key 'planer' \(did you mean "
                                          r"'planner'\?\)$"):
        check_keys({"world": 1, "planer": 2}, ("world", "planner"), "s.yaml")
    with pytest.raises(OwnError, match=r"^s.yaml: people\[0\]: unknown key 'zzz' \(valid keys: "
                                       r"name, pose\)$"):
        check_keys({"zzz": 1}, ("name", "pose"), "s.yaml: people[0]", OwnError)
    with pytest.raises(ConfigError, match=r"expected a mapping, got \[1\]"):
        check_keys([1], ("name",), "s.yaml")
    assert check_keys({"name": 1}, ("name",), "s.yaml") == {"name": 1}


def test_a_named_file_is_found_next_to_its_file_then_in_the_fallbacks(tmp_path):
    near, resources = tmp_path / "near", tmp_path / "resources" / "scenarios"
    near.mkdir()
    resources.mkdir(parents=True)
    (tmp_path / "resources" / "world.yaml").write_text("")
    assert find_file("../world.yaml", near, resources) == (tmp_path / "resources" / "world.yaml")
    (tmp_path / "world.yaml").write_text("")
    assert find_file("../world.yaml", near, resources) == tmp_path / "world.yaml"
    assert find_file("../other.yaml", near, resources) is None
    assert find_file(tmp_path / "world.yaml", near) == tmp_path / "world.yaml"
