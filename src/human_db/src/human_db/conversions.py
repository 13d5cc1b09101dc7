"""tamp_msgs/Human, Schedule <-> human_db.model.Human, ScheduleEntry."""
import rospy
from tamp_msgs.msg import Human as HumanMsg
from tamp_msgs.msg import Schedule as ScheduleMsg

from human_db.model import Human, ScheduleEntry


def schedule_to_msg(entry):
    return ScheduleMsg(start=entry.start, end=entry.end, place=entry.place,
                       activity=entry.activity)


def schedule_from_msg(msg):
    """Raises InvalidHuman naming the offending entry."""
    return ScheduleEntry(start=msg.start, end=msg.end, place=msg.place, activity=msg.activity)


def colours_to_msg(shirt_colour):
    """((r, g, b) x 3 joints) -> the 9 uint8 values r1 g1 b1 r2 g2 b2 r5 g5 b5."""
    return [int(channel) for joint in shirt_colour for channel in joint]


def colours_from_msg(field):
    """A uint8[9] field (bytes or list, as genpy hands it over) -> 3 x (r, g, b)."""
    values = list(field)
    return tuple(tuple(values[i:i + 3]) for i in range(0, len(values), 3))


def stamp_or_none(stamp):
    """rospy.Time -> seconds, with 0 (never / not given) -> None."""
    return None if stamp.is_zero() else stamp.to_sec()


def human_to_msg(human):
    return HumanMsg(
        name=human.name, ip=human.ip, gender=human.gender == "male", age=human.age,
        shirt_color=colours_to_msg(human.shirt_colour or ((0, 0, 0),) * 3),
        shirt_known=human.shirt_colour is not None, location=human.location,
        activity=human.activity, schedules=[schedule_to_msg(e) for e in human.schedules],
        last_seen=rospy.Time(0) if human.last_seen is None else rospy.Time.from_sec(
            human.last_seen))


def human_from_msg(msg):
    """Raises InvalidHuman naming the offending field."""
    return Human(
        name=msg.name, ip=msg.ip, gender="male" if msg.gender else "female", age=int(msg.age),
        shirt_colour=colours_from_msg(msg.shirt_color) if msg.shirt_known else None,
        location=msg.location,
        activity=msg.activity, schedules=tuple(schedule_from_msg(s) for s in msg.schedules),
        last_seen=stamp_or_none(msg.last_seen))
