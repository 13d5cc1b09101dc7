import math

import pytest

from nav_mocks.param_checks import non_negative_number, positive_number


@pytest.mark.parametrize("value", [0, 0.0, -10.0, math.nan, math.inf, "fast", None, True])
def test_positive_number_refuses_naming_parameter_and_value(value):
    with pytest.raises(ValueError) as error:
        positive_number("~controller_frequency", value, "Hz")
    assert str(error.value) == (f"parameter ~controller_frequency must be a finite number > 0 "
                                f"[Hz], got {value!r}")


def test_positive_number_accepts_numbers_and_numeric_strings():
    assert positive_number("~update_rate", 10, "Hz") == 10.0
    assert positive_number("~update_rate", "2.5", "Hz") == 2.5


@pytest.mark.parametrize("value", [-0.1, math.nan, -math.inf, "x"])
def test_non_negative_number_refuses(value):
    with pytest.raises(ValueError, match=r"parameter r must be a finite number >= 0 \[m\]"):
        non_negative_number("r", value, "m")
    assert non_negative_number("r", 0, "m") == 0.0
