"""A node's health: faults caught by the guard and a liveness heartbeat per worker.

ROS-free: `supervision.ros_supervisor` wraps it for rospy timers, subscribers, services and
threads and publishes `report()` on /diagnostics. A rospy timer whose callback raises loses its
thread for good and rospy restarts nothing, so every worker runs through `Health.run`, which
catches everything, logs each kind of fault once with its context, and keeps the node at ERROR
while it is degraded: a worker's last run failed, a fault is recent, or a worker stopped beating.
"""
import os
import threading
import time
import traceback
from dataclasses import dataclass

OK, WARN, ERROR = 0, 1, 2  # diagnostic_msgs/DiagnosticStatus levels


@dataclass(frozen=True)
class HealthConfig:
    fault_hold_s: float = 10.0  # [s] ERROR lasts at least this long after a fault
    stale_periods: float = 5.0  # a periodic worker is silent after this many missed periods...
    stale_min_s: float = 2.0    # [s] ...and never sooner than this

    def __post_init__(self):
        for name in ("fault_hold_s", "stale_periods", "stale_min_s"):
            value = getattr(self, name)
            if not (value == value and 0 < value < float("inf")):
                raise ValueError(f"HealthConfig.{name} must be a positive finite number; "
                                 f"got {value!r}")


@dataclass
class Worker:
    name: str
    period_s: float = None  # expected time between beats; None: event-driven, never silent
    last_beat: float = None
    runs: int = 0
    faults: int = 0
    failing: bool = False   # its last run raised
    last_fault: str = ""


def fault_text(exc):
    """'TypeName: message' of an exception, on one line."""
    text = str(exc).replace("\n", " ").strip()
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def fault_origin(exc):
    """'file.py:line in function' where an exception was raised (its innermost frame); ''
    for one never raised."""
    frames = traceback.extract_tb(exc.__traceback__)
    if not frames:
        return ""
    frame = frames[-1]
    return f"{os.path.basename(frame.filename)}:{frame.lineno} in {frame.name}"


def fatal_report(exc):
    """(message, [(key, value)]) of the ERROR status a node says before it dies of `exc`."""
    origin = fault_origin(exc)
    message = f"not running: {fault_text(exc)}" + (f" (raised at {origin})" if origin else "")
    return message, [("exception", type(exc).__name__), ("reason", str(exc)),
                     ("raised at", origin)]


class Health:
    """Workers, their beats and faults; thread-safe. `clock` is a monotonic clock in seconds."""

    def __init__(self, node, config=HealthConfig(), clock=time.monotonic, log=None):
        self.node = node
        self.config = config
        self.clock = clock
        self.log = log or (lambda text: None)  # called once per kind of fault, with traceback
        self._lock = threading.Lock()
        self._workers = {}
        self._logged = set()
        self._last_fault_at = None
        self._last_fault = ""
        self.faults = 0

    def worker(self, name, period_s=None):
        """Declare a worker; with `period_s` it must beat at least that often or it is silent."""
        if period_s is not None and not (0 < period_s < float("inf")):
            raise ValueError(f"worker {name!r}: period_s must be positive and finite; "
                             f"got {period_s!r}")
        with self._lock:
            worker = self._workers.get(name)
            if worker is None:
                worker = self._workers[name] = Worker(name, period_s, last_beat=self.clock())
            elif period_s is not None:
                worker.period_s = period_s
            return worker

    def beat(self, name):
        """A sign of life from a worker."""
        with self._lock:
            self._get(name).last_beat = self.clock()

    def run(self, name, context, fn, *args, on_error=None):
        """fn(*args) under the guard: return its result, or None when it raised.

        A fault is logged once per (worker, kind, message) with `context` and the traceback, then
        counted; `on_error(exc)` turns the affected item into a failure with a reason (itself
        guarded: a fault there is logged and counted too)."""
        self.beat(name)
        try:
            result = fn(*args)
        except Exception as exc:  # noqa: BLE001 - the guard's whole purpose
            self.fault(name, context, exc, traceback.format_exc())
            if on_error is not None:
                try:
                    on_error(exc)
                except Exception as inner:  # noqa: BLE001
                    self.fault(name, f"{context}: handling the fault", inner,
                               traceback.format_exc())
            return None
        self.succeeded(name)
        return result

    def succeeded(self, name):
        """A run of worker `name` ended without a fault: it is no longer failing."""
        with self._lock:
            worker = self._get(name)
            worker.runs += 1
            worker.failing = False
            worker.last_beat = self.clock()

    def fault(self, name, context, exc, trace=""):
        """Record a fault of worker `name`; returns the one-line description."""
        text = f"{name}: {context}: {fault_text(exc)}" if context else f"{name}: {fault_text(exc)}"
        signature = (name, type(exc).__name__, str(exc))
        with self._lock:
            worker = self._get(name)
            worker.runs += 1
            worker.faults += 1
            worker.failing = True
            worker.last_fault = text
            worker.last_beat = self.clock()
            self.faults += 1
            self._last_fault_at = self.clock()
            self._last_fault = text
            first = signature not in self._logged
            self._logged.add(signature)
        if first:
            self.log(f"{self.node}: {text} (logged once; later repeats are only counted)\n"
                     f"{trace}".rstrip())
        return text

    def report(self):
        """(level, message, [(key, value)]) of the node's health now."""
        now = self.clock()
        with self._lock:
            problems, values = [], [("faults", str(self.faults))]
            for worker in self._workers.values():
                if worker.failing:
                    problems.append(f"failing: {worker.last_fault}")
                silent = now - worker.last_beat
                if worker.period_s is not None and silent > self._stale_after(worker):
                    problems.append(f"worker {worker.name} silent for {silent:.1f} s "
                                    f"(expected every {worker.period_s:g} s)")
                values.append((f"{worker.name} last beat [s ago]", f"{silent:.1f}"))
                values.append((f"{worker.name} runs/faults", f"{worker.runs}/{worker.faults}"))
            recent = self._last_fault_at is not None and \
                now - self._last_fault_at < self.config.fault_hold_s
            if recent and not problems:
                problems.append(f"fault {now - self._last_fault_at:.1f} s ago: "
                                f"{self._last_fault}")
            if self._last_fault:
                values.append(("last fault", self._last_fault))
        if problems:
            return ERROR, "degraded: " + "; ".join(problems), values
        return OK, "all workers alive", values

    def _stale_after(self, worker):
        return max(self.config.stale_periods * worker.period_s, self.config.stale_min_s)

    def _get(self, name):
        worker = self._workers.get(name)
        if worker is None:
            worker = self._workers[name] = Worker(name, last_beat=self.clock())
        return worker
