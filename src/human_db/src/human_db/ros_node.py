"""The human_db node: the household store behind ROS services, a latched table and diagnostics.

Every service handler and timer runs under one supervision.ros_supervisor.Supervisor: a request
the database refuses is answered with success false (or found false) and the reason; an
unexpected fault while serving a request is answered with rospy's service error naming the
reason, counted as a failed request, and raises the node's "human_db: human_db: supervision"
status to ERROR; the next request is served as usual. People whose rows do not load (the store's
quarantine) are left out and keep "human_db: database" at WARN, naming each row and why."""
import dataclasses
import os
import threading
import time as wallclock
from dataclasses import dataclass

import rospkg
import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from tamp_msgs.msg import HumanArray
from tamp_msgs.srv import (GetHuman, GetHumanResponse, IdentifyHuman, IdentifyHumanResponse,
                           ListHumans, ListHumansResponse, RegisterHuman, RegisterHumanResponse,
                           UpdateHuman, UpdateHumanResponse, WhereWasHuman,
                           WhereWasHumanResponse)

from human_db.colour import ColourIndex, IdentificationConfig
from human_db.conversions import (colours_from_msg, human_from_msg, human_to_msg,
                                  schedule_from_msg)
from human_db.errors import HumanDbError, InvalidHuman, StoreBusy
from human_db.household import import_household, register_shirts
from human_db.model import check_observation_time
from human_db.store import HumanStore, StoreConfig
from supervision.health import fault_text
from supervision.ros_params import config_from_params
from supervision.ros_supervisor import Supervisor

QUARANTINE_SHOWN = 20   # quarantined rows listed on /diagnostics (their count always is)


@dataclass(frozen=True)
class NodeParams:
    db_path: str                    # SQLite file; created when missing
    household: str = ""             # YAML imported when the database holds nobody; "" = none
    shirts: str = ""                # with household: a shirts file registered right after the
                                    # import (everyone met before the run); "" = nobody met
    threshold: float = 200.0        # identification threshold (mean ΔC, §5.2.3)
    ambiguity_margin: float = 60.0  # a runner-up within this of the closest (both below the
                                    # threshold) identifies nobody: the robot asks, never guesses
    publish_period: float = 0.1     # [s] how often a change is looked for and /humans/known sent
    diagnostics_period: float = 1.0  # [s]
    busy_timeout: float = 5.0       # [s] SQLite busy timeout per statement
    retry_timeout: float = 30.0     # [s] total retry budget of one operation
    synchronous: str = "FULL"       # SQLite synchronous level
    future_tolerance: float = 5.0   # [s] an update stamped further after the node's clock is
                                    # refused (it would pin the person's current state)
    open_retry_s: float = 10.0      # [s] at start, a database locked by another process is
                                    # retried this long (a warning per retry), then the node exits


def read_params():
    """Read the node's ~parameters once."""
    default_db = os.path.join(rospkg.get_ros_home(), "human_db.sqlite")
    params = config_from_params(NodeParams, db_path=default_db)
    return dataclasses.replace(params, db_path=os.path.expanduser(params.db_path))


class HumanDbNode:
    """Services register/get/update/identify/list/where_was, /humans/known, /diagnostics."""

    def __init__(self, params):
        self.params = params
        self.store = None
        self._lock = threading.Lock()    # guards the colour index and the counters below
        self._index, self._index_revision = None, None
        self._published_revision = None
        self._counts = {"requests": 0, "refused": 0, "failed": 0}
        self._last_failure = ""
        self._failed_at_last_report = 0  # WARN only while new failures keep coming
        self._write_seconds = 0.0        # latency of the last write [s]
        self._services, self._timers = [], []
        self._known = self._diagnostics = None
        self.sup = None

    def setup(self):
        """Open (or create) the database, import the household if it is empty, start the ROS API.

        Raises DatabaseUnusable when the file is corrupted, truncated or foreign (it is left
        untouched), StoreBusy when another process kept it locked for ~open_retry_s,
        InvalidHuman/DuplicateHuman when the household file is bad, ValueError for bad params."""
        config = StoreConfig(busy_timeout=self.params.busy_timeout,
                             retry_timeout=self.params.retry_timeout,
                             synchronous=self.params.synchronous,
                             open_retry=self.params.open_retry_s)
        self.store = HumanStore(self.params.db_path, config,
                                on_retry=lambda message: rospy.logwarn("human_db: %s", message))
        rospy.loginfo("human_db: database %s holds %d people", self.store.path,
                      self.store.count())
        if self.params.household and self.store.count() == 0:
            names = import_household(self.store, self.params.household, now=rospy.get_time())
            rospy.loginfo("human_db: imported %s from %s", ", ".join(names),
                          self.params.household)
            if self.params.shirts:
                met = register_shirts(self.store, self.params.shirts, now=rospy.get_time())
                rospy.loginfo("human_db: %s met before the run (shirts from %s)",
                              ", ".join(met), self.params.shirts)
        self.sup = sup = Supervisor("human_db: human_db", hardware_id=self.store.path)
        self._known = rospy.Publisher("humans/known", HumanArray, queue_size=1, latch=True)
        self._diagnostics = rospy.Publisher("/diagnostics", DiagnosticArray, queue_size=1)
        self._publish_table()
        for row, reason in self.store.quarantined.items():
            rospy.logwarn("human_db: humans row %d: %s", row, reason)
        handlers = (("~register", RegisterHuman, self._register), ("~get", GetHuman, self._get),
                    ("~update", UpdateHuman, self._update),
                    ("~identify", IdentifyHuman, self._identify),
                    ("~list", ListHumans, self._list), ("~where_was", WhereWasHuman,
                                                        self._where_was))
        self._services = [sup.service(name, kind, self._counted(name.lstrip("~"), handler))
                          for name, kind, handler in handlers]
        self._timers = [
            sup.timer(self.params.publish_period, self._on_publish_timer, worker="publish"),
            sup.timer(self.params.diagnostics_period, self._on_diagnostics,
                      worker="diagnostics")]

    def close(self):
        for timer in self._timers:
            timer.shutdown()
        for service in self._services:
            service.shutdown()
        if self.store is not None:
            self.store.close()

    # -- services -----------------------------------------------------------------------------
    def _counted(self, what, handler):
        """handler(request), counted; an unexpected fault counts as a failed request (the
        Supervisor answers the caller with the reason)."""
        def wrapped(request):
            with self._lock:
                self._counts["requests"] += 1
            try:
                return handler(request)
            except rospy.ServiceException:
                raise                      # identify/list refusal, counted by _refused
            except Exception as error:
                with self._lock:
                    self._counts["failed"] += 1
                    self._last_failure = f"{what}: {fault_text(error)}"
                raise
        return wrapped

    def _refused(self, what, error):
        """Count and log a request the database did not carry out; return its message."""
        failed = isinstance(error, StoreBusy)
        with self._lock:
            self._counts["failed" if failed else "refused"] += 1
            if failed:
                self._last_failure = str(error)
        (rospy.logerr if failed else rospy.logwarn)("human_db: %s: %s", what, error)
        return str(error)

    def _timed_write(self, write):
        start = wallclock.monotonic()
        result = write()
        with self._lock:
            self._write_seconds = wallclock.monotonic() - start
        return result

    def _register(self, request):
        try:
            human = human_from_msg(request.human)
            self._timed_write(lambda: self.store.register(human, request.replace,
                                                          now=rospy.get_time()))
        except HumanDbError as error:
            return RegisterHumanResponse(False, self._refused("register", error))
        return RegisterHumanResponse(True, f"registered {human.name}")

    def _get(self, request):
        try:
            if request.name:
                human = self.store.get(request.name)
            elif request.ip:
                human = self.store.get_by_ip(request.ip)
            else:
                raise InvalidHuman("get: give a name or a phone IP")
        except HumanDbError as error:
            return GetHumanResponse(found=False, message=self._refused("get", error))
        return GetHumanResponse(found=True, human=human_to_msg(human))

    def _update(self, request):
        try:
            colours = colours_from_msg(request.shirt_color) if request.set_shirt_color else None
            schedules = ([schedule_from_msg(s) for s in request.schedules]
                         if request.set_schedules else None)
            present = rospy.get_time()
            now = check_observation_time(
                present if request.stamp.is_zero() else request.stamp.to_sec(), present,
                self.params.future_tolerance, request.name)
            self._timed_write(lambda: self.store.update(
                request.name, now=now, location=request.location, activity=request.activity,
                source=request.source, shirt_colour=colours, schedules=schedules))
        except HumanDbError as error:
            return UpdateHumanResponse(False, self._refused("update", error))
        return UpdateHumanResponse(True, f"updated {request.name}")

    def _identify(self, request):
        try:
            match = self._colour_index().identify(colours_from_msg(request.shirt_color))
        except HumanDbError as error:
            self._refused("identify", error)
            raise rospy.ServiceException(str(error)) from error
        if match is None:
            return IdentifyHumanResponse(found=False, name="", distance=0.0)
        return IdentifyHumanResponse(found=True, name=match.name, distance=match.distance)

    def _list(self, _request):
        try:
            humans = self.store.humans()
        except HumanDbError as error:
            self._refused("list", error)
            raise rospy.ServiceException(str(error)) from error
        return ListHumansResponse([human_to_msg(h) for h in humans])

    def _where_was(self, request):
        when = rospy.get_time() if request.stamp.is_zero() else request.stamp.to_sec()
        try:
            entry = self.store.where_was(request.name, when)
        except HumanDbError as error:
            return WhereWasHumanResponse(found=False, message=self._refused("where_was", error))
        if entry is None:
            return WhereWasHumanResponse(found=False,
                                         message=f"nothing recorded for {request.name} at or "
                                                 f"before t = {when:.3f} s")
        return WhereWasHumanResponse(found=True, location=entry.location,
                                     activity=entry.activity, source=entry.source,
                                     recorded=rospy.Time.from_sec(entry.time))

    def _colour_index(self):
        """The stored colours as one array, rebuilt only after a write."""
        revision = self.store.revision
        with self._lock:
            if self._index is not None and self._index_revision == revision:
                return self._index
        names, colours = self.store.shirt_colour_table()
        index = ColourIndex(names, colours, IdentificationConfig(self.params.threshold,
                                                                 self.params.ambiguity_margin))
        with self._lock:
            self._index, self._index_revision = index, revision
        return index

    # -- timers -------------------------------------------------------------------------------
    def _on_publish_timer(self, _event):
        if self.store.revision != self._published_revision:
            self._publish_table()

    def _publish_table(self):
        revision = self.store.revision
        try:
            humans = self.store.humans()
        except HumanDbError as error:
            rospy.logwarn_throttle(10.0, "human_db: cannot read the table: %s", error)
            return
        message = HumanArray(humans=[human_to_msg(h) for h in humans])
        message.header.stamp = rospy.Time.now()
        self._known.publish(message)
        self._published_revision = revision

    def _on_diagnostics(self, _event):
        with self._lock:
            counts, last_failure = dict(self._counts), self._last_failure
            write_ms = self._write_seconds * 1000.0
        status = DiagnosticStatus(name="human_db: database", hardware_id=self.store.path)
        try:
            people = self.store.count()
        except HumanDbError as error:
            status.level, status.message = DiagnosticStatus.ERROR, f"unreadable: {error}"
            people = -1
        else:
            new_failures = counts["failed"] - self._failed_at_last_report
            status.level = DiagnosticStatus.WARN if new_failures else DiagnosticStatus.OK
            status.message = (f"{people} people" if not new_failures else
                              f"{new_failures} failed requests; last: {last_failure}")
        quarantined = self.store.quarantined
        if quarantined and status.level != DiagnosticStatus.ERROR:
            status.level = DiagnosticStatus.WARN
            status.message += (f"; {len(quarantined)} row(s) that do not load quarantined "
                               "(reasons in the values)")
        self._failed_at_last_report = counts["failed"]
        values = dict(people=people, requests=counts["requests"], refused=counts["refused"],
                      failed=counts["failed"], busy_retries=self.store.busy_retries,
                      last_write_ms=f"{write_ms:.2f}", revision=self.store.revision,
                      quarantined_rows=len(quarantined))
        values.update((f"humans row {row}", reason)
                      for row, reason in list(quarantined.items())[:QUARANTINE_SHOWN])
        status.values = [KeyValue(key, str(value)) for key, value in values.items()]
        array = DiagnosticArray(status=[status])
        array.header.stamp = rospy.Time.now()
        self._diagnostics.publish(array)
