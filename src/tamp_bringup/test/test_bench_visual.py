"""scripts/bench_visual's library: the crowded frame, latency lines, arguments (no models)."""
import numpy as np
import pytest

from supervision.latency import summarise
from tamp_bringup.tools import bench_visual as bench


def test_crowded_frame_fills_up_to_the_object_count():
    frame = bench.crowded_frame(3, 25, seed=0)
    assert len(frame.objects) == 25
    assert len(frame.people) >= 3              # a conversation scene brings its partner
    extra = frame.objects[-1]
    assert extra.label in bench.OBJECT_LABELS and (extra.width, extra.height) == (40, 40)


def test_latency_line_names_p50_p99_and_max():
    figures = summarise([1.0, 2.0, 3.0, 10.0])
    assert bench.latency_line("stage", figures, 1) == (
        f"stage: p50 2.5 ms, p99 {np.percentile([1, 2, 3, 10], 99):.1f} ms, max 10.0 ms")


def test_heuristics_and_stitch_benches_on_tiny_inputs():
    frame, line = bench.bench_heuristics(2, people=2, objects=10)
    assert len(frame.objects) == 10
    assert line.startswith("heuristics (2 people, 10 objects): p50 ") and " p99 " in line
    image = np.zeros((240, 320, 3), dtype=np.uint8)
    stitched, line = bench.bench_stitch(image, 2)
    assert stitched.shape[:2] == (960, 640)
    assert line.startswith("stitch 2 x 640x480: p50 ")


def test_repeats_must_be_positive(capsys):
    with pytest.raises(SystemExit):
        bench.parse_args(["--repeats", "0"])
    assert "--repeats must be at least 1" in capsys.readouterr().err
