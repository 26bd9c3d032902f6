"""`checks`: the one message shape of a bad number, "NAME = VALUE: allowed range [LOW, HIGH]",
for counts too (`check_integer`)."""

import math

import numpy as np
import pytest

from ballimpact import InputError
from ballimpact.checks import check_integer, check_range


def message(call) -> str:
    with pytest.raises(InputError) as raised:
        call()
    return str(raised.value)


def test_check_integer_returns_an_int():
    assert check_integer("--runs", 10, 1) == 10
    for value in (np.int64(7), 7.0):  # NumPy's integers and whole floats: a plain int
        assert check_integer("n", value, 2, 9) == 7
        assert type(check_integer("n", value, 2, 9)) is int
    assert check_integer("divisions", 16, 4, 64, even=True) == 16
    assert check_integer("seed", 0, 0) == 0


def test_check_integer_out_of_range_has_the_one_shape():
    assert message(lambda: check_integer("--population", 3, 4)) == \
        "--population = 3: allowed range [4, inf)"
    assert message(lambda: check_integer("--population", 3, 4, note="NSGA-II needs pairs")) == \
        "--population = 3: allowed range [4, inf) (NSGA-II needs pairs)"
    assert message(lambda: check_integer("terms", 11, 1, 10)) == \
        "terms = 11: allowed range [1, 10]"
    assert message(lambda: check_integer("seed", np.int64(-1), 0)) == \
        "seed = -1: allowed range [0, inf)"


@pytest.mark.parametrize("value, shown", [(True, "True"), (False, "False"), (2.5, "2.5"),
                                          ("3", "'3'"), (None, "None"), (math.nan, "nan"),
                                          (math.inf, "inf"), ([3], "[3]")])
def test_check_integer_refuses_what_is_not_an_integer(value, shown):
    assert message(lambda: check_integer("--runs", value, 1)) == \
        f"--runs = {shown}: expected an integer in [1, inf)"


def test_check_integer_non_integer_message_carries_the_range_and_note():
    assert message(lambda: check_integer("terms", 2.5, 1, 10, note="Prony terms")) == \
        "terms = 2.5: expected an integer in [1, 10] (Prony terms)"


def test_check_integer_even():
    assert message(lambda: check_integer("divisions", 5, 4, 64, even=True)) == \
        "divisions = 5: expected an even integer in [4, 64]"
    assert message(lambda: check_integer("divisions", 2, 4, even=True)) == \
        "divisions = 2: allowed range [4, inf) (even)"
    assert message(lambda: check_integer("divisions", 66, 4, 64, even=True, note="cube edge")) == \
        "divisions = 66: allowed range [4, 64] (even; cube edge)"


def test_check_range_shape():
    assert message(lambda: check_range("lambda", -0.1, 0.0, unit="s/m")) == \
        "lambda = -0.1: allowed range [0, inf) s/m"
    assert message(lambda: check_range("cor", 1.5, 0.0, 1.0, low_open=True)) == \
        "cor = 1.5: allowed range (0, 1]"
    assert message(lambda: check_range("x", "a", 0.0, low_open=True)) == \
        "x = 'a': expected a finite number in (0, inf)"
