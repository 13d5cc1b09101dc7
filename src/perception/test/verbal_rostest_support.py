"""Helpers of the perception rostest nodes: household set-up through human_db's services,
collectors for the topics under test and the task planner's submit service as perception sees it
(imported by the rostest executables of this directory).

Every wait is for a condition with a wall-clock limit (`HANG`) that only catches a hang: these
nodes run on the wall clock, and a loaded machine makes them slow, never wrong."""
import threading

import rospy
from diagnostic_msgs.msg import DiagnosticArray
from tamp_msgs.msg import Human, HumanArray, Utterance
from tamp_msgs.srv import (RegisterHuman, SubmitInstruction, SubmitInstructionResponse,
                           UpdateHuman)

ALEX_IP = "192.168.1.110"     # the seed's speaker (Fig. 3-15), registered by the tests
ALICE_IP = "192.168.1.101"    # config/household.yaml; the caregiver of config/keywords.yaml
LIVING_ROOM, WELCOME, OFFICE, BEDROOM = 2, 3, 5, 6  # node ids of maps/household.graph.yaml
CHAT, CHECK_STATUS, REPORT, PLAY_MUSIC = 1, 3, 7, 6  # function codes of config/keywords.yaml
PLACES = {"Alex": "living_room", "Alice": "office", "Bob": "bedroom"}
HANG = 60.0  # [s] wall-clock limit of a wait: catches a hang, never a slow machine


def wait_until(predicate, timeout=HANG):
    """predicate()'s first true value, or None after `timeout` seconds (wall clock)."""
    deadline = rospy.get_time() + timeout
    while True:
        value = predicate()
        if value or rospy.get_time() >= deadline or rospy.is_shutdown():
            return value or None
        rospy.sleep(0.05)


class Inbox:
    """Messages in arrival order."""

    def __init__(self):
        self._lock = threading.Lock()
        self._messages = []

    def messages(self):
        with self._lock:
            return list(self._messages)

    def wait_for(self, count, timeout=HANG):
        """Messages once at least `count` arrived, or what arrived by `timeout` [s]."""
        deadline = rospy.get_time() + timeout
        while len(self.messages()) < count and rospy.get_time() < deadline:
            rospy.sleep(0.05)
        return self.messages()


class Collector(Inbox):
    """Messages of one topic, in arrival order."""

    def __init__(self, topic, kind):
        super().__init__()
        self._subscriber = rospy.Subscriber(topic, kind, self._on_message, queue_size=50)

    def _on_message(self, msg):
        with self._lock:
            self._messages.append(msg)

    def connected(self):
        """Whether a publisher of the topic is connected."""
        return self._subscriber.get_num_connections() > 0


class Statuses:
    """The latest values of each named status on /diagnostics ({key: value})."""

    def __init__(self):
        self._lock, self._latest = threading.Lock(), {}
        self._subscriber = rospy.Subscriber("/diagnostics", DiagnosticArray, self._on_message,
                                            queue_size=50)

    def _on_message(self, msg):
        with self._lock:
            for status in msg.status:
                self._latest[status.name] = {kv.key: kv.value for kv in status.values}

    def values(self, name):
        with self._lock:
            return dict(self._latest.get(name, {}))

    def runs(self, name, worker):
        """Runs of `worker` in the supervision status `name` so far (0 if not yet seen)."""
        value = self.values(name).get(f"{worker} runs/faults")
        return int(value.split("/")[0]) if value else 0


class TaskPlannerSubmit(Inbox):
    """/task_planner/submit as the task planner answers it: a request with id 0 gets the next id
    from `first_id` on; the instructions taken, with their ids, in arrival order. `refuse_next`:
    the reason with which the next request is refused ("" = take it)."""

    def __init__(self, first_id=41):
        super().__init__()
        self.first_id, self.requested_ids, self.refuse_next = first_id, [], ""
        self._service = rospy.Service("/task_planner/submit", SubmitInstruction, self._on_submit)

    def _on_submit(self, request):
        msg = request.instruction
        with self._lock:
            self.requested_ids.append(msg.id)
            if self.refuse_next:
                reason, self.refuse_next = self.refuse_next, ""
                return SubmitInstructionResponse(accepted=False, id=0, message=reason)
            if msg.id == 0:
                msg.id = self.first_id + len(self._messages)
            self._messages.append(msg)
        return SubmitInstructionResponse(accepted=True, id=msg.id, message="")


def instructions():
    """The instructions perception submits to the (played) task planner."""
    return TaskPlannerSubmit()


def voice_messages():
    return Collector("/voice_message", Utterance)


def place_household(timeout=HANG):
    """Register Alex and put Alex, Alice and Bob at their places; wait until /humans/known shows
    it (the verbal node reads the same latched table)."""
    rospy.wait_for_service("/human_db/register", timeout)
    rospy.wait_for_service("/human_db/update", timeout)
    alex = Human(name="Alex", ip=ALEX_IP, gender=Human.GENDER_MALE, age=30,
                 shirt_color=[250, 250, 250, 245, 245, 245, 248, 248, 248],
                 location=PLACES["Alex"])
    reply = rospy.ServiceProxy("/human_db/register", RegisterHuman)(human=alex, replace=True)
    assert reply.success, reply.message
    update = rospy.ServiceProxy("/human_db/update", UpdateHuman)
    for name in ("Alice", "Bob"):
        reply = update(name=name, location=PLACES[name], source="rostest")
        assert reply.success, reply.message
    table = Collector("/humans/known", HumanArray)
    statuses = Collector("/diagnostics", DiagnosticArray)
    deadline = rospy.get_time() + timeout
    while rospy.get_time() < deadline:
        latest = table.messages()[-1:] or [None]
        if latest[0] is not None:
            places = {h.name: h.location for h in latest[0].humans}
            if all(places.get(name) == place for name, place in PLACES.items()):
                break
        rospy.sleep(0.05)
    else:
        raise AssertionError(f"/humans/known never showed {PLACES}")
    # the verbal node reads the same latched table: wait until its status says it holds it
    stamp = round(latest[0].header.stamp.to_sec(), 6)   # or a later table: human_db's own
    while rospy.get_time() < deadline:
        if any(kv.key == "people_table_stamp" and float(kv.value) >= stamp
               for array in statuses.messages() for status in array.status
               if status.name == "perception: verbal" for kv in status.values):
            return
        rospy.sleep(0.05)
    raise AssertionError(f"the verbal node never read the table stamped {stamp}")
