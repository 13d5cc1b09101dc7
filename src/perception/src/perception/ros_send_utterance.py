"""Command-line tool: publish one tamp_msgs/Utterance on /voice_message, as the phone app does."""
import argparse

import rospy
from tamp_msgs.msg import Utterance

from task_planner.ros_oneshot import publish_when_heard

from perception.conversions import utterance_to_msg


def parse_args(argv):
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("text", help="the sentence, e.g. 'Chat with me, I feel bad.'")
    parser.add_argument("--ip", default="", help="IP of the sender's phone (identifies them)")
    parser.add_argument("--wait", type=float, default=5.0,
                        help="wall-clock seconds to wait for a subscriber before giving up")
    return parser.parse_args(argv)


def main(argv):
    args = parse_args(argv)
    rospy.init_node("send_utterance", anonymous=True)
    publisher = rospy.Publisher("voice_message", Utterance, queue_size=1, latch=True)
    if not publish_when_heard(publisher, utterance_to_msg(args.text, args.ip), args.wait):
        rospy.logerr("not sent: nobody subscribes to /voice_message after %.1f s", args.wait)
        return 1
    rospy.loginfo("sent %d characters from %s", len(args.text), args.ip or "no IP")
    return 0
