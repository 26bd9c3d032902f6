"""Traced programs kept on disk (`fe.programs`, issue 28 item 4): a program is traced once, read
back by a later process without tracing, keyed by everything its trace depends on, and the runs
it gives are the runs the plain jitted program gives, bit for bit."""

import subprocess
import sys

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from ballimpact.fe import SolverOptions, load_ball, programs, simulate


@pytest.fixture
def folder(tmp_path):
    programs.use_folder(tmp_path / "programs")
    yield tmp_path / "programs"
    programs.use_folder(None)


def _count_exports(monkeypatch) -> list:
    """The calls of `jax.export.export` from now on (a program traced again is exported again;
    a failed export would be caught by the cache, so the calls are counted, not refused)."""
    calls = []
    export = jax.export.export

    def counted(*args, **kwargs):
        calls.append(args)
        return export(*args, **kwargs)

    monkeypatch.setattr(jax.export, "export", counted)
    return calls


def _polynomial(x, y):
    return {"sum": jnp.sum(x ** 3 - 2.0 * x * y["a"]), "shifted": x + y["b"]}


def test_a_program_is_read_back_without_tracing_and_gives_the_same_values(folder, monkeypatch):
    x = jnp.linspace(0.0, 1.0, 7)
    y = {"a": jnp.asarray(0.5), "b": jnp.arange(7.0)}
    first = programs.cached_jit(_polynomial, "poly", "static")(x, y)
    assert len(list(folder.glob("poly-*.jaxexport"))) == 1
    exports = _count_exports(monkeypatch)  # a fresh wrapper is a new process's: it reads the file
    again = programs.cached_jit(_polynomial, "poly", "static")(x, y)
    assert exports == []
    expected = jax.jit(_polynomial)(x, y)
    for key in expected:
        np.testing.assert_array_equal(first[key], expected[key])
        np.testing.assert_array_equal(again[key], expected[key])


def test_the_key_holds_the_static_data_shapes_and_dtypes(folder):
    y = {"a": jnp.asarray(0.5), "b": jnp.zeros(3)}
    programs.cached_jit(_polynomial, "poly", "one")(jnp.ones(3), y)
    programs.cached_jit(_polynomial, "poly", "two")(jnp.ones(3), y)  # other static data
    fn = programs.cached_jit(_polynomial, "poly", "one")
    fn(jnp.ones(3), y)  # the same: read back
    assert len(list(folder.glob("*.jaxexport"))) == 2
    fn(jnp.ones(4), {"a": jnp.asarray(0.5), "b": jnp.zeros(4)})  # another shape
    with jax.enable_x64(True):
        fn(jnp.ones(3, jnp.float64), {"a": jnp.asarray(0.5, jnp.float64),
                                       "b": jnp.zeros(3, jnp.float64)})  # another dtype
    assert len(list(folder.glob("*.jaxexport"))) == 4


def test_a_damaged_program_is_traced_again_and_replaced(folder, monkeypatch):
    x, y = jnp.ones(3), {"a": jnp.asarray(2.0), "b": jnp.zeros(3)}
    programs.cached_jit(_polynomial, "poly", "static")(x, y)
    (path,) = folder.glob("poly-*.jaxexport")
    path.write_bytes(b"not a program")
    exports = _count_exports(monkeypatch)
    out = programs.cached_jit(_polynomial, "poly", "static")(x, y)
    assert len(exports) == 1
    assert float(out["sum"]) == pytest.approx(3.0 * (1.0 - 4.0))
    assert path.read_bytes() != b"not a program"


def test_without_a_folder_nothing_is_written(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    exports = _count_exports(monkeypatch)
    out = programs.cached_jit(_polynomial, "poly", "static")(
        jnp.ones(2), {"a": jnp.asarray(1.0), "b": jnp.zeros(2)})
    assert exports == []
    assert float(out["sum"]) == pytest.approx(-2.0)
    assert list(tmp_path.rglob("*.jaxexport")) == []


def test_the_kernel_fingerprint_follows_the_mesh_and_the_material_model():
    ball = load_ball("cricket-universal", impact_speed_m_s=20.0)
    options = SolverOptions(element_size_m=4e-3)
    from ballimpact.fe.engine import Axisymmetric, kernel_for

    def kernel(options):
        return kernel_for(ball, Axisymmetric(options))[0]

    same = programs.fingerprint(kernel(options))
    assert programs.fingerprint(kernel(SolverOptions(element_size_m=4e-3))) == same
    assert programs.fingerprint(kernel(SolverOptions(element_size_m=3e-3))) != same
    assert programs.fingerprint(kernel(SolverOptions(element_size_m=4e-3,
                                                     integration="full"))) != same


def test_the_kernel_fingerprint_is_the_same_in_another_process():
    code = ("from ballimpact.fe import SolverOptions, load_ball, programs; "
            "from ballimpact.fe import Axisymmetric, Hexahedral, Options3D; "
            "from ballimpact.fe.engine import kernel_for; "
            "ball = load_ball('cricket-universal', impact_speed_m_s=20.0); "
            "print(programs.fingerprint(kernel_for(ball, Axisymmetric(SolverOptions("
            "element_size_m=4e-3)))[0])); "
            "print(programs.fingerprint(kernel_for(ball, Hexahedral(Options3D(divisions=6), "
            "half=True))[0]))")
    runs = [subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                           check=True).stdout.split() for _ in range(2)]
    assert runs[0] == runs[1] and len(runs[0]) == 2


def test_an_fe_run_from_a_kept_program_is_the_plain_run_bit_for_bit(folder, monkeypatch):
    ball = load_ball("cricket-universal", impact_speed_m_s=20.0)
    options = SolverOptions(element_size_m=4e-3)
    programs.use_folder(None)
    plain = simulate(ball, 20.0, options)
    programs.use_folder(folder)
    programs._COMPILED.clear()  # as in a new process
    written = simulate(ball, 20.0, options)
    assert sorted(p.name.split("-")[0] for p in folder.glob("*.jaxexport")) == [
        "chunk", "initial_state"]
    programs._COMPILED.clear()
    exports = _count_exports(monkeypatch)
    read = simulate(ball, 20.0, options)
    assert exports == []
    for run in (written, read):
        assert run.steps == plain.steps
        for name, values in plain.history.items():
            np.testing.assert_array_equal(run.history[name], values, err_msg=name)


@pytest.mark.slow  # 38 s on 2 cores: three compilations of the 3D programs
def test_a_3d_run_keeps_its_programs_and_reads_them_back(folder, monkeypatch):
    """The hexahedral kernel's programs (its named parameters and state serialized too) are
    kept and read back, and the run read back is the plain one, bit for bit."""
    from ballimpact.oblique import ImpactCondition, Options3D, simulate_oblique

    ball = load_ball("cricket-universal", impact_speed_m_s=20.0)
    condition, options = ImpactCondition(20.0, 30.0, 0.0, 0.3), Options3D(divisions=4)
    programs.use_folder(None)
    plain = simulate_oblique(ball, condition, options)
    programs.use_folder(folder)
    programs._COMPILED.clear()
    simulate_oblique(ball, condition, options)
    assert sorted(p.name.split("-")[0] for p in folder.glob("*.jaxexport")) == [
        "chunk", "initial_state"]
    programs._COMPILED.clear()
    exports = _count_exports(monkeypatch)
    read = simulate_oblique(ball, condition, options)
    assert exports == []
    for name, values in plain.history.items():
        np.testing.assert_array_equal(read.history[name], values, err_msg=name)


def test_materialized_values_are_the_same_bits():
    """`fe.hex.element.materialized` (F and the hourglass terms computed once into memory by a
    gather with a run-time index) changes no value: jitted with and without it, bit for bit."""
    from ballimpact.fe.hex.element import materialized

    x = jnp.asarray(np.random.default_rng(5).normal(size=(3, 257)))

    def chain(x, index):
        y = materialized(x * x - 1.5 * x, index)
        return sum(y[i] * y[(i + 1) % 3] for i in range(3))

    index = jnp.arange(257, dtype=jnp.int32)
    with_it = jax.jit(chain)(x, index)
    without = jax.jit(lambda x: chain(x, None))(x)
    np.testing.assert_array_equal(with_it, without)
