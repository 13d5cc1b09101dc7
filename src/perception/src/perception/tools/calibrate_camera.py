"""Measure YOLOv3-tiny, mediapipe pose and the shirt-colour sampling on real photos under the
conditions a home produces (distance, occlusion, lighting) and write the calibration table the
simulated camera takes its errors from (perception.camera_calibration says how).

    source scripts/env.sh && scripts/calibrate_camera [--table config/camera_calibration.yaml]
        [--doc docs/perception/camera_calibration.md]

Photos: Debian's darknet samples, matplotlib's grace_hopper.jpg and the photos scripts/setup
fetches (photos_ultralytics, photos_skimage in config/models.yaml).
"""
import argparse
import sys
import time
from pathlib import Path

import yaml

from perception.camera_calibration import calibrate
from perception.stt import model_cache_root

DARKNET_PHOTOS = Path("/usr/share/darknet/data")
PHOTOS = (   # (where, file): where is "darknet", "matplotlib" or a cache artefact
    ("darknet", "person.jpg"), ("darknet", "kite.jpg"), ("darknet", "dog.jpg"),
    ("darknet", "horses.jpg"), ("darknet", "giraffe.jpg"), ("darknet", "eagle.jpg"),
    ("matplotlib", "grace_hopper.jpg"),
    ("photos_ultralytics", "bus.jpg"), ("photos_ultralytics", "zidane.jpg"),
    ("photos_skimage", "astronaut.png"), ("photos_skimage", "coffee.png"),
    ("photos_skimage", "chelsea.png"), ("photos_skimage", "motorcycle_left.png"),
)
COLUMNS = (("people", "people"), ("miss_rate", "miss"), ("pose_miss_rate", "pose miss"),
           ("box_error", "box err"), ("keypoint_error", "kp err"),
           ("colour_factor", "colour factor RGB"), ("colour_residual", "colour resid."),
           ("false_people_per_image", "false ppl/img"),
           ("false_objects_per_image", "false obj/img"), ("object_miss_rate", "obj miss"),
           ("label_confusion_rate", "label conf."))


def photo_path(where, name):
    if where == "darknet":
        return DARKNET_PHOTOS / name
    if where == "matplotlib":
        import matplotlib
        return Path(matplotlib.get_data_path()) / "sample_data" / name
    return model_cache_root() / where / name


def load_photos():
    """[(name, BGR image)]; a missing photo is an error naming the setup step."""
    import cv2
    photos = []
    for where, name in PHOTOS:
        path = photo_path(where, name)
        image = cv2.imread(str(path)) if path.is_file() else None
        if image is None:
            raise SystemExit(f"calibrate_camera: photo {path} is missing (run scripts/setup)")
        photos.append((name, image))
    return photos


def markdown(table, command):
    """The table as Markdown, one section per factor."""
    lines = ["# Camera calibration: the real detectors under a home's conditions", "",
             "Made by `" + command + "` (perception.camera_calibration says how each figure is "
             "measured). Rates are those each condition adds to what the detectors find in the "
             "clear photo; errors are shares of the person's height; colour factor and residual "
             "are per RGB channel at joints 1, 2, 5; false detections overlap nothing found in "
             "the clear photo.", "",
             f"Photos: {', '.join(table['photos'])}; detector {table['detector']}; pose "
             f"{table['pose']}.", ""]
    for kind, key in (("scale", "person_height_px"), ("occlusion", "hidden_fraction"),
                      ("lighting", "light")):
        lines += [f"## {kind.capitalize()}", "",
                  "| condition | " + key.replace("_", " ") + " | "
                  + " | ".join(title for _, title in COLUMNS) + " |",
                  "|---" * (len(COLUMNS) + 2) + "|"]
        for row in table[kind]:
            cells = [row["name"], row.get(key if kind != "occlusion" else "hidden_fraction")]
            cells += [row.get(field) for field, _ in COLUMNS]
            lines.append("| " + " | ".join("–" if c is None else
                                           ", ".join(f"{v:g}" for v in c) if isinstance(c, list)
                                           else f"{c:g}" if isinstance(c, float) else str(c)
                                           for c in cells) + " |")
        lines.append("")
    for key, what in (("miss_curve", "person height"), ("object_miss_curve",
                                                         "object size (square root of area)")):
        curve = table[key]
        lines += [f"- Miss rate against apparent {what} h [px] (logistic, maximum likelihood, "
                  f"{curve['missed']} missed of {curve['samples']}): 1 / (1 + exp((h - "
                  f"{curve['h50']:g}) / {curve['width']:g}))."]
    lines.append("")
    confusions = {}
    for kind in ("scale", "occlusion", "lighting"):
        for row in table[kind]:
            for key, count in row["confusions"].items():
                confusions[key] = confusions.get(key, 0) + count
    lines += ["## Label confusions (all conditions)", ""]
    lines += [f"- {key}: {count}" for key, count in sorted(confusions.items(),
                                                             key=lambda kv: -kv[1])] or ["- none"]
    return "\n".join(lines) + "\n"


def parse_args(argv=None):
    parser = argparse.ArgumentParser(prog="calibrate_camera", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--table", default="config/camera_calibration.yaml")
    parser.add_argument("--doc", default="docs/perception/camera_calibration.md")
    parser.add_argument("--seed", type=int, default=0)
    return parser.parse_args(argv)


def main(argv=None):
    args = parse_args(argv)
    from perception.detector_registry import make_detector, make_pose_estimator
    models = model_cache_root() / "yolov3_tiny"
    detector = make_detector("darknet", {"cfg": str(models / "yolov3-tiny.cfg"),
                                         "weights": str(models / "yolov3-tiny.weights"),
                                         "names": str(models / "coco.names")})
    pose = make_pose_estimator("mediapipe")
    photos = load_photos()
    start = time.monotonic()

    def progress(done, total):
        if done % 13 == 0 or done == total:
            elapsed = time.monotonic() - start
            eta = elapsed / done * (total - done)
            print(f"[calibrate_camera] {done}/{total} frames, {elapsed:.0f} s, ETA {eta:.0f} s",
                  file=sys.stderr, flush=True)

    table = calibrate(photos, detector, pose, seed=args.seed, progress=progress)
    command = "scripts/calibrate_camera"
    table = {"command": command, "photos": [name for name, _ in photos],
             "detector": "yolov3-tiny (416 px input, confidence 0.25)",
             "pose": "mediapipe pose (model_complexity 1) on each person box", **table}
    Path(args.table).write_text("# Made by scripts/calibrate_camera; read by sim2d's calibrated "
                                "detection model. Do not edit by hand.\n"
                                + yaml.safe_dump(table, sort_keys=False, width=100))
    Path(args.doc).write_text(markdown(table, command))
    print(f"calibrate_camera: wrote {args.table} and {args.doc}")
    return 0
