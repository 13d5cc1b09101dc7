"""Terminal front end of the teleoperation program (curses; works inside tmux and over ssh).

ROS-free: it drives a TeleopState from the keyboard and hands (v, omega) to a `publish` callable.
The terminal is always restored (curses.wrapper) and a zero command is always published on exit
(try/finally), however the program ends.
"""
import curses
import os

from penguin_base.record_format import NUM_CLASSES
from penguin_base.teleop import DOWN, LEFT, RIGHT, STOP, UP

KEY_ACTIONS = {curses.KEY_UP: UP, curses.KEY_DOWN: DOWN, curses.KEY_LEFT: LEFT,
               curses.KEY_RIGHT: RIGHT, ord(" "): STOP}
QUIT_KEYS = {ord("q"), ord("Q")}
END_SEQUENCE_KEY = ord("e")
# Digit keys start a record of instruction classes 1..NUM_CLASSES (record_format.NUM_CLASSES,
# Table 3.1-1: ten): '1'..'9' -> class 1..9, '0' -> class 10. The ten digits cover ten classes
# at most; a class beyond the tenth gets no key.
KEYED_CLASSES = min(NUM_CLASSES, 10)
CLASS_KEYS = {ord(str(n % 10)): n for n in range(1, KEYED_CLASSES + 1)}
_DIGITS = "1-9, 0" if KEYED_CLASSES == 10 else f"1-{KEYED_CLASSES}"
HELP = ("Up: faster   Down: slower   Left/Right: tap = nudge, hold = rotate   Space: stop",
        f"{_DIGITS}: start a record of instruction class 1-{KEYED_CLASSES}   e: end the record   "
        "q: quit")


def run_teleop(state, publish, clock, running, announce_class=None):
    """Run the keyboard loop until `q`, Ctrl-C or running() is False; always publish zero after.

    Args:
        state: a TeleopState.
        publish: callable(v, omega) sending the command.
        clock: callable() -> now [s].
        running: callable() -> False to stop (e.g. ROS shutdown).
        announce_class: optional callable(class_number), 0 ending a record sequence.
    """
    os.environ.setdefault("ESCDELAY", "25")  # arrow keys arrive as ESC sequences; do not wait 1 s
    try:
        curses.wrapper(_loop, state, publish, clock, running, announce_class)
    except KeyboardInterrupt:
        pass
    finally:
        publish(0.0, 0.0)


def _loop(screen, state, publish, clock, running, announce_class):
    period = 1.0 / state.config.publish_rate
    screen.keypad(True)
    _hide_cursor()
    next_publish = clock()
    status = "ready"
    while running():
        screen.timeout(max(1, int((next_publish - clock()) * 1000)))  # wake up for the next send
        key = screen.getch()
        now = clock()
        if key in QUIT_KEYS:
            return
        status = _handle_key(key, state, now, announce_class) or status
        if now >= next_publish:
            publish(*state.command(now))
            next_publish = max(next_publish + period, now)  # keep the rate; never a burst
        _draw(screen, state.command(now), status)


def _handle_key(key, state, now, announce_class):
    """Apply one key; returns a status line when the key did something."""
    if key in KEY_ACTIONS:
        state.press(KEY_ACTIONS[key], now)
        return f"key: {KEY_ACTIONS[key]}"
    if announce_class is not None and key in CLASS_KEYS:
        announce_class(CLASS_KEYS[key])
        return f"recording instruction class {CLASS_KEYS[key]}"
    if announce_class is not None and key == END_SEQUENCE_KEY:
        announce_class(0)
        return "record ended"
    return None


def _hide_cursor():
    try:
        curses.curs_set(0)
    except curses.error:  # some terminals cannot hide the cursor
        pass


def _draw(screen, command, status):
    v, omega = command
    lines = ("Penguin teleoperation (thesis 002 Fig. 3.3.3)", *HELP, "",
             f"v = {v:+.2f} m/s   omega = {omega:+.2f} rad/s", status)
    screen.erase()
    height, width = screen.getmaxyx()
    for row, text in enumerate(lines[:height]):
        try:
            screen.addnstr(row, 0, text, max(0, width - 1))
        except curses.error:  # a terminal too small for the text: draw what fits
            pass
    screen.refresh()
