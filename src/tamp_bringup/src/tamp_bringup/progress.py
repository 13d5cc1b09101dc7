"""Progress lines with an ETA for the long jobs of the bringup (scenario runs, recorded episodes).

A job that runs simulated time knows how much simulated time it may take at most (a scenario's
last request plus its timeout, an episode's timeout); the rate of simulated over wall-clock time
measured so far turns the rest into wall-clock time.
"""
import re

# the scenario node's event for a request it sent (tamp_bringup.ros_scenario._send), as the
# launch log shows it: `scenario 70.1 s: Bob (phone 192.168.1.101) sends: "..."`
SENT_REQUEST = re.compile(r"scenario \d+(?:\.\d+)? s: .*\) (?:sends|speaks): ")


def duration_text(seconds):
    """`45 s`, `3 min 05 s`, `1 h 02 min`: a duration for a progress line."""
    seconds = max(0, int(round(seconds)))
    if seconds < 60:
        return f"{seconds} s"
    minutes, seconds = divmod(seconds, 60)
    if minutes < 60:
        return f"{minutes} min {seconds:02d} s"
    hours, minutes = divmod(minutes, 60)
    return f"{hours} h {minutes:02d} min"


class SimRate:
    """Simulated seconds per wall-clock second, measured from the first simulated time seen;
    `fallback` (the requested speed-up) until two samples are at least a second apart."""

    def __init__(self, fallback):
        self.fallback = float(fallback)
        self.first = None          # (wall [s], sim [s]) of the first sample

    def update(self, wall_s, sim_s):
        if self.first is None:
            self.first = (wall_s, sim_s)
        return self.rate(wall_s, sim_s)

    def rate(self, wall_s, sim_s):
        if self.first is None or wall_s - self.first[0] < 1.0 or sim_s <= self.first[1]:
            return self.fallback
        return (sim_s - self.first[1]) / (wall_s - self.first[0])


def remaining_wall_s(sim_s, sim_total_s, rate):
    """Wall-clock seconds left until `sim_total_s` of simulated time at `rate`."""
    return max(0.0, sim_total_s - sim_s) / rate if rate > 0 else float("inf")


def count_sent_requests(log_text):
    """How many requests the scenario node has sent, from the text of the run's launch log."""
    return len(SENT_REQUEST.findall(log_text))


def scenario_line(wall_s, sim_s, rate, last_request_s, timeout_s, requests, sent,
                  started=False):
    """One progress line of a scenario run. `sim_s` None: no simulated time, before the
    simulator has started or, `started`, once the launch is shutting down. The run ends once
    every request has been served after the last one was sent, or `timeout_s` after the last
    request: the ETA is the wall time to that bound."""
    if sim_s is None:
        return (f"[scenario] {duration_text(wall_s)}: "
                + ("the scenario has ended; stopping the launch" if started
                   else "starting (the simulator has not started)"))
    bound_s = last_request_s + timeout_s
    line = (f"[scenario] {duration_text(wall_s)}: simulated {sim_s:.0f} s at {rate:.1f}x, "
            f"requests sent {sent} of {requests}")
    if sim_s < last_request_s:
        line += (f"; last request in {duration_text(remaining_wall_s(sim_s, last_request_s, rate))}"
                 f", ends when they are served, at most "
                 f"{duration_text(remaining_wall_s(sim_s, bound_s, rate))} left")
    else:
        line += (f"; waiting for the open requests to be served, at most "
                 f"{duration_text(remaining_wall_s(sim_s, bound_s, rate))} left "
                 f"(gives up at {bound_s:.0f} s simulated)")
    return line
