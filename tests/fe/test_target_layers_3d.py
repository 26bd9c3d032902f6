"""A 3D slab target's per-layer figures (`fe.hex.kernel.Kernel.layer_step`): each layer's internal
work and compression at the slab's centre, under the axisymmetric geometry's history columns
and `energies_j` keys (`fe.axi.target_kernel`, `fe.axi.geometry.target_energies`)."""

from __future__ import annotations

import dataclasses
import warnings
from pathlib import Path

import numpy as np
import pytest

from ballimpact import fe
from ballimpact.errors import InputWarning
from ballimpact.fe import load_ball
from ballimpact.fe.hex.geometry import Hexahedral
from ballimpact.fe.hex.kernel import BACKING_HISTORY, HISTORY, target_layer_history
from ballimpact.fe.hex.target import load_target

TARGETS = Path(__file__).resolve().parents[2] / "examples" / "targets"
#: the state's works at the end of a run (`Probe`), kept per result
WORKS = ("w_ball", "w_layers", "w_int")
FINALS: dict[int, dict] = {}


@dataclasses.dataclass(frozen=True)
class Probe(Hexahedral):
    """The 3D geometry, keeping the state's works at each run's end (`FINALS`, by the result's
    id)."""

    FINAL = Hexahedral.FINAL + WORKS

    def result(self, ball, target, condition, history, final, *args):
        result = super().result(ball, target, condition, history, final, *args)
        FINALS[id(result)] = {k: np.asarray(final[k]) for k in WORKS}
        return result


def _run(geometry, ball_name: str, speed: float, target_file: str):
    ball = load_ball(ball_name, impact_speed_m_s=speed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", InputWarning)  # a coarse mesh's contact warnings
        return fe.simulate(ball, speed, geometry=geometry, target=load_target(TARGETS / target_file))


@pytest.fixture(scope="module")
def soft_pad():
    """The universal ball at 25 m/s on the soft pad (20 mm foam on a 10 mm stiff layer, fixed
    base), 4 divisions."""
    return _run(Probe(fe.Options3D(divisions=4)), "cricket-universal", 25.0, "soft-pad.json")


def test_layer_columns_and_figures(soft_pad):
    r, names = soft_pad, target_layer_history(2)
    assert names == ("target_layer_0_work_j", "target_layer_1_work_j",
                     "target_layer_0_compression", "target_layer_1_compression")
    assert set(names) <= set(r.history) and set(BACKING_HISTORY).isdisjoint(r.history)
    e = r.energies_j
    for k, layer in enumerate(("foam", "backing")):
        assert e[f"target_{layer}_work_j"] == r.history[f"target_layer_{k}_work_j"][-1]
        assert e[f"target_{layer}_max_compression"] == np.max(
            r.history[f"target_layer_{k}_compression"])
    # the layers' histories are figures of their own, not energies of the whole
    assert not any(name.startswith("target_layer_") for name in e)
    # a fixed base: no transmitted force column, so no largest transmitted force
    assert "target_max_transmitted_force_n" not in e
    # the soft foam takes most of the work and compresses far more than the stiff layer
    foam, stiff = e["target_foam_max_compression"], e["target_backing_max_compression"]
    assert 0.0 < foam < 1.0 and 0.0 < stiff < 0.2 * foam
    assert e["target_foam_work_j"] > 10 * e["target_backing_work_j"] > 0.0


def test_layer_works_add_up_to_the_internal_work(soft_pad):
    """The ball's work (its nodes' share) and each layer's (its elements' corner forces) add up
    to the total internal work (the state at the run's end)."""
    final = FINALS[id(soft_pad)]
    total = float(final["w_int"])
    parts = float(final["w_ball"]) + float(np.sum(final["w_layers"]))
    assert abs(parts - total) <= 1e-9 * abs(total)
    assert np.all(final["w_layers"] > 0.0) and final["w_ball"] > 0.0


def test_no_target_keeps_its_columns():
    ball = load_ball("cricket-universal", impact_speed_m_s=25.0)
    kernel, _ = Hexahedral(fe.Options3D(divisions=4), half=True).build(ball, None)
    assert kernel.history_names == HISTORY and kernel.centre_column is None


def test_centre_column_sits_on_the_layer_interfaces():
    ball = load_ball("cricket-men", impact_speed_m_s=19.0)
    target = load_target(TARGETS / "helmet-on-headform.json")
    kernel, mesh = Hexahedral(fe.Options3D(divisions=4), half=True).build(ball, target)
    assert kernel.history_names == HISTORY + target_layer_history(2) + BACKING_HISTORY
    x = mesh.nodes_m[kernel.centre_column]
    np.testing.assert_allclose(x[:, :2], 0.0, atol=1e-15)
    np.testing.assert_allclose(-x[:, 2], [0.0, 0.003, 0.025], atol=1e-12)
    assert not np.any(mesh.ball_nodes[kernel.centre_column])
    assert set(kernel.centre_column[-1:]) <= set(mesh.fixed_nodes)


@pytest.mark.slow
def test_axisymmetric_and_3d_liners_agree():
    """The men's ball at 19 m/s on the helmet's flat shell and liner on a 5 kg headform: the
    liner's largest compression and its work within 15% in both geometries."""
    axi = _run(fe.Axisymmetric(), "cricket-men", 19.0, "helmet-on-headform.json")
    hexa = _run(Hexahedral(fe.Options3D(divisions=6)), "cricket-men", 19.0,
                "helmet-on-headform.json")
    assert set(k for k in hexa.energies_j if k.startswith("target_")) == set(
        k for k in axi.energies_j if k.startswith("target_"))
    for key in ("target_liner_max_compression", "target_liner_work_j"):
        a, b = axi.energies_j[key], hexa.energies_j[key]
        assert abs(b - a) <= 0.15 * a, (key, a, b)
