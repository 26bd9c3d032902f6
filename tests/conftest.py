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
@pytest.fixture(scope="session")
def single_params():
    """Known single-element parameters (SI) that the synthetic tests are made from."""
    from ballimpact.lumped.synthetic import SINGLE

    return dict(SINGLE)


@pytest.fixture(scope="session")
def three_params():
    """Known three-element parameters (SI) that the synthetic tests are made from."""
    from ballimpact.lumped.synthetic import THREE

    return dict(THREE)


@pytest.fixture(scope="session")
def clean_pulse():
    """`clean_pulse(model, params, speed=20.0, rate_hz=200e3)` (`lumped.synthetic.clean`)."""
    from ballimpact.lumped.synthetic import clean

    return clean


@pytest.fixture(scope="session")
def noisy_pulse():
    """`noisy_pulse(record, fraction, seed)` (`lumped.synthetic.noisy`)."""
    from ballimpact.lumped.synthetic import noisy

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
