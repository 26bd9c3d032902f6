"""`ballimpact calibrate`: material constants of a layered FE ball from impact and compression
tests."""

from __future__ import annotations

import argparse
import math
import shlex
from pathlib import Path
from typing import Any

from ..errors import InputError
from .common import (add_processing, assignments, print_lines, record_options,
                     use_compilation_cache)
from .simulate import add_solver_options, solver_options


def add_parser(verbs) -> argparse.ArgumentParser:
    from ..calibrate.calibration import METHODS
    from ..calibrate.decision import METHODS as DECISIONS
    from ..calibrate.problem import OBJECTIVES

    p = verbs.add_parser(
        "calibrate", help="calibrate a layered FE ball's material constants against tests",
        description="Multi-objective search (pymoo NSGA-II; NSGA-III for four objectives) of "
                    "free parameters of a ball specification against impact tests and/or "
                    "compression tests (force-deflection curves), a decision "
                    "on the Pareto front, and/or a Levenberg-Marquardt refinement with gradients "
                    "through the explicit FE runs (JAX). Stages calibrate component by "
                    "component, earlier results frozen (thesis 5.2-5.3).")
    p.add_argument("--ball", required=True, help="template: preset or ball specification file")
    p.add_argument("--test", action="append", default=[], metavar="FILE[:SPEED[:LAYER]]",
                   help="test record (CSV/WAV), named by its file stem (a repeated stem gets "
                        "-N); SPEED (m/s) overrides the side file's and --impact-speed-m-s; "
                        "LAYER: the outermost layer of the ball tested (e.g. core) if not the "
                        "whole ball. Repeat for several tests")
    p.add_argument("--compression", action="append", default=[], metavar="FILE.csv[:LAYER]",
                   help="compression test: a force-deflection CSV (header deflection_m or "
                        "deflection_mm, force_n or force_kn; '#' comments), named by its file "
                        "stem; LAYER: the outermost layer of the part tested (e.g. core). "
                        "Objective: compression. Repeat for several")
    p.add_argument("--compression-rate-m-s", type=float, metavar="R",
                   help="platen speed of the compression tests (m/s); default: the long-term, "
                        "fully relaxed curve")
    p.add_argument("--compression-steps", type=int, default=20,
                   help="increments of the FE compression curve up to the largest measured "
                        "deflection (default 20)")
    p.add_argument("--free", action="append", required=True, metavar="PATH=LOW:HIGH",
                   help="free parameter by its path in the ball specification, with bounds "
                        "(SI), e.g. layers.core.material.c10_pa=3e6:7e6. Repeat")
    p.add_argument("--objectives",
                   help=f"comma-separated, any of {', '.join(OBJECTIVES)} (default "
                        "nrmse,cor,contact_time for impact tests, compression for compression "
                        "tests)")
    p.add_argument("--method", choices=METHODS, default="nsga2",
                   help="nsga2 (default), gradient (Levenberg-Marquardt from the template's "
                        "values), "
                        "or nsga2+gradient (refine the chosen design)")
    p.add_argument("--stage", action="append", metavar="SPEC",
                   help="a stage: 'free=PATTERN,...;tests=NAME,...;objectives=...;name=...' "
                        "(tests by file stem); stages run in order, earlier results frozen")
    p.add_argument("--population", type=int, default=24, help="NSGA population (default 24)")
    p.add_argument("--generations", type=int, default=8, help="generations (default 8)")
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument("--decision", choices=DECISIONS, default="knee",
                   help="how to choose from the Pareto front (default knee)")
    p.add_argument("--weights", help="comma-separated objective weights for pseudo-weights/asf")
    p.add_argument("--max-evaluations", type=int, default=30,
                   help="gradient refinement: misfit evaluations at most (default 30)")
    p.add_argument("--out", type=Path, help="folder for evaluations, plots and the ball file")
    p.add_argument("--resume", action="store_true",
                   help="continue a stopped search in --out with the same options (designs "
                        "already run are reused; --generations may grow)")
    add_solver_options(p)
    add_processing(p)
    return p


def command_line(args: argparse.Namespace) -> str:
    """The command as given, for the resume hint: the options that differ from their defaults,
    read from `args` by this verb's flags (`sys.argv` is not the command when the verb runs
    inside another program or a test), plus --resume."""
    verbs = argparse.ArgumentParser().add_subparsers()
    words = ["ballimpact", "calibrate"]
    for action in add_parser(verbs)._actions:
        if not action.option_strings or action.dest in ("help", "resume"):
            continue
        value = getattr(args, action.dest, action.default)
        if value is None or value == action.default or value == []:
            continue
        flag = action.option_strings[0]
        if action.nargs == 0:  # store_true
            words.append(flag)
        else:
            words += [part for item in (value if isinstance(value, list) else [value])
                      for part in (flag, str(item))]
    return shlex.join(words + ["--resume"])


def _weights(text: str | None) -> list[float] | None:
    """--weights 'a,b,...' -> finite numbers >= 0."""
    if not text:
        return None
    try:
        weights = [float(w) for w in text.split(",")]
    except ValueError:
        raise InputError(f"--weights {text!r}: expected comma-separated numbers") from None
    if not all(math.isfinite(w) and w >= 0 for w in weights):
        raise InputError(f"--weights {text}: expected finite numbers >= 0")
    return weights


def run(args: argparse.Namespace) -> dict[str, Any]:
    from ..calibrate.calibration import parse_stage
    from ..calibrate.files import calibrate_from_files
    from ..calibrate.text import calibration_lines

    bounds = assignments(args.free, "--free", bounds=True)
    stages = [parse_stage(s, i) for i, s in enumerate(args.stage or [])] or None
    objectives = None if args.objectives is None else \
        tuple(o.strip() for o in args.objectives.split(",") if o.strip())
    weights = _weights(args.weights)
    options = solver_options(args)
    use_compilation_cache()
    if "nsga2" in args.method:  # what Ctrl-C (cli.main) adds to its line
        args.resume_hint = (f"resume with: {command_line(args)}" if args.out is not None else
                            "no checkpoint was kept: give --out DIR to be able to --resume")
    result, stage_results = calibrate_from_files(
        args.ball, bounds, options, tests=args.test, compressions=args.compression,
        record_options=record_options(args),
        impact_speed_m_s=args.impact_speed_m_s, compression_rate_m_s=args.compression_rate_m_s,
        compression_steps=args.compression_steps, objectives=objectives, method=args.method,
        stages=stages, population=args.population, generations=args.generations,
        seed=args.seed, decision=args.decision, weights=weights, out=args.out,
        resume=args.resume, max_evaluations=args.max_evaluations, allow=args.allow,
        plot_path=args.plot)
    if not args.json:
        print_lines(calibration_lines(result, stage_results))
    return result
