"""Thesis 000 Sec. 5.2.1 in simulation: a person walks a 1.2 m square whose front edge is 1.5 m in
front of the robot; each frame the person is localised from a noisy depth image (adaptive depth
rectangle + pinhole Eqs. 3-3..3-5 + camera->robot transform). Prints the mean and max error
(seed: 0.28 m / 0.58 m) and writes docs/perception/localisation.png.

    source scripts/env.sh && scripts/eval_localisation [--step 0.05] [--seed 0]

Depth image model: background at --background m, the person a vertical cylinder (radius 0.2 m,
height 1.7 m) whose visible surface depth is the cylinder's front; every pixel gets Gaussian noise
sigma = 0.02 m + 1 % of depth and a --dropout fraction of pixels read 0 (no return).
"""
import argparse
from pathlib import Path

import numpy as np
from perception.localisation import (DepthWindowConfig, Intrinsics, localise_box,
                                     optical_to_map_transform)
from sim2d.camera import CameraConfig, camera_points, project

RADIUS, HEIGHT = 0.2, 1.7        # [m] person cylinder
FRONT, SIDE = 1.5, 1.2           # [m] square front edge distance and side (Sec. 5.2.1)
RING_POINTS = 24                 # points per horizontal ring of the cylinder's outline


def square_path(step):
    """Points [m] along the square x in [FRONT, FRONT+SIDE], y in [-SIDE/2, SIDE/2]."""
    corners = np.array([[FRONT, -SIDE / 2], [FRONT, SIDE / 2], [FRONT + SIDE, SIDE / 2],
                        [FRONT + SIDE, -SIDE / 2], [FRONT, -SIDE / 2]])
    points = []
    for a, b in zip(corners[:-1], corners[1:]):
        n = max(1, int(round(np.linalg.norm(b - a) / step)))
        points += [a + (b - a) * i / n for i in range(n)]
    return np.array(points)


def distance_to_square(p):
    """Euclidean distance [m] from p to the square's outline."""
    x0, x1, y0, y1 = FRONT, FRONT + SIDE, -SIDE / 2, SIDE / 2
    cx, cy = np.clip(p[0], x0, x1), np.clip(p[1], y0, y1)
    if x0 < p[0] < x1 and y0 < p[1] < y1:
        return min(p[0] - x0, x1 - p[0], p[1] - y0, y1 - p[1])
    return float(np.hypot(p[0] - cx, p[1] - cy))


def person_box(person_xy, cam):
    """The person's image box (x0, y0, x1, y1) [px], clipped to the image."""
    angles = np.linspace(0, 2 * np.pi, RING_POINTS, endpoint=False)
    ring = np.column_stack([person_xy[0] + RADIUS * np.cos(angles),
                            person_xy[1] + RADIUS * np.sin(angles)])
    pts = np.vstack([np.column_stack([ring, np.zeros(RING_POINTS)]),
                     np.column_stack([ring, np.full(RING_POINTS, HEIGHT)])])
    u, v, _ = project(camera_points(pts, (0.0, 0.0, 0.0), cam), cam)
    x0, x1 = np.clip([u.min(), u.max()], 0, cam.width - 1).astype(int)
    y0, y1 = np.clip([v.min(), v.max()], 0, cam.height - 1).astype(int)
    return x0, y0, x1, y1


def render(person_xy, cam, background, dropout, rng):
    """Noisy depth image and the person's box (x, y, w, h) [px] for the robot at the origin."""
    x0, y0, x1, y1 = person_box(person_xy, cam)
    depth = np.full((cam.height, cam.width), background)
    cols = np.arange(x0, x1 + 1)
    # surface depth per column: ray x_opt/z = (u - cx)/fx hits the cylinder's front
    centre = camera_points(np.array([[person_xy[0], person_xy[1], cam.mount_height]]),
                           (0.0, 0.0, 0.0), cam)[0]
    slope = (cols - cam.cx) / cam.fx
    # solve |(s z, z) - (cx_c, cz_c)| = R for the nearer z
    a, b = slope ** 2 + 1, -2 * (slope * centre[0] + centre[2])
    c = centre[0] ** 2 + centre[2] ** 2 - RADIUS ** 2
    disc = b ** 2 - 4 * a * c
    hit = disc >= 0
    z = np.where(hit, (-b - np.sqrt(np.maximum(disc, 0))) / (2 * a), background)
    depth[y0:y1 + 1, cols] = z[None, :]
    depth += rng.normal(0.0, 1.0, depth.shape) * (0.02 + 0.01 * depth)
    depth[rng.random(depth.shape) < dropout] = 0.0
    return depth, (x0, y0, x1 - x0, y1 - y0)


def evaluate(step, background, dropout, seed):
    """(truth points, localised points, errors to the truth, errors to the outline) [m]."""
    rng = np.random.default_rng(seed)
    cam = CameraConfig(tilt=0.1)          # Pepper's top camera as in config/worlds/household.yaml
    intr = Intrinsics(cam.fx, cam.fy, cam.cx, cam.cy, cam.width, cam.height)
    to_robot = optical_to_map_transform((0.0, 0.0, 0.0), cam.mount_x, cam.mount_height, cam.tilt)
    truth, found, to_truth, to_outline = square_path(step), [], [], []
    for p in truth:
        depth, box = render(p, cam, background, dropout, rng)
        est = localise_box(depth, box, intr, to_robot, DepthWindowConfig())
        if est is None:
            continue
        found.append(est[:2])
        to_truth.append(float(np.hypot(*(est[:2] - p))))
        to_outline.append(distance_to_square(est[:2]))
    return truth, np.array(found).reshape(-1, 2), to_truth, to_outline


def plot(found, to_outline, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(5, 5))
    sq = square_path(0.01)
    ax.plot(sq[:, 1], sq[:, 0], "g-", label="ground-truth square")
    ax.plot(found[:, 1], found[:, 0], "b.", ms=4, label="localised")
    ax.plot([0], [0], "r^", ms=10, label="robot")
    ax.set_xlabel("y (left) [m]")
    ax.set_ylabel("x (forward) [m]")
    ax.invert_xaxis()
    ax.set_aspect("equal")
    ax.legend(loc="lower right", fontsize=8)
    ax.set_title(f"Sec. 5.2.1 in simulation: mean {np.mean(to_outline):.2f} m, "
                 f"max {np.max(to_outline):.2f} m")
    Path(out).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=100, bbox_inches="tight")
    plt.close(fig)


def parse_args(argv=None):
    parser = argparse.ArgumentParser(prog="eval_localisation", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--step", type=float, default=0.05, help="[m] spacing of path samples")
    parser.add_argument("--background", type=float, default=5.0, help="[m] wall behind the person")
    parser.add_argument("--dropout", type=float, default=0.05, help="fraction of zero pixels")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", default="docs/perception/localisation.png")
    args = parser.parse_args(argv)
    if not 0 < args.step <= SIDE:
        parser.error(f"--step must be in (0, {SIDE}] m; got {args.step}")
    if not args.background > FRONT + SIDE + RADIUS:
        parser.error(f"--background must be behind the square (> {FRONT + SIDE + RADIUS} m); "
                     f"got {args.background}")
    if not 0 <= args.dropout < 1:
        parser.error(f"--dropout must be in [0, 1); got {args.dropout}")
    return args


def main(argv=None):
    args = parse_args(argv)
    truth, found, to_truth, to_outline = evaluate(args.step, args.background, args.dropout,
                                                  args.seed)
    print(f"frames {len(truth)}, localised {len(found)}")
    if not to_truth:
        print("no frame was localised")
        return 1
    print(f"error to the true position: mean {np.mean(to_truth):.3f} m, "
          f"max {np.max(to_truth):.3f} m")
    print(f"error to the square outline: mean {np.mean(to_outline):.3f} m, "
          f"max {np.max(to_outline):.3f} m   (seed Sec. 5.2.1: 0.28 m / 0.58 m)")
    plot(found, to_outline, args.out)
    print(f"wrote {args.out}")
    return 0
