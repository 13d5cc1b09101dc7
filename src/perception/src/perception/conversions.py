"""tamp_msgs messages <-> perception's verbal core types."""
import rospy
from tamp_msgs.msg import Utterance

from perception.stt import pcm16_to_float, resample
from perception.verbal_instructions import Person


def person_from_msg(msg):
    """tamp_msgs/Human -> Person (name, phone IP, last known place)."""
    return Person(name=msg.name, ip=msg.ip, location=msg.location)


def utterance_to_msg(text, ip, stamp=None):
    msg = Utterance(text=text, ip=ip)
    msg.header.stamp = stamp if stamp is not None else rospy.Time.now()
    return msg


def utterance_time(msg):
    """When the utterance was spoken [s]; now when the sender left the stamp at 0."""
    return rospy.get_time() if msg.header.stamp.is_zero() else msg.header.stamp.to_sec()


def audio_from_msg(msg):
    """tamp_msgs/AudioUtterance -> float32 mono at 16 kHz (raises AudioError on a bad rate)."""
    return resample(pcm16_to_float(msg.samples), msg.sample_rate)

