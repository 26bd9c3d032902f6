"""The text of the material results, as `ballimpact material fit|ball|check` prints it (a fit of
material tests, a ball file written from fitted materials, the Drucker-stable stretch ranges of
a ball's materials): each function returns the lines (without their line ends), so that a
Python user gets the command's text. The results are those of `material.fitting`,
`material.ball_file` and `material.stability`."""

from __future__ import annotations

from pathlib import Path
from typing import Any


def fit_lines(run) -> list[str]:
    """`material.fitting.fit_material_files`' run: a Prony series with its terms, or the
    hyperelastic constants with their standard errors, R^2 per test, the stable stretch range
    per mode and the notes."""
    out = run.result
    if out["model"] == "prony":
        test = run.tests[0]
        return [f"Prony series ({len(out['prony'])} terms) fitted to {test.path} ({test.mode}), "
                f"R^2 = {run.fit.r2:.5f}",
                *(f"  g = {term['g']:.5g}  k = {term['k']:.5g}  tau_s = {term['tau_s']:.5g}"
                  for term in out["prony"])]
    errors = out["standard_errors"]
    return [f"{out['model']} fitted to {len(run.tests)} test(s), error {out['error']}",
            *(f"  {key:<18} {value:>14.6g}  +/- {errors.get(key, 0.0):.3g}"
              for key, value in out["constants"].items()),
            "  R^2: " + ", ".join(f"{Path(k).name if k != 'overall' else k} {v:.5f}"
                                  for k, v in out["r2"].items()),
            *(f"  Drucker-stable {mode:<12} stretch {low:.4g} to {high:.4g}"
              for mode, (low, high) in out["stable_range"].items()),
            *(f"  note: {note}" for note in out["notes"])]


def ball_file_lines(out: dict[str, Any], path: Path) -> list[str]:
    """A ball file written to `path` (`material.ball_file.write_ball`'s specification): its
    size and mass, and each layer's radius, density, mass and model."""
    return [f"wrote {path}: {out['name']}, {len(out['layers'])} layer(s), diameter "
            f"{out['diameter_m']:g} m, mass {out['mass_kg']:.5g} kg",
            *(f"  {e['name']:<10} to r = {e['outer_radius_m']:g} m, "
              f"{e['density_kg_m3']:.5g} kg/m^3, {e['mass_kg']:.4g} kg, {e['model']}"
              + (f" + {e['prony_terms']} Prony term(s)" if e["prony_terms"] else "")
              for e in out["layers"])]


def stability_lines(out: dict[str, Any]) -> list[str]:
    """`material.stability.stability_report`: each layer's stable stretch range per mode
    (whether a run stays inside it), and the stretches the run reaches."""
    lines = [f"{out['name']}: Drucker-stable stretch ranges"]
    for e in out["layers"]:
        if not e["checked"]:
            lines.append(f"  {e['name']} ({e['model']}): not checked")
            continue
        for mode, (low, high) in e["stable_range"].items():
            inside = e.get("inside", {}).get(mode)
            tag = "" if inside is None else ("  run inside" if inside else "  RUN OUTSIDE")
            lines.append(f"  {e['name']} ({e['model']}) {mode:<12} {low:.4g} to {high:.4g}{tag}")
    if "stretch_range" in out:
        lo, hi = out["stretch_range"]
        lines.append(f"  run at {out['speed_m_s']:g} m/s reaches stretches {lo:.4g} to {hi:.4g}")
    return lines


__all__ = ["ball_file_lines", "fit_lines", "stability_lines"]
