"""The launch files read like a ROS package's, and the robots have a body in rviz (no roscore).

Every `<arg>` that a launch file declares has a `doc`; none has an empty default, which
`roslaunch --ros-args` would list as "Required" (it counts every empty default as required):
an argument that means "nothing" by default says so with a word (`none`) its launch file
understands, and a truly required argument has no default at all. The launch files that start
a robot load its URDF as `robot_description`; the URDFs agree with the simulator's robots and do
not name a frame that the simulator or penguin_base already publishes.
"""
import os
import subprocess
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
import rospkg
import yaml
from tamp_resources import resource

LAUNCH_DIR = Path(rospkg.RosPack().get_path("tamp_bringup"), "launch")
LAUNCH_FILES = sorted(LAUNCH_DIR.glob("*.launch"))
URDF_DIR = resource("urdf")
RVIZ_DIR = resource("config", "rviz")
# frames sim2d publishes for a robot (sim2d.ros_node: odometry and static transforms) and
# penguin_base's mount_tf: a URDF link of one of these names would be published twice
PUBLISHED_ELSEWHERE = {"map", "odom", "base_laser", "camera_top", "camera_bottom",
                       "camera_top_optical", "camera_bottom_optical"}
WHEEL_JOINTS = ("left_wheel_joint", "right_wheel_joint")   # sim2d's and penguin_base's names


def declared_args(path):
    """(name, attributes) of the <arg>s a launch file declares (not the values it passes to an
    <include>), in document order."""
    out = []

    def walk(element):
        for child in element:
            if child.tag == "arg":
                out.append((child.get("name"), dict(child.attrib)))
            elif child.tag != "include":
                walk(child)
    walk(ET.parse(path).getroot())
    return out


def test_all_launch_files_are_checked():
    assert {p.name for p in LAUNCH_FILES} >= {
        "sim.launch", "social_household.launch", "semantic_nav.launch", "penguin_base.launch",
        "penguin_sim.launch", "record_demos.launch"}


@pytest.mark.parametrize("path", LAUNCH_FILES, ids=lambda p: p.name)
def test_every_argument_is_documented(path):
    undocumented = [name for name, attrs in declared_args(path)
                    if not " ".join(attrs.get("doc", "").split())]
    assert not undocumented, f"{path.name}: no doc for {undocumented}"


@pytest.mark.parametrize("path", LAUNCH_FILES, ids=lambda p: p.name)
def test_no_argument_has_an_empty_default(path):
    empty = [name for name, attrs in declared_args(path) if attrs.get("default") == ""]
    assert not empty, (f"{path.name}: empty default of {empty}; roslaunch --ros-args shows "
                       "these as Required: give a real default or a documented word (none)")


@pytest.mark.parametrize("path", LAUNCH_FILES, ids=lambda p: p.name)
def test_roslaunch_lists_no_undocumented_or_required_argument(path):
    """What `roslaunch --ros-args tamp_bringup <file>` prints, from roslaunch's own parser."""
    arg_dump = pytest.importorskip("roslaunch.arg_dump")
    args = arg_dump.get_args([str(path)])
    assert args
    assert not [name for name, (doc, _) in args.items() if not doc], "undocumented"
    # None: no default at all, a truly required argument; "": shown as Required by mistake
    assert not [name for name, (_, default) in args.items() if default == ""], "Required"


def load_launch(name):
    return ET.parse(LAUNCH_DIR / name).getroot()


@pytest.mark.parametrize("name, urdf", [("sim.launch", "pepper.urdf"),
                                        ("penguin_base.launch", "penguin.urdf")])
def test_the_robots_launch_files_load_their_urdf(name, urdf):
    root = load_launch(name)
    params = [p for p in root.iter("param") if p.get("name") == "robot_description"]
    assert len(params) == 1 and params[0].get("textfile") == "$(arg urdf)"
    default = {n: a for n, a in declared_args(LAUNCH_DIR / name)}["urdf"]["default"]
    assert default == f"$(find tamp_resources)/urdf/{urdf}"


def test_robot_state_publisher_runs_where_the_urdf_has_joints():
    nodes = {n.get("type") for n in load_launch("penguin_base.launch").iter("node")}
    assert "robot_state_publisher" in nodes
    # the companion robot is one link: no robot_state_publisher in the household
    for name in ("sim.launch", "social_household.launch"):
        assert "robot_state_publisher" not in {n.get("type") for n in load_launch(name).iter(
            "node")}


def urdf(name):
    return ET.parse(URDF_DIR / name).getroot()


def footprint_radius(robot):
    """Largest cylinder radius drawn on base_link [m]."""
    base = next(link for link in robot.iter("link") if link.get("name") == "base_link")
    return max(float(c.get("radius")) for c in base.iter("cylinder"))


def world_robot(world):
    config = yaml.safe_load(resource("config", "worlds", world).read_text())
    return config["robots"][0]


def test_companion_robot_urdf_is_one_link_of_the_simulated_radius():
    robot = urdf("pepper.urdf")
    assert [link.get("name") for link in robot.iter("link")] == ["base_link"]
    assert not list(robot.iter("joint"))
    assert footprint_radius(robot) == pytest.approx(world_robot("household.yaml")["radius"])


def test_penguin_urdf_matches_the_base_and_the_simulator():
    robot = urdf("penguin.urdf")
    links = {link.get("name") for link in robot.iter("link")}
    assert "base_link" in links and not links & PUBLISHED_ELSEWHERE
    joints = {j.get("name"): j for j in robot.iter("joint")}
    assert sorted(joints) == sorted(WHEEL_JOINTS)
    base = yaml.safe_load(resource("config", "penguin.yaml").read_text())["base"]
    world = world_robot("office_penguin.yaml")
    assert footprint_radius(robot) == pytest.approx(world["radius"])
    assert world["wheels"]["separation"] == pytest.approx(base["wheel_separation"])
    ys = []
    for name, joint in joints.items():
        assert joint.get("type") == "continuous"
        assert joint.find("parent").get("link") == "base_link"
        x, y, z = (float(v) for v in joint.find("origin").get("xyz").split())
        assert z == pytest.approx(base["wheel_radius"])
        ys.append(y)
        wheel = next(link for link in robot.iter("link")
                     if link.get("name") == joint.find("child").get("link"))
        assert float(next(wheel.iter("cylinder")).get("radius")) == pytest.approx(
            base["wheel_radius"])
    assert max(ys) - min(ys) == pytest.approx(base["wheel_separation"])


def test_fleet_runs_each_robots_navigation_and_executor_on_its_machine():
    robot, fleet = load_launch("fleet_robot.launch"), load_launch("fleet_sim.launch")
    machines = {m.get("name"): m for m in list(robot.iter("machine")) + list(fleet.iter("machine"))}
    assert set(machines) == {"$(arg robot)"}
    assert all(m.get("env-loader") == "$(arg env_loader)" for m in machines.values())
    nodes = {n.get("name"): n.get("machine") for n in robot.iter("node")}
    assert nodes == {"amcl": "$(arg robot)", "move_base": "$(arg robot)",
                     "task_planner": "$(arg robot)"}
    robots = [i for i in fleet.iter("include") if i.get("file").endswith("fleet_robot.launch")]
    assert [{a.get("name"): a.get("value") for a in i.iter("arg")}["address"] for i in robots] == [
        "$(arg robot1_address)", "$(arg robot2_address)"]


def test_the_env_loader_runs_a_command_in_the_workspace_environment(tmp_path):
    loader = LAUNCH_DIR.parent / "env_loader.sh"
    environment = {"PATH": "/usr/bin:/bin", "HOME": str(tmp_path), "TAMP_ROS_HOSTNAME": "robot7"}
    shown = subprocess.run(
        [str(loader), "python3", "-c", "import os, sys, task_planner; "
         "print(sys.prefix, os.environ['ROS_HOSTNAME'], os.environ['ROS_PACKAGE_PATH'])"],
        env=environment, capture_output=True, text=True, check=True).stdout.split()
    workspace = Path(os.environ["TAMP_WS"])   # set by scripts/env.sh, as in every test run
    assert shown[0] == str(workspace / ".venv") and shown[1] == "robot7"
    assert str(workspace / "src") in shown[2]


def rviz_displays(name):
    config = yaml.safe_load((RVIZ_DIR / name).read_text())
    return config, config["Visualization Manager"]["Displays"]


@pytest.mark.parametrize("name", ["sim.rviz", "social_household.rviz", "semantic_nav.rviz"])
def test_rviz_configs_show_the_robot_in_distinct_colours(name):
    _, displays = rviz_displays(name)
    models = [d for d in displays if d["Class"] == "rviz/RobotModel"]
    assert len(models) == 1 and models[0]["Robot Description"] == "robot_description"
    colours = {}
    for display in displays:
        colour = display.get("Color") or (display.get("Shape") or {}).get("Color")
        if colour and display["Class"] not in ("rviz/Grid", "rviz/Map"):
            colours.setdefault(colour, []).append(display["Name"])
    assert not {c: n for c, n in colours.items() if len(n) > 1}, "displays share a colour"


def test_fleet_view_shows_each_robot_under_its_namespace_in_its_own_colour():
    _, displays = rviz_displays("fleet.rviz")
    models = [d for d in displays if d["Class"] == "rviz/RobotModel"]
    assert sorted(m["TF Prefix"] for m in models) == ["robot1", "robot2"]
    colours = {}
    for display in displays:
        robot = display["Name"].split()[0]
        topic = display.get("Topic") or display.get("Marker Topic")
        if robot in ("robot1", "robot2"):
            assert display["Class"] == "rviz/RobotModel" or topic.startswith(f"/{robot}/")
            if "Color" in display:
                colours.setdefault(robot, set()).add(display["Color"])
    assert len(colours["robot1"]) == len(colours["robot2"]) == 1
    assert colours["robot1"] != colours["robot2"]


def test_direction_following_view_follows_the_robot():
    config, _ = rviz_displays("semantic_nav.rviz")
    view = config["Visualization Manager"]["Views"]["Current"]
    assert view["Class"] == "rviz/TopDownOrtho" and view["Target Frame"] == "base_link"
