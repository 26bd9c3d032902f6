"""The compiled programs of the explicit kernels (both geometries), and traced programs kept on
disk so that a new process need not trace them again.

`compiled_run(kernel, n_steps, batched)` gives a kernel's (chunk, initial state) functions,
jitted (vmapped for a batch) and kept for the process. JAX's persistent compilation cache keeps
the compiled executables between processes, but a new process still traces the Python code and
lowers it to StableHLO before it can look one up: 0.8 s of the 1.7 s that a `ballimpact
simulate` of the axisymmetric ball spent in the solver. With a folder set (`use_folder`; the
command line sets one beside the compilation cache) each program's lowered form is kept there
(`jax.export`, serialized) under a key of everything its trace depends on: the kernel's data
(mesh arrays, material models, flags), the arguments' structure, shapes and dtypes, the package's
source, JAX's version and the backend. A later process reads it back and goes straight to the
compilation cache. The library alone leaves the folder unset: nothing is written.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import json
import os
import tempfile
import time
from pathlib import Path
from typing import Any, Callable

import jax
import numpy as np

_FOLDER: Path | None = None
_COMPILED: dict[Any, tuple[Callable, Callable]] = {}


def use_folder(folder: str | os.PathLike | None) -> None:
    """Keep traced programs in `folder` (created when needed), or nowhere (None)."""
    global _FOLDER
    _FOLDER = None if folder is None else Path(folder)


def is_compiled(kernel, n_steps: int, batched: bool) -> bool:
    """Whether `compiled_run(kernel, n_steps, batched)` has run in this process already: its
    first call then waits for no compilation."""
    return (id(kernel), n_steps, batched) in _COMPILED


#: What a first compilation is expected to take (s) when none was timed on this machine yet:
#: measured on 2 CPU cores (a new two-layer ball, `ballimpact simulate`; `ballimpact compress
#: --ball cricket-men`, 3.75 s; empty caches).
DEFAULT_COMPILE_S = {"axisymmetric": 8.0, "3D": 15.0, "compression": 4.0}
#: A first call shorter than this (s) found its program in JAX's cache: not a compilation.
COMPILE_MIN_S = 2.0


def kernel_kind(kernel) -> str:
    """"3D" for the hexahedral kernels (`fe.hex`), "axisymmetric" for the others."""
    return "3D" if ".hex." in type(kernel).__module__ else "axisymmetric"


class CompileWait:
    """A first call that compiles: a `progress.Waiting` line ("compiling the axisymmetric kernel
    for 2,318 elements (once per ball layout): 4 s, about 4 s left") whose expected time is what
    the last such compilation (the same `key`) took on this machine (kept beside the traced
    programs, `use_folder`; else `DEFAULT_COMPILE_S` of the key's first word), and this one's
    time kept for the next."""

    def __init__(self, text: str, key: str) -> None:
        from ..progress import Waiting

        self.key = key
        self.waiting = Waiting(text, _compile_times().get(
            key, DEFAULT_COMPILE_S[key.split()[0]]))

    @classmethod
    def of_kernel(cls, kernel, batched: bool, members: int) -> CompileWait:
        """The wait of an explicit kernel's first chunk, keyed by its geometry, batching and
        number of layers (the program grows with them: a material law each)."""
        kind = kernel_kind(kernel)
        layers = len(getattr(kernel, "energies", ()) or ())
        elements = getattr(getattr(kernel, "geom", None), "n_elements", None)
        size = f" for {elements:,} elements" if elements else ""
        batch = f", a batch of {members}" if batched else ""
        return cls(f"compiling the {kind} kernel{size}{batch} (once per ball layout)",
                   f"{kind}{' batched' if batched else ''}{f' {layers} layers' if layers else ''}")

    def __enter__(self) -> CompileWait:
        self.started = time.perf_counter()
        self.waiting.__enter__()
        return self

    def __exit__(self, *exc) -> None:
        self.waiting.__exit__(*exc)
        seconds = time.perf_counter() - self.started
        if exc[0] is None and seconds >= COMPILE_MIN_S and _FOLDER is not None:
            times = _compile_times()
            times[self.key] = round(seconds, 2)
            try:
                _write_bytes(_FOLDER / "compile_seconds.json", json.dumps(times).encode())
            except OSError:  # a cache: nothing lost when it cannot be written
                pass


def _compile_times() -> dict[str, float]:
    """The last first-call times (s) kept in the folder of `use_folder` ({} when none)."""
    if _FOLDER is None:
        return {}
    try:
        times = json.loads((_FOLDER / "compile_seconds.json").read_text())
    except (OSError, ValueError):
        return {}
    return {k: float(v) for k, v in times.items()
            if isinstance(v, (int, float)) and 0 < v < 3600} if isinstance(times, dict) else {}


def compiled_run(kernel, n_steps: int, batched: bool) -> tuple[Callable, Callable]:
    """(chunk of `n_steps` steps, initial state) of a kernel (`fe.steps.ChunkedSteps`): jitted,
    vmapped over a leading batch axis when `batched`, kept for the process."""
    key = (id(kernel), n_steps, batched)
    if key not in _COMPILED:
        fns = (functools.partial(kernel.chunk, n_steps=n_steps), kernel.initial_state)
        if batched:
            fns = tuple(jax.vmap(fn) for fn in fns)
        static = f"{fingerprint(kernel)}|{n_steps}|{batched}"
        _COMPILED[key] = tuple(cached_jit(fn, name, static)
                               for fn, name in zip(fns, ("chunk", "initial_state")))
    return _COMPILED[key]


def cached_jit(fn: Callable, name: str, static_key: str) -> Callable:
    """`jax.jit(fn)`, its lowered program read from (or written to) the folder of `use_folder`
    when one is set. `static_key`: everything the trace depends on besides the arguments'
    structure, shapes and dtypes and the package's source (those are added here). A program that
    cannot be exported or kept (e.g. no `flatbuffers`, a read-only folder) is simply traced."""
    jitted = jax.jit(fn)
    programs: dict[tuple, Callable] = {}

    def call(*args):
        if _FOLDER is None:
            return jitted(*args)
        leaves, tree = jax.tree_util.tree_flatten(args)
        signature = (str(tree), tuple(str(jax.typeof(x)) for x in leaves),
                     bool(jax.config.read("jax_enable_x64")))
        if signature not in programs:
            programs[signature] = _kept_program(jitted, name, static_key, signature, args)
        return programs[signature](*args)

    return call


def _kept_program(jitted: Callable, name: str, static_key: str, signature: tuple,
                  args: tuple) -> Callable:
    key = hashlib.sha256(repr((name, static_key, signature, source_fingerprint(),
                               jax.__version__, jax.default_backend())).encode()).hexdigest()
    path = _FOLDER / f"{name}-{key[:40]}.jaxexport"
    try:
        exported = jax.export.deserialize(bytearray(path.read_bytes()))
    except Exception:  # noqa: BLE001 - not there, damaged or unreadable: trace it again
        exported = None
    if exported is None:
        try:
            exported = jax.export.export(jitted)(*args)
            _write_bytes(path, exported.serialize())
        except Exception:  # noqa: BLE001 - a cache: any failure leaves the plain jitted function
            return jitted
    return jax.jit(exported.call)


def _write_bytes(path: Path, data: bytes) -> None:
    """Write through a unique temporary file renamed into place: processes writing the same
    program at once (a sweep's workers) leave one whole file."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.NamedTemporaryFile(dir=path.parent, prefix=path.stem, suffix=".tmp",
                                     delete=False) as tmp:
        tmp.write(data)
    os.replace(tmp.name, path)


@functools.cache
def source_fingerprint() -> str:
    """sha256 of the package's Python sources: a program traced by other code is never reused."""
    root = Path(__file__).resolve().parents[1]
    digest = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        digest.update(str(path.relative_to(root)).encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()


def fingerprint(value: Any) -> str:
    """sha256 of what a trace closes over: arrays by dtype, shape and bytes, functions by their
    qualified name, dataclasses, dicts and sequences by their items, anything else by repr. The
    same in every process (no object addresses): tests/fe/test_programs.py checks it."""
    digest = hashlib.sha256()

    def feed(v):
        if isinstance(v, (np.ndarray, jax.Array)):
            a = np.asarray(v)
            digest.update(f"array{a.dtype.str}{a.shape}".encode())
            digest.update(np.ascontiguousarray(a).tobytes())
        elif dataclasses.is_dataclass(v) and not isinstance(v, type):
            digest.update(type(v).__qualname__.encode())
            for field in dataclasses.fields(v):
                digest.update(field.name.encode())
                feed(getattr(v, field.name))
        elif isinstance(v, dict):
            for k in sorted(v, key=repr):
                digest.update(repr(k).encode())
                feed(v[k])
        elif isinstance(v, (tuple, list)):
            digest.update(f"{type(v).__name__}{len(v)}".encode())
            for item in v:
                feed(item)
        elif isinstance(v, functools.partial):
            feed((v.func, v.args, v.keywords))
        elif callable(v):
            digest.update(f"{getattr(v, '__module__', '')}.{getattr(v, '__qualname__', repr(v))}"
                          .encode())
        else:
            digest.update(repr(v).encode())

    feed(value)
    return digest.hexdigest()
