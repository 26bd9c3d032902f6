"""`lumped.fit_records` (the library side of `ballimpact fit`): the fits, their model checks,
the unit-slip check of search bounds and the scatter over repeated tests, called from Python."""

import math
import warnings

import pytest

from ballimpact.errors import InputError, InputWarning
from ballimpact.lumped import SpeedTable, fit_records, get_model
from ballimpact.lumped.base import Scale
from ballimpact.lumped.fit_records import (
    check_bound_scales,
    model_check,
    parameter_scatter,
    typical_values,
)
from ballimpact.records.pipeline import process


def test_typical_values_are_the_middle_of_the_default_bounds():
    model = get_model("single_element")
    scale = Scale(0.16, 20.0, 1e-3, 5e3, 2e-3)
    bounds = model.default_bounds(scale)
    typical = typical_values(model, scale, {"alpha": 1.5})
    assert typical["alpha"] == pytest.approx(math.sqrt(bounds["alpha"][0] * bounds["alpha"][1]))
    assert bounds["c"][0] == 0.0 and typical["c"] == pytest.approx(0.5 * bounds["c"][1])
    # a power-law stiffness: the middle force over the compression to the given exponent
    assert typical["k"] == pytest.approx(math.sqrt(bounds["k"][0] * bounds["k"][1])
                                         / 2e-3 ** 1.5)


def test_bounds_far_from_the_record_are_a_unit_slip(single_params, clean_pulse):
    processed = process(clean_pulse("single_element", single_params))
    model = get_model("single_element")
    # the synthetic ball's own k (2e7 N/m^1.3) is inside the plausible range: no complaint
    check_bound_scales(model, processed, {"k": (1e7, 4e7)}, {"alpha": 1.3})
    with pytest.raises(InputError, match="--bound"):
        check_bound_scales(model, processed, {"k": (1e3, 4e3)}, {"alpha": 1.3})
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_bound_scales(model, processed, {"k": (1e3, 4e3)}, {"alpha": 1.3},
                           allow=["unit-slip"])
    assert any(issubclass(w.category, InputWarning) for w in caught)


def test_parameter_scatter_of_repeats():
    table = SpeedTable("kelvin_voigt", (10.0, 20.0, 20.0), {"k": (1e6, 2e6, 4e6), "c": (1, 2, 4)})
    (group,) = parameter_scatter(table)
    assert group["speed_m_s"] == 20.0 and group["count"] == 2
    assert group["params_mean"] == pytest.approx({"k": 3e6, "c": 3.0})
    assert group["params_sd"] == pytest.approx({"k": math.sqrt(2) * 1e6, "c": math.sqrt(2)})


def test_one_record_fit_and_its_model_check(single_params, clean_pulse):
    processed = process(clean_pulse("single_element", single_params))
    fits = fit_records([processed], "single_element", ["a.csv"], generations=20, seed=1)
    assert fits.table is None and fits.repeats == [] and fits.labels == ["a.csv"]
    (fitted,) = fits.fits
    assert fitted.params["alpha"] == pytest.approx(single_params["alpha"], rel=0.02)
    assert fits.checks[0] == model_check(fitted, processed)
    assert fits.checks[0]["passed"] is True and fits.checks[0]["force_nrmse"] < 0.01
    out = fits.to_dict()
    assert out["file"] == "a.csv" and out["check"] == fits.checks[0]
    assert out["params"] == fitted.params


def test_several_records_make_a_table_in_speed_order(single_params, clean_pulse):
    processed = [process(clean_pulse("single_element", single_params, speed))
                 for speed in (20.0, 10.0)]
    fits = fit_records(processed, "single_element", ["fast.csv", "slow.csv"], generations=2,
                       population=8, polish=False)
    assert fits.labels == ["slow.csv", "fast.csv"]
    assert fits.table.speeds_m_s == pytest.approx((10.0, 20.0))
    # each check against its own record: the slow fit's measured peak is the slow record's
    assert fits.checks[0]["peak_force_measured_n"] == pytest.approx(
        processed[1].features.values["P6"])
    out = fits.to_dict()
    assert [f["file"] for f in out["fits"]] == ["slow.csv", "fast.csv"]
    assert out["model"] == "single_element" and "repeats" not in out
