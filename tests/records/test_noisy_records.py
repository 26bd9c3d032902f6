"""Issue 39: features of noisy load-cell records with the default processing (fitted edges, the
record's own smoothing, the load cell's resonance divided out), their uncertainty, and a filter
that smooths nothing."""

import json
import warnings
from importlib import resources

import numpy as np
import pytest

from ballimpact import apply_filter, process
from ballimpact.records import pulses
from ballimpact.errors import InputWarning
from ballimpact.records.record import contact_window, remove_baseline
from ballimpact.records.ringing import find_resonance

SAMPLE = resources.files("ballimpact") / "data" / "sample_impact.csv"
#: The sample's exact contact time and peak (its header, examples/make_sample_record.py).
SAMPLE_CONTACT_S, SAMPLE_PEAK_N = 1.09704e-3, 11219.9
MASS, SPEED = 0.16, 20.8


def quiet_process(record, **options):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", InputWarning)
        return process(record, warn_noisy=False, **options)


def test_the_sample_reads_its_contact_time_within_2_percent(capsys):
    """The package's own sample (1% noise, 14 kHz ringing, an offset) read 0.939 ms (-14%)
    before issue 39; with the defaults within 2% of its exact 1.097 ms, its peak within 2%, and
    the exact value inside the stated 90% interval."""
    from ballimpact.cli import main

    with resources.as_file(SAMPLE) as path:
        assert main(["features", str(path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    contact, u = out["contact_time_s"], out["uncertainty"]["contact_time_s"]
    assert contact == pytest.approx(SAMPLE_CONTACT_S, rel=0.02)
    assert abs(contact - SAMPLE_CONTACT_S) <= 1.645 * u
    assert out["peak_force_n"] == pytest.approx(SAMPLE_PEAK_N, rel=0.02)
    assert out["pulse_method"] == "fit"
    # every feature has its standard uncertainty in the JSON, positive where the noise acts
    assert set(out["uncertainty"]["features"]) == set(out["features"])
    assert out["uncertainty"]["features"]["P6"] > 0 and out["uncertainty"]["peak_force_n"] > 0


def test_the_sample_text_shows_the_uncertainties(capsys):
    from ballimpact.cli import main

    with resources.as_file(SAMPLE) as path:
        assert main(["features", str(path)]) == 0
    out = capsys.readouterr().out
    line = next(x for x in out.splitlines() if "contact_time_s" in x)
    assert "+/-" in line and "pulse: fit" in out


def noisy_cases(noise, seed, method="fit"):
    """Contact-time errors of Hunt-Crossley (COR 0.6 and 0.9) and half-sine pulses, 50-200 kHz,
    an ideal load cell, `noise` x the peak."""
    rng = np.random.default_rng(seed)
    shapes = [pulses.hunt_crossley_pulse(cor, SPEED, MASS) for cor in (0.6, 0.9)]
    shapes.append((lambda t: np.where((t > 0) & (t < 1e-3),
                                      1e4 * np.sin(np.pi * np.clip(t, 0, 1e-3) / 1e-3), 0.0),
                   1e-3, None))
    errors = []
    for k in range(12):
        pulse, duration, rebound = shapes[k % 3]
        record = pulses.load_cell_record(pulse, duration, (50e3, 100e3, 200e3)[k % 3 - 1],
                                         noise=noise, offset=0.01, rng=rng, mass_kg=MASS,
                                         impact_speed_m_s=SPEED, rebound_speed_m_s=rebound)
        found = quiet_process(record, method=method, uncertainty=False).features.values["P1"]
        errors.append(found / duration - 1)
    return np.array(errors)


def test_contact_time_of_noisy_records_is_not_cut_short():
    """1% noise: the fitted edges read the contact time within 2% at the median and without the
    bias of the samples' description (the threshold cuts up to 7% off; docs/features.md)."""
    fitted = noisy_cases(0.01, 1)
    samples = noisy_cases(0.01, 1, method="samples")
    assert np.median(np.abs(fitted)) < 0.02
    assert abs(np.mean(fitted)) < 0.01
    assert np.mean(samples) < -0.025  # what the default did before issue 39


def test_a_clean_record_is_described_by_its_samples():
    """Noise that does not raise the threshold: the samples, exactly as before (a simulation's
    features do not move)."""
    record = pulses.half_sine(1e4, 1e-3, 50e3, phase=0.3, mass_kg=MASS, impact_speed_m_s=SPEED)
    features = quiet_process(record).features
    assert features.method == "samples"
    assert features.values["P1"] == pytest.approx(1e-3, rel=1e-3)


def test_the_uncertainty_is_reproducible_and_shrinks_with_the_noise():
    pulse, duration, rebound = pulses.hunt_crossley_pulse(0.6, SPEED, MASS)
    u = []
    for noise in (0.005, 0.02):
        record = pulses.load_cell_record(pulse, duration, 100e3, noise=noise,
                                         rng=np.random.default_rng(3), mass_kg=MASS,
                                         impact_speed_m_s=SPEED)
        first = quiet_process(record).features.uncertainty
        assert quiet_process(record).features.uncertainty == first  # seeded bootstrap
        u.append(first)
    for key in ("P1", "P6", "impulse_n_s", "P17"):
        assert 0 < u[0][key] < u[1][key], key


def test_the_load_cells_resonance_is_found_and_divided_out():
    """A half-sine through an 8 kHz load cell (damping ratio 0.03) rings on after the contact:
    the resonance is found within 1% (damping ratio within 0.01) and dividing it out brings the
    peak, 2-3% high through the cell, within 1%."""
    rng = np.random.default_rng(4)
    pulse = lambda t: np.where((t > 0) & (t < 1e-3),  # noqa: E731
                               1e4 * np.sin(np.pi * np.clip(t, 0, 1e-3) / 1e-3), 0.0)
    record = pulses.load_cell_record(pulse, 1e-3, 100e3, noise=0.005, resonance_hz=8e3,
                                     rng=rng, mass_kg=MASS, impact_speed_m_s=SPEED)
    base = remove_baseline(record)
    resonance = find_resonance(base, contact_window(base))
    assert resonance.frequency_hz == pytest.approx(8e3, rel=0.01)
    assert resonance.damping_ratio == pytest.approx(0.03, abs=0.01)
    kept = quiet_process(record, ringing=False).features.values["P6"]
    divided = quiet_process(record)
    assert kept / 1e4 - 1 > 0.015
    assert divided.features.values["P6"] == pytest.approx(1e4, rel=0.01)
    assert divided.filtered.metadata["load_cell_resonance"]["frequency_hz"] == pytest.approx(
        8e3, rel=0.01)


def test_a_cell_is_found_from_the_ringing_inside_the_contact():
    """A damped ball (Hunt-Crossley, COR 0.45) through an 8 kHz cell at 1% noise: its free
    vibration after the contact is 1-2 x the noise, which the first search (a damped sine
    fitted there alone, taken at 4 x the noise) missed; the ringing inside the contact gives the
    cell away. Four records: found within 4% (damping ratio 0.02-0.05 for 0.03) and the peak,
    2.9-4.2% high through the cell, within 0.6%."""
    pulse, duration, rebound = pulses.hunt_crossley_pulse(0.45, SPEED, MASS)
    exact = float(pulse(np.linspace(0, duration, 20001)).max())
    for seed in range(4):
        record = pulses.load_cell_record(pulse, duration, 100e3, noise=0.01, resonance_hz=8e3,
                                         rng=np.random.default_rng(seed), mass_kg=MASS,
                                         impact_speed_m_s=SPEED, rebound_speed_m_s=rebound)
        base = remove_baseline(record)
        resonance = find_resonance(base, contact_window(base))
        assert resonance.frequency_hz == pytest.approx(8e3, rel=0.04)
        assert 0.02 <= resonance.damping_ratio <= 0.05
        kept = quiet_process(record, ringing=False, uncertainty=False).features.values["P6"]
        divided = quiet_process(record, uncertainty=False).features.values["P6"]
        assert kept / exact - 1 > 0.025
        assert divided == pytest.approx(exact, rel=0.006)


def test_a_ball_that_rings_only_in_the_contact_is_not_taken_for_a_cell():
    """A ball's own ringing (4% at 18 kHz, as the FE pulses' penalty contact rings) ends with the
    contact; a cell's rings on. Through an ideal cell at 1% noise nothing is divided out."""
    hertz, duration, _ = pulses.hunt_crossley_pulse(None, SPEED, MASS)
    ringing = lambda t: hertz(t) * (1 + 0.04 * np.sin(2 * np.pi * 18e3 * t))  # noqa: E731
    for seed in range(4):
        record = pulses.load_cell_record(ringing, duration, 100e3, noise=0.01,
                                         rng=np.random.default_rng(seed), mass_kg=MASS,
                                         impact_speed_m_s=SPEED)
        base = remove_baseline(record)
        assert find_resonance(base, contact_window(base)) is None


def test_the_cells_inertia_delays_the_onset_until_it_is_divided_out():
    """docs/features.md, "The load cell's inertia delays the onset": the sample's Hertz ball
    through an 8 kHz cell at 200 kHz, noise-free (0.01%): the raw record's fitted start is
    1.5% of the contact time late (asserted over 1.2%); with the resonance given its start is
    within 0.3% of the force's."""
    pulse, duration, rebound = pulses.hunt_crossley_pulse(None, SPEED, MASS)
    record = pulses.load_cell_record(pulse, duration, 200e3, noise=1e-4, resonance_hz=8e3,
                                     rng=np.random.default_rng(3), mass_kg=MASS,
                                     impact_speed_m_s=SPEED, rebound_speed_m_s=rebound)
    raw = quiet_process(record, ringing=False, uncertainty=False).features.window.start_s
    given = quiet_process(record, resonance_hz=8e3, uncertainty=False).features.window.start_s
    assert raw / duration > 0.012
    assert abs(given / duration) < 0.003


def test_a_filter_that_smooths_nothing_warns():
    """LOESS with its default window (10% of a 1 ms contact) is 5 samples at 50 kHz, whose
    tricube weights leave the 3 middle ones: it returns the record as it was. A warning says
    so, naming the filter, instead of the JSON saying it was applied."""
    pulse, duration, rebound = pulses.hunt_crossley_pulse(0.6, SPEED, MASS)
    record = pulses.load_cell_record(pulse, duration, 50e3, noise=0.01,
                                     rng=np.random.default_rng(5), mass_kg=MASS,
                                     impact_speed_m_s=SPEED)
    with pytest.warns(InputWarning, match=r"filter loess .* smoothed nothing"):
        filtered = apply_filter(remove_baseline(record), "loess")
    assert filtered.metadata["filter_change_rms_n"] < 0.1 * 0.01 * filtered.force_n.max()


@pytest.mark.parametrize("argv, words", [
    (["--load-cell-hz", "-5"], ["--load-cell-hz", "(0, inf)"]),
    (["--load-cell-hz", "8"], ["--load-cell-hz", "looks like kHz", "use 8000"]),
    (["--load-cell-hz", "150000"], ["--load-cell-hz", "Nyquist", "100000"]),
    (["--load-cell-hz", "8000", "--load-cell-damping", "3"],
     ["--load-cell-damping", "(0, 1)", "use 0.03"]),
    (["--load-cell-hz", "8000", "--load-cell-damping", "-0.1"], ["--load-cell-damping", "(0, 1)"]),
    (["--pulse-method", "spline"], ["--pulse-method", "fit", "samples"]),
])
def test_new_processing_flags_refuse_bad_values(bad_input, argv, words):
    with resources.as_file(SAMPLE) as path:
        bad_input(["features", path, *argv], *words)


@pytest.mark.slow
def test_the_90_percent_intervals_cover_the_exact_values():
    """40 Hunt-Crossley records (COR 0.6, 100 kHz, 1% noise, an ideal load cell): the stated
    90% intervals (value +- 1.645 u) hold the exact contact time and peak force in 75-100% of
    them (90% expected; binomial scatter of 40 records: +-8%)."""
    pulse, duration, rebound = pulses.hunt_crossley_pulse(0.6, SPEED, MASS)
    fine = np.linspace(0.0, duration, 200001)
    peak = float(pulse(fine).max())
    rng = np.random.default_rng(9)
    covered = {"P1": [], "P6": []}
    for _ in range(40):
        record = pulses.load_cell_record(pulse, duration, 100e3, noise=0.01, rng=rng,
                                         mass_kg=MASS, impact_speed_m_s=SPEED,
                                         rebound_speed_m_s=rebound)
        features = quiet_process(record).features
        for key, exact in (("P1", duration), ("P6", peak)):
            covered[key].append(abs(features.values[key] - exact)
                                <= 1.645 * features.uncertainty[key])
    for key, hits in covered.items():
        assert 0.75 <= np.mean(hits) <= 1.0, (key, np.mean(hits))


def test_a_given_value_gets_no_uncertainty():
    """The impact speed P15 is an input, not read from the record: the bootstrap's draws all give
    it back, and no model-error floor is added to it (`reconstruct.uncertainty_model`)."""
    pulse, duration, rebound = pulses.hunt_crossley_pulse(0.6, SPEED, MASS)
    record = pulses.load_cell_record(pulse, duration, 100e3, noise=0.01,
                                     rng=np.random.default_rng(5), mass_kg=MASS,
                                     impact_speed_m_s=SPEED, rebound_speed_m_s=rebound)
    u = quiet_process(record).features.uncertainty
    assert u["P15"] == 0.0 and u["P16"] == 0.0 and u["P17"] == 0.0  # measured speeds
    assert u["P1"] > 0.0 and u["P6"] > 0.0
