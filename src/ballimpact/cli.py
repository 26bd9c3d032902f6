"""The `ballimpact` command (DESIGN.md "Command line contract").

Exit codes: 0 success, 2 bad input (one line on stderr naming the problem), 1 failed run.
With `--json` one JSON object goes to stdout; warnings and progress go to stderr.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
import warnings
from pathlib import Path
from typing import Any

from . import __version__
from .errors import InputError, SimulationError
from .features import DEFAULT_IMPULSE_TOLERANCE, FEATURE_NAMES
from .filters import FILTER_NAMES
from .loaders import load_record
from .pipeline import ProcessedImpact, process

DEMO_PLOT = "ballimpact-demo.png"
DEMO_IMPACTS = (("cricket-universal", 25.0), ("cricket-3layer", 20.8))


class SolverDefaults:
    """FE defaults shown in --help (kept equal to `fe.SolverOptions` by a test)."""

    element_size_m = 1.5e-3
    penalty_scale = 1.0
    integration = "reduced"
    precision = "float64"


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # one line, exit 2, no usage dump
        raise InputError(f"{self.prog}: {message}")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="ballimpact", description="Sports-ball impact modelling (SI units).")
    parser.add_argument("--version", action="version", version=f"ballimpact {__version__}")
    verbs = parser.add_subparsers(dest="verb", required=True, metavar="VERB")

    features = verbs.add_parser(
        "features", help="characteristic values of a measured impact (CSV or WAV)",
        description="Load an impact test, remove the load-cell offset, filter, and print the 19 "
                    "characteristic values (thesis table 6-1) with COR, impulse check, "
                    "compression, energy lost and dynamic stiffness.")
    features.add_argument("file", type=Path, help="test record: CSV with unit headers or WAV")
    _add_record_options(features)
    _add_processing(features)

    fit = verbs.add_parser(
        "fit", help="identify a lumped model from a test, or from tests at several speeds",
        description="Fit a lumped model (see `ballimpact models`) to the force pulse of a test by "
                    "a genetic algorithm or differential evolution and a least-squares polish. "
                    "With several files (one per impact speed) the parameters form a table "
                    "against speed, as thesis tables 7-1 and 7-2.")
    fit.add_argument("files", type=Path, nargs="+", metavar="FILE",
                     help="test record(s): CSV with unit headers or WAV")
    fit.add_argument("--model", required=True, help="lumped model name (see `ballimpact models`)")
    fit.add_argument("--method", default="ga",
                     help="ga (genetic algorithm) or de (differential evolution); default ga")
    fit.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    fit.add_argument("--population", type=int,
                     help="population size (default 4 per searched quantity, at least 32)")
    fit.add_argument("--generations", type=int,
                     help="generations (default 8 per searched quantity, at least 40)")
    fit.add_argument("--no-polish", action="store_true", help="skip the least-squares polish")
    fit.add_argument("--bound", action="append", default=[], metavar="NAME=LOW:HIGH",
                     help="search bounds of a parameter in SI (repeatable)")
    fit.add_argument("--fix", action="append", default=[], metavar="NAME=VALUE",
                     help="hold a parameter at a value in SI (repeatable)")
    fit.add_argument("--cor-weight", type=float, default=0.0,
                     help="weight of the COR error in the fitness (default 0)")
    fit.add_argument("--contact-time-weight", type=float, default=0.0,
                     help="weight of the relative contact-time error in the fitness (default 0)")
    fit.add_argument("--table", type=Path, help="with several files: write the speed table CSV")
    _add_record_options(fit)
    _add_processing(fit)

    models = verbs.add_parser("models", help="list the lumped models and their parameters",
                              description="The lumped models, their parameters and SI units.")
    models.add_argument("--json", action="store_true", help="print one JSON object")

    simulate = verbs.add_parser(
        "simulate", help="FE normal impact of a ball on a rigid plane",
        description="Explicit FE (axisymmetric, F-bar quads, hyper-viscoelastic layers, penalty "
                    "contact) of a ball hitting a rigid flat surface at normal incidence: "
                    "contact force history, COR, contact time, energies and the 19 features.")
    simulate.add_argument("--ball", required=True,
                          help="preset (see `ballimpact balls`) or ball specification JSON/TOML")
    simulate.add_argument("--speed-m-s", type=float, required=True, help="impact speed (m/s)")
    simulate.add_argument("--angle-deg", type=float, default=0.0,
                          help="angle from the surface normal (deg); only 0 so far")
    simulate.add_argument("--spin-rad-s", type=float, default=0.0, help="spin (rad/s); only 0 so far")
    simulate.add_argument("--friction", type=float, default=0.0,
                          help="Coulomb coefficient (irrelevant at normal incidence)")
    simulate.add_argument("--solver", default="axisymmetric", help="axisymmetric (3d: not yet)")
    simulate.add_argument("--element-size-m", type=float, default=SolverDefaults.element_size_m,
                          help=f"element length on the outer surface (m; default "
                               f"{SolverDefaults.element_size_m:g})")
    simulate.add_argument("--pole-element-size-m", type=float,
                          help="refine toward the contact pole to this element length (m)")
    simulate.add_argument("--integration", choices=("reduced", "full"),
                          default=SolverDefaults.integration,
                          help="reduced: one point with hourglass control (default); full: 2x2 "
                               "points with F-bar")
    simulate.add_argument("--precision", choices=("float64", "float32"),
                          default=SolverDefaults.precision,
                          help="arithmetic of the explicit steps (default float64)")
    simulate.add_argument("--penalty-scale", type=float, default=SolverDefaults.penalty_scale,
                          help="contact penalty scale (default 1)")
    simulate.add_argument("--moduli", help="override the balls' moduli convention: long_term or "
                                           "instantaneous")
    simulate.add_argument("--json", action="store_true", help="print one JSON object")
    simulate.add_argument("--csv", type=Path, help="write the histories (one row per step)")
    simulate.add_argument("--plot", type=Path,
                          help="PNG: force-time curve and deformed shape at peak force")

    balls = verbs.add_parser("balls", help="list the built-in ball presets",
                             description="The built-in ball presets usable with --ball.")
    balls.add_argument("--json", action="store_true", help="print one JSON object")

    demo = verbs.add_parser(
        "demo", help="the main job: FE impacts of the two cricket-ball presets",
        description="Simulate the cricket-universal ball at 25 m/s and the cricket-3layer ball "
                    "at 20.8 m/s on a rigid plane; print peak force, contact time, COR and the "
                    "energy balance error, and write one PNG.")
    demo.add_argument("--json", action="store_true", help="print one JSON object")
    demo.add_argument("--plot", type=Path, default=Path(DEMO_PLOT),
                      help=f"PNG to write (default {DEMO_PLOT})")
    return parser


def _add_record_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--mass-kg", type=float, help="ball mass (kg)")
    parser.add_argument("--impact-speed-m-s", type=float, help="impact speed (m/s)")
    parser.add_argument("--rebound-speed-m-s", type=float,
                        help="measured rebound speed (m/s); from the impulse if not given")
    parser.add_argument("--sensitivity-v-per-n", type=float, help="WAV: load-cell sensitivity (V/N)")
    parser.add_argument("--amplifier-gain", type=float, help="WAV: amplifier gain (default 1)")
    parser.add_argument("--full-scale-v", type=float, help="WAV: volts at digital full scale (default 1)")
    parser.add_argument("--channel", type=int, help="WAV: channel index (default 0)")


def _add_processing(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--filter", default="none",
                        help=f"one of {', '.join(FILTER_NAMES)}, or cfc<N> (default none)")
    parser.add_argument("--filter-window-s", type=float,
                        help="window of savgol/lowess/loess (s); default 10%% of contact time")
    parser.add_argument("--resample-hz", type=float, help="resample to this uniform rate first")
    parser.add_argument("--impulse-tolerance", type=float, default=DEFAULT_IMPULSE_TOLERANCE,
                        help="relative misfit allowed between impulse and m(v_in + v_out) "
                             f"(default {DEFAULT_IMPULSE_TOLERANCE})")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument("--plot", type=Path, help="write force-time and force-displacement PNG")


def main(argv: list[str] | None = None) -> int:
    try:
        args = build_parser().parse_args(argv)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            run = {"features": _run_features, "fit": _run_fit, "models": _run_models,
                   "simulate": _run_simulate, "balls": _run_balls, "demo": _run_demo}[args.verb]
            result = run(args)
        notes = list(dict.fromkeys(str(w.message) for w in caught))
    except InputError as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    except SimulationError as error:
        print(f"error: failed run: {error}", file=sys.stderr)
        return 1
    except Exception as error:  # noqa: BLE001 - a failed run, reported in one line
        print(f"error: failed run: {type(error).__name__}: {error}", file=sys.stderr)
        return 1
    for note in notes:
        print(f"warning: {note}", file=sys.stderr)
    result["warnings"] = notes
    if args.json:
        print(json.dumps(_json_safe(result), indent=2))
    return 0


def _load(path: Path, args: argparse.Namespace):
    return load_record(
        path, mass_kg=args.mass_kg, impact_speed_m_s=args.impact_speed_m_s,
        rebound_speed_m_s=args.rebound_speed_m_s, sensitivity_v_per_n=args.sensitivity_v_per_n,
        amplifier_gain=args.amplifier_gain, full_scale_v=args.full_scale_v, channel=args.channel)


def _run_features(args: argparse.Namespace) -> dict[str, Any]:
    _check_plot_path(args.plot)
    started = time.perf_counter()
    processed = _process(_load(args.file, args), args)
    result = _summary(processed, time.perf_counter() - started)
    if not args.json:
        _print_table(processed)
    if args.plot:
        _plot(processed, args.plot, title=str(args.file.name))
        result["plot"] = str(args.plot)
    return result


def _run_demo(args: argparse.Namespace) -> dict[str, Any]:
    from .fe import load_ball, simulate
    from .plotting import plot_fe

    _check_plot_path(args.plot)
    _use_compilation_cache()
    started = time.perf_counter()
    results = []
    for name, speed in DEMO_IMPACTS:
        print(f"simulating {name} at {speed:g} m/s ...", file=sys.stderr, flush=True)
        results.append(simulate(load_ball(name, impact_speed_m_s=speed), speed))
    plot_fe(results, args.plot, title="ballimpact demo: cricket balls on a rigid plane (FE)")
    if not args.json:
        print("ballimpact demo: explicit FE, normal impact on a rigid plane")
        print(f"{'ball':<28}{'speed m/s':>10}{'peak kN':>9}{'contact ms':>11}{'COR':>7}"
              f"{'energy err':>11}{'elements':>9}{'steps':>7}{'wall s':>8}")
        for r in results:
            print(f"{r.ball_name:<28}{r.impact_speed_m_s:>10.4g}{r.peak_force_n / 1e3:>9.3f}"
                  f"{r.contact_time_s * 1e3:>11.4f}{r.cor:>7.3f}{r.energy_balance_error:>11.1e}"
                  f"{r.elements:>9d}{r.steps:>7d}{r.wall_time_s:>8.2f}")
        print(f"plot written to {args.plot}")
    return {"impacts": [r.summary() for r in results], "plot": str(args.plot),
            "wall_time_s": time.perf_counter() - started}


def _run_simulate(args: argparse.Namespace) -> dict[str, Any]:
    from .fe import SolverOptions, load_ball, simulate

    _check_plot_path(args.plot)
    if args.csv is not None and not args.csv.parent.is_dir():
        raise InputError(f"--csv: folder {args.csv.parent} does not exist")
    if args.solver != "axisymmetric":
        raise InputError(f"--solver {args.solver}: only 'axisymmetric' is available so far")
    for flag, value in (("--angle-deg", args.angle_deg), ("--spin-rad-s", args.spin_rad_s)):
        if value != 0.0:
            raise InputError(f"{flag} = {value:g}: oblique and spinning impacts need the 3D "
                             "solver, not available yet; only 0 is allowed")
    if not (math.isfinite(args.friction) and args.friction >= 0):
        raise InputError(f"--friction = {args.friction:g}: allowed range [0, inf)")
    _use_compilation_cache()
    ball = load_ball(args.ball, impact_speed_m_s=args.speed_m_s)
    if args.moduli is not None:
        ball = ball.with_moduli(args.moduli)
    options = SolverOptions(element_size_m=args.element_size_m,
                            pole_element_size_m=args.pole_element_size_m,
                            penalty_scale=args.penalty_scale, integration=args.integration,
                            precision=args.precision)
    result = simulate(ball, args.speed_m_s, options)
    from .features import extract_features

    out = result.summary()
    out["features"] = extract_features(result.record()).to_dict()["features"]
    out["materials"] = ball.to_dict()
    out["material_constants_used"] = [  # instantaneous, as the solver uses them (SI)
        {"layer": layer.name, "model": layer.material.model,
         **{k: (v.tolist() if hasattr(v, "tolist") else v)
            for k, v in layer.material.constants().items()}} for layer in ball.layers]
    if args.csv is not None:
        import numpy as np

        names = list(result.history)
        np.savetxt(args.csv, np.column_stack([result.history[n] for n in names]),
                   delimiter=",", header=",".join(names), comments="", fmt="%.10g")
        out["csv"] = str(args.csv)
    if args.plot is not None:
        from .plotting import plot_fe

        plot_fe([result], args.plot)
        out["plot"] = str(args.plot)
    if not args.json:
        print(f"{result.ball_name} at {args.speed_m_s:g} m/s ({out['moduli']} moduli): "
              f"peak force {result.peak_force_n:.5g} N at {result.time_of_peak_s * 1e3:.4g} ms, "
              f"contact time {result.contact_time_s * 1e3:.4g} ms, COR {result.cor:.4f}")
        e = result.energies_j
        print(f"  energy balance error {result.energy_balance_error:.2e}; viscous "
              f"{e['viscous_dissipation_j']:.4g} J, bulk viscous "
              f"{e['bulk_viscous_dissipation_j']:.4g} J of {e['initial_kinetic_energy_j']:.4g} J")
        print(f"  {result.elements} elements, {result.steps} steps of "
              f"{result.stable_time_increment_s:.3g} s, {result.wall_time_s:.2f} s wall")
    return out


def _run_balls(args: argparse.Namespace) -> dict[str, Any]:
    from .fe import describe_presets

    presets = describe_presets()
    if not args.json:
        for preset in presets:
            print(f"{preset['name']}: {preset['description']}")
    return {"balls": presets}


def _use_compilation_cache() -> None:
    """Keep JAX's compiled programs between runs of the command (about 2 s saved per run after
    the first): in $BALLIMPACT_CACHE_DIR, else ~/.cache/ballimpact/jax. Set for this process by
    the command only; the library leaves JAX's configuration alone."""
    import jax

    folder = os.environ.get("BALLIMPACT_CACHE_DIR") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.expanduser("~/.cache"), "ballimpact", "jax")
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError:
        return  # no writable cache: compile every time
    jax.config.update("jax_compilation_cache_dir", folder)
    jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.0)


def _run_fit(args: argparse.Namespace) -> dict[str, Any]:
    from . import lumped  # JAX and pymoo load only for the verbs that need them

    _use_compilation_cache()
    _check_plot_path(args.plot)
    if args.table is not None and not args.table.parent.is_dir():
        raise InputError(f"--table: folder {args.table.parent} does not exist")
    if args.table is not None and len(args.files) < 2:
        raise InputError("--table: needs several files (one per impact speed)")
    model = lumped.get_model(args.model)
    options = dict(method=args.method, seed=args.seed, population=args.population,
                   generations=args.generations, polish=not args.no_polish,
                   bounds=_assignments(args.bound, "--bound", bounds=True),
                   fixed=_assignments(args.fix, "--fix", bounds=False),
                   cor_weight=args.cor_weight, contact_time_weight=args.contact_time_weight)
    started = time.perf_counter()
    processed = [_process(_load(path, args), args) for path in args.files]
    if len(processed) == 1:
        fitted = lumped.fit(processed[0], model, **options)
        result = {**fitted.to_dict(), "file": str(args.files[0])}
        if not args.json:
            _print_fit(fitted, args.files[0])
        if args.plot:
            from .plotting import plot_fit

            plot_fit(fitted, args.plot, title=str(args.files[0].name))
            result["plot"] = str(args.plot)
        result["wall_time_s"] = time.perf_counter() - started
        return result
    table, fits = lumped.fit_speed_table(processed, model, **options)
    files = [str(path) for path in args.files]
    order = sorted(range(len(files)), key=lambda i: processed[i].features.values["P15"])
    result = {"model": model.name, "units": model.units, "table": table.to_dict(),
              "fits": [{**f.to_dict(), "file": files[i]} for f, i in zip(fits, order)]}
    if args.table is not None:
        args.table.write_text(table.to_csv())
        result["table_csv"] = str(args.table)
    if not args.json:
        for f, i in zip(fits, order):
            _print_fit(f, Path(files[i]))
        print(table.to_csv(), end="")
    if args.plot:
        from .plotting import plot_speed_fits

        plot_speed_fits(fits, args.plot)
        result["plot"] = str(args.plot)
    result["wall_time_s"] = time.perf_counter() - started
    return result


def _assignments(items: list[str], flag: str, *, bounds: bool) -> dict[str, Any]:
    """Parse NAME=VALUE (or NAME=LOW:HIGH) flags into a dict of floats (or float pairs)."""
    parsed: dict[str, Any] = {}
    for item in items:
        name, sep, value = item.partition("=")
        try:
            if not sep or not name:
                raise ValueError
            parsed[name] = (tuple(float(x) for x in value.split(":", 1)) if bounds
                            else float(value))
            if bounds and len(parsed[name]) != 2:
                raise ValueError
        except ValueError:
            form = "NAME=LOW:HIGH" if bounds else "NAME=VALUE"
            raise InputError(f"{flag}: expected {form} with numbers in SI, got {item!r}") from None
    return parsed


def _print_fit(fitted, path: Path) -> None:
    m = fitted.measured
    print(f"{path.name}: {fitted.model} by {fitted.method.upper()} (seed {fitted.seed}), "
          f"{fitted.evaluations} model runs, {fitted.wall_time_s:.2f} s")
    for name, value in fitted.params.items():
        error = fitted.standard_errors.get(name, 0.0)
        spread = f" +/- {error:.3g}" if error > 0 else " (fixed)" if name not in fitted.bounds \
            else ""
        print(f"  {name:<10} {value:.6g}{spread} {fitted.units[name]}")
    print(f"  RMSE {fitted.rmse_n:.4g} N, NRMSE {fitted.nrmse:.2%} of the measured peak")
    print(f"  model:    peak {fitted.peak_force_n:.5g} N, contact {fitted.contact_time_s * 1e3:.4g} "
          f"ms, COR {fitted.cor:.4f}")
    print(f"  measured: peak {m['peak_force_n']:.5g} N, contact {m['contact_time_s'] * 1e3:.4g} ms, "
          f"COR {m['cor']:.4f}")
    if fitted.reproduction:
        print("  note: a reproduction of the thesis' appendix code, not a recommended model")


def _run_models(args: argparse.Namespace) -> dict[str, Any]:
    from .lumped import describe_models

    models = describe_models()
    if not args.json:
        for model in models:
            print(f"{model['name']}: {model['summary']}")
            for name, spec in model["params"].items():
                fixed = f" (fixed, default {spec['default']:g})" if "default" in spec else ""
                print(f"    {name:<18} [{spec['unit']}] {spec['description']}{fixed}")
    return {"models": models}


def _check_plot_path(path: Path | None) -> None:
    if path is None:
        return
    if path.suffix.lower() != ".png":
        raise InputError(f"--plot: {path} must be a .png file")
    if not path.parent.is_dir():
        raise InputError(f"--plot: folder {path.parent} does not exist")


def _process(record, args: argparse.Namespace) -> ProcessedImpact:
    return process(record, filter=args.filter, window_s=args.filter_window_s,
                   resample_hz=args.resample_hz, impulse_tolerance=args.impulse_tolerance)


def _summary(processed: ProcessedImpact, wall_time_s: float) -> dict[str, Any]:
    summary = processed.features.to_dict()
    summary["filter"] = processed.filtered.metadata.get("filter", "none")
    summary["baseline_offset_n"] = processed.raw.metadata.get("baseline_offset_n", 0.0)
    summary["wall_time_s"] = wall_time_s
    return summary


def _plot(processed: ProcessedImpact, path: Path, title: str, fit=None) -> None:
    from .plotting import plot_impact  # matplotlib only when a plot is asked for

    plot_impact(processed.raw, processed.filtered, processed.features, path, title=title, fit=fit)


def _print_table(processed: ProcessedImpact) -> None:
    f = processed.features
    print(f"filter: {processed.filtered.metadata.get('filter', 'none')}   "
          f"baseline offset removed: {processed.raw.metadata.get('baseline_offset_n', 0.0):.4g} N")
    for key, name in FEATURE_NAMES.items():
        print(f"  {key:>4}  {name:<42} {f.values[key]:.6g}")
    check = f.impulse_check_passed
    status = "not checked (rebound speed from impulse)" if check is None else (
        f"{f.impulse_relative_error:+.2%} ({'ok' if check else 'FAILED'}, "
        f"tolerance {f.impulse_tolerance:.1%})")
    print(f"  rebound speed source: {f.rebound_speed_source}")
    print(f"  impulse {f.impulse_n_s:.5g} N s; impulse check: {status}")
    print(f"  impulse COR {f.impulse_cor:.4f}; max compression {f.max_compression_m * 1e3:.4g} mm; "
          f"energy lost {f.energy_lost_j:.4g} J; dynamic stiffness {f.dynamic_stiffness_n_m:.4g} N/m")


def _json_safe(value: Any) -> Any:
    """Replace non-finite floats (invalid in JSON) by None."""
    if isinstance(value, dict):
        return {key: _json_safe(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [_json_safe(item) for item in value]
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


if __name__ == "__main__":
    sys.exit(main())
