"""Repeated tests (issue 26 item 4): `features` over many records grouped by speed, checked
against independent computations: five noisy repeats at each of three speeds of a Hunt-Crossley
ball (solved here with scipy), the per-group means and SDs against np.mean / np.std(ddof=1) of
the per-file `features --json` results, the group means against the exact pulses, and the mean
pulse band against the mean of the exact pulses."""

import csv
import json

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from ballimpact.records import repeats
from ballimpact.cli import main
from ballimpact.errors import InputError
from ballimpact.lumped import hunt_crossley_lambda

MASS_KG = 0.16
STIFFNESS_N_M15 = 2.06e7            # F = k y^1.5 (1 + lambda y'): about 1 ms at 20 m/s
LAMBDA_S_M = hunt_crossley_lambda(0.7, 20.0)  # COR 0.90, 0.82, 0.70 at 5, 10, 20 m/s
NOMINAL_M_S = (5.0, 10.0, 20.0)
REPEATS = 5
RATE_HZ = 200e3
NOISE_FRACTION = 0.003              # of the peak: below the pipeline's noisy-record warning


def hunt_crossley(speed_m_s, stiffness):
    """Exact pulse (dense solution), contact time (s) and rebound speed (m/s)."""
    force = lambda y, v: stiffness * max(y, 0.0) ** 1.5 * (1 + LAMBDA_S_M * v)
    leave = lambda t, s: s[0]
    leave.terminal, leave.direction = True, -1
    sol = solve_ivp(lambda t, s: [s[1], -force(*s) / MASS_KG], (0, 0.02), [0.0, speed_m_s],
                    events=leave, rtol=1e-10, atol=1e-14, dense_output=True, max_step=2e-6)
    contact = float(sol.t_events[0][0])

    def pulse(t):
        t = np.atleast_1d(np.asarray(t, dtype=float))
        inside = (t > 0) & (t < contact)
        out = np.zeros_like(t)
        out[inside] = [force(*sol.sol(x)) for x in t[inside]]
        return out

    return pulse, contact, float(-sol.sol(contact)[1])


def make_repeat(path, nominal, seed, noise=NOISE_FRACTION, mass_kg=MASS_KG):
    """A noisy repeat near `nominal` m/s: the speed off by up to 2%, the ball's stiffness by up
    to 3%, the contact instant anywhere between samples, a load-cell offset and white noise;
    the side file holds the mass, the measured speed and the exact rebound speed."""
    rng = np.random.default_rng(seed)
    speed = nominal * (1 + rng.uniform(-0.02, 0.02))
    pulse, contact, rebound = hunt_crossley(speed, STIFFNESS_N_M15 * (1 + rng.uniform(-.03, .03)))
    shift = rng.uniform(0, 1 / RATE_HZ)  # contact starts `shift` after a sample
    time = np.arange(-0.6e-3, contact + 0.6e-3, 1 / RATE_HZ)
    clean = pulse(time - shift)
    peak = clean.max()
    measured = clean + 25.0 + noise * peak * rng.standard_normal(time.size)
    path.write_text("time_s,force_n\n" + "".join(f"{t:.10e},{f:.10g}\n"
                                                 for t, f in zip(time, measured)))
    path.with_suffix(".json").write_text(json.dumps(
        {"mass_kg": mass_kg, "impact_speed_m_s": speed, "rebound_speed_m_s": round(rebound, 3)}))
    return {"speed": speed, "pulse": pulse, "contact": contact, "peak": peak, "shift": shift}


@pytest.fixture(scope="module")
def repeat_set(tmp_path_factory):
    """15 records (five at each nominal speed) in one folder, with their exact pulses."""
    folder = tmp_path_factory.mktemp("repeats")
    truth = {}
    for n, nominal in enumerate(NOMINAL_M_S):
        for k in range(REPEATS):
            path = folder / f"v{int(nominal):02d}_r{k + 1}.csv"
            truth[path] = {"nominal": nominal, **make_repeat(path, nominal, 100 * n + k)}
    return folder, truth


def run(capsys, *argv):
    code = main([str(arg) for arg in argv])
    out, err = capsys.readouterr()
    return code, out, err


def run_json(capsys, *argv):
    code, out, err = run(capsys, *argv, "--json")
    assert code == 0, err
    return json.loads(out)


# --------------------------------------------------------------------------- pure functions


def test_expand_records_takes_record_files_of_folders_and_refuses_mistakes(tmp_path):
    for name in ("b.csv", "a.CSV", "c.wav", "a.json", "notes.txt", ".hidden.csv"):
        (tmp_path / name).write_text("x")
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "d.csv").write_text("x")
    other = tmp_path / "sub" / "d.csv"
    assert repeats.expand_records([tmp_path]) == [tmp_path / n for n in ("a.CSV", "b.csv",
                                                                         "c.wav")]
    assert repeats.expand_records([other, tmp_path])[0] == other   # files as given, in order
    with pytest.raises(InputError, match="given twice"):
        repeats.expand_records([tmp_path / "b.csv", tmp_path])
    with pytest.raises(InputError, match="given twice"):
        repeats.expand_records([other, tmp_path / "sub" / ".." / "sub" / "d.csv"])
    with pytest.raises(InputError, match="no such file or folder"):
        repeats.expand_records([tmp_path / "absent"])
    empty = tmp_path / "empty"
    empty.mkdir()
    with pytest.raises(InputError, match=r"holds no test records \(\*.csv, \*.wav\)"):
        repeats.expand_records([empty])


def test_group_by_speed_clusters_and_assigns_to_nominal_speeds():
    speeds = [5.1, 19.6, 4.9, 10.2, 20.5, 9.8, 5.0]
    labels = repeats.group_by_speed(speeds)
    # clusters: {4.9, 5.0, 5.1}, {9.8, 10.2}, {19.6, 20.5}: each labelled with its mean speed
    expected = [5.0, 20.05, 5.0, 10.0, 20.05, 10.0, 5.0]
    np.testing.assert_allclose(labels, expected, rtol=1e-12)
    np.testing.assert_array_equal(repeats.group_by_speed(speeds, [20, 5, 10]),
                                  [5, 20, 5, 10, 20, 10, 5])
    # a group spans at most the tolerance: a series of steps each under 10% stays a series
    series = repeats.group_by_speed([10.0, 10.9, 11.8, 12.8], tolerance=0.1)
    assert np.unique(series).size == 2  # 10, 10.9 | 11.8, 12.8
    assert list(series) == pytest.approx([10.45, 10.45, 12.3, 12.3])
    # the split rule: a step of exactly the tolerance joins, more splits
    assert np.unique(repeats.group_by_speed([10.0, 10.5], tolerance=0.05)).size == 1
    assert np.unique(repeats.group_by_speed([10.0, 10.5001], tolerance=0.05)).size == 2
    with pytest.raises(InputError, match=r"b.csv: impact speed 14 m/s .* \(5, 10, 20 m/s\)"):
        repeats.group_by_speed([5.0, 14.0], [5, 10, 20], files=["a.csv", "b.csv"])
    with pytest.raises(InputError, match="a percentage"):
        repeats.group_by_speed([5.0], tolerance=10)
    with pytest.raises(InputError, match="given twice"):
        repeats.group_by_speed([5.0], [5, 5])


def test_check_masses_compares_within_each_speed_group():
    files = ["a.csv", "b.csv", "c.csv", "d.csv"]
    groups = [5.0, 5.0, 10.0, 10.0]
    repeats.check_masses([0.16, 0.1615, 0.145, 0.145], files, groups)  # 0.94%; other groups
    with pytest.raises(InputError, match=r"c.csv \(0.145 kg\) and d.csv \(0.16 kg\)"):
        repeats.check_masses([0.16, 0.16, 0.145, 0.16], files, groups)


# --------------------------------------------------------------------------- the command


def test_repeats_give_per_speed_means_and_sds_of_independent_per_file_results(
        capsys, repeat_set, tmp_path):
    folder, truth = repeat_set
    table = tmp_path / "table.csv"
    result = run_json(capsys, "features", folder, "--table", table)
    # independently: each file through `features FILE --json`, grouped by how it was made
    single = {path: run_json(capsys, "features", path) for path in truth}
    groups = result["groups"]
    assert [g["count"] for g in groups] == [REPEATS] * 3
    assert result["grouping"]["rule"] == "clustered"
    for group, nominal in zip(groups, NOMINAL_M_S):
        members = [p for p in truth if truth[p]["nominal"] == nominal]
        assert sorted(group["files"]) == sorted(str(p) for p in members)
        speeds = [truth[p]["speed"] for p in members]
        assert group["speed_m_s"] == pytest.approx(np.mean(speeds), rel=1e-12)
        for name in repeats.FEATURE_COLUMNS:
            if name in single[members[0]]:
                values = [single[p][name] for p in members]
            else:  # the 19 values keyed by their descriptive names
                key = next(k for k, v in single[members[0]]["feature_names"].items() if v == name)
                values = [single[p]["features"][key] for p in members]
            assert group["mean"][name] == pytest.approx(np.mean(values), rel=1e-9, abs=1e-12)
            assert group["sd"][name] == pytest.approx(np.std(values, ddof=1), rel=1e-9,
                                                      abs=1e-12)
        # and against the physics: the exact pulses' contact time and peak force. The noise
        # threshold (5 x 0.3% of the peak) cuts the slow y^1.5 ends: a record's contact time
        # reads up to 3% short, its peak up to 1% high (noise on the top samples)
        exact_tc = np.mean([truth[p]["contact"] for p in members])
        exact_peak = np.mean([truth[p]["peak"] for p in members])
        assert group["mean"]["contact_time_s"] == pytest.approx(exact_tc, rel=0.03)
        assert group["mean"]["peak_force_n"] == pytest.approx(exact_peak, rel=0.015)
    # the table: a row per record, numbers as the per-file results give them (round trip)
    with table.open() as handle:
        rows = list(csv.DictReader(handle))
    assert list(rows[0]) == list(repeats.TABLE_COLUMNS)
    assert len(rows) == 3 * REPEATS
    for row in rows:
        one = single[folder / row["file"].split("/")[-1]]
        assert float(row["peak_force_n"]) == one["peak_force_n"]
        assert float(row["dynamic_stiffness_n_m"]) == one["dynamic_stiffness_n_m"]
        assert float(row["kurtosis"]) == one["features"]["P11"]
    assert "table.csv" not in " ".join(r["file"] for r in rows)
    # the same folder again, with the table inside it: the table is not taken for a record
    inside = folder / "table.csv"
    try:
        for _ in range(2):  # the second run finds the first run's table in the folder
            again = run_json(capsys, "features", folder, "--table", inside)
            assert len(again["records"]) == 3 * REPEATS
        assert inside.read_text() == table.read_text().replace(str(table), str(inside))
    finally:
        inside.unlink(missing_ok=True)


def test_nominal_speeds_label_the_groups_and_the_text_output(capsys, repeat_set):
    folder, _ = repeat_set
    result = run_json(capsys, "features", folder, "--speeds", "20,5,10")
    assert [g["speed_m_s"] for g in result["groups"]] == list(NOMINAL_M_S)
    assert result["grouping"]["rule"] == "nominal"
    clustered = run_json(capsys, "features", folder)
    for a, b in zip(result["groups"], clustered["groups"]):
        assert a["mean"] == b["mean"] and a["files"] == b["files"]
    code, out, err = run(capsys, "features", folder, "--speeds", "5,10,20,40")
    assert code == 0, err
    assert "warning: nominal speed 40 m/s: no record within the speed tolerance" in err
    assert "15 records in 3 speed groups" in out
    g = result["groups"][1]
    cor = f"{g['mean']['cor']:.5g} ± {g['sd']['cor']:.2g}"
    assert cor in out


def test_mean_pulse_band_matches_the_exact_pulses(repeat_set):
    _, truth = repeat_set
    from ballimpact import load_record, process

    paths = sorted(truth)
    processed = [process(load_record(p), warn_noisy=False) for p in paths]
    groups = repeats.group_by_speed([p.features.values["P15"] for p in processed])
    bands = repeats.pulse_bands(processed, groups, points=301)
    found = dict(zip(paths, processed))
    for band, nominal in zip(bands, NOMINAL_M_S):
        members = [p for p in paths if truth[p]["nominal"] == nominal]
        assert band.count == len(members)
        # the grid spans the longest contact time (as found: up to 3% short, see above)
        assert band.time_s[-1] == pytest.approx(max(truth[p]["contact"] for p in members),
                                                rel=0.03)
        # the contact start as the features find it, against the true contact instant: the
        # noise threshold (1.5% of the peak) and the line to zero through the two outermost
        # (noisy) samples of the y^1.5 rise put it off by less than 4 samples (20 us)
        offset = [found[p].features.window.start_s - truth[p]["shift"] for p in members]
        assert np.max(np.abs(offset)) < 4 / RATE_HZ
        # independent: the exact pulses at the grid, each from the contact start the features
        # found (band time 0 = record time start_s = exact time start_s - shift); only the
        # noise (0.3% of the peak) remains: mean and SD within 1% of the peak
        exact = np.array([truth[p]["pulse"](band.time_s + found[p].features.window.start_s
                                            - truth[p]["shift"]) for p in members])
        peak = exact.max()
        assert np.max(np.abs(band.mean_n - exact.mean(axis=0))) < 0.01 * peak
        assert np.max(np.abs(band.sd_n - exact.std(axis=0, ddof=1))) < 0.01 * peak
        assert np.max(np.abs(band.min_n - exact.min(axis=0))) < 0.015 * peak
        assert np.max(np.abs(band.max_n - exact.max(axis=0))) < 0.015 * peak


def test_band_of_clean_pulses_is_their_exact_mean(tmp_path):
    """Without noise the band is the mean, SD, min and max of the exact pulses aligned at the
    contact starts the features found, to the sampling's linear-interpolation error (0.2% of
    the peak at 200 kHz); those starts lie within a sample of the true contact instants."""
    from ballimpact import load_record, process

    truth = [make_repeat(tmp_path / f"c{k}.csv", 10.0, 7 + k, noise=0.0) for k in range(3)]
    processed = [process(load_record(tmp_path / f"c{k}.csv")) for k in range(3)]
    band = repeats.pulse_band([p.features for p in processed], 10.0, points=401)
    starts = [p.features.window.start_s - t["shift"] for p, t in zip(processed, truth)]
    assert np.max(np.abs(starts)) < 1 / RATE_HZ
    exact = np.array([t["pulse"](band.time_s + start) for t, start in zip(truth, starts)])
    peak = exact.max()
    assert np.max(np.abs(band.mean_n - exact.mean(axis=0))) < 2e-3 * peak
    assert np.max(np.abs(band.sd_n - exact.std(axis=0, ddof=1))) < 2e-3 * peak
    assert np.max(np.abs(band.min_n - exact.min(axis=0))) < 2e-3 * peak
    assert np.max(np.abs(band.max_n - exact.max(axis=0))) < 2e-3 * peak


def test_plot_draws_the_band_per_group(capsys, repeat_set, tmp_path):
    folder, _ = repeat_set
    plot = tmp_path / "band.png"
    result = run_json(capsys, "features", folder, "--plot", plot)
    assert result["plot"] == str(plot)
    assert plot.stat().st_size > 20_000


def test_one_record_keeps_the_single_record_output(capsys, repeat_set, tmp_path):
    _, truth = repeat_set
    path = min(truth)
    alone = tmp_path / "alone"
    alone.mkdir()
    for suffix in (".csv", ".json"):
        (alone / path.with_suffix(suffix).name).write_text(path.with_suffix(suffix).read_text())
    by_file = run_json(capsys, "features", path)
    by_folder = run_json(capsys, "features", alone)
    assert "groups" not in by_folder
    assert by_folder["features"] == by_file["features"]


# --------------------------------------------------------------------------- bad input


def test_bad_input_of_repeats(bad_input, repeat_set, tmp_path):
    folder, truth = repeat_set
    empty = tmp_path / "empty"
    empty.mkdir()
    (empty / "x.json").write_text("{}")
    bad_input(["features", empty], "empty", "holds no test records", "*.csv, *.wav")
    bad_input(["features", folder, "--table", tmp_path / "t.txt"], "--table", "t.txt",
              "must be a .csv file")
    bad_input(["features", folder, "--speeds", "5,10"], "v20_r1.csv", "not within 5%",
              "5, 10 m/s")
    bad_input(["features", folder, "--speeds", "5,ten"], "--speeds", "not a number")
    bad_input(["features", folder, "--speed-tolerance", "10"], "--speed-tolerance",
              "a percentage")
    first = min(truth)
    bad_input(["features", folder, first], first.name, "given twice")
    bad_input(["features", first, "--table", first], "--table", "one of the records given")
    mixed = tmp_path / "mixed"
    mixed.mkdir()
    make_repeat(mixed / "a.csv", 10.0, 1)
    make_repeat(mixed / "b.csv", 10.0, 2, mass_kg=0.145)
    bad_input(["features", mixed], "a.csv (0.16 kg)", "b.csv (0.145 kg)", "mixed masses")


def test_mean_pulse_record_carries_the_mean_impulse(repeat_set):
    """The integral is linear: the mean pulse's impulse is the mean of the impulses (to the
    resampling of each piecewise-linear pulse on the band's grid: 401 points, 0.1%)."""
    _, truth = repeat_set
    from ballimpact import extract_features, load_record, process

    members = [p for p in sorted(truth) if truth[p]["nominal"] == 10.0]
    processed = [process(load_record(p), warn_noisy=False) for p in members]
    band = repeats.pulse_band([p.features for p in processed], 10.0, points=401)
    mean, _ = repeats.mean_sd([repeats.record_row(p, f, 10.0)
                               for p, f in zip(processed, members)])
    record = band.record(mean["mass_kg"], mean["impact_speed_m_s"])
    features = extract_features(record)
    assert features.impulse_n_s == pytest.approx(mean["impulse_n_s"], rel=1e-3)
    # rebound from the impulse: J/m - v_in, with J the mean impulse
    assert features.values["P16"] == pytest.approx(
        mean["impulse_n_s"] / MASS_KG - mean["impact_speed_m_s"], rel=2e-3)
