"""The text of the universal ball's results, as `ballimpact identify`, `universal run|train|
report` and `demo` print it: each function returns the lines (without their line ends), so that
a Python user gets the command's text."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ..fileio import table_text
from ..verdict import verdict_line
from .by_speed import IdentifiedTests
from .demo import DEMO_IMPACTS, DEMO_NOTES, SAMPLE_CONTACT_TIME_S, SAMPLE_PEAK_FORCE_N
from .identify import Identification
from .model import TARGET_UNITS


def _unit(name: str) -> str:
    """A parameter's unit as printed: none for a ratio."""
    return TARGET_UNITS[name] if TARGET_UNITS[name] != "1" else ""


def identification_lines(path: Path, found: Identification) -> list[str]:
    """One test `path` identified (`identify.identify`): the ball's size and groups, each
    parameter with its 90% interval and where it lies on the training range, and the FE
    check."""
    size = found.ball_size
    lines = [f"{path.name}: universal ball at {found.impact_speed_m_s:g} m/s "
             f"(refine: {found.refine})",
             f"  ball     diameter {size['diameter_m']:g} m ({size['diameter_source']}), mass "
             f"{size['mass_kg']:g} kg; groups "
             + ", ".join(f"{k} {v:.4g}" for k, v in found.groups.items())]
    for name, value in found.params.items():
        low, high = found.interval_90[name]
        note = (" ON THE TRAINING BOUND" if name in found.at_training_bound else
                " (clipped to the training range)" if name in found.clipped_to_training_range
                else "")
        lines.append(f"  {name:<8} {value:11.5g} {_unit(name):<3} 90% interval {low:.4g} .. "
                     f"{high:.4g}{note}")
    v = found.verification
    if v:
        lines += [f"  FE check {verdict_line(v)}",
                  f"  force NRMSE {v['force_nrmse']:.2%}; COR {v['cor_simulated']:.4f} vs "
                  f"{v['cor_measured']:.4f}; contact time "
                  f"{v['contact_time_simulated_s'] * 1e3:.4g} vs "
                  f"{v['contact_time_measured_s'] * 1e3:.4g} ms; peak "
                  f"{v['peak_force_simulated_n']:.5g} vs {v['peak_force_measured_n']:.5g} N"]
    if v and "compression" in v:
        c = v["compression"]
        lines.append(f"  compression NRMSE {c['compression_nrmse']:.2%}; force at "
                     f"{c['deflection_m'] * 1e3:.4g} mm {c['force_simulated_n']:.5g} vs "
                     f"{c['force_measured_n']:.5g} N ({c['test']})")
    return lines


def identified_tests_lines(found: IdentifiedTests, out: dict[str, Any]) -> list[str]:
    """What `by_speed.identify_files` adds to the identifications of its tests
    (`identification_lines`, shown as each is made): the repeats at one speed, each parameter's
    mean +- SD with the mean pulse's estimate, and with several speeds the speed table (CSV)."""
    lines = []
    for group in found.repeats:
        lines.append(f"repeats at {group['speed_m_s']:.4g} m/s ({group['count']} tests): mean "
                     "+/- SD of their identifications; the mean pulse's estimate [90% interval]")
        pulse = group["mean_pulse"]
        for name, mean in group["params_mean"].items():
            low, high = pulse["params_interval_90"][name]
            lines.append(f"  {name:<8} {mean:11.5g} +/- {group['params_sd'][name]:.3g} "
                         f"{_unit(name):<3} mean pulse {pulse['params'][name]:.5g} [{low:.4g} .. "
                         f"{high:.4g}]")
    if "table" in out:
        lines += table_text(list(out["table"][0]), out["table"], ".6g").removesuffix(
            "\n").split("\n")
    return lines


def design_lines(summary: dict[str, Any]) -> list[str]:
    """A design of experiments run (`steps.run_design`): runs finished and failed, the failures
    listed."""
    return [f"{summary['folder']}: {summary['finished_runs']}/{summary['runs']} runs finished "
            f"({summary['new_runs']} now, {summary['wall_time_s']:.1f} s), "
            f"{summary['failed_runs']} failed",
            *(f"  run {failure['run_id']}: {failure['reason']}"
              for failure in summary["failures"])]


def trained_lines(out: dict[str, Any]) -> list[str]:
    """A model trained (`steps.train_model`): its files, then its held-out figures."""
    return [f"model written to {out['model_json']} and {out['model_npz']} "
            f"({out['wall_time_s']:.1f} s)", *held_out_lines(out)]


def held_out_lines(metadata: dict[str, Any]) -> list[str]:
    """The held-out figures of a model (its metadata, or `steps.held_out`'s dict): per parameter
    the errors, R^2 and interval coverage, the held-out check, the identifiability and the
    forward surrogate's errors."""
    report = metadata["held_out"]
    w = max(10, *(len(name) + 1 for name in report["inverse"]))  # groups' names are long
    lines = [f"held-out runs: {report['runs']} (never used in training or early stopping)",
             f"{'parameter':<{w}}{'median err':>12}{'p90 err':>10}{'R^2':>8}{'90% cover':>11}"
             f"{'width/range':>13}"]
    for name, entry in report["inverse"].items():
        err = entry["relative_error"] or entry["range_relative_error"]
        kind = "" if entry["relative_error"] else " (of range)"
        lines.append(f"{name:<{w}}{err['median']:>12.2%}{err['p90']:>10.2%}"
                     f"{entry['range_relative_error']['r2']:>8.3f}"
                     f"{entry['interval_90_coverage']:>11.1%}"
                     f"{entry['interval_90_mean_width_of_range']:>13.2f}{kind}")
    check = metadata.get("held_out_check")
    if check is not None:
        lines.append(f"held-out check (R^2 >= {check.get('min_r2', 0.5):g} for "
                     f"{', '.join(check.get('r2', {}))}): "
                     + ("passed" if check["passed"] else "FAILED, written with --force"))
    change = report["identifiability"]["median_rms_change_standardised"]
    fwd = report["forward"]
    return lines + [
        "impact change for a 10% step of the range (standardised RMS): "
        + ", ".join(f"{k} {v:.3f}" for k, v in change.items()),
        f"forward surrogate: force shape RMS {fwd['force_shape_rms_of_peak']['median']:.2%} of "
        f"peak (median), COR error {fwd['cor_absolute_error']['median']:.4f} (median); "
        f"peak force error {fwd['P6']['median']:.2%}, contact time error "
        f"{fwd['P1']['median']:.2%}"]


def closed_loop_lines(out: dict[str, Any]) -> list[str]:
    """The closed loop of `steps.report_model` (none without one): per figure the median, 90th
    percentile and largest error over the held-out runs, and the intervals' coverage (the
    held-out figures are `held_out_lines`', shown before the loop runs)."""
    if "closed_loop" not in out:
        return []
    s = out["closed_loop"]["summary"]
    lines = [f"closed loop on {s['runs']} held-out runs (noise {s['noise_of_peak']:.0%} of "
             f"peak, refine {s['refine']}), {s['failed']} failed:"]
    for key in ("force_nrmse", "cor_error", "contact_time_relative_error",
                "peak_force_relative_error"):
        lines.append(f"  |{key}|: median {s[key]['median']:.4g}, 90th percentile "
                     f"{s[key]['p90']:.4g}, max {s[key]['max']:.4g}")
    return lines + ["  90% interval coverage: " + ", ".join(
        f"{k} {v:.0%}" for k, v in s["interval_90_coverage"].items())]


def demo_lines(results: list, plot_path: Path) -> list[str]:
    """The demo's impacts (`demo.demo_impacts`), a row each, with their notes and the plot."""
    lines = ["ballimpact demo: explicit FE, normal impact on a rigid plane",
             f"{'ball':<28}{'speed m/s':>10}{'peak kN':>9}{'contact ms':>11}{'COR':>7}"
             f"{'energy err':>11}{'elements':>9}{'steps':>7}{'wall s':>8}"]
    for (name, _), r in zip(DEMO_IMPACTS, results):
        label = r.ball_name + (" *" if name in DEMO_NOTES else "")
        lines.append(f"{label:<28}{r.impact_speed_m_s:>10.4g}{r.peak_force_n / 1e3:>9.3f}"
                     f"{r.contact_time_s * 1e3:>11.4f}{r.cor:>7.3f}"
                     f"{r.energy_balance_error:>11.1e}{r.elements:>9d}{r.steps:>7d}"
                     f"{r.wall_time_s:>8.2f}")
    return lines + [f"* {name}: {note}" for name, note in DEMO_NOTES.items()] + [
        f"plot written to {plot_path}"]


def sample_lines(sample) -> list[str]:
    """The built-in sample identified (`demo.identify_sample`): its contact time and peak force
    against the exact ones, the identified parameters, the FE check and the notes."""
    found, contact, u = sample.found, sample.contact_time_s, sample.contact_time_uncertainty_s
    p, v = found.params, found.verification
    return [f"sample test: contact time {contact * 1e3:.3f} +/- {u * 1e3:.3f} ms with the "
            f"default processing (exact {SAMPLE_CONTACT_TIME_S * 1e3:.3f} ms: "
            f"{contact / SAMPLE_CONTACT_TIME_S - 1:+.1%}), peak force "
            f"{sample.peak_force_n:.0f} N (exact {SAMPLE_PEAK_FORCE_N:.0f} N)",
            f"identify (built-in sample test at {found.impact_speed_m_s:g} m/s, built-in "
            f"model): C10 {p['c10_pa'] / 1e6:.3f} MPa, C01 {p['c01_pa'] / 1e6:.3f} MPa, "
            f"g1 {p['g1']:.3f}, tau1 {p['tau1_s'] * 1e6:.1f} us",
            f"  FE check {verdict_line(v)}",
            f"  force NRMSE {v['force_nrmse']:.1%}, COR {v['cor_simulated']:.3f} "
            f"(test {v['cor_measured']:.3f}), contact time "
            f"{v['contact_time_simulated_s'] * 1e3:.3f} ms (test "
            f"{v['contact_time_measured_s'] * 1e3:.3f} ms), {found.wall_time_s:.1f} s",
            *(f"  note: {note}" for note in sample.notes)]


__all__ = ["closed_loop_lines", "demo_lines", "design_lines", "held_out_lines",
           "identification_lines", "identified_tests_lines", "sample_lines", "trained_lines"]
