"""Latency of the visual perception per frame (issue 7). Prints p50, p99 and max of each stage;
nothing is asserted.

    source scripts/env.sh && scripts/bench_visual [--repeats 50]

heuristics: analyse_frame (Algorithm 3-2, Eqs. 3-11..3-13, posture, localisation) on a simulator
frame with 5 people and 30 objects, with the cameras at the robot's pose as the visual node has
them (the joints and the objects' boxes in the map); yolov3-tiny: cv2.dnn Darknet on darknet's
person.jpg (416x416 input); mediapipe: solutions.pose (model_complexity=1) on the same photo;
stitch: two 640x480 images.
"""
import argparse

import cv2
import numpy as np
from perception.activity import ActivityConfig, load_affordances
from perception.detectors import DarknetConfig, DarknetDetector, MediapipePose, stitch
from perception.stt import model_cache_root
from perception.visual_pipeline import FrameView, ObjectBox, analyse_frame
from supervision.latency import summarise, time_calls_ms
from tamp_resources import resource

from tamp_bringup.sim_activity_set import (ROBOT_POSE, SCENES, make_camera, scene_frame,
                                           stacked_cameras)

PHOTO = "/usr/share/darknet/data/person.jpg"   # Debian's darknet package
OBJECT_LABELS = ["cup", "book", "tv", "bowl", "chair", "bottle", "remote", "laptop"]


def timed(fn, repeats):
    """LatencySummary [ms] of `repeats` calls after one warm-up call."""
    return summarise(time_calls_ms(fn, repeats, warmup=1))


def latency_line(what, figures, digits):
    return (f"{what}: p50 {figures.p50:.{digits}f} ms, p99 {figures.p99:.{digits}f} ms, "
            f"max {figures.max:.{digits}f} ms")


def crowded_frame(people, objects, seed):
    """people simulator persons side by side plus random COCO objects, `objects` boxes in all."""
    camera = make_camera({"miss_probability": 0.0}, seed)
    frame = FrameView(*camera.frame_size)
    for i, scene in enumerate(SCENES[:people]):
        one = scene_frame(scene, camera, 2.0 + 0.3 * i, -0.4 + 0.2 * i, 0.5)
        frame.people += one.people
        frame.objects += one.objects
    rng = np.random.default_rng(seed)
    while len(frame.objects) < objects:
        x, y = rng.uniform(0, 600), rng.uniform(0, 900)
        frame.objects.append(ObjectBox(str(rng.choice(OBJECT_LABELS)), 0.8, x, y, 40, 40, 2.5))
    return frame


def bench_heuristics(repeats, people=5, objects=30):
    """The frame and the latency line of analyse_frame on a crowded simulator frame."""
    table = load_affordances(resource("config", "affordances.yaml"))
    frame = crowded_frame(people, objects, seed=0)
    cameras = stacked_cameras(make_camera({"miss_probability": 0.0}, 0), ROBOT_POSE)
    figures = timed(lambda: analyse_frame(frame, table, ActivityConfig(), cameras), repeats)
    return frame, latency_line(f"heuristics ({people} people, {objects} objects)", figures, 2)


def bench_stitch(image, repeats):
    """(stitched frame, latency line) of stitching two copies of a 640x480 image."""
    top = cv2.resize(image, (640, 480))
    figures = timed(lambda: stitch(top, top), repeats)
    return stitch(top, top), latency_line("stitch 2 x 640x480", figures, 3)


def bench_models(stitched, repeats):
    """Latency lines of yolov3-tiny and mediapipe pose on the stitched frame."""
    models = model_cache_root() / "yolov3_tiny"
    yolo = DarknetDetector(DarknetConfig(str(models / "yolov3-tiny.cfg"),
                                         str(models / "yolov3-tiny.weights"),
                                         str(models / "coco.names")))
    lines = [latency_line("yolov3-tiny on a stitched 640x960 frame",
                          timed(lambda: yolo.detect(stitched), repeats), 1)]
    pose = MediapipePose()
    try:
        lines.append(latency_line("mediapipe pose on a stitched 640x960 frame",
                                  timed(lambda: pose.skeletons(stitched), repeats), 1))
    finally:
        pose.close()
    return lines


def parse_args(argv=None):
    parser = argparse.ArgumentParser(prog="bench_visual", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeats", type=int, default=50)
    args = parser.parse_args(argv)
    if args.repeats < 1:
        parser.error(f"--repeats must be at least 1; got {args.repeats}")
    return args


def main(argv=None):
    args = parse_args(argv)
    frame, line = bench_heuristics(args.repeats)
    print(f"frame: {len(frame.people)} people, {len(frame.objects)} objects")
    print(line)
    image = cv2.imread(PHOTO)
    if image is None:
        raise SystemExit(f"bench_visual: cannot read {PHOTO}: install Debian's darknet package "
                         "(scripts/setup does)")
    stitched, line = bench_stitch(image, args.repeats)
    print(line)
    for line in bench_models(stitched, max(5, args.repeats // 5)):
        print(line)
    return 0
