"""task_planner.conversions: what the executor takes from visual perception's analysed frames."""
import genpy
from tamp_msgs.msg import ObservedHuman, ObservedHumanArray

from task_planner.conversions import sightings_from_observed

NAMES = ["charging_place", "office", "bedroom"]


def test_an_analysed_frame_gives_its_stamp_and_the_identified_people_at_places():
    frame = ObservedHumanArray(humans=[
        ObservedHuman(name="Alice", localised=True, location="office", x=1.0, y=2.0),
        ObservedHuman(name="", localised=True, location="office"),          # not identified
        ObservedHuman(name="", localised=True, location="bedroom",          # nor in a whole
                      shirt_color=bytes([90, 20, 30] * 3)),                 # shirt
        ObservedHuman(name="Bob", localised=False, location="bedroom"),     # no depth
        ObservedHuman(name="Carol", localised=True, location=""),           # between places
    ])
    frame.header.stamp = genpy.Time.from_sec(12.5)
    frame.humans[1].x, frame.humans[1].y = 1.5, 2.5
    assert sightings_from_observed(frame, NAMES) == (
        12.5, [("Alice", 1, 1.0, 2.0)], [(1, 1.5, 2.5, False), (2, 0.0, 0.0, True)])
    empty = ObservedHumanArray()
    empty.header.stamp = genpy.Time.from_sec(13.0)
    assert sightings_from_observed(empty, NAMES) == (13.0, [], [])   # still a frame analysed
