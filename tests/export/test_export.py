"""Ball models for other codes (issue: export): decks that parse, materials that read back,
units that convert field by field, and bad input that exits 2."""

import json
import re

import meshio
import numpy as np
import pytest

from ballimpact.cli import main
from ballimpact.errors import InputError
from ballimpact.export import ImpactSetup, export_ball, read_ball, read_materials
from ballimpact.export import lsdyna
from ballimpact.export.importer import blocks
from ballimpact.fe import load_ball

UNIVERSAL = ("cricket-universal", 25.0)
THREE_LAYER = ("cricket-3layer", None)
# meshio's ABAQUS reader has no axisymmetric or rigid element types: read the same topology
MESHIO_NAMES = {"CAX4R": "CPS4R", "CAX4": "CPS4", "RAX2": "T2D2", "R3D4": "S4R"}


def run(capsys, *argv):
    code = main([str(arg) for arg in argv])
    out, err = capsys.readouterr()
    return code, out, err


def same_spec(a, b, rel=1e-10):
    """Specifications equal, floats to `rel` (decks hold 12 significant digits)."""
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(same_spec(a[k], b[k], rel) for k in a)
    if isinstance(a, list):
        return len(a) == len(b) and all(same_spec(x, y, rel) for x, y in zip(a, b))
    if isinstance(a, float):
        return a == pytest.approx(b, rel=rel, abs=1e-300)
    return a == b


def ball_of(preset):
    name, speed = preset
    return load_ball(name, impact_speed_m_s=speed)


def mesh_part(path, tmp_path):
    text = path.read_text()
    for ours, theirs in MESHIO_NAMES.items():
        text = text.replace(f"TYPE={ours},", f"TYPE={theirs},")
    copy = tmp_path / f"meshio-{path.name}"
    copy.write_text(text)
    return meshio.read(copy, file_format="abaqus")


@pytest.mark.parametrize("fmt", ["abaqus", "calculix"])
@pytest.mark.parametrize("solver", ["axisymmetric", "3d"])
@pytest.mark.parametrize("preset", [UNIVERSAL, THREE_LAYER])
def test_abaqus_and_calculix_decks_read_back(fmt, solver, preset, tmp_path):
    ball = ball_of(preset)
    ball_only = fmt == "calculix" and solver == "axisymmetric"
    path = tmp_path / "ball.inp"
    written = export_ball(ball, path, fmt, solver=solver, setup=ImpactSetup(20.0),
                          ball_only=ball_only, divisions=4)
    mesh = mesh_part(path, tmp_path)
    n_ball = written.n_nodes
    # every layer is an element set with the solver's elements, and the mesh is whole
    counts = {name.lower(): sum(len(block) for block in sets)
              for name, sets in mesh.cell_sets.items()}
    layers = [layer.name for layer in ball.layers]
    assert sum(counts[name] for name in layers) == written.n_elements
    assert max(c.data.max() for c in mesh.cells) < len(mesh.points)
    assert len(mesh.points) >= n_ball
    # nodes in the file's units (mm): the ball stands on its pole at the origin
    ball_points = mesh.points[:n_ball]
    axis = 1 if solver == "axisymmetric" else 2
    assert ball_points[:, axis].min() == pytest.approx(0.0, abs=1e-9)
    assert ball_points[:, axis].max() == pytest.approx(2e3 * ball.outer_radius_m)
    # the material part reads back through our importer, in SI
    materials = {m["name"]: m for m in read_materials(path.read_text())}
    for layer in ball.layers:
        read = materials[layer.name]
        assert read["density_kg_m3"] == pytest.approx(layer.density_kg_m3, rel=1e-9)
        assert read["material"]["model"] == layer.material.model


@pytest.mark.parametrize("solver", ["axisymmetric", "3d"])
@pytest.mark.parametrize("preset", [UNIVERSAL, THREE_LAYER])
def test_abaqus_round_trip_gives_the_same_ball(solver, preset, tmp_path, capsys):
    ball = ball_of(preset)
    path = tmp_path / "ball.inp"
    export_ball(ball, path, "abaqus", solver=solver, setup=ImpactSetup(20.0), divisions=4)
    spec = read_ball(path.read_text())
    assert same_spec(load_ball(spec).to_dict(), ball.to_dict())
    # and through the command line, as a ball file that simulate accepts
    out = tmp_path / "ball.json"
    code, _, err = run(capsys, "import-material", path, "--ball", "--out", out, "--json")
    assert code == 0, err
    assert same_spec(load_ball(out).to_dict(), ball.to_dict())


def test_abaqus_cards_carry_the_conventions(tmp_path):
    ball = ball_of(THREE_LAYER)
    path = tmp_path / "b.inp"
    export_ball(ball, path, "abaqus", ball_only=True)
    text = path.read_text()
    found = {(kw, tuple(sorted(params))): rows for kw, params, rows, _ in blocks(text)}
    core = next(rows for (kw, params), rows in found.items() if kw == "HYPERELASTIC"
                and "MODULI" in params)
    assert [float(v) for v in core[0]] == [4.72, -0.45, 0.0]   # MPa, D1 = 0 as ABAQUS reads it
    assert "*HYPERFOAM, N=1, MODULI=LONG TERM\n70.3, 4, 0\n" in text
    assert "*VISCOELASTIC, TIME=PRONY\n0.41, 0, 7e-05\n" in text
    assert "** units mm-tonne-s" in text and "*STEP" not in text  # ball only
    # D1 = 0 beside a Prony series: the header pins the K it stands for (1/MPa here)
    k_core = ball.layers[0].material.bulk_modulus_pa()
    assert f"write D1 = {2.0 / k_core * 1e6:.6g} in the deck's units" in text


def test_abaqus_plane_faces_the_ball(tmp_path):
    """RAX2: the normal is node 1 -> node 2 turned 90 degrees counter-clockwise; R3D4: the
    right-hand rule. Both must point +y / +z, into the ball, with the SPOS side in contact."""
    ball = ball_of(UNIVERSAL)
    for solver in ("axisymmetric", "3d"):
        path = tmp_path / f"{solver}.inp"
        export_ball(ball, path, "abaqus", solver=solver, setup=ImpactSetup(20.0), divisions=4)
        found = blocks(path.read_text())
        nodes = {int(r[0]): np.array([float(v) for v in r[1:]])
                 for k, _, rows, _ in found if k == "NODE" for r in rows}
        plane = next(rows[0] for k, p, rows, _ in found if k == "ELEMENT"
                     and p["TYPE"] in ("RAX2", "R3D4"))
        corners = [nodes[int(n)] for n in plane[1:]]
        if solver == "axisymmetric":
            tangent = corners[1] - corners[0]
            normal = np.array([-tangent[1], tangent[0]])
        else:
            normal = np.cross(corners[1] - corners[0], corners[2] - corners[1])
        assert normal[-1] > 0 and np.allclose(normal[:-1], 0.0)
        surface = next(rows for k, p, rows, _ in found if k == "SURFACE"
                       and p["NAME"] == "PLANE_SURFACE")
        assert surface == [["PLANE", "SPOS"]]


def test_calculix_writes_the_elastic_ball_it_can_express(tmp_path, capsys):
    path = tmp_path / "c.inp"
    code, out, err = run(capsys, "export", "--ball", "cricket-universal", "--speed-m-s", 25,
                         "--format", "calculix", "--solver", "3d", "--divisions", 4,
                         "--moduli", "instantaneous", "--out", path, "--json")
    assert code == 0, err
    assert "no Prony viscoelasticity" in err and "instantaneous elastic ball" in err
    text = path.read_text()
    assert "** note: BALL: CalculiX has no Prony" in text and "*VISCOELASTIC" not in text
    material = read_materials(text)[0]["material"]
    ball = load_ball("cricket-universal", 25.0).with_moduli("instantaneous")
    constants = ball.layers[0].material.hyperelastic_constants()
    assert material["c10_pa"] == pytest.approx(constants.c10_pa, rel=1e-9)
    assert material["d1_per_pa"] == pytest.approx(2.0 / constants.k_pa, rel=1e-9)
    # long-term: the relaxed shear modulus, the same bulk (no k_i)
    export_ball(load_ball("cricket-universal", 25.0), path, "calculix", solver="3d",
                setup=ImpactSetup(25.0), divisions=4, moduli="long_term")
    material = read_materials(path.read_text())[0]["material"]
    constants = load_ball("cricket-universal", 25.0).layers[0].material.hyperelastic_constants()
    assert material["c10_pa"] == pytest.approx(4.02e6, rel=1e-9)
    assert material["d1_per_pa"] == pytest.approx(2.0 / constants.k_pa, rel=1e-9)


#: SI -> mm-tonne-s factor of each value of a data row, by card (materials: `read_materials`)
STRESS, LENGTH, TIME, DENSITY = 1e-6, 1e3, 1.0, 1e-12
ROW_FACTORS = {"NODE": (1, LENGTH, LENGTH, LENGTH), "DENSITY": (DENSITY,),
               "INITIAL CONDITIONS": (None, 1, LENGTH / TIME), "DYNAMIC": (TIME,) * 4,
               "SURFACE BEHAVIOR": (STRESS / LENGTH, STRESS), "FRICTION": (1, STRESS / LENGTH),
               "ELASTIC": (STRESS, 1), "VISCOELASTIC": (1, 1, TIME)}
MATERIAL_CARDS = {"HYPERELASTIC", "HYPERFOAM"}


@pytest.mark.parametrize("fmt", ["abaqus", "calculix"])
def test_si_and_mm_tonne_s_decks_agree_field_by_field(fmt, tmp_path):
    ball = ball_of(THREE_LAYER)
    setup = ImpactSetup(20.0, angle_deg=30.0, friction=0.3)
    decks = {}
    for units in ("si", "mm-tonne-s"):
        path = tmp_path / f"{units}.inp"
        export_ball(ball, path, fmt, solver="3d", setup=setup, divisions=4, units=units)
        decks[units] = path.read_text()
    si, mm = blocks(decks["si"]), blocks(decks["mm-tonne-s"])
    assert [(k, p) for k, p, _, _ in si] == [(k, p) for k, p, _, _ in mm]
    checked = 0
    for (keyword, _, rows_si, _), (_, _, rows_mm, _) in zip(si, mm):
        assert len(rows_si) == len(rows_mm), keyword
        if keyword in MATERIAL_CARDS:
            continue
        for row_si, row_mm in zip(rows_si, rows_mm):
            factors = ROW_FACTORS.get(keyword)
            for i, (a, b) in enumerate(zip(row_si, row_mm)):
                if not a or factors is None or i >= len(factors) or factors[i] is None:
                    assert a == b, keyword  # labels, set names, dimensionless
                    continue
                assert float(b) == pytest.approx(float(a) * factors[i], rel=1e-10,
                                                 abs=1e-9), keyword
                checked += 1
    assert checked > 3000
    # the material cards, value by value through the importer: the same SI constants
    assert same_spec(read_materials(decks["si"]), read_materials(decks["mm-tonne-s"]))


def test_lsdyna_decks_validate_and_convert(tmp_path):
    ball = ball_of(UNIVERSAL)
    for solver in ("axisymmetric", "3d"):
        path = tmp_path / f"{solver}.k"
        written = export_ball(ball, path, "lsdyna", solver=solver, setup=ImpactSetup(25.0),
                              divisions=4)
        # 4 divisions lose 9% of the sphere to the chords (and say so); the default mesh 0.04%
        coarse = any("below the ball's" in note for note in written.notes)
        assert coarse == (solver == "3d")
        text = path.read_text()
        counts = lsdyna.validate(text)
        assert counts["*MAT_HYPERELASTIC_RUBBER_TITLE"] == 1 and counts["*RIGIDWALL_PLANAR"] == 1
        assert max(len(line) for line in text.splitlines() if not line.startswith("$")) <= 80
        nodes, elements, parts = lsdyna.read_nodes_elements(text)
        assert elements.shape[1] == (4 if solver == "axisymmetric" else 8)
        assert nodes[:, 1 if solver == "axisymmetric" else 2].max() == pytest.approx(72.0)
    # *MAT_077 constants: long-term C10, C01 (MPa), PR from K0 = 20 mu0, G1 = g1 mu0_inst
    card = text.split("*MAT_HYPERELASTIC_RUBBER_TITLE\n")[1].splitlines()
    head = [float(card[1][i:i + 10]) for i in range(0, len(card[1]), 10)]
    assert head[1] == pytest.approx(ball.layers[0].density_kg_m3 * 1e-12)
    # PR gives our K (20 x the instantaneous mu0) from the long-term mu that LS-DYNA sees
    mu_long, k = 2 * (4.02e6 - 0.41e6), 20 * 2 * (4.02e6 - 0.41e6) / (1 - 0.79)
    assert head[2] == pytest.approx((3 * k - 2 * mu_long) / (2 * (3 * k + mu_long)), abs=1e-6)
    assert head[2] == pytest.approx(0.4948, abs=1e-4) and head[4] == 1
    assert float(card[2][:10]) == pytest.approx(4.02) and float(card[2][10:20]) == -0.41
    mu_inst = ball.layers[0].material.shear_modulus_pa() * 1e-6
    assert float(card[3][:10]) == pytest.approx(0.79 * mu_inst, rel=1e-6)
    assert float(card[3][10:20]) == pytest.approx(1.0 / 8e-5)


def test_lsdyna_validator_catches_defects(tmp_path):
    path = tmp_path / "u.k"
    export_ball(ball_of(UNIVERSAL), path, "lsdyna", solver="3d", setup=ImpactSetup(25.0),
                divisions=4)
    good = path.read_text()
    defects = {
        "characters": good.replace("*NODE\n", "*NODE\n" + " " * 81 + "\n", 1),
        "real field": good.replace("\n      4.02", "\n      4,02", 1),
        "viscoelastic cards": good.replace("         1       0.0       0.0       0.0\n",
                                           "         2       0.0       0.0       0.0\n", 1),
        "not defined": re.sub(r"(\*ELEMENT_SOLID\n\s+1\s+1)\s+(\d+)", r"\1  999999", good),
        "starts with": good.replace("*KEYWORD\n", "", 1),
    }
    for expected, text in defects.items():
        assert text != good, expected
        with pytest.raises(InputError, match=expected):
            lsdyna.validate(text)


def written_2d_elements(ball):
    from ballimpact.export import ball_geometry
    return len(ball_geometry(ball, "axisymmetric").elements)


def test_lsdyna_reads_in_pydyna(tmp_path):
    """The deck in Ansys' maintained reader (ansys-dyna-core, a test dependency)."""
    dyna = pytest.importorskip("ansys.dyna.core", reason="ansys-dyna-core is not installed")
    ball = ball_of(UNIVERSAL)
    path = tmp_path / "u.k"
    written = export_ball(ball, path, "lsdyna", solver="3d", setup=ImpactSetup(25.0, 30.0, 0.4),
                          divisions=4)
    deck = dyna.Deck()
    deck.loads(path.read_text())
    kinds = {type(kw).__name__: kw for kw in deck.all_keywords}
    assert not deck.string_keywords if hasattr(deck, "string_keywords") else True
    assert len(kinds["Node"].nodes) == written.n_nodes
    assert len(kinds["ElementSolid"].elements) == written.n_elements
    mat = kinds["MatHyperelasticRubber"]
    assert mat.c10 == pytest.approx(4.02) and mat.nv == 1
    assert mat.constants["betai"][0] == pytest.approx(12500.0)
    assert kinds["InitialVelocity"].vz == pytest.approx(-25e3 * np.cos(np.radians(30)), rel=1e-6)
    assert kinds["RigidwallPlanar"].fric == pytest.approx(0.4)
    assert kinds["RigidwallPlanar"].zh == 1.0
    # the axisymmetric deck: 2D solids as shells of formulation 15, the wall normal along +y
    export_ball(ball, path, "lsdyna", setup=ImpactSetup(25.0))
    deck = dyna.Deck()
    deck.loads(path.read_text())
    kinds = {type(kw).__name__: kw for kw in deck.all_keywords}
    assert kinds["SectionShell"].elform == 15 and kinds["RigidwallPlanar"].yh == 1.0
    assert len(kinds["ElementShell"].elements) == written_2d_elements(ball)


def test_lsdyna_refuses_what_it_cannot_express_unless_approximate(tmp_path, capsys):
    path = tmp_path / "three.k"
    code, _, err = run(capsys, "export", "--ball", "cricket-3layer", "--format", "lsdyna",
                       "--speed-m-s", 20, "--out", path)
    assert code == 2 and not path.exists()
    assert "midsole: ogden_hyperfoam" in err and "--approximate" in err and "PR = 0.0000" in err
    code, _, err = run(capsys, "export", "--ball", "cricket-3layer", "--format", "lsdyna",
                       "--speed-m-s", 20, "--out", path, "--approximate")
    assert code == 0, err
    assert "written instead: *MAT_OGDEN_RUBBER" in err
    text = path.read_text()
    assert "$ note: midsole: ogden_hyperfoam" in text
    assert text.count("\n*MAT_OGDEN_RUBBER_TITLE\n") == 1
    lsdyna.validate(text)
    # Ogden rubber mu_i = 2 mu_i / alpha_i (hyperfoam), the same energy at J = 1
    card = text.split("*MAT_OGDEN_RUBBER_TITLE\n")[1].splitlines()
    assert float(card[2][:10]) == pytest.approx(2 * 70.3 / 4.0)


def test_vtk_export_carries_layers(tmp_path, capsys):
    for solver, suffix in (("3d", ".vtu"), ("axisymmetric", ".vtk")):
        path = tmp_path / f"ball{suffix}"
        flags = ("--divisions", 4) if solver == "3d" else ()  # (each solver refuses the other's)
        code, out, err = run(capsys, "export", "--ball", "cricket-3layer", "--format", "vtk",
                             "--solver", solver, *flags, "--out", path, "--json")
        assert code == 0, err
        mesh = meshio.read(path)
        layer = mesh.cell_data["layer"][0]
        assert sorted(set(layer.tolist())) == [0, 1, 2]
        assert mesh.cell_data["density"][0][layer == 2][0] == pytest.approx(1132.0)
        assert json.loads(out)["units"] == "si"
    # XDMF: meshio's writer needs h5py, which is not a dependency: a clear error, not a crash
    try:
        import h5py  # noqa: F401
    except ModuleNotFoundError:
        code, _, err = run(capsys, "export", "--ball", "cricket-3layer", "--format", "vtk",
                           "--out", tmp_path / "ball.xdmf")
        assert code == 2 and "needs the Python package 'h5py'" in err


@pytest.mark.parametrize("argv, message", [
    (("--format", "nastran"), "format = 'nastran': allowed abaqus, calculix, lsdyna, vtk"),
    (("--format", "abaqus", "--out", "{tmp}/no/such/ball.inp"), "does not exist"),
    (("--format", "abaqus", "--out", "{tmp}/file.txt/ball.inp"), "does not exist"),
    (("--format", "lsdyna", "--out", "{tmp}/ball.inp"), "ends in .k"),
    (("--format", "calculix"), "CalculiX 2.20 drops initial velocities on axisymmetric"),
    (("--format", "abaqus", "--angle-deg", "30"), "use --solver 3d for oblique impacts"),
    (("--format", "abaqus", "--speed-m-s", "-3"), "speed"),
])
def test_bad_export_input_exits_2(argv, message, tmp_path, capsys):
    (tmp_path / "file.txt").write_text("a file, not a folder")
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    if "--out" not in argv:
        argv += ["--out", str(tmp_path / ("ball.k" if "lsdyna" in argv else "ball.inp"))]
    if "--speed-m-s" not in argv:
        argv += ["--speed-m-s", "20"]
    code, _, err = run(capsys, "export", "--ball", "cricket-3layer", *argv)
    assert code == 2, err
    assert message in err


def test_import_material_reads_users_blocks(tmp_path, capsys):
    user = tmp_path / "user.inp"
    user.write_text("""** a user's rubber, mm-tonne-s
*MATERIAL, NAME=Rubber
*DENSITY
1.1e-9,
*HYPERELASTIC, MOONEY-RIVLIN, MODULI=INSTANTANEOUS
0.5, 0.1, 0.
*VISCOELASTIC, TIME=PRONY
0.3, 0., 1e-4
0.2, 0.1, 1e-2
*DAMPING, ALPHA=2.
*MATERIAL, NAME=foam
*HYPERFOAM, N=2
0.1, 8., -0.02, -2., 0., 0.
*DENSITY
2e-10
""")
    code, out, err = run(capsys, "import-material", user, "--units", "mm-tonne-s")
    assert code == 0, err
    materials = json.loads(out)["materials"]
    rubber, foam = materials
    assert rubber["name"] == "rubber" and rubber["density_kg_m3"] == pytest.approx(1100.0)
    assert rubber["material"] == {"model": "mooney_rivlin", "c10_pa": 5e5, "c01_pa": 1e5,
                                  "d1_per_pa": 0.0, "moduli": "instantaneous",
                                  "prony": [{"g": 0.3, "k": 0.0, "tau_s": 1e-4},
                                            {"g": 0.2, "k": 0.1, "tau_s": 1e-2}]}
    assert foam["material"]["terms"] == [{"mu_pa": 1e5, "alpha": 8.0, "nu": 0.0},
                                         {"mu_pa": -2e4, "alpha": -2.0, "nu": 0.0}]
    assert "DAMPING in material 'rubber': not read" in err
    # no units line and no --units: refused, naming the flag
    code, _, err = run(capsys, "import-material", user)
    assert code == 2 and "--units" in err
    bad = tmp_path / "bad.inp"
    bad.write_text("*MATERIAL, NAME=x\n*HYPERELASTIC, ARRUDA-BOYCE\n1, 2, 0\n")
    code, _, err = run(capsys, "import-material", bad, "--units", "si")
    assert code == 2 and "ARRUDA-BOYCE: not supported" in err and "bad.inp" in err
    code, _, err = run(capsys, "import-material", tmp_path / "missing.inp")
    assert code == 2 and "missing.inp: cannot read" in err
    code, _, err = run(capsys, "import-material", user, "--units", "furlongs")
    assert code == 2 and "--units" in err


def test_layer_labels_stay_distinct_from_each_other_and_the_decks_own():
    from ballimpact.export.setup import layer_labels

    layer = {"outer_radius_m": 0.01, "density_kg_m3": 1000.0,
             "material": {"model": "neo_hookean", "c10_pa": 1e6}}
    ball = load_ball({"name": "odd", "layers": [
        {**layer, "name": "plane"}, {**layer, "name": "a b", "outer_radius_m": 0.02},
        {**layer, "name": "a_b", "outer_radius_m": 0.03},
        {**layer, "name": "2nd", "outer_radius_m": 0.04}]})
    assert layer_labels(ball) == ["PLANE_0", "A_B", "A_B_2", "L_2ND"]


# ---- Yeoh and Ogden rubber ---------------------------------------------------------------------
_RUBBER_PRONY = [{"g": 0.3, "k": 0.0, "tau_s": 1e-4}]
RUBBER_SPEC = {"name": "rubber", "layers": [
    {"name": "core", "outer_radius_m": 0.02, "density_kg_m3": 900.0,
     "material": {"model": "yeoh", "c10_pa": 1.2e6, "c20_pa": -3e4, "c30_pa": 800.0,
                  "d1_per_pa": 0.0, "prony": _RUBBER_PRONY}},
    {"name": "cover", "outer_radius_m": 0.036, "density_kg_m3": 1100.0,
     "material": {"model": "ogden", "d1_per_pa": 5e-8, "moduli": "instantaneous",
                  "prony": _RUBBER_PRONY,
                  "terms": [{"mu_pa": 1.5e6, "alpha": 2.5}, {"mu_pa": -2e4, "alpha": -2.0},
                            {"mu_pa": 3e3, "alpha": 6.0}]}}]}


@pytest.mark.parametrize("solver", ["axisymmetric", "3d"])
def test_yeoh_and_ogden_round_trip_through_abaqus(solver, tmp_path, capsys):
    ball = load_ball(RUBBER_SPEC)
    path = tmp_path / "rubber.inp"
    export_ball(ball, path, "abaqus", solver=solver, setup=ImpactSetup(20.0), divisions=4)
    text = path.read_text()
    # MPa: C10, C20, C30, D1 = 0 (ABAQUS's K0 = 20 mu0), D2 = D3 = 0
    assert "*HYPERELASTIC, YEOH, MODULI=LONG TERM\n1.2, -0.03, 0.0008, 0, 0, 0\n" in text
    # mu_i (MPa), alpha_i, then D_1 (1/MPa), D_2 = D_3 = 0: eight values a line
    assert ("*HYPERELASTIC, OGDEN, N=3, MODULI=INSTANTANEOUS\n1.5, 2.5, -0.02, -2, 0.003, 6, "
            "0.05, 0\n0\n*VISCOELASTIC, TIME=PRONY\n0.3, 0, 0.0001\n") in text
    assert same_spec(load_ball(read_ball(text)).to_dict(), ball.to_dict())
    out = tmp_path / "rubber.json"
    code, _, err = run(capsys, "import-material", path, "--ball", "--out", out, "--json")
    assert code == 0, err
    assert same_spec(load_ball(out).to_dict(), ball.to_dict())


def test_calculix_rubber_cards_carry_d1_and_refuse_what_ccx_cannot_read(tmp_path):
    ball = load_ball(RUBBER_SPEC)
    path = tmp_path / "rubber.inp"
    written = export_ball(ball, path, "calculix", solver="3d", setup=ImpactSetup(20.0),
                          divisions=4)
    text = path.read_text()
    # each layer's elastic ball in its own convention; D1 = 0 becomes 2 / K with K = 20 x the
    # instantaneous mu0 (long-term C10 given: mu0 = 2 C10 / (1 - 0.3)), unrelaxed (k = 0)
    k_core = 20 * 2 * 1.2e6 / 0.7
    assert f"*HYPERELASTIC, YEOH\n1.2, -0.03, 0.0008, {2 / k_core * 1e6:.12g}, 0, 0\n" in text
    assert "*HYPERELASTIC, OGDEN, N=3\n1.5, 2.5, -0.02, -2, 0.003, 6, 0.05, 0\n0\n" in text
    # --moduli long_term: the instantaneous Ogden set times (1 - 0.3), D1 as given (k = 0)
    export_ball(ball, path, "calculix", solver="3d", ball_only=True, moduli="long_term")
    assert ("*HYPERELASTIC, OGDEN, N=3\n1.05, 2.5, -0.014, -2, 0.0021, 6, 0.05, 0\n0\n"
            in path.read_text())
    assert any("D1 = 0 written as D1 = 2/K" in note for note in written.notes)
    four = load_ball({**RUBBER_SPEC, "layers": [{**RUBBER_SPEC["layers"][1], "material": {
        **RUBBER_SPEC["layers"][1]["material"],
        "terms": RUBBER_SPEC["layers"][1]["material"]["terms"] + [{"mu_pa": 1e3, "alpha": 8.0}]}}]})
    with pytest.raises(InputError, match="at most 3 terms"):
        export_ball(four, tmp_path / "four.inp", "calculix", solver="3d", ball_only=True)
    export_ball(four, tmp_path / "four.inp", "abaqus", solver="3d", ball_only=True)  # ABAQUS: 6


def test_lsdyna_writes_yeoh_and_ogden(tmp_path):
    ball = load_ball(RUBBER_SPEC)
    path = tmp_path / "rubber.k"
    export_ball(ball, path, "lsdyna", solver="3d", setup=ImpactSetup(20.0), divisions=4)
    text = path.read_text()
    counts = lsdyna.validate(text)
    assert counts["*MAT_HYPERELASTIC_RUBBER_TITLE"] == 1 and counts["*MAT_OGDEN_RUBBER_TITLE"] == 1

    def fields(line):
        return [float(line[i:i + 10]) if line[i:i + 10].strip() else 0.0
                for i in range(0, len(line), 10)]

    yeoh = text.split("*MAT_HYPERELASTIC_RUBBER_TITLE\n")[1].splitlines()
    # polynomial card C10, C01, C11, C20, C02, C30 (long-term, MPa)
    assert fields(yeoh[2])[:6] == pytest.approx([1.2, 0.0, 0.0, -0.03, 0.0, 0.0008])
    ogden = text.split("*MAT_OGDEN_RUBBER_TITLE\n")[1].splitlines()
    mus, alphas = fields(ogden[2])[:3], fields(ogden[3])[:3]
    assert alphas == [2.5, -2.0, 6.0]
    # LS-DYNA's energy sum_j mu_j / a_j (sum_i l_i^a_j - 3) equals ours, the long-term
    # sum_j 2 mu_j / a_j^2 (...), at isochoric stretches (MPa)
    lam = np.array([1.7, 0.9, 1 / (1.7 * 0.9)])
    ours = sum(2 * m * 0.7 / a ** 2 * (np.sum(lam ** a) - 3)
               for m, a in ((1.5, 2.5), (-0.02, -2.0), (0.003, 6.0)))
    theirs = sum(m / a * (np.sum(lam ** a) - 3) for m, a in zip(mus, alphas))
    assert theirs == pytest.approx(ours, rel=1e-6)


def test_import_material_reads_yeoh_and_ogden_blocks(tmp_path, capsys):
    user = tmp_path / "rubber.inp"
    user.write_text("""*MATERIAL, NAME=tread
*DENSITY
1.2e-9
*HYPERELASTIC, YEOH
0.6, -0.01, 0.0002, 0.002
*MATERIAL, NAME=seal
*DENSITY
1.0e-9
*HYPERELASTIC, OGDEN, N=2, MODULI=INSTANTANEOUS
0.9, 3., -0.05, -1.5, 0.004, 0.
*VISCOELASTIC, TIME=PRONY
0.4, 0.2, 1e-3
""")
    code, out, err = run(capsys, "import-material", user, "--units", "mm-tonne-s")
    assert code == 0, err
    tread, seal = json.loads(out)["materials"]
    assert tread["material"] == {"model": "yeoh", "c10_pa": 6e5, "c20_pa": -1e4, "c30_pa": 200.0,
                                 "d1_per_pa": 2e-9, "moduli": "long_term"}
    assert seal["material"] == {"model": "ogden", "d1_per_pa": 4e-9, "moduli": "instantaneous",
                                "terms": [{"mu_pa": 9e5, "alpha": 3.0},
                                          {"mu_pa": -5e4, "alpha": -1.5}],
                                "prony": [{"g": 0.4, "k": 0.2, "tau_s": 1e-3}]}
    bad = tmp_path / "bad.inp"
    for block, message in (("*HYPERELASTIC, YEOH\n0.6, 0, 0, 0.002, 0.001, 0\n", "D2 = 0.001"),
                           ("*HYPERELASTIC, OGDEN, N=2\n-0.9, 3, 0.05, 1.5, 0, 0\n",
                            "sum of mu_pa"),
                           ("*HYPERELASTIC, OGDEN, N=2\n0.9, 3, -0.05, -1.5, 0\n",
                            "expected 6 values")):
        bad.write_text("*MATERIAL, NAME=x\n*DENSITY\n1e-9\n" + block)
        code, _, err = run(capsys, "import-material", bad, "--units", "mm-tonne-s")
        assert code == 2 and message in err, err
