"""Fixtures shared by the tests: test modules do not import each other, what several of them
use is here."""

import json

import numpy as np
import pytest


@pytest.fixture
def bad_input(capsys):
    """`bad_input(argv, *fragments)`: run the command line in this process and check the contract
    for bad input (exit code 2, exactly one stderr line starting with 'error:', no traceback, no
    progress line before it, nothing on stdout); every fragment must appear in that line
    (case-insensitive). Returns the line."""
    from ballimpact.cli import main

    def check(argv, *fragments):
        capsys.readouterr()  # drop what earlier steps printed
        code = main([str(arg) for arg in argv])
        out, err = capsys.readouterr()
        lines = [line for line in err.replace("\r", "\n").splitlines() if line.strip()]
        assert code == 2, f"exit {code}, stderr: {err}"
        assert len(lines) == 1, f"expected one stderr line, got: {err!r}"
        assert lines[0].startswith("error: "), lines[0]
        assert "Traceback" not in err and out == "", (out, err)
        for fragment in fragments:
            assert fragment.lower() in lines[0].lower(), f"{fragment!r} not in {lines[0]!r}"
        return lines[0]

    return check


# ---- synthetic lumped-model impacts, for the identification tests ------------------------------
LUMPED_MASS_KG, LUMPED_SPEED_M_S, LUMPED_RATE_HZ = 0.16, 20.0, 200e3
SINGLE_ELEMENT = {"k": 2e7, "alpha": 1.3, "c": 80.0}
THREE_ELEMENT = {"k1": 2e7, "alpha1": 1.3, "c1": 40.0, "k2": 5e6, "alpha2": 1.1, "c2": 60.0,
                 "k3": 4e7, "alpha3": 1.45, "c3": 20.0, "m1": 0.06, "m2": 0.04, "m3": 0.06}


@pytest.fixture(scope="session")
def single_params():
    """Known single-element parameters (SI) that the synthetic tests are made from."""
    return dict(SINGLE_ELEMENT)


@pytest.fixture(scope="session")
def three_params():
    """Known three-element parameters (SI) that the synthetic tests are made from."""
    return dict(THREE_ELEMENT)


@pytest.fixture(scope="session")
def clean_pulse():
    """`clean_pulse(model, params, speed=20.0, rate_hz=200e3)`: the model's pulse of a 0.16 kg
    ball sampled at `rate_hz`, the grid shifted by 0.37 of a sample from the contact start; the
    measured rebound speed is the exact one."""
    from ballimpact.lumped import simulate

    def clean(model, params, speed=LUMPED_SPEED_M_S, rate_hz=LUMPED_RATE_HZ):
        record = simulate(model, params, impact_speed_m_s=speed, mass_kg=LUMPED_MASS_KG,
                          rate_hz=rate_hz)
        return record.replace(time_s=record.time_s + 0.37 / rate_hz, velocity_m_s=None)

    return clean


@pytest.fixture(scope="session")
def noisy_pulse():
    """`noisy_pulse(record, fraction, seed)`: white noise of RMS `fraction` of the peak force
    added to every sample."""

    def noisy(record, fraction, seed):
        rng = np.random.default_rng(seed)
        noise = fraction * record.force_n.max() * rng.standard_normal(record.force_n.size)
        return record.replace(force_n=record.force_n + noise)

    return noisy


# ---- a half-sine test record, for the calibrate command's tests --------------------------------
@pytest.fixture(scope="session")
def half_sine_record():
    """`half_sine_record(folder, contact_s)`: `folder/ball.csv` (time_s, force_n), a half-sine
    pulse of `contact_s` from 0.2 ms on, whose impulse is m (v_in + v_out) of a 0.16 kg ball at
    20 m/s with COR 0.6, sampled at 100 kHz over 2 ms; with a JSON side file giving the mass and
    the impact speed. Cheap to process, so that a case runs the FE solver only where it means
    to. Returns the CSV's path."""
    mass_kg, speed_m_s, cor = 0.16, 20.0, 0.6

    def write(folder, contact_s):
        t = np.arange(0.0, 2e-3, 1e-5)
        peak = mass_kg * speed_m_s * (1 + cor) * np.pi / (2 * contact_s)
        inside = (t > 2e-4) & (t < 2e-4 + contact_s)
        force = np.where(inside, peak * np.sin(np.pi * (t - 2e-4) / contact_s), 0.0)
        csv = folder / "ball.csv"
        np.savetxt(csv, np.column_stack([t, force]), delimiter=",", header="time_s,force_n",
                   comments="")
        (folder / "ball.json").write_text(json.dumps({"mass_kg": mass_kg,
                                                      "impact_speed_m_s": speed_m_s}))
        return csv

    return write


# ---- the report command's tests ------------------------------------------------------------------
@pytest.fixture
def fail_model(monkeypatch):
    """`fail_model(error, name=None)`: make the report's runs of the model `name` (every model
    if None) raise `error`; the other models run as usual (undone after the test)."""
    import ballimpact.report.build as build

    def fail(error, name=None):
        original = build.run_model  # a model made to fail before keeps failing

        def run_model(spec, test, **options):
            if name is None or spec.name == name:
                raise error
            return original(spec, test, **options)

        monkeypatch.setattr(build, "run_model", run_model)

    return fail
