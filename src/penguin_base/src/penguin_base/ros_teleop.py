"""ROS node `teleop`: the five-key teleoperation program (thesis 002 §3.3.2) on /cmd_vel."""
import signal
import time
from dataclasses import dataclass, field

import rospy
from geometry_msgs.msg import Twist
from std_msgs.msg import UInt8
from supervision.ros_params import config_from_params

from penguin_base.config import ConfigError, TeleopConfig
from penguin_base.conversions import twist_msg
from penguin_base.teleop import TeleopState
from penguin_base.teleop_terminal import run_teleop

FLUSH_DELAY = 0.3  # [s] let the final zero command reach the subscribers before exiting


@dataclass(frozen=True)
class TeleopParams:
    teleop: dict = field(default_factory=dict)   # TeleopConfig's fields (config/penguin.yaml)


def _raise_interrupt(_signum, _frame):
    raise KeyboardInterrupt


def main():
    rospy.init_node("teleop", disable_signals=True)
    signal.signal(signal.SIGTERM, _raise_interrupt)
    try:
        config = TeleopConfig.from_dict(config_from_params(TeleopParams).teleop)
    except (ConfigError, ValueError) as error:
        rospy.logfatal("teleop: bad configuration: %s", error)
        return 2
    cmd_pub = rospy.Publisher("cmd_vel", Twist, queue_size=1)
    # latched: a class key pressed before the recorder connected still reaches it
    class_pub = rospy.Publisher("instruction_class", UInt8, queue_size=5, latch=True)

    def publish(v, omega):
        cmd_pub.publish(twist_msg(v, omega))

    def announce_class(instruction_class):
        class_pub.publish(UInt8(data=instruction_class))

    try:
        run_teleop(TeleopState(config), publish, time.monotonic,
                   lambda: not rospy.is_shutdown(), announce_class)
    finally:
        publish(0.0, 0.0)  # run_teleop published zero already; a second one costs nothing
        time.sleep(FLUSH_DELAY)
        rospy.signal_shutdown("teleop exiting")
    return 0
