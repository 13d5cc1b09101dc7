"""Activity recognition on the household's own people (home_activity_set): each person of a
world file at the given times, watched from a ring of viewpoints (3 distances x 8 bearings,
5 s of frames at 5 Hz each) with the world's detection model (the household's: calibrated against
YOLOv3-tiny and mediapipe). Per true activity: frames in which the person was detected, the share
read right frame by frame (thesis 000 Sec. 3.2.4) and fused over the frames of the last
`--window` seconds (perception.activity_track, as the visual node publishes for identified
people). Writes docs/perception/activity_home.md.

    source scripts/env.sh && scripts/eval_activity_home [--world config/worlds/household_day.yaml]
        [--times 60,300] [--window 8]
"""
import argparse
import time
from collections import Counter, defaultdict
from pathlib import Path

from perception.activity import ActivityConfig, load_affordances
from perception.activity_track import ActivityTrackConfig, ActivityTracks
from perception.visual_pipeline import analyse_frame
from tamp_resources import resource, workspace

from tamp_bringup.home_activity_set import viewings

FRAME_S = 0.2    # [s] between frames (the household camera's 5 Hz)


def evaluate(world_file, times, window_s, report=print):
    """({true activity: Counter(framewise reading)}, {true activity: Counter(fused reading)},
    viewpoints) over every viewing."""
    table, config = load_affordances(resource("config", "affordances.yaml")), ActivityConfig()
    framewise, fused = defaultdict(Counter), defaultdict(Counter)
    started, count = time.perf_counter(), 0
    for viewing in viewings(world_file, times):
        tracks = ActivityTracks(ActivityTrackConfig(window_s=window_s))
        for k, (frame, names) in enumerate(viewing.frames):
            for result, name in zip(analyse_frame(frame, table, config, viewing.cameras),
                                    names):
                if name != viewing.person:
                    continue
                act = result.activity
                framewise[viewing.activity][act.activity] += 1
                fused[viewing.activity][tracks.update(name, k * FRAME_S, "here", act.activity,
                                                      act.probabilities, act.posture,
                                                      act.holding)] += 1
        count += 1
        if count % 20 == 0:
            report(f"  {count} viewpoints, {time.perf_counter() - started:.0f} s")
    return framewise, fused, count


def table_lines(framewise, fused, window_s):
    lines = ["| true activity | frames | framewise | fused over "
             f"{window_s:g} s | fused: read instead (frames) |", "|---|---|---|---|---|"]
    for activity in sorted(framewise, key=lambda a: -sum(framewise[a].values())):
        n = sum(framewise[activity].values())
        wrong = ", ".join(f"{k} ({v})" for k, v in fused[activity].most_common()
                          if k != activity)
        lines.append(f"| {activity} | {n} | {framewise[activity][activity] / n:.2f} | "
                     f"{fused[activity][activity] / n:.2f} | {wrong} |")
    return lines


def parse_args(argv=None):
    parser = argparse.ArgumentParser(prog="eval_activity_home", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--world", default="config/worlds/household_day.yaml")
    parser.add_argument("--times", default="60,300",
                        help="comma-separated simulated times [s] at which people are watched")
    parser.add_argument("--window", type=float, default=ActivityTrackConfig.window_s,
                        help="[s] fusion window (0: framewise)")
    parser.add_argument("--out", default=str(workspace() / "docs" / "perception"
                                             / "activity_home.md"))
    args = parser.parse_args(argv)
    try:
        args.times = [float(t) for t in args.times.split(",")]
    except ValueError:
        parser.error(f"--times must be comma-separated seconds; got {args.times!r}")
    if any(t < 0 for t in args.times) or args.window < 0:
        parser.error("--times and --window must not be negative")
    if not Path(args.world).is_file():
        parser.error(f"--world {args.world}: no such file")
    return args


def main(argv=None):
    args = parse_args(argv)
    command = (f"scripts/eval_activity_home --world {args.world} --times "
               f"{','.join(f'{t:g}' for t in args.times)} --window {args.window:g}")
    framewise, fused, count = evaluate(args.world, args.times, args.window)
    lines = table_lines(framewise, fused, args.window)
    text = ["# Activity recognition on the household's people", "",
            f"Written by `{command}`: every person of the world at each time, from {count} "
            "viewpoints in all (rings of 1.2, 1.8 and 2.5 m around them, 8 bearings, each facing "
            "them, where the robot can stand and the person is in its line of sight), 25 frames "
            "(5 s) each, with the world's detection model. Frames in which the detector found "
            "the person; framewise: the seed's reading of each frame; fused: the visual node's "
            "reading for an identified person (perception.activity_track).", ""] + lines + [""]
    Path(args.out).write_text("\n".join(text))
    print("\n".join(lines))
    print(f"wrote {args.out}")
    return 0
