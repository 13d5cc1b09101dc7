"""Publish one latched message from a command-line tool once somebody listens."""
import time


def publish_when_heard(publisher, message, wait_s):
    """Publish `message` once `publisher` has a subscriber, waiting at most `wait_s` seconds of
    wall-clock time (under a fast simulator a few seconds of simulated time pass before the
    subscriber can connect); False when nobody subscribed in time."""
    deadline = time.monotonic() + wait_s
    while publisher.get_num_connections() == 0 and time.monotonic() < deadline:
        time.sleep(0.05)
    if publisher.get_num_connections() == 0:
        return False
    publisher.publish(message)
    time.sleep(0.5)  # let the latched message reach the subscriber before the node exits
    return True
