"""Bad input to the ball, the FE verbs and export (issue 24): unit slips in ball specifications
(the `ball-units` check), the memory guard before meshing (`large-run`), the 3D solver's and
export's flags and files, and imported materials. Each case ends with exit code 2 and one line
naming the problem, before anything is meshed (the `no_meshing` fixture fails any attempt)."""

import json
import re
import time
import warnings
from pathlib import Path

import pytest

from ballimpact.errors import InputError, InputWarning
from ballimpact.fe import load_ball, simulate
from ballimpact.fe import SolverOptions, engine
from ballimpact.fe.progress import RunEstimate
from ballimpact.balls.checks import BALL_RANGES, check_ball
from ballimpact.checks import CHECKS

RUBBER = {"model": "neo_hookean", "c10_pa": 1.0e6}
#: a plausible one-layer ball (a 73 mm rubber ball); each case changes one thing
GOOD = {"name": "rubber", "layers": [{"name": "rubber", "outer_radius_m": 0.0366,
                                      "density_kg_m3": 1130.0, "material": RUBBER}]}
ELASTIC = {"model": "linear_elastic", "youngs_modulus_pa": 2e9, "poissons_ratio": 0.3}
TARGET = {"name": "plate", "half_width_m": 0.1,
          "layers": [{"thickness_m": 0.015, "density_kg_m3": 2000.0, "material": ELASTIC}]}


def ball(**layer):
    """`GOOD` with the layer's keys replaced."""
    spec = json.loads(json.dumps(GOOD))
    spec["layers"][0].update(layer)
    return spec


@pytest.fixture(autouse=True)
def no_meshing(monkeypatch):
    """Every case must fail before a mesh is built (a mis-scaled ball can exhaust memory)."""
    def refuse(*args, **kwargs):
        raise AssertionError("meshed before the input was checked")
    monkeypatch.setattr(engine, "kernel_for", refuse)
    import ballimpact.export as export

    monkeypatch.setattr(export, "ball_geometry", refuse)


@pytest.fixture
def files(tmp_path):
    """`files(name=content, ...)`: write JSON (dicts, lists) or text into tmp_path; returns it."""
    def write(**contents):
        for name, content in contents.items():
            text = content if isinstance(content, str) else json.dumps(content)
            (tmp_path / name.replace("_", ".")).write_text(text)
        return tmp_path
    return write


# ---- ball unit slips (`ball-units`) -------------------------------------------------------------

@pytest.mark.parametrize("layer, fragments", [
    ({"outer_radius_m": 36.6}, ("layers[0].outer_radius_m = 36.6 m", "0.005..0.2 m",
                                "millimetres", "0.0366")),
    ({"outer_radius_m": 3.66}, ("outer_radius_m = 3.66 m", "centimetres", "0.0366")),
    ({"outer_radius_m": 0.001}, ("outer_radius_m = 0.001 m", "0.005..0.2 m")),
    ({"density_kg_m3": 1.13}, ("density_kg_m3 = 1.13 kg/m^3", "10..20000", "g/cm^3", "1130")),
    ({"density_kg_m3": 8.65e-10}, ("density_kg_m3 = 8.65e-10", "T/mm^3", "865")),
    ({"material": {"model": "mooney_rivlin", "c10_pa": 4.72, "c01_pa": -0.45}},
     ("shear modulus = 8.54 Pa", "1e+10", "MPa", "c10_pa, c01_pa", "8.54e+06")),
    ({"material": {"model": "linear_elastic", "youngs_modulus_pa": 10.0, "poissons_ratio": 0.3}},
     ("shear modulus", "MPa", "youngs_modulus_pa")),
    ({"material": {"model": "neo_hookean", "c10_pa": 1e6, "d1_per_pa": 1e-3}},
     ("bulk modulus = 2000 Pa", "d1_per_pa", "1/MPa")),
    ({"outer_radius_m": 0.2, "density_kg_m3": 19000.0}, ("mass = 636.696 kg", "0.001..30 kg",
                                                         "check the radii")),
])
def test_simulate_refuses_a_unit_slip_in_a_ball_file(bad_input, files, layer, fragments):
    folder = files(slip_json=ball(**layer))
    bad_input(["simulate", "--ball", folder / "slip.json", "--speed-m-s", "10"],
              "slip.json", *fragments, "solid sports balls", "--allow ball-units")


def test_mass_in_grams_is_named(bad_input, files):
    folder = files(grams_json={**GOOD, "mass_kg": 1000 * load_ball(GOOD).mass_kg})
    bad_input(["simulate", "--ball", folder / "grams.json", "--speed-m-s", "10"],
              "mass_kg", "looks like grams")


def test_speed_table_in_millimetres(bad_input, files):
    from ballimpact.fe import describe_presets

    entry = describe_presets()[1]
    entry = {key: value for key, value in entry.items() if key in ("name", "speed_table")}
    entry["speed_table"]["outer_radius_m"] = 36.0
    folder = files(table_json=entry)
    bad_input(["simulate", "--ball", folder / "table.json", "--speed-m-s", "10"],
              "outer_radius_m = 36 m", "millimetres")


def test_export_refuses_a_unit_slip(bad_input, files):
    folder = files(slip_json=ball(density_kg_m3=1.13))
    bad_input(["export", "--ball", folder / "slip.json", "--format", "abaqus", "--out",
               folder / "ball.inp", "--speed-m-s", "20"], "g/cm^3", "--allow ball-units")


def test_import_material_ball_in_the_wrong_units(bad_input, tmp_path):
    """A deck written in mm-tonne-s, read as SI: densities 1e12 too small, moduli 1e6."""
    from ballimpact.export import ImpactSetup, export_ball
    from ballimpact.export.geometry import ball_geometry

    deck = tmp_path / "ball.inp"
    with pytest.MonkeyPatch.context() as patch:  # this step meshes on purpose
        import ballimpact.export as export

        patch.setattr(export, "ball_geometry", ball_geometry)
        export_ball(load_ball("cricket-3layer"), deck, "abaqus", setup=ImpactSetup(20.0))
    bad_input(["import-material", deck, "--units", "si"], "ball.inp", "density_kg_m3",
              "T/mm^3", "--allow ball-units")


# ---- the memory guard before meshing (`large-run`) ----------------------------------------------

def test_millimetre_ball_allowed_is_still_stopped_quickly(bad_input, files):
    """The ball of the issue: --allow ball-units, and the cost guard stops it before meshing."""
    folder = files(mm_json=ball(outer_radius_m=36.6))
    start = time.perf_counter()
    bad_input(["simulate", "--ball", folder / "mm.json", "--speed-m-s", "10", "--allow",
               "ball-units"], "would need about", "GiB of memory", "GiB available", "h on a",
              "--element-size-m", "--allow large-run")
    assert time.perf_counter() - start < 20.0


def test_export_of_the_millimetre_ball_is_stopped(bad_input, files):
    folder = files(mm_json=ball(outer_radius_m=36.6))
    bad_input(["export", "--ball", folder / "mm.json", "--format", "abaqus", "--out",
               folder / "ball.inp", "--speed-m-s", "20", "--allow", "ball-units"],
              "the export would need about", "GiB", "--element-size-m", "--allow large-run")


def test_tiny_elements_are_stopped(bad_input):
    bad_input(["simulate", "--ball", "cricket-3layer", "--speed-m-s", "20", "--element-size-m",
               "1e-5"], "would need about", "elements x", "steps", "--element-size-m",
              "large-run")


def test_3d_thick_target_is_stopped(bad_input, files, monkeypatch):
    """A slab given in mm as m: its cells follow the ball's pole spacing through 9 m."""
    monkeypatch.setattr("ballimpact.fe.progress.available_memory_bytes", lambda: 8 * 2 ** 30)
    thick = {**TARGET, "layers": [{**TARGET["layers"][0], "thickness_m": 9.0}]}
    folder = files(thick_json=thick)
    bad_input(["simulate", "--solver", "3d", "--ball", "cricket-universal", "--speed-m-s", "20",
               "--target", folder / "thick.json", "--divisions", "32"],
              "would need about", "than the 8 GiB available", "--divisions", "--target")


# ---- the 3D solver's flags and files ------------------------------------------------------------

THREE_D = ["simulate", "--solver", "3d", "--ball", "cricket-universal", "--speed-m-s", "20"]


@pytest.mark.parametrize("flags, fragments", [
    (["--divisions", "0"], ("divisions = 0: allowed range [4, 64] (even)",)),
    (["--divisions", "-2"], ("divisions = -2",)),
    (["--divisions", "7"], ("divisions = 7",)),
    (["--divisions", "66"], ("divisions = 66",)),
    (["--angle-deg", "95"], ("angle_deg = 95", "[0, 89]")),
    (["--angle-deg", "-5"], ("angle_deg = -5",)),
    (["--friction", "-0.1"], ("--friction", "[0, inf)")),
    (["--pole-grading", "0.5"], ("pole_grading = 0.5", "[1, 40]")),
    (["--stick-scale", "0"], ("stick_scale = 0",)),
    (["--slab-depth-growth", "1.15"], ("--slab-depth-growth", "--target")),
    (["--slab-depth-growth", "3", "--target", "{repo}/examples/targets/stiff-slab.json"],
     ("slab_depth_growth = 3", "(1, 2]")),
    (["--slab-depth-cell-m", "0.003"], ("--slab-depth-cell-m", "--target")),
    (["--slab-depth-cell-m", "3", "--target", "{repo}/examples/targets/stiff-slab.json"],
     ("slab_depth_cell_m = 3", "0.1")),
    (["--slab-depth-cell-m", "2.75", "--target", "{repo}/examples/targets/stiff-slab.json"],
     ("slab_depth_cell_m = 2.75", "looks like millimetres", "use 0.00275")),
    (["--slab-depth-cell-m", "0.003", "--slab-depth-growth", "1.2", "--target",
      "{repo}/examples/targets/stiff-slab.json"], ("slab_depth_cell_m", "not both")),
    (["--spin-rad-s", "1e6"], ("spin_rad_s = 1e+06",)),
    (["--element-size-m", "0.002"], ("--element-size-m", "--divisions")),
    (["--pole-element-size-m", "0.001"], ("--pole-element-size-m",)),
    (["--target", "{tmp}/missing.json"], ("--target", "neither a preset", "existing file")),
    (["--target", "{tmp}"], ("--target", "a folder")),
    (["--vtk", "{tmp}/no/such/run.pvd"], ("--vtk", "does not exist")),
    (["--vtk", "{tmp}/run.vtu"], ("--vtk", ".pvd or .xdmf")),
    (["--animate", "{tmp}/run.avi"], ("--animate", ".gif or .mp4")),
    (["--speed-m-s", "50"], ("impact speed 50 m/s", "0.001..45 m/s", "checked",
                             "--allow speed-range")),
    (["--allow", "large-runs"], ("unknown check 'large-runs'",)),
])
def test_3d_flags(bad_input, tmp_path, flags, fragments):
    repo = str(Path(__file__).resolve().parents[2])
    flags = [flag.replace("{tmp}", str(tmp_path)).replace("{repo}", repo) for flag in flags]
    bad_input(THREE_D + flags, *fragments)


@pytest.mark.parametrize("target, fragments", [
    ({**TARGET, "colour": "red"}, ("unknown key 'colour'",)),
    ({**TARGET, "layers": [{**TARGET["layers"][0], "thickness_m": -0.01}]},
     ("thickness_m = -0.01", "allowed range")),
    ({**TARGET, "half_width_m": 0.01}, ("half_width_m = 0.01 m", "ball's radius")),
    ({**TARGET, "layers": []}, ("layers", "non-empty")),
    ([TARGET], ("expected an object", "list")),
    ("{not json", ("not valid JSON",)),
])
def test_3d_target_files(bad_input, files, target, fragments):
    folder = files(target_json=target)
    bad_input(THREE_D + ["--target", folder / "target.json"], "target.json", *fragments)


@pytest.mark.parametrize("target, fragments", [
    ({**TARGET, "layers": [{**TARGET["layers"][0], "thickness_m": 15}]},
     ("thickness_m = 15", "looks like millimetres", "use 0.015")),
    ({**TARGET, "half_width_m": 100}, ("half_width_m = 100", "looks like millimetres")),
    ({**TARGET, "sphere_radius_m": 116}, ("sphere_radius_m = 116", "looks like millimetres")),
    ({**TARGET, "sphere_radius_m": 0.05}, ("sphere_radius_m = 0.05", "allowed range")),
    ({**TARGET, "sphere_radius_m": 0.07, "layers": [{**TARGET["layers"][0], "thickness_m": 0.08}]},
     ("sphere_radius_m = 0.07", "layers' total thickness")),
    ({**TARGET, "backing": {"mass_kg": 4500}}, ("backing.mass_kg = 4500", "grams")),
    ({**TARGET, "backing": {"mass_kg": 5, "spring_n_m": -1}}, ("backing.spring_n_m = -1",)),
    ({**TARGET, "backing": {"weight": 5}}, ("unknown key 'weight'",)),
])
def test_axisymmetric_target_files(bad_input, files, target, fragments):
    """A target file on the axisymmetric solver: unit slips named, one line, exit 2."""
    folder = files(target_json=target)
    bad_input(AXI + ["--target", folder / "target.json"], "target.json", *fragments)


def test_3d_target_file_not_text(bad_input, tmp_path):
    (tmp_path / "target.json").write_bytes(b"\xff\xfe\x00{")
    bad_input(THREE_D + ["--target", tmp_path / "target.json"], "target.json", "not valid JSON")


def test_3d_mp4_without_ffmpeg(bad_input, tmp_path, monkeypatch):
    from matplotlib import animation

    monkeypatch.setattr(animation.FFMpegWriter, "isAvailable", classmethod(lambda cls: False))
    bad_input(THREE_D + ["--animate", tmp_path / "run.mp4"], "--animate", "ffmpeg", ".gif")


def test_api_narrow_target_is_refused_before_meshing():
    from ballimpact.fe import Hexahedral, ImpactCondition, estimate
    from ballimpact.fe.hex.target import Target

    narrow = Target.from_dict({**TARGET, "half_width_m": 0.01}, where="target")
    with pytest.raises(InputError, match="half_width_m = 0.01 m is less than the ball's radius"):
        estimate(load_ball("cricket-3layer"), ImpactCondition(speed_m_s=20.0),
                 geometry=Hexahedral(), target=narrow)


def test_3d_unresolved_contact_names_the_3d_options():
    """The note's advice is the 3D mesh's options, not the axisymmetric pole size (a grading
    given: the default would refine the pole for the contact)."""
    from ballimpact.oblique import ImpactCondition, Options3D, simulate_oblique

    with pytest.warns(InputWarning, match="^contact not resolved.*--divisions, --pole-grading"), \
            pytest.raises(AssertionError, match="meshed"):
        simulate_oblique(load_ball("cricket-3layer"), ImpactCondition(speed_m_s=0.05),
                         Options3D(pole_grading=2.0))


# ---- the axisymmetric solver's flags and ball files --------------------------------------------

AXI = ["simulate", "--ball", "cricket-universal", "--speed-m-s", "20"]


@pytest.mark.parametrize("flags, fragments", [
    (["--element-size-m", "0.1"], ("element_size_m", "outer radius/2 = 0.018")),
    (["--element-size-m", "-0.001"], ("element_size_m = -0.001",)),
    (["--pole-element-size-m", "0.003"], ("pole_element_size_m", "(0, element_size_m = 0.0015]")),
    (["--divisions", "8"], ("--divisions", "--solver 3d")),
    (["--full-model"], ("--full-model", "--solver 3d")),
    (["--target", "x.json"], ("--target", "neither a preset", "existing file")),
    (["--target", "cricket-helmet", "--speed-m-s", "5,10"], ("--target", "one speed")),
    (["--moduli", "short"], ("--moduli", "invalid choice")),
    (["--speed-m-s", "100"], ("impact speed 100 m/s", "0.001..80 m/s", "unstable")),
    (["--speed-m-s", "0.0001"], ("impact speed 0.0001 m/s", "0.001..80 m/s")),
    (["--speed-m-s", "0"], ("impact_speed_m_s = 0",)),
])
def test_axisymmetric_flags(bad_input, flags, fragments):
    bad_input(AXI + flags, *fragments)


@pytest.mark.parametrize("content, fragments", [
    ("{garbage", ("not valid JSON",)),
    ([GOOD], ("JSON array", "'layers'")),
    ("42", ("got a number",)),
    ({}, ("missing key 'layers'",)),
    ({"layers": [{"outer_radius_m": 0.03, "density_kg_m3": -5, "material": RUBBER}]},
     ("density_kg_m3 = -5",)),
])
def test_ball_file_contents(bad_input, files, content, fragments):
    folder = files(ball_json=content)
    bad_input(AXI[:2] + [folder / "ball.json"] + AXI[3:], "ball.json", *fragments)


def test_ball_is_a_folder(bad_input, tmp_path):
    bad_input(["simulate", "--ball", tmp_path, "--speed-m-s", "10"], "a folder")


# ---- export ------------------------------------------------------------------------------------

@pytest.mark.parametrize("flags, fragments", [
    (["--format", "nastran"], ("format = 'nastran'", "abaqus")),
    (["--units", "furlongs"], ("--units", "invalid choice")),
    (["--out", "{tmp}/no/such/ball.inp"], ("does not exist",)),
    (["--out", "{tmp}/ball.k"], ("ends in .inp",)),
    (["--divisions", "8"], ("--divisions", "--element-size-m")),
    (["--solver", "3d", "--element-size-m", "0.002"], ("--element-size-m", "--divisions")),
    (["--solver", "3d", "--divisions", "3"], ("divisions = 3",)),
    (["--solver", "3d", "--pole-grading", "50"], ("pole_grading = 50",)),
    (["--element-size-m", "0.5"], ("element_size_m", "0.018")),
    (["--step-time-s", "-1"], ("step_time_s = -1",)),
    (["--friction", "-1"], ("friction = -1",)),
    (["--half-model"], ("half",)),
    (["--speed-m-s", "0"], ("impact_speed_m_s = 0",)),
    (["--allow", "everything"], ("unknown check 'everything'",)),
])
def test_export_flags(bad_input, tmp_path, flags, fragments):
    argv = ["export", "--ball", "cricket-universal", "--format", "abaqus"]
    flags = [flag.replace("{tmp}", str(tmp_path)) for flag in flags]
    if "--out" not in flags:
        flags += ["--out", str(tmp_path / "ball.inp")]
    if "--speed-m-s" not in flags:
        flags += ["--speed-m-s", "20"]
    bad_input(argv + flags, *fragments)


# ---- import-material ---------------------------------------------------------------------------

DECK = """** units si: m, kg, s, Pa
*MATERIAL, NAME=core
*DENSITY
{density}
*HYPERELASTIC, MOONEY-RIVLIN
{c10}, {c01}, 0
*VISCOELASTIC, TIME=PRONY
{prony}
"""


@pytest.mark.parametrize("values, fragments", [
    ({"density": "-865"}, ("material 'core'", "density_kg_m3 = -865", "> 0")),
    ({"density": "nan"}, ("material 'core'", "density_kg_m3 = nan")),
    ({"density": "0"}, ("density_kg_m3 = 0",)),
    ({"prony": "1.2, 0, 7e-5"}, ("material 'core'", "prony[0].g = 1.2", "[0, 1)")),
    ({"prony": "0.6, 0, 7e-5\n0.5, 0, 1e-3"}, ("material 'core'", "sum of g must be < 1")),
    ({"prony": "0.4, 0, 0"}, ("prony[0].tau_s = 0",)),
    ({"prony": "0.4, 0, -1e-4"}, ("prony[0].tau_s = -0.0001",)),
    ({"c10": "-5e6"}, ("material 'core'", "c10")),
    ({"c10": "inf"}, ("material 'core'", "c10_pa", "finite")),
    ({"c10": "4.72", "c01": "-0.45"}, ("material 'core'", "MPa", "--allow ball-units")),
])
def test_import_material_numbers(bad_input, tmp_path, values, fragments):
    values = {"density": "865", "c10": "4.72e6", "c01": "-4.5e5", "prony": "0.41, 0, 7e-5",
              **values}
    deck = tmp_path / "core.inp"
    deck.write_text(DECK.format(**values))
    bad_input(["import-material", deck], "core.inp", *fragments)


@pytest.mark.parametrize("text, fragments", [
    ("** units si:\n*MATERIAL, NAME=e\n*DENSITY\n1000\n*ELASTIC\n2e9\n", ("*ELASTIC", "E, nu")),
    ("** units si:\n*MATERIAL, NAME=f\n*DENSITY\n100\n*HYPERFOAM, N=x\n1e5, 4, 0\n",
     ("N=x", "positive integer")),
    ("** units si:\n*MATERIAL, NAME=d\n*DENSITY\n\n*ELASTIC\n2e9, 0.3\n", ("*DENSITY", "no value")),
])
def test_import_material_cards(bad_input, tmp_path, text, fragments):
    deck = tmp_path / "deck.inp"
    deck.write_text(text)
    bad_input(["import-material", deck], "deck.inp", *fragments)


def test_import_material_ball_with_bad_node_rows(bad_input, tmp_path):
    deck = tmp_path / "ball.inp"
    deck.write_text(DECK.format(density="865", c10="4.72e6", c01="-4.5e5", prony="0.41, 0, 7e-5")
                    + "*NODE\n1, 0.0, x\n")
    bad_input(["import-material", deck, "--ball"], "ball.inp", "*NODE", "label and numbers")


def test_import_material_files(bad_input, tmp_path):
    bad_input(["import-material", tmp_path / "missing.inp"], "missing.inp", "cannot read")
    bad_input(["import-material", tmp_path], "a folder")
    deck = tmp_path / "core.inp"
    deck.write_text(DECK.format(density="865", c10="4.72e6", c01="-4.5e5",
                                prony="0.41, 0, 7e-5"))
    bad_input(["import-material", deck, "--out", tmp_path / "no" / "core.json"], "--out",
              "does not exist")


# ---- Python API ----------------------------------------------------------------------------------

def test_api_millimetre_ball_raises_and_allow_warns():
    with pytest.raises(InputError, match=re.escape("outer_radius_m = 36.6 m")):
        load_ball(ball(outer_radius_m=36.6))
    with pytest.warns(InputWarning, match="^ball-units: ball.layers.0..outer_radius_m = 36.6 m"):
        mm = load_ball(ball(outer_radius_m=36.6), allow={"ball-units"})
    assert mm.outer_radius_m == 36.6
    # the cost guard still stops the run, before meshing (`no_meshing`)
    with pytest.raises(InputError, match="would need about .* GiB of memory"):
        simulate(mm, 10.0)
    with pytest.raises(InputError, match="allow: unknown check"):
        load_ball(GOOD, allow={"ball-unit"})


def test_presets_and_examples_are_plausible():
    from pathlib import Path

    with warnings.catch_warnings():
        warnings.simplefilter("error", InputWarning)
        check_ball(load_ball("cricket-3layer"))
        check_ball(load_ball("cricket-universal", 20.0))
        for path in sorted((Path(__file__).parents[2] / "examples" / "balls").glob("*")):
            check_ball(load_ball(path, impact_speed_m_s=20.0))


def test_ranges_and_check_names():
    assert {"ball-units", "large-run"} <= set(CHECKS)
    low, high, unit = BALL_RANGES["outer radius"]
    assert (low, high, unit) == (0.005, 0.2, "m")  # docs/balls.md states them


def test_large_run_check_uses_the_available_memory():
    estimate = RunEstimate(elements=10, steps=10, end_time_s=1e-3, memory_bytes=2e9,
                           element_steps_limit=1e9, seconds_per_element_step=1e-7,
                           hint="a coarser mesh", model_bytes=1e9)
    estimate.check_memory(available_bytes=4e9)  # fits
    with pytest.raises(InputError, match="about 2.79 GiB of memory .* than the 0.931 GiB"):
        estimate.check_memory(available_bytes=1e9)
    with pytest.warns(InputWarning, match="^large-run: the run would need"):
        estimate.check_memory({"large-run"}, available_bytes=1e9)


@pytest.fixture
def fresh_judgements(monkeypatch):
    """The large-run check as in a new process (nothing judged yet)."""
    from ballimpact.fe import progress

    monkeypatch.setattr(progress, "_JUDGED_BYTES", {"fitted": 0.0, "allowed": 0.0})
    return progress


GIB = 2 ** 30


def test_large_run_check_counts_only_what_the_process_does_not_hold(fresh_judgements,
                                                                     monkeypatch):
    """JAX already loaded: a small run is not refused because less than the base is free."""
    estimate = RunEstimate(elements=10, steps=10, end_time_s=1e-3, memory_bytes=0.05 * GIB,
                           element_steps_limit=1e9, seconds_per_element_step=1e-7,
                           model_bytes=0.65 * GIB, base_bytes=0.6 * GIB)
    monkeypatch.setattr(fresh_judgements, "process_memory_bytes", lambda: 0.4 * GIB)
    estimate.check_memory(available_bytes=0.35 * GIB)  # needs 0.3 GiB more
    with pytest.raises(InputError, match="about 0.3 GiB of memory besides the 0.4 GiB this "
                                         "process holds .* than the 0.2 GiB available"):
        estimate.check_memory(available_bytes=0.2 * GIB)
    monkeypatch.setattr(fresh_judgements, "process_memory_bytes", lambda: 2.0 * GIB)
    estimate.check_memory(available_bytes=0.15 * GIB)  # the whole base held: 0.1 GiB more


def test_large_run_check_judges_a_size_once_per_process(fresh_judgements, monkeypatch):
    """A brief dip in free memory does not stop a search whose batches fitted before; a larger
    batch is still checked."""
    balls = [load_ball("cricket-3layer")] * 4
    available = [16 * GIB]
    monkeypatch.setattr(fresh_judgements, "available_memory_bytes", lambda: available[0])
    engine.check_memory(engine.Axisymmetric(), balls, [20.0] * 4, group_size=4)
    available[0] = 1.0  # the dip
    engine.check_memory(engine.Axisymmetric(), balls, [20.0] * 4, group_size=4)
    engine.check_memory(engine.Axisymmetric(), balls[:2], [20.0] * 2)
    with pytest.raises(InputError, match="would need about"):
        engine.check_memory(engine.Axisymmetric(SolverOptions(element_size_m=1e-3)), balls,
                            [20.0] * 4, group_size=4)


def test_large_run_allowed_warns_once_for_the_same_run(fresh_judgements, monkeypatch):
    """`fe.estimate` then `fe.simulate` (the command line's order) check the same run: one
    warning."""
    monkeypatch.setattr(fresh_judgements, "available_memory_bytes", lambda: 1.0)
    ball, geometry = load_ball("cricket-3layer"), engine.Axisymmetric()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for _ in range(2):
            engine.check_memory(geometry, [ball], [20.0], None, {"large-run"})
    assert [str(w.message)[:25] for w in caught] == ["large-run: the run would "]
    with pytest.raises(InputError, match="large-run"):  # not allowed: still refused
        engine.check_memory(geometry, [ball], [20.0])
