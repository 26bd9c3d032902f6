"""The text of the standards' results, as `ballimpact standard` prints it (the methods, a method
on a lab's records or on a model, a ball from a specification, a bat's BBCOR): each function
returns the lines (without their line ends), so that a Python user gets the command's text."""

from __future__ import annotations

from typing import Any

from ..records.loaders import LBF_N
from .results import stats_text


def methods_lines(methods: list[dict[str, Any]]) -> list[str]:
    """The methods (`methods.describe_methods`), one line each."""
    return [f"{entry['method']:<18} {entry['designation']:<11} {entry['description']}"
            for entry in methods]


def method_lines(result: dict[str, Any]) -> list[str]:
    """`run.run_method`'s result: on records (`records_lines`) or on a model (`model_lines`)."""
    return (model_lines if result["source"] == "model" else records_lines)(result)


def records_lines(result: dict[str, Any]) -> list[str]:
    """A method on a lab's records (`lab.from_records`): per ball mean +- SD (n) of each
    quantity, then the line over the balls."""
    quantities, overall = result["quantities"], result["overall"]
    lines = [f"{result['designation']} {result['method']}: {overall['shots']} records, "
             f"{overall['balls']} balls" + (f" ({result['nominal_speed_note']})"
                                            if "nominal_speed_note" in result else "")]
    for entry in result["balls"]:
        parts = [stats_text(entry[key], unit) for key, unit in quantities.items()]
        if "impact_speed_m_s" in entry:
            parts.append(f"inbound {stats_text(entry['impact_speed_m_s'], 'm/s')}")
        lines.append(f"  {entry['ball']:<16} " + "; ".join(parts) + f" (n={entry['count']})")
    parts = [stats_text(overall[key], unit) for key, unit in quantities.items()]
    return lines + [f"  {'all balls':<16} " + "; ".join(parts)
                    + f" (mean and SD of {overall['balls']} ball means)"]


def model_lines(result: dict[str, Any]) -> list[str]:
    """A method on a ball model (`model.on_model`): its quantities, then the model's cost."""
    values, cost = result["result"], result["cost"]
    parts = [f"{values[key]:.5g}" + (f" {unit}" if unit else "")
             for key, unit in result["quantities"].items()]
    where = (f"at {values['impact_speed_m_s']:.4g} m/s" if "impact_speed_m_s" in values
             else f"at {values['deflection_m'] * 1e3:.3g} mm")
    steps = (f"{cost['steps']} steps" if "steps" in cost
             else f"{cost['increments']} increments, {cost['newton_iterations']} Newton "
                  "iterations")
    return [f"{result['designation']} {result['method']} of {result['ball']} (model) {where}: "
            + "; ".join(parts),
            f"  cost: {cost['wall_time_s']:.2f} s wall, {steps}, {cost['elements']} elements "
            f"({cost['element_size_m']:g} m)"]


def specified_ball_lines(out: dict[str, Any]) -> list[str]:
    """A ball calibrated to a specification (`specification.write_specified_ball`): the
    specification, the constants found, their FE check and the runs it took."""
    s, p, c = out["specification"], out["params"], out["check"]
    lbf = s["compression_force_n"] / LBF_N
    return [f"{out['ball']['name']}: a homogeneous ball of {s['diameter_m'] * 1e3:.2f} mm and "
            f"{s['mass_kg'] * 1e3:.2f} g calibrated to COR {s['cor']:g} at "
            f"{s['impact_speed_m_s']:.4g} m/s and {s['compression_force_n']:.4g} N "
            f"({lbf:.4g} lbf) at {s['compression_deflection_m'] * 1e3:.3g} mm",
            f"  C10 {p['c10_pa'] / 1e6:.4g} MPa, C01 0, g1 {p['g1']:.4f}, tau1 "
            f"{p['tau1_s'] * 1e6:.4g} us (long-term moduli, K = 20 mu0 / (1 - g1))",
            f"  FE check ({out['element_size_m'] * 1e3:.3g} mm elements): COR {c['cor']:.4f} "
            f"({c['cor_error']:+.4f}), compression {c['compression_force_n']:.5g} N "
            f"({c['compression_relative_error']:+.2%}); DS {c['dynamic_stiffness_n_m']:.4g} "
            f"N/m, peak force {c['peak_force_n']:.5g} N, contact time "
            f"{c['contact_time_s'] * 1e3:.3f} ms",
            f"  {out['runs']['impacts']} impacts, {out['runs']['compressions']} compressions, "
            f"{out['wall_time_s']:.1f} s" + (f"; wrote {out['out']}" if "out" in out else "")]


def bbcor_lines(out: dict[str, Any]) -> list[str]:
    """A bat's BBCOR (`bbcor.bbcor_certification`): the BBCOR against the limit, the test's
    figures, where the largest BBCOR is, and the scan along the barrel."""
    verdict = "meets it" if out["meets_limit"] else "EXCEEDS it"
    model = "FE ball" if out["ball"].get("model") == "fe" else "ball law"
    return [f"{out['designation']} of {out['bat']} with {out['ball']['name']} ({model}): BBCOR "
            f"{out['bbcor']:.4f} (limit {out['limit']:.3f}: {verdict})",
            f"  ball {out['speed_m_s']:.4g} m/s ({out['ball_speed_mph']:.0f} mph) at the bat at "
            f"rest, pinned {out['pivot_m']:g} m ({out['pivot_in']:g} in) from the knob; I pivot "
            f"{out['moi_pivot_kg_m2']:.4f} kg m^2, ball {out['ball_mass_kg']:.4g} kg",
            f"  largest BBCOR at {out['impact_m']:.4f} m from the knob "
            f"({out['from_barrel_end_m']:.4f} m, {out['from_barrel_end_in']:.2f} in from the "
            f"barrel end): e_A {out['collision_efficiency']:.4f}, r {out['r']:.4f}; a rigid bat "
            f"(the ball's COR on a rigid plane) {out['rigid_bbcor']:.4f}",
            "  scan, in from the barrel end: "
            + ", ".join(f"{p['from_barrel_end_in']:.1f} {p['bbcor']:.4f}" for p in out["scan"])]


__all__ = ["bbcor_lines", "method_lines", "methods_lines", "model_lines", "records_lines",
           "specified_ball_lines"]
