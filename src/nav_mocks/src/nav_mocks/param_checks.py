"""Checks of numeric parameters at start, ROS-free: a bad value is refused with its name.

A rate of 0 Hz becomes a division by zero (or a timer that never fires) deep inside a node;
these checks turn it into one error at start that names the parameter and the value.
"""
import math


def positive_number(name, value, unit):
    """`value` as a float when it is a finite number > 0; else a ValueError naming the
    parameter `name`, its `unit` and the value given."""
    try:
        number = float(value)
    except (TypeError, ValueError):
        number = math.nan
    if not (math.isfinite(number) and number > 0.0) or isinstance(value, bool):
        raise ValueError(f"parameter {name} must be a finite number > 0 [{unit}], "
                         f"got {value!r}")
    return number


def non_negative_number(name, value, unit):
    """`value` as a float when it is a finite number >= 0; else a ValueError naming it."""
    try:
        number = float(value)
    except (TypeError, ValueError):
        number = math.nan
    if not (math.isfinite(number) and number >= 0.0) or isinstance(value, bool):
        raise ValueError(f"parameter {name} must be a finite number >= 0 [{unit}], "
                         f"got {value!r}")
    return number
