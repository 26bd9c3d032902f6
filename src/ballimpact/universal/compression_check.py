"""The compression criterion of `identify`'s FE check: the homogeneous ball identified from an
impact, squeezed between two platens as the ball was in a compression test, against that test's
force-deflection curve.

An impact sees the ball's instantaneous moduli, a slow compression its relaxed ones. One
homogeneous layer ties the two together through its own g1; a layered ball (a lossy core under
a stiffer cover, say) does not. When the identified ball gives the impact but not the
compression, one layer cannot be the ball, and the way on is a layered calibration against both
tests (`ballimpact calibrate --test ... --compression ...`, docs/calibrate.md, "Layered balls
from tests").
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ..checks import check_fraction
from ..errors import InputError
from ..verdict import COMPRESSION_TOLERANCE

#: Where the layered path is explained.
LAYERED_PATH = "docs/calibrate.md, 'Layered balls from tests'"


def check_compression_tolerance(value: float) -> float:
    """A compression NRMSE limit: a fraction of the test's largest force in (0, 1]."""
    return check_fraction("max_compression_error (--max-compression-error)", float(value))


def load_compression_test(path: str | Path):
    """The `calibrate.compression.CompressionTest` of a compression CSV (the long-term curve of
    a slow test), named by the file's stem. `InputError` naming the file and line."""
    from ..calibrate.compression import CompressionTest, read_compression_csv

    path = Path(path)
    if not path.is_file():
        raise InputError(f"--compression: {path}: " + ("is a folder; give a CSV file"
                                                       if path.is_dir() else "no such file"))
    deflection, force = read_compression_csv(path)
    return CompressionTest(path.stem, deflection, force, source=str(path))


def judge_compression(verification: dict[str, Any], ball_spec: dict, test,
                      tolerance: float = COMPRESSION_TOLERANCE,
                      allow=()) -> dict[str, Any]:
    """Compress the ball `ball_spec` (long-term, or at the test's platen rate) to the test's
    largest deflection on the mesh that resolves the platens' contact (`fe.compress`'s default),
    compare (`compare_compression`) and add the criterion "compression" to `verification`
    (`verdict.judge`'s dict, changed in place: its `criteria`, `missed` and `passed`; the curve's
    figures under `verification["compression"]`). Returns `verification`. `InputError` for a
    test deeper than the ball can be squeezed. `allow`: the ball's checks to pass
    (`load_ball`)."""
    from ..calibrate.compression import compare_compression, compression_run
    from ..fe import load_ball

    ball = load_ball(ball_spec, allow=allow)
    test.check_against(ball)
    curve = compression_run(test, ball, None)
    figures = compare_compression(test, curve)
    nrmse = figures["compression_nrmse"]
    end = test.max_deflection_m
    verification["compression"] = {
        "test": test.source or test.name, "compression_nrmse": nrmse,
        "end_force_relative_error": figures["end_force_relative_error"],
        "deflection_m": end, "force_measured_n": float(test.force_n[-1]),
        "force_simulated_n": float(curve.force_at(end)),
        "rate_m_s": test.rate_m_s, "elements": curve.elements}
    passed = bool(nrmse <= tolerance)  # NaN fails
    verification["criteria"]["compression"] = {"value": nrmse, "allowed": tolerance,
                                               "tolerance": tolerance, "passed": passed}
    verification["tolerances"]["compression"] = tolerance
    if not passed:
        verification["missed"].append(
            f"compression NRMSE {nrmse:.1%} > {tolerance:.1%} (--max-compression-error; the "
            f"force at {end * 1e3:.3g} mm {figures['end_force_relative_error']:+.1%}): one "
            "homogeneous layer does not give this ball's impact and compression together; "
            f"calibrate a layered ball (core and cover) against both tests ({LAYERED_PATH})")
        verification["passed"] = False
    return verification
