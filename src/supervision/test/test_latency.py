"""Latency percentiles agree with numpy's; summaries and timing helpers."""
import numpy as np
import pytest

from supervision.latency import percentile, summarise, time_calls_ms


@pytest.mark.parametrize("size", [1, 2, 7, 100, 1001])
@pytest.mark.parametrize("q", [0, 12.5, 50, 95, 99, 100])
def test_percentile_matches_numpy(size, q):
    samples = np.random.default_rng(size).exponential(3.0, size)
    assert percentile(samples.tolist(), q) == pytest.approx(float(np.percentile(samples, q)))


def test_percentile_of_a_known_set():
    # ranks 0..4 of [1, 2, 3, 4, 10]: p50 at rank 2, p99 at rank 3.96 -> 4 + 0.96 * 6
    assert percentile([10, 1, 4, 2, 3], 50) == 3.0
    assert percentile([10, 1, 4, 2, 3], 99) == pytest.approx(9.76)


def test_percentile_rejects_empty_samples_and_bad_q():
    with pytest.raises(ValueError, match="no samples"):
        percentile([], 50)
    with pytest.raises(ValueError, match="within"):
        percentile([1.0], 101)


def test_summary_figures_and_description():
    summary = summarise(range(1, 101))
    assert (summary.count, summary.mean, summary.max) == (100, 50.5, 100.0)
    assert summary.p50 == pytest.approx(50.5)
    assert summary.p99 == pytest.approx(99.01)
    assert summary.describe(digits=1) == "p50 50.5 ms, p95 95.0 ms, p99 99.0 ms, max 100.0 ms"
    with pytest.raises(ValueError, match="no samples"):
        summarise([])


def test_time_calls_counts_warmup_and_repeats():
    calls = []
    samples = time_calls_ms(lambda: calls.append(1), repeats=4, warmup=2)
    assert len(calls) == 6 and len(samples) == 4 and all(s >= 0.0 for s in samples)
    with pytest.raises(ValueError, match="repeats"):
        time_calls_ms(lambda: None, 0)
