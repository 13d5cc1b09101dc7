"""rospy timers, subscribers, services and threads under `supervision.health.Health`.

    sup = Supervisor("task_planner: executor")
    sup.timer(0.05, self._tick, worker="tick", on_error=self._fail_current)
    sup.subscriber("humans/known", HumanArray, self._on_humans)
    sup.service("~submit", SubmitInstruction, self._submit)

The health status ("<name>: supervision") goes out on /diagnostics from a thread of its own on
the wall clock, so it keeps reporting when a worker hangs or the ROS clock stops.

A node's main runs under `run_node`, the last guard: whatever it raises (a parameter, file or
journal that cannot be used, or a bug) is said on /diagnostics as an ERROR before the node exits
1, so a node that respawns and keeps dying says why.
"""
import contextlib
import threading
import time
import traceback

import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue

from supervision.health import Health, HealthConfig, fatal_report
from supervision.ros_params import config_from_params


def health_config_from_ros():
    """~supervision/fault_hold_s, ~supervision/stale_periods, ~supervision/stale_min_s."""
    return config_from_params(HealthConfig, "~supervision")


FATAL_WAIT_S = 3.0   # [s wall] a dying node waits this long for a /diagnostics subscriber
FATAL_FLUSH_S = 0.5  # [s wall] and lets rospy's sending thread deliver its status this long


def run_node(name, main, hardware_id="", expected=(ValueError,), log_name=""):
    """main() of a node (after rospy.init_node) under a last guard; returns the exit status.

    An exception main raises is logged ("<log_name>: not starting: ...", log_name defaulting
    to `name`) and said on /diagnostics as an ERROR status `name` ("not running: TypeError: ...
    (raised at file.py:47 in f)") before the node exits 1. `expected` ones (a parameter or file
    the user must fix) are logged on one line, the others with their traceback."""
    try:
        return main()
    except Exception as exc:  # noqa: BLE001 - the last guard: say why, then die
        if isinstance(exc, expected):
            rospy.logfatal("%s: not starting: %s", log_name or name, exc)
        else:
            rospy.logfatal("%s: not running:\n%s", log_name or name, traceback.format_exc())
        say_fatal(name, exc, hardware_id)
        return 1


def say_fatal(name, exc, hardware_id=""):
    """Publish the ERROR status of a node about to die of `exc` (supervision.health
    .fatal_report) on /diagnostics, latched, after waiting up to FATAL_WAIT_S for a
    subscriber (a monitor or the aggregator)."""
    if rospy.is_shutdown():
        return
    message, values = fatal_report(exc)
    status = DiagnosticStatus(level=DiagnosticStatus.ERROR, name=name, message=message,
                              hardware_id=hardware_id or rospy.get_name(),
                              values=[KeyValue(key=k, value=v) for k, v in values])
    pub = rospy.Publisher("/diagnostics", DiagnosticArray, queue_size=10, latch=True)
    deadline = time.monotonic() + FATAL_WAIT_S
    while pub.get_num_connections() == 0 and time.monotonic() < deadline:
        time.sleep(0.05)
    array = DiagnosticArray(status=[status])
    array.header.stamp = rospy.Time.now()
    pub.publish(array)
    time.sleep(FATAL_FLUSH_S)   # publish only queues the message: the process must outlive it


class Supervisor:
    """One per node. `name` titles its /diagnostics status; `rate_hz` is how often it goes out."""

    def __init__(self, name, hardware_id="", rate_hz=1.0, config=None):
        self.name = name
        self.hardware_id = hardware_id or rospy.get_name()
        self.health = Health(name, config or health_config_from_ros(), log=rospy.logerr)
        self._period = 1.0 / rate_hz
        self._pub = rospy.Publisher("/diagnostics", DiagnosticArray, queue_size=2)
        self._thread = threading.Thread(target=self._publish_loop, name="supervision",
                                        daemon=True)
        self._thread.start()

    def timer(self, period_s, callback, worker=None, on_error=None, oneshot=False):
        """rospy.Timer whose callback can never kill its thread; the worker must beat every
        `period_s` (ROS time, checked on the wall clock)."""
        worker = worker or callback.__name__.lstrip("_")
        if not oneshot:
            self.health.worker(worker, period_s)
        return rospy.Timer(rospy.Duration(period_s), self.wrap(worker, callback, on_error),
                           oneshot=oneshot)

    def subscriber(self, topic, msg_type, callback, worker=None, on_error=None, **kwargs):
        """rospy.Subscriber whose callback faults are counted and shown, not only logged."""
        worker = worker or f"{topic} callback"
        self.health.worker(worker)
        return rospy.Subscriber(topic, msg_type, self.wrap(worker, callback, on_error), **kwargs)

    def service(self, name, srv_type, handler, worker=None):
        """rospy.Service; a fault is recorded and the caller gets rospy's error with the reason.
        A rospy.ServiceException the handler raises is its refusal: passed on, not a fault."""
        worker = worker or f"{name} service"
        self.health.worker(worker)

        def guarded(request):
            refusal, failure = [], []

            def call(req):
                try:
                    return handler(req)
                except rospy.ServiceException as exc:  # the handler refuses: no fault
                    refusal.append(exc)
                    return None
            result = self.health.run(worker, "request", call, request, on_error=failure.append)
            if refusal:
                raise refusal[0]
            if failure:
                raise rospy.ServiceException(f"{self.name}: {worker} failed: {failure[0]!r}")
            return result
        return rospy.Service(name, srv_type, guarded)

    def wrap(self, worker, callback, on_error=None):
        """callback(arg) under the guard, for any rospy callback with one argument. A
        rospy.ROSException while the node shuts down (a publisher closed under the callback) is
        the end of the node, not a fault: it is not reported. That includes the moment the
        node's own shutdown hooks run, before rospy.is_shutdown() turns true."""
        def quiet_at_shutdown(arg):
            try:
                return callback(arg)
            except rospy.ROSException:
                if rospy.is_shutdown() or rospy.core.is_shutdown_requested():
                    return None
                raise

        def guarded(arg):
            return self.health.run(worker, "", quiet_at_shutdown, arg, on_error=on_error)
        return guarded

    def worker(self, name, period_s=None):
        """Declare a thread's worker; it must call `beat(name)` every `period_s`."""
        self.health.worker(name, period_s)

    def beat(self, name):
        self.health.beat(name)

    @contextlib.contextmanager
    def guard(self, worker, context=""):
        """`with sup.guard("work", "utterance 3"):` for code in a thread of the node's own.
        A fault inside is recorded and swallowed; the block's remaining code is skipped."""
        failure = []
        self.health.beat(worker)
        try:
            yield failure
        except Exception as exc:  # noqa: BLE001 - the guard's whole purpose
            self.health.fault(worker, context, exc, traceback.format_exc())
            failure.append(exc)
        else:
            self.health.succeeded(worker)

    def status(self):
        """This node's health as a DiagnosticStatus."""
        level, message, values = self.health.report()
        return DiagnosticStatus(level=level, name=f"{self.name}: supervision", message=message,
                                hardware_id=self.hardware_id,
                                values=[KeyValue(key=k, value=v) for k, v in values])

    def _publish_loop(self):
        while not rospy.is_shutdown():
            try:
                array = DiagnosticArray(status=[self.status()])
                array.header.stamp = rospy.Time.now()
                self._pub.publish(array)
            except Exception as exc:  # noqa: BLE001 - shutting down, or the clock not yet up
                if rospy.is_shutdown():
                    return
                rospy.logwarn_throttle(10.0, f"{self.name}: supervision report failed: {exc}")
            time.sleep(self._period)
