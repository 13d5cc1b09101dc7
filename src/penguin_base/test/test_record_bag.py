"""Recording -> export -> import round trip through a real rosbag file (no roscore needed)."""
import math
import random
import struct

import rosbag
import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import LaserScan
from std_msgs.msg import UInt8

from penguin_base.record_format import RecordSequence, Sample, read_records
from penguin_base.tools.ros_records import main as records_main


def as_float32(value):
    return struct.unpack("<f", struct.pack("<f", value))[0]


def write_demo_bag(path, rng):
    """A bag as the recorder writes it: two sequences, velocities at 50 Hz, scans at 40 Hz."""
    expected = {"odom": [], "cmd_vel": []}
    latest = {}
    t = 10.0
    with rosbag.Bag(str(path), "w") as bag:
        def write(topic, msg):
            bag.write(topic, msg, rospy.Time.from_sec(t))

        for instruction_class in (3, 7):
            write("/instruction_class", UInt8(data=instruction_class))
            for source in expected:
                expected[source].append(RecordSequence(instruction_class, []))
            for step in range(200):
                t += 0.005
                if step % 4 == 0:
                    v, w = rng.uniform(0, 0.4), rng.uniform(-1, 1)
                    cmd = Twist()
                    cmd.linear.x, cmd.angular.z = v, w
                    write("/cmd_vel", cmd)
                    latest["cmd_vel"] = (v, w)
                    odom = Odometry()
                    odom.twist.twist.linear.x, odom.twist.twist.angular.z = 0.9 * v, 0.9 * w
                    write("/odom", odom)
                    latest["odom"] = (0.9 * v, 0.9 * w)
                if step % 5 == 0:
                    ranges = [rng.uniform(0.1, 30.0) for _ in range(1081)]
                    ranges[7] = math.inf
                    write("/scan", LaserScan(ranges=ranges))
                    stored = tuple(as_float32(r) for r in ranges)  # LaserScan carries float32
                    for source in expected:
                        expected[source][-1].samples.append(Sample(*latest[source], stored))
            write("/instruction_class", UInt8(data=0))
            t += 1.0
            write("/scan", LaserScan(ranges=[1.0] * 1081))  # between sequences: not a sample
            t += 1.0
    return expected


def test_bag_export_import_preserves_every_sample(tmp_path, capsys):
    bag = tmp_path / "demo.bag"
    expected = write_demo_bag(bag, random.Random(4))
    for source in ("odom", "cmd_vel"):
        out = tmp_path / f"demo_{source}.txt"
        assert records_main(["export", str(bag), str(out), "--velocity-source", source]) == 0
        imported = read_records(out)
        assert [len(s.samples) for s in imported] == [40, 40]
        assert imported == expected[source]
    assert records_main(["check", str(tmp_path / "demo_odom.txt")]) == 0
    assert "sequence 2: class 7, 40 samples, 1081 ranges each" in capsys.readouterr().out


def test_export_of_a_bag_without_sequences_is_a_clear_error(tmp_path, capsys):
    bag = tmp_path / "empty.bag"
    with rosbag.Bag(str(bag), "w") as writer:
        writer.write("/scan", LaserScan(ranges=[1.0]), rospy.Time.from_sec(1.0))
    assert records_main(["export", str(bag), str(tmp_path / "out.txt")]) == 1
    assert "no recording sequence" in capsys.readouterr().err


def test_check_reports_a_malformed_file_with_its_line(tmp_path, capsys):
    path = tmp_path / "bad.txt"
    path.write_text("R;2\n0.1;0.0;1.0\n0.1;0.0;x\nSTOP\n")
    assert records_main(["check", str(path)]) == 1
    assert f"{path}:3: field 3 is not a number: 'x'" in capsys.readouterr().err
