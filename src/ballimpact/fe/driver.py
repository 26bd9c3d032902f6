"""The run loop of the explicit engine (`fe.engine`), whatever its geometry (axisymmetric or
hexahedral).

A kernel (`fe.steps.ChunkedSteps`: the axisymmetric `fe.axi.kernel.Kernel` or the hexahedral
`fe.hex.kernel.Kernel`) gives an initial state and a chunk of steps, compiled once per process
by `programs.compiled_run`. `run_chunks` steps the members of a vmapped group chunk by chunk and
decides, between chunks and on the host, what the kernels flag in their state: the time reached
`t`, the first non-finite or inverted state `t_bad`, the first energy-balance error above the
limit `t_energy`, and the contact's start and separation `t_start`, `t_separation`. A member ends
`end_margin` of its contact time after separation; one that fails before its end, or reaches
its time limit without separating, fails with a reason. The state's increment re-estimates
happen inside the chunk (the kernels'); the results are each geometry's own.
"""

from __future__ import annotations

import contextlib
from dataclasses import dataclass
from functools import partial
from typing import Callable, Sequence

import jax
import jax.numpy as jnp
import numpy as np

from ..errors import SimulationError
from ..progress import waits_announced
from .steps import cast
from .programs import CompileWait, compiled_run, is_compiled

#: the state's scalars the loop reads between chunks
FLAGS = ("t", "t_bad", "t_energy", "t_start", "t_separation")


@dataclass(frozen=True)
class RunOutcome:
    """What `run_chunks` returns, per member of the group (the leading axis of each array):
    `history` (members, rows, columns of the kernel's HISTORY), `final` (state name -> value at
    the end), `t_end_s` (s; the member's end, not finite without separation) and `failed` (member ->
    reason)."""

    history: np.ndarray
    final: dict[str, np.ndarray]
    t_end_s: np.ndarray
    failed: dict[int, str]


@dataclass(frozen=True, eq=False)
class RunFigures:
    """What a run of either geometry reports (SI), the base of `fe.result.ImpactResult`:
    histories per step (name -> values), the peak contact force (N; the whole ball's), its time and the contact time (s), the largest energy balance error
    (fraction of the impact energy), the stable increment at the start and at the end (s), the
    steps, the mesh's elements and nodes, the ball's mass (kg) and outer radius (m), and the
    range of principal stretches that occurred."""

    ball_name: str
    history: dict[str, np.ndarray]
    peak_force_n: float
    time_of_peak_s: float
    contact_time_s: float
    energy_balance_error: float
    stable_time_increment_s: float   # at the start; shrinks as the ball stiffens
    final_time_increment_s: float
    steps: int
    elements: int
    nodes: int
    mass_kg: float
    outer_radius_m: float
    stretch_range: tuple[float, float]


def failure(label: str, t_bad: float, t_energy: float, t_end: float, options,
            refine: str) -> str | None:
    """Why a member (`label`, e.g. "ball NAME") failed before `t_end` (s), or None. `refine`:
    what to try against an inverted element ("element size", "more divisions")."""
    if t_bad < t_end and t_bad < t_energy:
        return (f"{label}: inverted element or non-finite state at t = {t_bad:.4g} s "
                f"(try a smaller time_step_scale or {refine})")
    if t_energy < t_end:
        return (f"{label}: energy balance error above energy_error_limit = "
                f"{options.energy_error_limit:g} of the impact energy at t = {t_energy:.4g} s: "
                "the run is unstable (an increment too large for the ball: time_step_scale = "
                f"{options.time_step_scale:g}, 1 the stability limit; or elements crushed by a "
                "ball too soft for the speed)")
    return None


def run_chunks(kernel, params, initial: Sequence[np.ndarray], options, *, batched: bool,
               limits_s: np.ndarray, labels: Sequence[str], final_keys: Sequence[str],
               refine: str, progress: Callable[[float], None] | None = None,
               on_chunk: Callable[[int, object, dict], None] | None = None,
               on_failure: str = "raise") -> RunOutcome:
    """Run a group of members (one when not `batched`) to their ends.

    `params`: the kernel's parameters (stacked over members when `batched`); `initial`: the
    initial state's arguments, one array over members each (speeds; angles and spins in 3D);
    `options`: `chunk_steps`, `end_margin`, `energy_error_limit`, `time_step_scale`;
    `limits_s`: each member's time limit (s); `labels`: each member's name in messages.
    `progress(t_s)` is called after each chunk with the least time reached, `on_chunk(n, params,
    state)` after the n-th chunk (1, 2, ...). `on_failure`: "raise" (a `SimulationError` for the
    first failed member, as soon as one fails) or "return" (failed members keep stepping with
    the group and come back in `failed`)."""
    # a new program's first call compiles it, silently: say so when the run reports progress or
    # the command line asks (`progress.announce_waits`)
    wait = contextlib.ExitStack()
    if ((progress is not None or waits_announced())
            and not is_compiled(kernel, options.chunk_steps, batched)):
        wait.enter_context(CompileWait.of_kernel(kernel, batched, len(labels)))
    chunk_fn, init_fn = compiled_run(kernel, options.chunk_steps, batched)
    n = len(labels)
    with wait, jax.enable_x64(True), np.errstate(invalid="ignore"):
        # device_put, not jnp.asarray: the latter compiles (or loads) a small program per array
        # kind, a tenth of a second of a single run's process
        params = jax.device_put(cast(params, kernel.dtype))
        state = init_fn(params, *(jax.device_put(np.asarray(x if batched else x[0], kernel.dtype))
                                  for x in initial))
        rows, failed, chunks = [], {}, 0
        while True:
            state, chunk_rows = chunk_fn(params, state)
            chunks += 1
            if chunks == 1:
                wait.close()
            rows.append(np.asarray(chunk_rows, dtype=np.float64))
            if on_chunk is not None:
                on_chunk(chunks, params, state)
            flags = {k: np.atleast_1d(np.asarray(getattr(state, k), dtype=np.float64))
                     for k in FLAGS}
            t, t_start, t_sep = flags["t"], flags["t_start"], flags["t_separation"]
            t_end = t_sep + options.end_margin * (t_sep - t_start)
            done = np.isfinite(t_sep) & (t >= t_end)
            # a failure counts only before the member's own end (members that are done keep
            # stepping until the whole group is)
            for i in range(n):
                if i not in failed:
                    reason = failure(labels[i], flags["t_bad"][i], flags["t_energy"][i],
                                     t_end[i] if done[i] else np.inf, options, refine)
                    if reason is not None:
                        failed[i] = reason
            if failed and on_failure == "raise":
                raise SimulationError(failed[min(failed)])
            if progress is not None:
                progress(float(t.min()))
            finished = done.copy()
            finished[list(failed)] = True
            if np.all(finished | (t >= limits_s)):
                break
        for i in np.flatnonzero(~finished):
            failed[int(i)] = f"{labels[i]}: no separation within the time limit {limits_s[i]:.4g} s"
        if failed and on_failure == "raise":
            raise SimulationError(failed[min(failed)])
        final = {k: np.asarray(getattr(state, k), dtype=np.float64) for k in final_keys}
    history = np.concatenate(rows, axis=1 if batched else 0)
    if not batched:
        history = history[None]
        final = {k: v[None] for k, v in final.items()}
    return RunOutcome(history, final, t_end, failed)


def fixed_increment_run(kernel, params, initial: Sequence, increment_s, n_chunks: int,
                        chunk_steps: int, columns: Sequence[int]):
    """One member's run of `n_chunks` x `chunk_steps` steps at the fixed increment `increment_s`
    (s), differentiable in `params` (JAX arrays, the kernel's dtype) in forward and reverse mode:
    each chunk is under `jax.checkpoint`, so reverse mode stores only the chunk boundaries. No
    increment re-estimate and no end rule (a fixed window: the misfit of `calibrate.gradient`
    stays smooth). `initial`: the initial state's arguments (speed; angle and spin in 3D).
    Returns the history's `columns` (indices into the kernel's HISTORY) at t = (i + 1) dt,
    shape (n_chunks * chunk_steps, len(columns))."""
    state = kernel.initial_state(params, *initial)
    # the fixed increment replaces the stable-increment estimate (whose outputs go unused)
    dt = jnp.asarray(increment_s, kernel.dtype)
    state = state._replace(dt=dt, dt0=dt, x_top=jnp.zeros_like(state.x_top))
    step = partial(kernel.step, params, jnp.asarray(0.0, kernel.dtype))
    picked = jnp.asarray(columns)

    @jax.checkpoint
    def chunk(state, indices):
        state, rows = jax.lax.scan(step, state, indices)
        return state, rows[:, picked]

    indices = jnp.arange(n_chunks * chunk_steps, dtype=kernel.dtype).reshape(n_chunks, -1)
    _, rows = jax.lax.scan(chunk, state, indices)
    return rows.reshape(n_chunks * chunk_steps, len(columns))
