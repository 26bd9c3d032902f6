"""`ballimpact standard ball --diameter-m D --mass-kg M --cor E --compression-n F --out FILE`: the
ball file of a homogeneous ball calibrated to a specification's COR (ASTM F1887) and compression
(ASTM F1888) by FE runs (`standards.specification`); docs/balls.md, "Presets from a
specification". The `standard` verb's parser is `cli/standard.py`'s; its options for this method
are added here."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from ..errors import CheckFailed, InputError

#: the names `standard` takes for this method (lower case)
NAMES = ("ball",)
#: the `standard` options of the other methods, with what they are for
OTHER_OPTIONS = (("paths", "FILES_OR_DIRS", "a lab's records"),
                 ("ball", "--ball", "a ball model to test; this method writes one"),
                 ("bat", "--bat", "bbcor's bat"),
                 ("ball_id_pattern", "--ball-id-pattern", "records' ball ids"),
                 ("table", "--table", "the methods' CSV table"))
#: this method's own options (attribute names): the other methods refuse them
OWN_OPTIONS = ("diameter_m", "cor", "compression_n", "deflection_m", "tau1_s", "name", "out")


def add_arguments(standard: argparse.ArgumentParser) -> None:
    """The options of `standard ball` (with `--mass-kg`, `--impact-speed-m-s` and
    `--element-size-m`, which `standard` has already)."""
    group = standard.add_argument_group(
        "ball (a ball file calibrated to a specification's COR and compression)")
    group.add_argument("--diameter-m", type=float, help="ball: the ball's diameter (m)")
    group.add_argument("--cor", type=float,
                       help="ball: its COR off a rigid wall at --impact-speed-m-s (default 60 "
                            "mph), ASTM F1887")
    group.add_argument("--compression-n", type=float,
                       help="ball: its quasi-static compression force (N; 375 lbf = 1668 N) at "
                            "--deflection-m, ASTM F1888")
    group.add_argument("--deflection-m", type=float,
                       help="ball: the platens' approach of that force (m; default 0.00635, "
                            "F1888's 0.25 in)")
    group.add_argument("--tau1-s", type=float,
                       help="ball: its Prony relaxation time (s; default 31.6 us x R / 36 mm, "
                            "the universal model's choice)")
    group.add_argument("--name", help="ball: the ball's name (default: the --out file's name)")
    group.add_argument("--out", type=Path, help="ball: the ball file to write (.json)")


def is_ball(method: str | None) -> bool:
    return method is not None and method.strip().lower() in NAMES


def run(args: argparse.Namespace) -> dict[str, Any]:
    from ..progress import progress_line
    from ..standards.specification import write_specified_ball
    from .common import use_compilation_cache

    for attribute, flag, what in OTHER_OPTIONS:
        if getattr(args, attribute, None) not in (None, []):
            raise InputError(f"{flag}: not taken by `standard ball` ({what})")
    for attribute, flag in (("diameter_m", "--diameter-m"), ("mass_kg", "--mass-kg"),
                            ("cor", "--cor"), ("compression_n", "--compression-n"),
                            ("out", "--out")):
        if getattr(args, attribute) is None:
            raise InputError(f"{flag}: missing; `standard ball` needs --diameter-m, --mass-kg, "
                             "--cor, --compression-n and --out")
    use_compilation_cache()
    out = write_specified_ball(
        args.out, args.diameter_m, args.mass_kg, args.cor, args.compression_n,
        compression_deflection_m=args.deflection_m, impact_speed_m_s=args.impact_speed_m_s,
        tau1_s=args.tau1_s, name=args.name, element_size_m=args.element_size_m,
        progress=progress_line)
    if not args.json:
        print_ball(out)
    missed = out["check"]["missed"]
    if missed:  # not written: a ball that does not meet its specification
        raise CheckFailed(f"the calibration did not close ({'; '.join(missed)}); "
                          f"{args.out} not written", out)
    return out


def print_ball(out: dict[str, Any]) -> None:
    from ..records.loaders import LBF_N

    s, p, c = out["specification"], out["params"], out["check"]
    lbf = s["compression_force_n"] / LBF_N
    print(f"{out['ball']['name']}: a homogeneous ball of {s['diameter_m'] * 1e3:.2f} mm and "
          f"{s['mass_kg'] * 1e3:.2f} g calibrated to COR {s['cor']:g} at "
          f"{s['impact_speed_m_s']:.4g} m/s and {s['compression_force_n']:.4g} N ({lbf:.4g} lbf) "
          f"at {s['compression_deflection_m'] * 1e3:.3g} mm")
    print(f"  C10 {p['c10_pa'] / 1e6:.4g} MPa, C01 0, g1 {p['g1']:.4f}, tau1 "
          f"{p['tau1_s'] * 1e6:.4g} us (long-term moduli, K = 20 mu0 / (1 - g1))")
    print(f"  FE check ({out['element_size_m'] * 1e3:.3g} mm elements): COR {c['cor']:.4f} "
          f"({c['cor_error']:+.4f}), compression {c['compression_force_n']:.5g} N "
          f"({c['compression_relative_error']:+.2%}); DS {c['dynamic_stiffness_n_m']:.4g} N/m, "
          f"peak force {c['peak_force_n']:.5g} N, contact time {c['contact_time_s'] * 1e3:.3f} ms")
    print(f"  {out['runs']['impacts']} impacts, {out['runs']['compressions']} compressions, "
          f"{out['wall_time_s']:.1f} s" + (f"; wrote {out['out']}" if "out" in out else ""))
