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
from ballimpact.errors import InputError, InputWarning
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
    """The men's ball at 19 m/s on the helmet's flat shell and liner on a 5 kg headform, both
    geometries: the same target figures' keys; the largest transmitted force within 15%, the
    liner's largest compression and work lower in 3D, within 25% and 40%.

    Measured (axisymmetric / 3D at 4, 6, 8, 10 divisions): liner compression 0.360 / 0.292,
    0.303, 0.298, 0.296; liner work 3.36 / 2.26, 2.38, 2.27, 2.26 J; largest transmitted force
    5646 / 5652, 6506, 5931, 6176 N. The 3D slab's default layout puts 2 cells of 11 mm through
    the 22 mm liner at 4 to 10 divisions (`geometry.slab_layout`: about 4 pole spacings, at least
    2 a layer; the axisymmetric target has 8 of 2.75 mm on the axis): a stiffer liner under the
    ball, which compresses less and takes less work, the ball more (internal work at the end
    8.77 J axisymmetric, 8.46 J in 3D at 8 divisions), whatever the ball's divisions."""
    axi = _run(fe.Axisymmetric(), "cricket-men", 19.0, "helmet-on-headform.json")
    hexa = _run(Hexahedral(fe.Options3D(divisions=4)), "cricket-men", 19.0,
                "helmet-on-headform.json")
    a, b = axi.energies_j, hexa.energies_j
    assert {k for k in b if k.startswith("target_")} == {k for k in a if k.startswith("target_")}
    force = "target_max_transmitted_force_n"
    assert abs(b[force] - a[force]) <= 0.15 * a[force]
    for key, tolerance in (("target_liner_max_compression", 0.25), ("target_liner_work_j", 0.4)):
        assert (1.0 - tolerance) * a[key] <= b[key] <= a[key], (key, a[key], b[key])


def test_slab_cells_through_the_depth():
    """`Options3D.slab_depth_cell_m` sets the default slab's cells through the depth (a layer of
    a whole number of them gets that number, at least 2); unset, 4 pole spacings as before
    (docs/equipment.md: the helmet's 3 mm shell and 22 mm liner get 2 and 2)."""
    from ballimpact.fe.hex.geometry import slab_layout

    ball = load_ball("cricket-men", impact_speed_m_s=19.0)
    target = load_target(TARGETS / "helmet-on-headform.json")
    default = slab_layout(ball, target, fe.Options3D(divisions=4))
    assert np.allclose(default[2], [0.0, 1.5e-3, 3e-3, 14e-3, 25e-3])
    for cell, through in ((5.5e-3, (2, 4)), (2.75e-3, (2, 8)), (1e-3, (3, 22))):
        cells, grading, depths = slab_layout(ball, target, fe.Options3D(
            divisions=4, slab_depth_cell_m=cell))
        assert (cells, grading) == default[:2]  # in plane unchanged
        assert np.count_nonzero(depths <= 3e-3 + 1e-12) - 1 == through[0]
        assert len(depths) - 1 == sum(through)
        assert depths[-1] == pytest.approx(25e-3, rel=1e-12)
    with pytest.raises(InputError, match="not both"):
        fe.Options3D(slab_depth_cell_m=2e-3, slab_depth_growth=1.2)
