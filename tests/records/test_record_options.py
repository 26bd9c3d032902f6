"""`RecordOptions`: one value for how every verb loads and processes a record file, with the
library's defaults, used by the verbs' library functions in place of a loader and a
processor."""

import dataclasses
import json
from pathlib import Path
import inspect

import pytest

from ballimpact.errors import InputError

from ballimpact.records.loaders import load_record
from ballimpact.records.options import LOADING_FIELDS, PROCESSING_FIELDS, RecordOptions
from ballimpact.records.pipeline import process
from ballimpact.records.summaries import features_of_files

SAMPLE = "builtin:sample"


def test_every_field_is_a_loading_or_a_processing_option():
    names = [f.name for f in dataclasses.fields(RecordOptions)]
    assert sorted(names) == sorted(LOADING_FIELDS + PROCESSING_FIELDS)
    assert not set(LOADING_FIELDS) & set(PROCESSING_FIELDS)


def test_the_processing_defaults_are_the_pipelines():
    """Each processing option's default is `pipeline.process`'s, and each is one of its keyword
    arguments (so a new one there shows here)."""
    parameters = inspect.signature(process).parameters
    assert set(PROCESSING_FIELDS) == set(parameters) - {"record"}
    defaults = RecordOptions()
    for name in PROCESSING_FIELDS:
        assert getattr(defaults, name) == parameters[name].default, name


def test_the_loading_defaults_leave_the_side_file_and_the_loader_to_decide():
    """None: the side file's value, else the loader's default (`load_record` takes them as keyword
    arguments and ignores None)."""
    assert RecordOptions().loading() == {name: None for name in LOADING_FIELDS}
    assert RecordOptions().load(SAMPLE).impact_speed_m_s == load_record(SAMPLE).impact_speed_m_s


def test_load_and_process_are_the_library_calls_with_the_options():
    options = RecordOptions(impact_speed_m_s=21.0, filter="loess", method="samples",
                            uncertainty=False)
    record = options.load(SAMPLE)
    assert record.impact_speed_m_s == 21.0  # over the side file's 20.8 m/s
    expected = process(load_record(SAMPLE, impact_speed_m_s=21.0), filter="loess",
                       method="samples", uncertainty=False)
    assert options.process(record).features.values == expected.features.values


def test_options_are_frozen():
    options = RecordOptions()
    with pytest.raises(dataclasses.FrozenInstanceError):
        options.filter = "loess"
    assert dataclasses.replace(options, filter="loess").filter == "loess"


def test_features_of_files_takes_the_options():
    result, processed = features_of_files([SAMPLE], options=RecordOptions(mass_kg=0.161))
    assert processed[0].raw.mass_kg == 0.161
    assert result["features"]["P15"] == pytest.approx(20.8)


def test_a_functions_allow_reaches_its_records_processing():
    """One set of allowed checks: `allow=` given to a function that reads records joins its
    `RecordOptions.allow` (a rebound faster than the impact is refused unless allowed)."""
    from importlib import resources

    from ballimpact.universal.by_speed import identify_files

    assert RecordOptions(allow=("clipping",)).allowing({"unit-slip"}).allow == \
        ("clipping", "unit-slip")
    sample = resources.files("ballimpact") / "data" / "sample_impact.csv"
    options = RecordOptions(mass_kg=0.16, impact_speed_m_s=20.8, rebound_speed_m_s=25.0)
    with pytest.raises(InputError, match="cor-above-one"):
        identify_files([Path(str(sample))], options=options, verify=False)
    _, out = identify_files([Path(str(sample))], options=options, verify=False,
                            allow={"cor-above-one"})
    assert "cor-above-one" not in json.dumps(out.get("errors", []))
