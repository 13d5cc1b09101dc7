"""The human_db node under a real roscore: kill -9 mid-update loses no acknowledged update, and a
corrupted database file stops the node with a message naming the file (the file is kept).

Needs the workspace environment (`source scripts/env.sh`): roscore, rosrun and the built package.
"""
import json
import os
import shutil
import signal
import socket
import sqlite3
import subprocess
import sys
import threading
import time

import pytest
from tamp_resources import resource

HOUSEHOLD = resource("config") / "household.yaml"
ACKS_BEFORE_KILL = 200   # acknowledged updates before the node is killed
TIMEOUT = 30.0           # [s] for anything to start or finish

WRITER = """
import rospy
from tamp_msgs.srv import UpdateHuman
rospy.init_node("writer", anonymous=True, disable_signals=True)
rospy.wait_for_service("/human_db/update", 30)
update = rospy.ServiceProxy("/human_db/update", UpdateHuman, persistent=True)
i = 0
while True:
    try:
        answer = update(name="Alice", location=("office", "alley")[i % 2], activity=f"step {i}",
                        source="writer", stamp=rospy.Time(1000 + i))
    except Exception as error:
        print("error", error, flush=True)
        break
    if not answer.success:
        print("refused", answer.message, flush=True)
        break
    print("ack", i, flush=True)
    i += 1
"""

READER = """
import json, sys
import rospy
from tamp_msgs.srv import GetHuman, WhereWasHuman
rospy.init_node("reader", anonymous=True, disable_signals=True)
rospy.wait_for_service("/human_db/where_was", 30)
where = rospy.ServiceProxy("/human_db/where_was", WhereWasHuman, persistent=True)
found = [where(name="Alice", stamp=rospy.Time(1000 + i)) for i in range(int(sys.argv[1]))]
alice = rospy.ServiceProxy("/human_db/get", GetHuman)(name="Alice", ip="").human
print(json.dumps({"history": [[f.found, f.location, f.activity, f.recorded.to_sec()]
                              for f in found], "current": alice.activity}))
"""


def _ros_ready():
    if not shutil.which("roscore") or not shutil.which("rosrun"):
        return False
    probe = subprocess.run(["rospack", "find", "human_db"], capture_output=True, text=True)
    return probe.returncode == 0


pytestmark = pytest.mark.skipif(not _ros_ready(),
                                reason="needs the workspace environment: source scripts/env.sh")


def _free_port():
    with socket.socket() as probe:
        probe.bind(("localhost", 0))
        return probe.getsockname()[1]


@pytest.fixture(scope="module")
def ros_env(tmp_path_factory):
    """A roscore of our own on a free port, with ROS_HOME in a temporary directory; one for the
    module's tests (each starts its own nodes, on databases of its own)."""
    port = _free_port()
    home = tmp_path_factory.mktemp("ros")
    env = dict(os.environ, ROS_MASTER_URI=f"http://localhost:{port}", ROS_HOSTNAME="localhost",
               ROS_HOME=str(home), ROS_LOG_DIR=str(home / "log"))
    core = subprocess.Popen(["roscore", "-p", str(port)], env=env, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL, start_new_session=True)
    deadline = time.monotonic() + TIMEOUT
    while True:
        with socket.socket() as probe:
            if probe.connect_ex(("localhost", port)) == 0:
                break
        assert time.monotonic() < deadline, "roscore did not start"
        time.sleep(0.2)
    yield env
    os.killpg(core.pid, signal.SIGINT)
    try:
        core.wait(TIMEOUT)
    except subprocess.TimeoutExpired:
        os.killpg(core.pid, signal.SIGKILL)
        core.wait()


def _start_node(env, db_path, *params):
    return subprocess.Popen(
        ["rosrun", "human_db", "human_db", f"_db_path:={db_path}", f"_household:={HOUSEHOLD}",
         *params],
        env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
        start_new_session=True)


def _stop(process):
    if process.poll() is None:
        process.send_signal(signal.SIGINT)
        try:
            process.wait(TIMEOUT)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()


def test_kill_9_mid_update_loses_no_acknowledged_update(ros_env, tmp_path):
    db_path = tmp_path / "humans.sqlite"
    node = _start_node(ros_env, db_path)
    writer = subprocess.Popen([sys.executable, "-c", WRITER], env=ros_env, text=True,
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    acked, lines = [], []
    watchdog = threading.Timer(TIMEOUT * 2, writer.kill)   # a hung writer ends the loop below
    watchdog.start()
    try:
        for line in writer.stdout:   # read to the end: acks may still come after the kill
            lines.append(line.strip())
            if line.startswith("ack"):
                acked.append(int(line.split()[1]))
            if len(acked) == ACKS_BEFORE_KILL and node.poll() is None:
                os.kill(node.pid, signal.SIGKILL)   # while the writer keeps updating
    finally:
        watchdog.cancel()
        _stop(writer)
        _stop(node)
    assert acked == list(range(len(acked))) and len(acked) >= ACKS_BEFORE_KILL
    assert lines[-1].startswith("error"), f"the writer should lose the node: {lines[-3:]}"
    assert node.returncode == -signal.SIGKILL

    restarted = _start_node(ros_env, db_path)
    try:
        reader = subprocess.run([sys.executable, "-c", READER, str(len(acked) + 1)],
                                env=ros_env, capture_output=True, text=True, timeout=TIMEOUT * 2)
    finally:
        _stop(restarted)
    assert reader.returncode == 0, reader.stdout + reader.stderr
    result = json.loads(reader.stdout.splitlines()[-1])
    for i in acked:
        assert result["history"][i] == [True, ("office", "alley")[i % 2], f"step {i}",
                                        1000.0 + i], f"acknowledged update {i} is lost"
    # the update in flight at the kill is either wholly there or wholly absent
    last = len(acked) - 1
    assert result["current"] in (f"step {last}", f"step {last + 1}")
    assert "imported" not in restarted.stdout.read(), "the restart must not re-import"


def test_a_corrupted_database_stops_the_node_naming_the_file(ros_env, tmp_path):
    db_path = tmp_path / "humans.sqlite"
    garbage = b"\x00\x01 definitely not SQLite \xff" * 200
    db_path.write_bytes(garbage)
    node = _start_node(ros_env, db_path)
    try:
        output = node.communicate(timeout=TIMEOUT)[0]
    finally:
        _stop(node)
    assert node.returncode == 1
    assert f"{db_path}: not an SQLite database" in output
    assert db_path.read_bytes() == garbage
    assert sorted(p.name for p in tmp_path.iterdir() if p.name.startswith("humans")) == \
        ["humans.sqlite"]


def test_a_locked_database_is_retried_then_stops_the_node_naming_the_file(ros_env, tmp_path):
    db_path = tmp_path / "humans.sqlite"
    holder = sqlite3.connect(db_path, isolation_level=None)
    holder.execute("BEGIN EXCLUSIVE")          # another process's exclusive lock
    try:
        # SQLite gives up on the lock after 0.1 s: one retry 0.9 s later, then the budget is out
        node = _start_node(ros_env, db_path, "_busy_timeout:=0.1", "_open_retry_s:=1.0")
        try:
            output = node.communicate(timeout=TIMEOUT)[0]
        finally:
            _stop(node)
    finally:
        holder.execute("ROLLBACK")
        holder.close()
    assert node.returncode == 1
    assert output.count(f"human_db: {db_path}: another process holds a lock on the database "
                        "(SQLite: database is locked); retry ") == 1
    assert (f"human_db: not starting: {db_path}: another process holds a lock on the database "
            "(SQLite: database is locked) and kept it for the 1 s start-up budget") in output
