"""`ballimpact universal run|train|report`: the design of experiments, the training of the
universal model and its held-out figures."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from ..progress import progress_bar
from .common import add_json, add_allow, assignments, print_lines, use_compilation_cache


def add_parser(verbs) -> None:
    universal = verbs.add_parser(
        "universal", help="universal FE ball: design of experiments, training, report",
        description="The universal (homogeneous Mooney-Rivlin + one Prony term) FE ball of "
                    "thesis chapter 6: run a design of experiments through the FE engine, train "
                    "the inverse and forward surrogates on it, and report their held-out figures.")
    steps = universal.add_subparsers(dest="step", required=True, metavar="STEP")

    run = steps.add_parser("run", help="run (or resume) a design of experiments into DIR",
                           description="Sample the parameter space (seeded Sobol or LHS), run "
                                       "each point through the batched FE engine, and append "
                                       "each batch atomically to DIR (Parquet + NPZ).")
    run.add_argument("dir", type=Path, help="study folder")
    run.add_argument("--runs", type=int, help="number of runs (default 600)")
    run.add_argument("--seed", type=int, help="random seed of the design (default 0)")
    run.add_argument("--method", choices=("sobol", "lhs"), help="design (default sobol)")
    run.add_argument("--design", choices=("material", "groups"),
                     help="design space: material (default; C10, C01, g1, tau1 and the speed "
                          "on the template) or groups (rho v^2/mu0, C01/C10, g1, tau1 v/R: any "
                          "homogeneous ball at any speed)")
    run.add_argument("--range", action="append", default=[], metavar="NAME=LOW:HIGH",
                     help="range of c10_pa, c01_pa, g1, tau1_s or impact_speed_m_s in SI "
                          "(repeatable; defaults: table 6-2, g1 0-0.9, 5-45 m/s); with --design "
                          "groups of rho_v2_over_mu0, c01_over_c10, g1 or tau1_v_over_r")
    run.add_argument("--template", help="ball preset or file giving radius, mass and moduli "
                                        "convention (default cricket-universal)")
    run.add_argument("--batch-size", type=int, help="runs per batch: the unit of checkpointing "
                                                    "and of Dask tasks (default 32)")
    run.add_argument("--group-size", type=int,
                     help="balls per vmapped FE group (default 4, best on a CPU; on a GPU give "
                          "--batch-size and --group-size 1024: 204 runs/s on an H100, float32)")
    run.add_argument("--element-size-m", type=float, help="FE element size (m; default 1.5e-3)")
    run.add_argument("--precision", choices=("float64", "float32"),
                     help="default float32: 1.33x faster than float64, features within 0.12%%")
    run.add_argument("--resume", action="store_true", help="continue the study stored in DIR")
    run.add_argument("--extend", type=int, metavar="N",
                     help="add N runs to the study stored in DIR (its Sobol sequence continued: "
                          "the study then equals one run with the total)")
    run.add_argument("--workers", type=int, help="run on a local Dask cluster of N processes")
    run.add_argument("--scheduler", help="run on the Dask scheduler at ADDRESS")
    add_allow(run)  # ball-units: a template or ranges outside sports balls (a foam ball)
    add_json(run)

    train = steps.add_parser("train", help="train the universal model on the study in DIR",
                             description="Train the inverse (features -> parameters with 90%% "
                                         "intervals) and forward (parameters -> features and "
                                         "pulse shape) deep ensembles; hold out 20%% of the runs "
                                         "for the report.")
    train.add_argument("dir", type=Path, help="study folder")
    train.add_argument("--out", type=Path, required=True,
                       help="model path: writes OUT.json and OUT.npz")
    train.add_argument("--seed", type=int, default=0, help="split and initialisation seed")
    train.add_argument("--steps", type=int, default=1500, help="optimiser steps (default 1500)")
    train.add_argument("--width", type=int, default=128, help="hidden width (default 128)")
    train.add_argument("--members", type=int, default=5, help="ensemble members (default 5)")
    train.add_argument("--noise-augment", type=float, default=0.02,
                       help="the inverse also learns from a noisy copy of each run, noise up to "
                            "this fraction of the peak force (default 0.02; 0: off)")
    train.add_argument("--force", action="store_true",
                       help="write the model even if it fails its held-out check (R^2 of mu0, "
                            "g1, contact time, peak force and COR >= 0.5 on the held-out runs); "
                            "it is then marked failed in its JSON")
    add_json(train)

    report = steps.add_parser("report", help="held-out figures of a model, with plots",
                              description="Per parameter median and 90th-percentile errors, "
                                          "R^2 and 90%% interval coverage on the held-out runs; "
                                          "with --closed-loop, re-simulate held-out runs from "
                                          "their identified parameters.")
    report.add_argument("model", nargs="?", help="model path (default: the built-in model)")
    report.add_argument("--plot", type=Path, help="PNG: predicted vs true per parameter")
    report.add_argument("--closed-loop", type=Path, metavar="DIR",
                        help="the model's study folder: identify held-out runs and re-simulate")
    report.add_argument("--runs", type=int, help="closed-loop runs (default 60)")
    report.add_argument("--noise", type=float,
                        help="closed loop: white noise as a fraction of the peak force, on the "
                             "pulses sampled at 100 kHz (e.g. 0.01; default 0)")
    report.add_argument("--filter",
                        help="closed loop with --noise: filter of the noisy records (default none)")
    report.add_argument("--refine", choices=("none", "surrogate"),
                        help="closed loop: refine on the forward surrogate, or not (default)")
    add_json(report)


def run(args: argparse.Namespace) -> dict[str, Any]:
    return {"run": _run, "train": _train, "report": _report}[args.step](args)


def _run(args: argparse.Namespace) -> dict[str, Any]:
    from ..universal.steps import run_design
    from ..universal.text import design_lines

    use_compilation_cache()
    # Ctrl-C from here on: the command line ends with exit 130 and this line (finished batches
    # are on disk, each written atomically)
    args.resume_hint = f"resume with: ballimpact universal run {args.dir} --resume"
    summary = run_design(args.dir, template=args.template,
                         ranges=assignments(args.range, "--range", bounds=True),
                         allow=args.allow, design=args.design, runs=args.runs, seed=args.seed,
                         method=args.method,
                         batch_size=args.batch_size, group_size=args.group_size,
                         element_size_m=args.element_size_m, precision=args.precision,
                         resume=args.resume, extend=args.extend, workers=args.workers,
                         scheduler=args.scheduler, progress=progress_bar)
    if not args.json:
        print_lines(design_lines(summary))
    return summary


def _train(args: argparse.Namespace) -> dict[str, Any]:
    from ..universal.steps import train_model
    from ..universal.text import trained_lines

    use_compilation_cache()
    out = train_model(args.dir, args.out, seed=args.seed, steps=args.steps, width=args.width,
                      members=args.members, noise_augment=args.noise_augment, force=args.force)
    if not args.json:
        print_lines(trained_lines(out))
    return out


def _report(args: argparse.Namespace) -> dict[str, Any]:
    from ..universal.steps import report_model
    from ..universal.text import closed_loop_lines, held_out_lines

    if args.closed_loop is not None:
        use_compilation_cache()
    out = report_model(args.model, study=args.closed_loop, runs=args.runs, noise=args.noise,
                       filter_name=args.filter, refine=args.refine, plot_path=args.plot,
                       shown=None if args.json else lambda held: print_lines(
                           held_out_lines(held)))
    if not args.json:
        print_lines(closed_loop_lines(out))
    return out
