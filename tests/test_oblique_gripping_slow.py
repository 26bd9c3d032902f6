"""The 3D solver in the gripping regime against the elastic-sphere reference (issue 27, "Must
show", as far as it stands): agreement from the contact point's reversal to gross sliding, and the
coupling that makes a compressible sphere on a rigid plane differ from the theory.
The figures behind docs/oblique.md come from examples/oblique_gripping.py."""

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "examples"))

import oblique_gripping as gripping  # noqa: E402

pytestmark = pytest.mark.slow


def test_fe_against_the_reference_from_reversal_to_sliding():
    """nu 0.23, a / R = 0.069, mu 0.5 (above the coupling), the sweep's mesh (16 divisions, 2.9
    elements across the Hertz radius): at Psi 5 and 7 the tangential COR within 0.01 of the
    reference and the spin within 3% (measured: +0.006 / -2.4%, +0.0004 / -0.9%); at Psi 3 the
    contact point's velocity reverses as the theory has it (e_cp 0.37 against 0.43). Below Psi 3
    the FE is not within 0.02 (docs/oblique.md: +0.045 at Psi 0.5). About 5 minutes."""
    _, rows = gripping.run(0.23, (3.0, 5.0, 7.0))
    for row in rows:
        assert row["energy_balance_error"] < 1e-4
        if row["psi"] >= 4.0:
            assert abs(row["tangential_cor_error"]) < 0.01, row
            assert abs(row["spin_relative_error"]) < 0.03, row
        else:
            assert row["fe_contact_point_cor"] > 0 and row["reference_contact_point_cor"] > 0


def test_coupling_makes_a_compressible_sphere_on_a_rigid_plane_depend_on_friction():
    """At a fixed Psi (0.5) the uncoupled theory's results do not depend on mu. On the rigid
    plane the FE's do for nu 0.23 (beta 0.35: e_t 0.620 at mu 0.1, 0.803 at mu 0.5; the
    reference 0.772), hardly for nu 0.45 (beta 0.09: 0.649 and 0.657); the share of the normal
    force carried by slipping nodes is far larger for nu 0.23 at mu 0.1."""
    mesh, speed = gripping.DIAGNOSIS_MESH, gripping.DIAGNOSIS_NORMAL_SPEED_M_S
    e_t, slipping = {}, {}
    for nu in (0.23, 0.45):
        for mu in (0.1, 0.5):
            _, rows = gripping.run(nu, (0.5,), mesh, mu, normal_speed=speed)
            e_t[nu, mu] = rows[0]["fe_tangential_cor"]
            slipping[nu, mu] = rows[0]["slipping_load_fraction_at_peak_force"]
    assert e_t[0.23, 0.5] - e_t[0.23, 0.1] > 0.1
    assert abs(e_t[0.45, 0.5] - e_t[0.45, 0.1]) < 0.03
    assert slipping[0.23, 0.1] > 2 * slipping[0.45, 0.1]
