"""Every rostest, roslaunch, rosrun and scripts/ command of the READMEs and docs pages names a
package and a file that exist (tamp_bringup.doc_commands); no ROS is started."""
import os
from pathlib import Path

from tamp_bringup.doc_commands import check, extract

WORKSPACE = Path(os.environ["TAMP_WS"])   # scripts/env.sh


def test_every_command_of_the_docs_names_a_package_and_file_that_exist():
    assert check(WORKSPACE) == []


def test_the_checker_flags_a_wrong_package_a_missing_file_and_a_missing_script(tmp_path):
    for package, files in {"good_pkg": ["test/faults.test", "nodes/tool"],
                           "other_pkg": ["launch/run.launch", "nodes/not_executable"]}.items():
        (tmp_path / "src" / package).mkdir(parents=True)
        (tmp_path / "src" / package / "package.xml").write_text(
            f"<package><name>{package}</name></package>\n")
        for name in files:
            (tmp_path / "src" / package / name).parent.mkdir(exist_ok=True)
            (tmp_path / "src" / package / name).write_text("#!/bin/sh\n")
    os.chmod(tmp_path / "src" / "good_pkg" / "nodes" / "tool", 0o755)
    (tmp_path / "scripts").mkdir()
    (tmp_path / "scripts" / "run").write_text("")
    (tmp_path / "docs").mkdir()
    (tmp_path / "docs" / "page.md").write_text(
        "Run `rostest other_pkg faults.test` or `roslaunch --ros-args other_pkg run.launch`,\n"
        "not `roslaunch --ros-args good_pkg\nrun.launch` (a span wrapped over two lines).\n"
        "```\n"
        "rostest --text good_pkg faults.test   # rosrun in a comment is prose\n"
        "rosrun good_pkg tool\n"
        "rosrun other_pkg not_executable\n"
        "roslaunch gone_pkg run.launch speed:=2\n"
        "roslaunch other_pkg <file>.launch\n"
        "scripts/run && scripts/gone\n"
        "```\n"
        "Prose naming rostest anything is not read.\n")
    problems = check(tmp_path, fallback=lambda name: None)
    assert problems == [
        "docs/page.md:1: rostest other_pkg faults.test: package other_pkg has no file "
        "faults.test (it is in good_pkg)",
        "docs/page.md:2: roslaunch good_pkg run.launch: package good_pkg has no file run.launch "
        "(it is in other_pkg)",
        "docs/page.md:7: rosrun other_pkg not_executable: package other_pkg has no executable "
        "not_executable",
        "docs/page.md:8: roslaunch gone_pkg run.launch: no package gone_pkg",
        "docs/page.md:10: scripts/gone: no file scripts/gone in the workspace"]


def test_launch_arguments_are_no_file_and_a_launch_path_names_no_package():
    commands = extract(Path("README.md"), "`roslaunch tamp_bringup sim.launch rviz:=true` and "
                                          "`roslaunch launch/sim.launch` and `rosrun pkg`")
    assert [(c.tool, c.package, c.target) for c in commands] == [
        ("roslaunch", "tamp_bringup", "sim.launch"), ("rosrun", "pkg", "")]
