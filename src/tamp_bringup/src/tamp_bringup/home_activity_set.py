"""The household's people as the robot's camera sees them: every person of a world file at given
times, watched from a ring of viewpoints around them (each a few seconds of frames at the camera's
rate) with the world's own detection model (the calibrated one for the household). Ground truth
labels each sequence with the activity the world file has the person do. Used by
scripts/eval_activity_home to measure the visual pipeline framewise and fused over frames
(perception.activity_track) where the home's furniture, lighting and detectors make it hard.
"""
import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass

from perception.visual_pipeline import FrameView, StackedCameras
from sim2d.world import World
from sim2d.world_config import WorldError

from tamp_bringup.sim_activity_set import object_box, person_view, stacked_cameras

STEP_S = 0.5    # [s] people are moved along their schedules in steps this long


@dataclass
class Viewing:
    """One viewpoint's frames of one person: who, what they do, from where, and the frames."""

    person: str
    activity: str
    robot_pose: tuple
    frames: list          # [(FrameView, [person name or "" per PersonView])]
    cameras: StackedCameras   # the robot's cameras at robot_pose



def frame_view(camera_frame) -> tuple[FrameView, list[str]]:
    """sim2d CameraFrame -> (FrameView, the true name of each PersonView)."""
    view = FrameView(camera_frame.width, camera_frame.height,
                     [object_box(o) for o in camera_frame.objects],
                     [person_view(s) for s in camera_frame.skeletons])
    return view, [s.truth for s in camera_frame.skeletons]


def ring(centre: Sequence[float], distances: Sequence[float], bearings: int) -> Iterator[tuple]:
    """Robot poses on circles around `centre`, each facing it."""
    x0, y0 = centre[:2]
    for distance in distances:
        for k in range(bearings):
            angle = 2.0 * math.pi * k / bearings
            x, y = x0 + distance * math.cos(angle), y0 + distance * math.sin(angle)
            yield (x, y, math.atan2(y0 - y, x0 - x))


def viewings(world_file: str, times: Sequence[float], distances: Sequence[float] = (1.2, 1.8, 2.5),
             bearings: int = 8, frames: int = 25) -> Iterator[Viewing]:
    """Every person at every time of `times` [s], from every ring pose the robot can stand on
    and from which the person is in its camera's line of sight; `frames` frames each."""
    for time in sorted(times):
        world = World.from_file(world_file)
        robot = world.robots[0]
        while world.time < time:
            world.step(STEP_S)
        for person in world.people:
            for pose in ring(person.pose, distances, bearings):
                try:
                    world.place_robot(robot.name, pose)
                except WorldError:
                    continue                       # in a wall or in the furniture
                if not robot.camera.in_line_of_sight(pose, [person.pose[:2]])[0]:
                    continue
                seen = [frame_view(world.camera_frame(robot.name)) for _ in range(frames)]
                yield Viewing(person.name, person.activity, pose, seen,
                              stacked_cameras(robot.camera, pose))
