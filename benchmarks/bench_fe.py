"""Benchmark: the explicit FE engine (issue 9 targets, 2-core CPU: universal ball at 25 m/s
< 0.5 s a run, >= 3 runs/s in batches, whole `ballimpact simulate` <= 3 s warm;
issue 28: <= 1.5 s, at least 40 times CalculiX).

Prints one JSON object:
- `single`: per ball and setting (`cricket-universal` at 25 m/s, `cricket-3layer` at 20.8 m/s;
  reduced integration float64 (the default), float32, and full integration = the F-bar element of
  the previous engine, with the new increment), the first call (`first_call_s`, mostly
  compilation), the median of 3 later calls (`wall_time_per_simulation_s`), compile estimate,
  steps, elements, element updates per second, the figures of the run, the fingerprint of its
  histories (`history_digest`: equal digests, the same bits) and the ratio to the thesis' ABAQUS
  time;
- `previous_engine`: the engine before issue 9 (F-bar, element-by-element increment 0.9 L/c_d),
  emulated in the same run by `integration="full"` with the increment scaled to the old one
  (`time_step_scale` = old / new increment; the per-chunk re-estimate stays, a few % of a run),
  and `speedup_vs_previous_engine`;
- `batch`: universal-ball parameter sets over the table 6-2 ranges (C10 4-7 MPa, C01 -1..1 MPa,
  g1 0-0.9, tau1 1e-5..1e-4 s) at speeds 5-45 m/s, through `simulate_batch`: runs per second
  in float64 and float32, and single runs of the same sets for the ratio;
- `cli`: whole-process time of `ballimpact simulate` (the CalculiX cross-run ball: Mooney-Rivlin
  C10 4.72 MPa, C01 -0.45 MPa, D1 = 0, 160 g, 72 mm, 20 m/s) cold and with warm caches, where
  the warm run's time goes (JAX's compile events: tracing, lowering, loading the compilation
  cache, compiling), and CalculiX on the same ball in the same run when ccx is installed (half
  model, 8 divisions, implicit dynamics, all cores), with the ratio; and against the 122 s of an
  independent explicit code on the same problem.

Run: python benchmarks/bench_fe.py [--quick] [--cli]   (--quick: 16 sets in the batch, no 3-layer
ball; --cli: only the whole-process part)
"""

import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import jax
import numpy as np

from ballimpact.fe import SolverOptions, load_ball, simulate, simulate_batch
from ballimpact.balls.ball import BallModel, Layer
from ballimpact.constitutive import MooneyRivlin, PronyTerm
from ballimpact.fe.engine import default_group_size

THESIS_S = {"cricket-universal": 25.0, "cricket-3layer": 87.0}
INDEPENDENT_CODE_S = 122.0  # the same Mooney-Rivlin impact in an independent explicit code
OLD_TIME_STEP_SCALE = 0.9   # previous engine: 0.9 x min(L_e / c_d), L_e = area / longest diagonal


def timed(fn, *args):
    start = time.perf_counter()
    out = fn(*args)
    return time.perf_counter() - start, out


def one_ball(name, speed, options, label):
    ball = load_ball(name, impact_speed_m_s=speed)
    first, result = timed(simulate, ball, speed, options)
    wall = statistics.median(timed(simulate, ball, speed, options)[0] for _ in range(3))
    return {"ball": name, "setting": label, "impact_speed_m_s": speed, "first_call_s": first,
            "compilation_s_estimate": first - wall, "wall_time_per_simulation_s": wall,
            "elements": result.elements, "steps": result.steps,
            "stable_time_increment_s": result.stable_time_increment_s,
            "element_updates_per_s": result.elements * result.steps / wall,
            "thesis_abaqus_s": THESIS_S[name], "speedup_vs_thesis": THESIS_S[name] / wall,
            "peak_force_n": result.peak_force_n, "contact_time_s": result.contact_time_s,
            "cor": result.cor, "energy_balance_error": result.energy_balance_error,
            "history_digest": result.history_digest(),
            "hourglass_fraction_of_peak_internal_energy":
                result.energies_j["peak_hourglass_energy_j"]
                / result.energies_j["peak_internal_energy_j"]}


def old_increment_s(ball_name, speed):
    """The previous engine's increment: 0.9 x min(L_e / c_d) (L_e = area / longest diagonal)
    with the bulk-viscosity factor, and its contact-spring limit."""
    from ballimpact.fe.engine import Axisymmetric, kernel_for

    ball = load_ball(ball_name, impact_speed_m_s=speed)
    options = SolverOptions(integration="full")
    geom = kernel_for(ball, Axisymmetric(options))[0].geom
    c_d = np.array([np.sqrt(layer.material.wave_modulus_pa() / layer.density_kg_m3)
                    for layer in ball.layers])
    element_layer = np.concatenate([np.full(b - a, i) for i, (a, b) in enumerate(geom.layer_slices)])
    xi = options.bulk_viscosity_linear
    return OLD_TIME_STEP_SCALE * min(
        np.min(geom.characteristic_length_m / c_d[element_layer]) * (np.sqrt(1 + xi * xi) - xi),
        np.min(geom.surface_length_m / c_d[-1]) * 2.0 / np.sqrt(5.0))


def universal_sets(n, seed=0):
    """Parameter sets over the table 6-2 ranges (g1 capped at 0.9) and speeds 5-45 m/s."""
    rng = np.random.default_rng(seed)
    radius = 0.036
    density = 0.16 / (4.0 / 3.0 * np.pi * radius ** 3)
    balls = []
    for i in range(n):
        material = MooneyRivlin(c10_pa=rng.uniform(4.0e6, 7.0e6), c01_pa=rng.uniform(-1.0e6, 1.0e6),
                                prony=(PronyTerm(g=rng.uniform(0.0, 0.9), k=0.0,
                                                 tau_s=rng.uniform(1e-5, 1e-4)),))
        balls.append(BallModel(f"set{i}", (Layer("ball", radius, density, material),)))
    return balls, rng.uniform(5.0, 45.0, n)


def batch(n, precision):
    balls, speeds = universal_sets(n)
    options = SolverOptions(precision=precision)
    group = default_group_size(n)
    timed(simulate_batch, balls[:group], speeds[:group], options)  # compile
    wall, results = timed(simulate_batch, balls, speeds, options)
    singles = [timed(simulate, b, s, options)[0] for b, s in zip(balls[:4], speeds[:4])]
    return {"sets": n, "precision": precision, "wall_s": wall, "simulations_per_s": n / wall,
            "single_runs_per_s_first_4": 4 / sum(singles), "group_size": group,
            "backend": jax.default_backend(), "steps_max": max(r.steps for r in results),
            "steps_median": float(np.median([r.steps for r in results]))}


#: the child process of `cli_breakdown`: `ballimpact` with JAX's compile events summed
_BREAKDOWN = """
import json, sys, time
start = time.perf_counter()
import jax.monitoring
totals = {}
def add(event, seconds, **kwargs):
    totals[event] = totals.get(event, 0.0) + seconds
jax.monitoring.register_event_duration_secs_listener(add)
from ballimpact.cli import main
code = main(sys.argv[1:])
totals["in_python_s"] = time.perf_counter() - start
print(json.dumps(totals), file=sys.stderr)
sys.exit(code)
"""


def cli_whole_process():
    """`ballimpact simulate` as a user runs it: cold (empty caches), then warm (median of 3);
    where the warm run's time goes; and CalculiX on the same ball (half model, 8 divisions,
    both cores) when ccx is installed."""
    from ballimpact.export.calculix import CROSS_RUN_BALL, ccx_path, run_impact

    spec = dict(CROSS_RUN_BALL, name="mr-72mm-160g")
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "ball.json"
        path.write_text(json.dumps(spec))
        script = Path(sys.executable).parent / "ballimpact"  # the installed command
        launcher = [str(script)] if script.exists() else [sys.executable, "-m", "ballimpact.cli"]
        argv = ["simulate", "--ball", str(path), "--speed-m-s", "20", "--json"]
        env = dict(os.environ, BALLIMPACT_CACHE_DIR=str(Path(folder) / "cache"))

        def run(command):
            return subprocess.run(command, capture_output=True, env=env, check=True, text=True)

        cold = timed(run, launcher + argv)
        warm = [timed(run, launcher + argv) for _ in range(3)]
        child = run([sys.executable, "-c", _BREAKDOWN] + argv)
        events = json.loads(child.stderr.strip().splitlines()[-1])
        theirs = None
        if ccx_path() is not None:
            ours = json.loads(cold[1].stdout)
            theirs = run_impact(load_ball(spec), 20.0, Path(folder) / "calculix",
                                step_time_s=1.15 * ours["contact_time_s"],
                                threads=os.cpu_count() or 1)
    out = json.loads(warm[-1][1].stdout)
    wall = statistics.median(w for w, _ in warm)
    result = {
        "cold_cache_s": cold[0], "warm_cache_s": wall, "steps": out["steps"],
        "solver_run_s": out["wall_time_s"], "peak_force_n": out["peak_force_n"],
        "cor": out["cor"],
        "warm_breakdown_s": {
            "process_in_python": events["in_python_s"],
            "tracing": events.get("/jax/core/compile/jaxpr_trace_duration", 0.0),
            "lowering": events.get("/jax/core/compile/jaxpr_to_mlir_module_duration", 0.0),
            "loading_compilation_cache": events.get(
                "/jax/compilation_cache/cache_retrieval_time_sec", 0.0),
            "compiling": events.get("/jax/core/compile/backend_compile_duration", 0.0)},
        "calculix": None if theirs is None else {
            "wall_s": theirs.wall_time_s, "threads": os.cpu_count(), "divisions": 8,
            "peak_force_n": theirs.peak_force_n, "cor": theirs.cor,
            "increments": len(theirs.time_s) - 1},
        "independent_code_s": INDEPENDENT_CODE_S,
        "speedup_vs_independent_code": INDEPENDENT_CODE_S / wall}
    if theirs is not None:
        result["speedup_vs_calculix"] = theirs.wall_time_s / wall
    return result


def main():
    quick = "--quick" in sys.argv
    out = {"machine": {"platform": platform.platform(), "processor": platform.processor(),
                       "cpu_count": os.cpu_count(), "python": platform.python_version(),
                       "jax": jax.__version__, "backend": jax.default_backend()},
           "single": []}
    if "--cli" in sys.argv:
        out["cli"] = cli_whole_process()
        print(json.dumps(out, indent=2))
        return
    balls = [("cricket-universal", 25.0)] + ([] if quick else [("cricket-3layer", 20.8)])
    for name, speed in balls:
        for label, options in (("reduced float64 (default)", SolverOptions()),
                               ("reduced float32", SolverOptions(precision="float32")),
                               ("full float64", SolverOptions(integration="full"))):
            out["single"].append(one_ball(name, speed, options, label))
            print(f"{name} {label}: done", file=sys.stderr, flush=True)
    out["previous_engine"] = previous_engine(out["single"][0])
    for precision in ("float64", "float32"):
        out.setdefault("batch", []).append(batch(16 if quick else 64, precision))
        print(f"batch {precision}: done", file=sys.stderr, flush=True)
    out["cli"] = cli_whole_process()
    print(json.dumps(out, indent=2))


def previous_engine(default):
    """The universal ball at 25 m/s with the previous engine's element and increment, and the
    speed-up over it of `default` (the new default's figures, measured in this run)."""
    name, speed = "cricket-universal", 25.0
    ball = load_ball(name, impact_speed_m_s=speed)
    old_dt = old_increment_s(name, speed)
    probe = simulate(ball, speed, SolverOptions(integration="full"))
    scale = SolverOptions().time_step_scale * old_dt / probe.stable_time_increment_s
    old = one_ball(name, speed, SolverOptions(integration="full", time_step_scale=scale),
                   "previous engine (F-bar, 0.9 L_e/c_d)")
    return {"run": old, "speedup_vs_previous_engine":
            old["wall_time_per_simulation_s"] / default["wall_time_per_simulation_s"]}


if __name__ == "__main__":
    main()
