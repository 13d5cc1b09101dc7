"""Navigating records in rosbags: the topics recorded and the export to recording sequences."""
import rosbag

from penguin_base.recording import SequenceBuilder

DEFAULT_TOPICS = {"scan": "/scan", "cmd_vel": "/cmd_vel", "odom": "/odom",
                  "instruction_class": "/instruction_class"}


class BagExportError(ValueError):
    """A bag that holds no usable navigating record."""


def sequences_from_bag(path, velocity_source="odom", topics=None):
    """Read a recorder bag and return its RecordSequences (thesis 002 §3.3.1) and the builder.

    Messages are taken in bag-time order; each /scan inside a sequence is one sample.
    """
    topics = {**DEFAULT_TOPICS, **(topics or {})}
    builder = SequenceBuilder(velocity_source)
    try:
        bag = rosbag.Bag(str(path))
    except (OSError, rosbag.ROSBagException) as error:
        raise BagExportError(f"cannot read bag {path}: {error}") from None
    with bag:
        for topic, msg, _stamp in bag.read_messages(topics=list(topics.values())):
            _feed(builder, topics, topic, msg)
    sequences = builder.finish()
    if not sequences:
        raise BagExportError(f"{path}: no recording sequence (no {topics['instruction_class']} "
                             "message with a class 1..10)")
    return sequences, builder


def _feed(builder, topics, topic, msg):
    if topic == topics["instruction_class"]:
        builder.on_instruction_class(msg.data)
    elif topic == topics["scan"]:
        builder.on_scan(msg.ranges)
    elif topic == topics["cmd_vel"]:
        builder.on_velocity("cmd_vel", msg.linear.x, msg.angular.z)
    elif topic == topics["odom"]:
        builder.on_velocity("odom", msg.twist.twist.linear.x, msg.twist.twist.angular.z)
