"""Latency figures of timed calls: percentiles (p50, p95, p99) and max, for benchmarks and health.

Plain Python (no numpy): `percentile` interpolates linearly between the closest ranks, as
`numpy.percentile` does by default, so the figures agree with numpy's on the same samples.
"""
import time
from dataclasses import dataclass


def percentile(samples, q):
    """The q-th percentile (0 <= q <= 100) of `samples`, linear between the closest ranks."""
    ordered = sorted(float(s) for s in samples)
    if not ordered:
        raise ValueError("percentile of no samples")
    if not 0.0 <= q <= 100.0:
        raise ValueError(f"percentile q must be within [0, 100]; got {q!r}")
    rank = (len(ordered) - 1) * q / 100.0
    low = int(rank)
    high = min(low + 1, len(ordered) - 1)
    return ordered[low] + (ordered[high] - ordered[low]) * (rank - low)


@dataclass(frozen=True)
class LatencySummary:
    """Figures of one set of latencies, in the unit of the samples (usually ms)."""
    count: int
    mean: float
    p50: float
    p95: float
    p99: float
    max: float

    def describe(self, unit="ms", digits=2):
        """`p50 1.00 ms, p95 2.00 ms, p99 3.00 ms, max 4.00 ms`."""
        return ", ".join(f"{name} {getattr(self, name):.{digits}f} {unit}"
                         for name in ("p50", "p95", "p99", "max"))


def summarise(samples):
    """LatencySummary of `samples`; ValueError when there are none."""
    samples = [float(s) for s in samples]
    if not samples:
        raise ValueError("latency summary of no samples")
    return LatencySummary(count=len(samples), mean=sum(samples) / len(samples),
                          p50=percentile(samples, 50), p95=percentile(samples, 95),
                          p99=percentile(samples, 99), max=max(samples))


def time_calls_ms(function, repeats, warmup=0):
    """Wall time [ms] of `repeats` calls of `function()`, after `warmup` untimed calls."""
    if repeats < 1:
        raise ValueError(f"repeats must be at least 1; got {repeats!r}")
    for _ in range(warmup):
        function()
    samples = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        samples.append((time.perf_counter() - start) * 1000.0)
    return samples
