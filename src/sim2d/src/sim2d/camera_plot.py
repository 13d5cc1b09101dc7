"""Plot a simulated camera frame: boxes with class, confidence and depth, COCO-18 skeletons."""
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from sim2d.camera import CameraFrame  # noqa: E402

# OpenPose COCO-18 limbs (keypoint index pairs) for drawing skeletons
LIMBS = ((1, 2), (2, 3), (3, 4), (1, 5), (5, 6), (6, 7), (1, 8), (8, 9), (9, 10), (1, 11),
         (11, 12), (12, 13), (1, 0), (0, 14), (14, 16), (0, 15), (15, 17))


def plot_camera_frame(frame: CameraFrame, title: str = "",
                      out_path: str | Path | None = None) -> Figure:
    """Draw a camera frame's detections: boxes with class and confidence, skeleton limbs,
    keypoints coloured by the shirt colour read at joints 1, 2, 5."""
    fig, ax = plt.subplots(figsize=(5.0, 5.0 * frame.height / frame.width + 0.4))
    ax.set_xlim(0, frame.width)
    ax.set_ylim(frame.height, 0)
    ax.axhline(frame.height / 2, color="grey", lw=0.6, ls=":")   # top | bottom camera seam
    for det in frame.objects:
        ax.add_patch(plt.Rectangle((det.x, det.y), det.width, det.height, fill=False,
                                   color="tab:orange", lw=1.0))
        ax.text(det.x, det.y - 3, f"{det.label} {det.confidence:.2f} {det.depth:.1f}m",
                fontsize=6, color="tab:orange")
    for sk in frame.skeletons:
        seen = sk.confidence > 0
        colour = sk.joint_colours[0] / 255.0 if seen[1] else (0.2, 0.2, 0.2)
        for a, b in LIMBS:
            if seen[a] and seen[b]:
                ax.plot([sk.x[a], sk.x[b]], [sk.y[a], sk.y[b]], color=colour, lw=1.5)
        ax.plot(sk.x[seen], sk.y[seen], "o", color=colour, ms=2.5)
    ax.set_title(title, fontsize=8)
    ax.set_xlabel("u [px]")
    ax.set_ylabel("v [px] (top camera above bottom camera)")
    fig.tight_layout()
    if out_path is not None:
        fig.savefig(out_path, dpi=110)
    plt.close(fig)
    return fig
