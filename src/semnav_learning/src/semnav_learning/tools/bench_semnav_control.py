"""Latency of one semantic_nav control step (DirectionFollower.step) on real sim2d scans of both
lasers along a corridor of office_ring, with its parts (closing doorways, the collision guard and
its worst case) and one step of the Keras model for comparison: scripts/bench_semnav_control."""
import argparse
import sys
import time

import numpy as np

from semantic_nav.collision_guard import guard_velocity, scan_points, steer_around
from semantic_nav.doorways import close_doorways
from semantic_nav.follower import DirectionFollower, ModelMissingError, model_file
from semnav_learning.demonstrations import world_for_floor
from semnav_learning.episodes import sim_laser_model
from semnav_learning.evaluation_run import laser_templates
from tamp_resources import resource

FLOOR = ("maps", "office_ring.yaml")       # of tamp_resources
SENTENCE = "go straight to the end, then turn left"
CORRIDOR = (6.0, 24.0, 5.0)                # x from, x to, y of office_ring's south corridor [m]
WALL_GAP = 0.36                            # [m] ahead in the guard's worst case (reach 0.35 m)
PLACES = 200                               # scans cast along the corridor, then repeated
KERAS_CALLS, WORST_CASE_CALLS = 100, 200   # timed calls of those parts (fewer in a short run)


def argument_parser(description=None):
    """The options of bench_semnav_control."""
    parser = argparse.ArgumentParser(description=description,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--model", help="model file (default: the follower's default)")
    parser.add_argument("--untrained", action="store_true")
    parser.add_argument("--steps", type=int, default=2000,
                        help="control steps per laser; also caps the timed Keras steps and "
                             "guard worst cases, and a run of fewer than 200 marches the "
                             "UTM-30LX's rays instead of using its range table")
    return parser


def keras_model(model_path, untrained):
    """The Keras network: freshly built (untrained) or loaded; ModelMissingError if absent."""
    from semantic_nav.network import build_network, load_network
    return build_network() if untrained else load_network(str(model_file(model_path)))


def follower(model):
    """A DirectionFollower on the numpy single-step twin of `model`, default GloVe vectors."""
    from semantic_nav.network import StepPolicy
    from semantic_nav.word_vectors import load_word_vectors
    return DirectionFollower(StepPolicy.from_keras(model), load_word_vectors(None))


def call_ms(function, calls):
    """Wall time of each of `calls` calls of `function` [ms] (an array)."""
    times = []
    for _ in range(calls):
        began = time.perf_counter()
        function()
        times.append(time.perf_counter() - began)
    return 1e3 * np.array(times)


def spread(ms):
    """"p50 X ms, p99 Y ms" of call times [ms]."""
    return f"p50 {np.percentile(ms, 50):.3f} ms, p99 {np.percentile(ms, 99):.3f} ms"


def scans(template, floor, count, raycast, places=PLACES):
    """`count` sim2d scans along the south ring corridor (at most `places` places, repeated)
    -> (scans, the laser's model)."""
    world = world_for_floor(template, floor, raycast=raycast)
    robot = world.robots[0]
    x_from, x_to, y = CORRIDOR
    out = [robot.lasers[0].scan((float(x), y, 0.0)) for x in np.linspace(x_from, x_to,
                                                                          min(count, places))]
    return [out[i % len(out)] for i in range(count)], sim_laser_model(robot)


def blocked_scan(templates, floor, laser_name):
    """One scan facing a wall WALL_GAP ahead (north from the ring corridor): the guard's
    footprint reach is 0.35 m, so every arc is blocked at its first checked pose. The wall is
    found with the UTM-30LX (30 m range; the URG-04LX reaches 5.6 m)."""
    lasers = {name: world_for_floor(templates[name], floor, raycast="march").robots[0].lasers[0]
              for name in {"utm30lx", laser_name}}
    x, y = 15.0, CORRIDOR[2]
    ahead = lasers["utm30lx"].scan((x, y, np.pi / 2))
    front = float(ahead[len(ahead) // 2])
    return lasers[laser_name].scan((x, y + front - WALL_GAP, np.pi / 2))


def step_times_ms(policy, ranges, laser):
    """Wall time of each control step over `ranges` [ms], restarting the sentence when done."""
    policy.start(SENTENCE)
    times = []
    for r in ranges:
        began = time.perf_counter()
        policy.step(r, laser)
        times.append(time.perf_counter() - began)
        if policy.done:
            policy.start(SENTENCE)
    return np.array(times) * 1e3


def bench_laser(policy, laser_name, templates, floor, steps):
    """Print the control step's latency on one laser and its parts. The UTM-30LX scans come
    from sim2d's range table as in the simulator, but a short run (fewer steps than PLACES)
    marches its few rays: building office_ring's table takes about a minute on a new machine."""
    table = laser_name == "utm30lx" and steps >= PLACES
    ranges, laser = scans(templates[laser_name], floor, steps, "table" if table else "march")
    ms = step_times_ms(policy, ranges, laser)
    print(f"{laser_name} ({laser.beams} beams): control step {spread(ms)}, "
          f"max {ms.max():.3f} ms over {len(ms)} steps "
          f"(budget {policy.control_period * 1e3:.0f} ms)")
    cycle = iter(ranges)
    doors = call_ms(lambda: close_doorways(next(cycle), laser, policy.config.doors),
                    len(ranges))
    print(f"  of which closing the doorways: {spread(doors)}")
    cycle = iter(ranges)
    guard = call_ms(lambda: guard_velocity(0.4, 0.5, scan_points(next(cycle), laser)),
                    len(ranges))
    print(f"  of which the collision guard (v 0.4 m/s, ω 0.5 rad/s): {spread(guard)}")
    wall = blocked_scan(templates, floor, laser_name)
    v_move = policy.config.postprocess.v_move
    steered = call_ms(lambda: steer_around(0.4, 0.0, scan_points(wall, laser), v_move,
                                           policy.config.guard, 0.5),
                      min(WORST_CASE_CALLS, steps))
    print(f"  the guard's worst case (a wall 0.36 m ahead, every arc tried on the base's "
          f"path from ω 0.5 rad/s): {spread(steered)}")


def keras_step_ms(model, calls=KERAS_CALLS):
    """Times of one Keras step (words + one scan, no state kept) [ms]."""
    from semantic_nav.network import CORNER_CLASSES, has_count_input
    rng = np.random.default_rng(0)
    inputs = {"words": rng.normal(size=(1, 6, 50)).astype(np.float32),
              "scans": rng.random((1, 1, 881)).astype(np.float32)}
    if has_count_input(model):      # the corner count (corner_count.CornerCounter): 0 here
        inputs["counts"] = np.eye(CORNER_CLASSES, dtype=np.float32)[[[0]]]
    return call_ms(lambda: model.predict_on_batch(inputs), calls)


def main(argv=None, description=None):
    """Parse, measure, print -> exit status 0 (no model file: exits naming --untrained)."""
    args = argument_parser(description).parse_args(argv)
    try:
        model = keras_model(args.model, args.untrained)
    except ModelMissingError as error:
        sys.exit(f"bench_semnav_control: {error}, or pass --untrained")
    policy = follower(model)
    name = "untrained network (same shape)" if args.untrained else args.model or "default"
    print(f"model: {name}")
    templates, floor = laser_templates(), resource(*FLOOR)
    for laser_name in ("utm30lx", "urg04lx"):
        bench_laser(policy, laser_name, templates, floor, args.steps)
    keras = keras_step_ms(model, min(KERAS_CALLS, args.steps))
    print(f"Keras model, one step (words + one scan, no state kept): {spread(keras)}")
    began = time.perf_counter()
    policy.start(SENTENCE)
    print(f"start(sentence): {1e3 * (time.perf_counter() - began):.2f} ms (split, GloVe, LSTM_w)")
    return 0
