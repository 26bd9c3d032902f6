"""A bat's specification (issue 41): files and dicts load, and each bad input is refused with an
`InputError` of one line naming the field and what is allowed."""

import copy
import json

import pytest

from ballimpact.bats import Grip, load_bat, modes
from ballimpact.errors import InputError

GOOD = {"name": "test-bat", "length_m": 0.84,
        "profile": [[0.0, 0.02], [0.04, 0.012], [0.5, 0.02], [0.84, 0.03]],
        "material": {"youngs_modulus_pa": 12e9, "density_kg_m3": 650.0,
                     "shear_modulus_pa": 1.0e9},
        "loss_factor": 0.01}
BLADE = {"width_m": 0.108, "profile_thickness": [[0.3, 0.03], [0.6, 0.05], [0.84, 0.035]]}


def changed(path, value):
    """`GOOD` with the key at `path` (a tuple of keys / indexes) set to `value` (or removed
    when value is `...`)."""
    spec = copy.deepcopy(GOOD)
    where = spec
    for key in path[:-1]:
        where = where[key]
    if value is ...:
        del where[path[-1]]
    else:
        where[path[-1]] = value
    return spec


def with_blade(**blade):
    spec = copy.deepcopy(GOOD)
    spec["profile"] = [[0.0, 0.018], [0.3, 0.016]]
    spec["section"] = {"blade": {**BLADE, **blade}}
    return spec


BAD = {
    "x not increasing": (changed(("profile", 2), [0.03, 0.02]), ["bat.profile[2][0]",
                                                               "strictly increasing"]),
    "x not from 0": (changed(("profile", 0), [0.01, 0.02]), ["bat.profile[0][0]", "[0, 0.84]"]),
    "x short of the length": (changed(("profile", 3), [0.8, 0.03]),
                              ["bat.profile[3][0]", "length_m = 0.84"]),
    "radius in mm": (changed(("profile", 3), [0.84, 33.0]),
                     ["bat.profile[3][1] = 33", "(0, 0.2] m", "millimetres"]),
    "negative radius": (changed(("profile", 1), [0.04, -0.01]), ["bat.profile[1][1]"]),
    "profile not a list of pairs": (changed(("profile",), [[0.0, 0.02, 1.0], [0.84, 0.03]]),
                                    ["bat.profile[0]", "pair"]),
    "length in mm": (changed(("length_m",), 864.0), ["bat.length_m = 864", "millimetres"]),
    "wall thicker than the radius": (changed(("wall_thickness_m",), 0.015),
                                     ["bat.wall_thickness_m = 0.015", "smallest outer radius"]),
    "wall in mm": (changed(("wall_thickness_m",), 2.8), ["bat.wall_thickness_m", "millimetres"]),
    "zero Young's modulus": (changed(("material", "youngs_modulus_pa"), 0.0),
                             ["bat.material.youngs_modulus_pa = 0", "(0, inf)"]),
    "negative shear modulus": (changed(("material", "shear_modulus_pa"), -1e9),
                               ["bat.material.shear_modulus_pa"]),
    "zero density": (changed(("material", "density_kg_m3"), 0.0),
                     ["bat.material.density_kg_m3 = 0"]),
    "density in g/cm^3 * 1e6": (changed(("material", "density_kg_m3"), 6.5e5),
                                ["bat.material.density_kg_m3", "25000"]),
    "no shear modulus nor Poisson": (changed(("material", "shear_modulus_pa"), ...),
                                     ["bat.material", "poissons_ratio", "shear_modulus_pa"]),
    "Poisson's ratio 0.5": (changed(("material", "poissons_ratio"), 0.5),
                            ["bat.material.poissons_ratio = 0.5"]),
    "missing density": (changed(("material", "density_kg_m3"), ...), ["density_kg_m3"]),
    "unknown key": (changed(("colour",), "red"), ["bat: unknown key 'colour'"]),
    "unknown material key": (changed(("material", "e_pa"), 1e9),
                             ["bat.material: unknown key 'e_pa'"]),
    "loss factor 1": (changed(("loss_factor",), 1.5), ["bat.loss_factor = 1.5"]),
    "text for a number": (changed(("length_m",), "0.84"), ["bat.length_m", "finite number"]),
    "missing profile": (changed(("profile",), ...), ["missing key 'profile'"]),
    "unknown section": (changed(("section",), "square"), ["bat.section = 'square'"]),
    "blade width in mm": (with_blade(width_m=108.0), ["bat.section.blade.width_m", "millimetres"]),
    "blade not reaching the end": (with_blade(profile_thickness=[[0.3, 0.03], [0.8, 0.04]]),
                                   ["bat.section.blade.profile_thickness[1][0]", "length_m"]),
    "blade not after the handle": (with_blade(profile_thickness=[[0.0, 0.03], [0.84, 0.04]]),
                                   ["bat.section.blade.profile_thickness[0][0]"]),
    "unknown blade key": (with_blade(depth_m=0.05), ["bat.section.blade: unknown key 'depth_m'"]),
}


@pytest.mark.parametrize("case", BAD)
def test_bad_input(case):
    spec, fragments = BAD[case]
    with pytest.raises(InputError) as caught:
        load_bat(spec)
    message = str(caught.value)
    print(case, "->", message)
    assert "\n" not in message
    for fragment in fragments:
        assert fragment in message, (fragment, message)


BAD_MODES = {
    "unknown support": (dict(support="clamped"), ["support = 'clamped'", "free, pivot"]),
    "pivot without its place": (dict(support="pivot"), ["pivot_m"]),
    "pivot off the bat": (dict(support="pivot", pivot_m=1.2), ["pivot_m = 1.2", "[0, 0.84] m"]),
    "pivot_m for a free bat": (dict(pivot_m=0.1), ["pivot_m = 0.1"]),
    "hand off the bat": (dict(grip=Grip(positions_m=(0.1, 2.0))), ["grip.positions_m[1] = 2"]),
    "negative grip stiffness": (dict(grip=Grip(stiffness_n_m=-1.0)), ["grip.stiffness_n_m"]),
    "zero modes": (dict(count=0), ["count = 0"]),
    "too few elements": (dict(elements=2), ["elements = 2"]),
}


@pytest.mark.parametrize("case", BAD_MODES)
def test_bad_modes_request(case):
    kwargs, fragments = BAD_MODES[case]
    with pytest.raises(InputError) as caught:
        modes(GOOD, **kwargs)
    message = str(caught.value)
    assert "\n" not in message
    for fragment in fragments:
        assert fragment in message, (fragment, message)


def test_files_and_dicts(tmp_path):
    bat = load_bat(GOOD)
    assert bat.material.shear_modulus_pa == 1.0e9 and bat.wall_thickness_m is None
    path = tmp_path / "mybat.json"
    path.write_text(json.dumps(bat.to_dict()))
    assert load_bat(path) == bat and load_bat(str(path)) == bat
    toml = tmp_path / "bat.toml"
    toml.write_text('name = "t"\nlength_m = 0.84\nprofile = [[0.0, 0.02], [0.84, 0.03]]\n'
                    '[material]\nyoungs_modulus_pa = 70e9\ndensity_kg_m3 = 2800.0\n'
                    'poissons_ratio = 0.33\n')
    tube = load_bat(toml)
    assert tube.material.shear_modulus_pa == pytest.approx(70e9 / 2.66)
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(changed(("length_m",), -1.0)))
    with pytest.raises(InputError, match=r"bad\.json: bat\.length_m = -1"):
        load_bat(bad)
    with pytest.raises(InputError, match="neither a preset"):
        load_bat(tmp_path / "missing.json")
    blade = load_bat(with_blade())
    assert blade.blade.start_m == 0.3 and blade.round_end_m == 0.3
    assert load_bat(blade.to_dict()) == blade
