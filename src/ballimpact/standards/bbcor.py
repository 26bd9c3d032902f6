"""The BBCOR certification of a baseball bat (ASTM F2219, NCAA's BBCOR standard) run on the
bat's model: docs/equipment.md, "BBCOR".

The method's facts (`BBCOR_METHOD`; sources in docs/equipment.md): a baseball fired at 136 mph
at the bat at rest, the bat free to turn about a pivot 6 in from the knob end; BBCOR from the
ball's inbound speed v, its rebound speed e_A v and the bat's moment of inertia I about the
pivot: BBCOR = e_A (1 + r) + r, r = m Q^2 / I, Q the distance from the pivot to the impact point
(angular momentum about the pivot: the bat's speed at the impact point after the hit is
r (1 + e_A) v, so BBCOR is the relative speed after the hit over the one before, and for a rigid
bat the ball-bat COR). The bat is certified at the location of its largest BBCOR; the limit is
0.500, not to be exceeded.

Not a `Method` of `methods.METHODS`: those are a ball on a rigid wall or between platens, run on
a lab's records or a ball model; this one needs a bat and runs on the bat's model only
(`bats.bat_impact`, support "pivot"), so it is kept apart.

Our choices (not the method's): the scan of impact points (`SCAN_STEP_M`, from `SCAN_FROM_M`
to `SCAN_TO_M` from the barrel end, extended by a step while the largest BBCOR is at an end),
the largest refined by a parabola through it and its neighbours and the bat hit once more
there; one hit per point (the model is deterministic: the method's six hits would be the same).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from ..errors import InputError
from .methods import INCH_M

#: 1 mph in m/s (exact: 1609.344 m / 3600 s)
MPH_M_S = 0.44704


@dataclass(frozen=True)
class BBCORMethod:
    """The facts of the BBCOR certification (docs/equipment.md, "BBCOR", for their sources)."""

    name: str
    designation: str
    description: str
    ball_speed_m_s: float
    pivot_m: float
    limit: float
    location: str
    formula: str
    sources: tuple[str, ...]

    def to_dict(self) -> dict[str, Any]:
        return {"method": self.name, "designation": self.designation,
                "description": self.description, "ball_speed_m_s": self.ball_speed_m_s,
                "ball_speed_mph": self.ball_speed_m_s / MPH_M_S, "pivot_m": self.pivot_m,
                "pivot_in": self.pivot_m / INCH_M, "limit": self.limit,
                "location": self.location, "formula": self.formula,
                "sources": list(self.sources)}


BBCOR_METHOD = BBCORMethod(
    "bbcor", "ASTM F2219 / NCAA BBCOR",
    "bat-ball coefficient of restitution: a baseball at 136 mph on the bat at rest, pivoted 6 in "
    "from the knob, at the location of the largest BBCOR; at most 0.500",
    136 * MPH_M_S, 6 * INCH_M, 0.500, "the location of the largest BBCOR along the barrel",
    "BBCOR = e_A (1 + r) + r, e_A = v_rebound / v_inbound, r = m_ball Q^2 / I_pivot, Q = impact "
    "point - pivot",
    ("ASTM F2219, Standard Test Methods for Measuring High-Speed Bat Performance (BBCOR, e_A "
     "and BBS of a bat at rest hit by a fired ball)",
     "NCAA Standard for Testing Baseball Bat Performance: Bat-Ball Coefficient of Restitution "
     "(pivot and MOI 6 in from the knob; BBCOR averaged over six hits at the maximum-BBCOR "
     "location must not exceed 0.500)",
     "NCAA Baseball Research Panel, BBCOR announcement, 16 Sep 2008 (limit 0.50; the test "
     "procedure of the BESR standard kept)",
     "A. M. Nathan, Bat performance standards in NCAA baseball, SABR Baseball Research Journal "
     "2003 (the BESR test: ball 70 mph, bat 66 mph, pivot 6 in from the knob: 136 mph relative)",
     "L. V. Smith, Sports Science Laboratory (WSU), Bat performance measures (BBCOR, e_A, BPF, "
     "BESR, BBS)"))

#: our scan (m from the barrel end): from, to, step (0.5 in); see the module docstring
SCAN_FROM_M, SCAN_TO_M, SCAN_STEP_M = 3 * INCH_M, 11 * INCH_M, 0.5 * INCH_M
#: the scan is not extended closer than this to the barrel end or to the pivot (m)
SCAN_MARGIN_M = 1 * INCH_M


@dataclass(frozen=True)
class BBCORResult:
    """The BBCOR of `bat` with `ball` (SI; the method's facts under `method`). `scan`: each
    impact point's figures, from the barrel end inward; the result is at `impact_m` (from the
    knob end), the scan's largest BBCOR refined (module docstring)."""

    bat: str
    ball: dict
    speed_m_s: float
    pivot_m: float
    impact_m: float
    bat_length_m: float
    bbcor: float
    collision_efficiency: float
    r: float
    moi_pivot_kg_m2: float
    ball_mass_kg: float
    rigid_bbcor: float
    bat_mass_kg: float
    energy_balance_error: float
    scan: tuple[dict, ...]

    @property
    def limit(self) -> float:
        return BBCOR_METHOD.limit

    @property
    def meets_limit(self) -> bool:
        """Whether the BBCOR does not exceed the limit (0.500)."""
        return self.bbcor <= self.limit

    @property
    def from_barrel_end_m(self) -> float:
        return self.bat_length_m - self.impact_m

    def summary(self) -> dict[str, Any]:
        """JSON-able: the method's facts, the figures, the scan and the choices made."""
        return {**BBCOR_METHOD.to_dict(), "source": "model", "bat": self.bat,
                "ball": self.ball, "bbcor": self.bbcor, "limit": self.limit,
                "meets_limit": self.meets_limit, "impact_m": self.impact_m,
                "from_barrel_end_m": self.from_barrel_end_m,
                "from_barrel_end_in": self.from_barrel_end_m / INCH_M,
                "collision_efficiency": self.collision_efficiency, "r": self.r,
                "moi_pivot_kg_m2": self.moi_pivot_kg_m2, "ball_mass_kg": self.ball_mass_kg,
                "speed_m_s": self.speed_m_s, "rigid_bbcor": self.rigid_bbcor,
                "bat_mass_kg": self.bat_mass_kg, "bat_length_m": self.bat_length_m,
                "energy_balance_error": self.energy_balance_error,
                "scan": [dict(p) for p in self.scan],
                "choices": {"scan_from_barrel_end_m": [self.scan[0]["from_barrel_end_m"],
                                                       self.scan[-1]["from_barrel_end_m"]],
                            "scan_points": len(self.scan),
                            "default_scan_m": {"from": SCAN_FROM_M, "to": SCAN_TO_M,
                                               "step": SCAN_STEP_M},
                            "location": "the scan's largest BBCOR refined by a parabola "
                                        "through it and its neighbours, hit once more",
                            "hits": "one per point (the model is deterministic)",
                            "bat": "Timoshenko beam pinned at the pivot (bats.bat_impact, "
                                   "support 'pivot'): no barrel hoop modes"}}


def bbcor_of(collision_efficiency: float, r: float) -> float:
    """BBCOR = e_A (1 + r) + r (module docstring)."""
    return collision_efficiency * (1.0 + r) + r


def bbcor(bat, ball, *, scan_from_end_m=None, modes: int | None = None,
          elements: int | None = None, allow=(), ball_model: str = "law",
          progress: Callable[[int, int], None] | None = None) -> BBCORResult:
    """The BBCOR certification on the model of `bat` (anything `bats.load_bat` takes) with
    `ball`: a ball preset, file or dict (its Hunt-Crossley law fitted to one FE run on a rigid
    plane at the method's speed, `bats.ball_law`; `allow` goes to it) or a
    `bats.HuntCrossleyBall`. The bat is pinned at the method's pivot and hit at rest at the
    method's speed along the scan (`scan_from_end_m`: the points, m from the barrel end;
    default ours, module docstring, extended while the largest is at an end); BBCOR at the
    largest, refined. `ball_model` "fe": the FE ball itself on the bat's modes
    (`bats.fe_impact`), not its law. `modes`, `elements`: `bats.bat_model`'s (default its
    own). `progress(i, n)` after each point of the scan."""
    from ..bats import ball_law, bat_model, bat_properties, impact_sweep, load_bat
    from ..bats.beam import DEFAULT_ELEMENTS
    from ..bats.impact import DEFAULT_MODES, bat_impact
    from ..bats.sweep import extremum_x

    spec = load_bat(bat)
    method = BBCOR_METHOD
    v, pivot, length = method.ball_speed_m_s, method.pivot_m, spec.length_m
    lowest, highest = SCAN_MARGIN_M / 2, length - pivot - SCAN_MARGIN_M / 2  # from the end
    if highest <= lowest:
        raise InputError(f"bat {spec.name}: {length:g} m long, too short for a pivot "
                         f"{pivot:g} m from the knob")
    extend = scan_from_end_m is None
    if extend:
        count = int(round((SCAN_TO_M - SCAN_FROM_M) / SCAN_STEP_M)) + 1
        ends = SCAN_FROM_M + SCAN_STEP_M * np.arange(count)
        ends = ends[(ends >= lowest) & (ends <= highest)]
    else:
        ends = np.unique(np.atleast_1d(np.asarray(scan_from_end_m, dtype=float)))
        if ends.size < 1 or not np.all(np.isfinite(ends)):
            raise InputError("scan_from_end_m: expected finite distances from the barrel end")
        bad = ends[(ends < 0.0) | (ends >= length - pivot)]
        if bad.size:
            raise InputError(f"scan_from_end_m = {bad[0]:g}: off the bat beyond the pivot, "
                             f"allowed [0, {length - pivot:g}) m from the barrel end")
    if ends.size < 1:
        raise InputError(f"bat {spec.name}: no impact point of the scan between the barrel end "
                         "and the pivot")
    if ball_model not in ("law", "fe"):
        raise InputError(f"ball_model = {ball_model!r}: allowed 'law' or 'fe'")
    if ball_model == "fe":
        from ..bats.fe_impact import fe_bat_impact
        from ..fe import BallModel, load_ball, simulate

        collider = ball if isinstance(ball, BallModel) else load_ball(
            ball, impact_speed_m_s=v, allow=allow)
        reference = simulate(collider, v, allow=allow)
        mass, rigid_cor = reference.mass_kg, reference.cor
        ball_summary = {"name": reference.ball_name, "mass_kg": mass, "model": "fe",
                        "rigid_plane_cor": rigid_cor}

        def one(x_knob: float):
            return fe_bat_impact(bm, collider, v, x_knob, pivot_m=pivot, reference=reference,
                                 allow=allow)
    else:
        collider, reference = ball_law(ball, v, allow=allow), None
        mass, rigid_cor = collider.mass_kg, collider.rigid_plane(v).cor
        ball_summary = collider.summary()

        def one(x_knob: float):
            return bat_impact(bm, collider, v, x_knob, pivot_m=pivot)
    bm = bat_model(spec, support="pivot", pivot_m=pivot,
                   modes=DEFAULT_MODES if modes is None else modes,
                   elements=DEFAULT_ELEMENTS if elements is None else elements)
    props = bat_properties(spec)
    moi = props.moi_about_kg_m2(pivot)

    def r_at(x_knob: float) -> float:
        return mass * (x_knob - pivot) ** 2 / moi

    results: dict[float, Any] = {}

    def hit(points_from_end) -> None:
        new = [float(e) for e in points_from_end if float(e) not in results]
        if new:
            sweep = impact_sweep(bm, collider, v, [length - e for e in new], pivot_m=pivot,
                                 allow=allow, reference=reference,
                                 progress=(None if progress is None else
                                           lambda i, n: progress(len(results) + i,
                                                                 len(results) + n)))
            results.update(zip(new, sweep.results))

    def values() -> tuple[np.ndarray, np.ndarray]:
        xs = np.array(sorted(results))
        return xs, np.array([bbcor_of(results[e].collision_efficiency, r_at(length - e))
                             for e in xs])

    hit(ends)
    while extend:  # the largest at an end of the scan: one more step beyond it
        xs, bb = values()
        i = int(np.argmax(bb))
        step = (xs[0] - SCAN_STEP_M if i == 0 else xs[-1] + SCAN_STEP_M
                if i == xs.size - 1 else None)
        if step is None or not lowest <= step <= highest:
            break
        hit([step])
    xs, bb = values()
    scan = tuple({"from_barrel_end_m": float(e), "from_barrel_end_in": float(e / INCH_M),
                  "impact_m": float(length - e), "r": r_at(length - e),
                  "collision_efficiency": results[e].collision_efficiency, "bbcor": float(b)}
                 for e, b in zip(xs, bb))
    i = int(np.argmax(bb))
    best_end = extremum_x(xs, bb, i)
    best = results.get(best_end)
    if best is None:
        best = one(length - best_end)
    x = length - best_end
    r = r_at(x)
    value = bbcor_of(best.collision_efficiency, r)
    if value < bb[i]:  # the parabola missed: the scan's own largest
        best_end, best = float(xs[i]), results[float(xs[i])]
        x, r, value = length - best_end, r_at(length - best_end), float(bb[i])
    return BBCORResult(
        spec.name, ball_summary, v, pivot, float(x), length, float(value),
        float(best.collision_efficiency), float(r), float(moi), mass, float(rigid_cor),
        props.mass_kg, best.energy_balance_error, scan)


def bbcor_certification(bat, ball, *, ball_model: str = "fe", allow=(),
                        progress: bool = False) -> dict[str, Any]:
    """`bbcor` as `ballimpact standard bbcor` runs it, as its summary: `bat` anything
    `bats.load_bat` takes; `ball` a `bats.HuntCrossleyBall`, or a preset, file or dict taken
    at the method's speed as the FE ball itself (`ball_model` "fe") or as its contact law
    ("law"; `bats.collider`). `progress`: the law's FE run and the scan's points reported on
    stderr. Raises `InputError`: naming --bat for a bat that does not load; for an unknown
    `allow` check; for a ball that does not load."""
    from ..bats import HuntCrossleyBall, collider, load_bat
    from ..checks import check_allow
    from ..progress import CountProgress

    try:
        spec = load_bat(bat)
    except InputError as error:
        raise InputError(f"--bat: {error}") from None
    allow = check_allow(allow)
    ball = collider(ball, BBCOR_METHOD.ball_speed_m_s, ball_model=ball_model, allow=allow,
                    announce=progress)
    return bbcor(spec, ball, allow=allow,
                 progress=CountProgress("impact point") if progress else None,
                 ball_model="law" if isinstance(ball, HuntCrossleyBall) else "fe").summary()
