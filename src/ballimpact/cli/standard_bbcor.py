"""`ballimpact standard bbcor --bat BAT --ball BALL`: the BBCOR certification of a baseball bat
(ASTM F2219 / NCAA BBCOR) on the bat's model (`standards.bbcor_certification`);
docs/equipment.md, "BBCOR".
The `standard` verb's parser is `cli/standard.py`'s; it hands the bbcor method to `run` here."""

from __future__ import annotations

import argparse
from typing import Any

from ..errors import CheckFailed, InputError

#: the names `standard` takes for this method (lower case)
NAMES = ("bbcor", "f2219", "astm f2219")
#: the `standard` options that belong to the ball methods, with what they are for
OTHER_OPTIONS = (("paths", "FILES_OR_DIRS", "a lab's records"),
                 ("mass_kg", "--mass-kg", "records' mass"),
                 ("ball_id_pattern", "--ball-id-pattern", "records' ball ids"),
                 ("impact_speed_m_s", "--impact-speed-m-s", "the ball methods' speed; bbcor "
                                                            "fires at its own 136 mph"),
                 ("element_size_m", "--element-size-m", "the ball methods' mesh"),
                 ("table", "--table", "the ball methods' CSV table"))


def is_bbcor(method: str | None) -> bool:
    return method is not None and method.strip().lower() in NAMES


def run(args: argparse.Namespace) -> dict[str, Any]:
    from ..standards.bbcor import bbcor_certification
    from .bat import ball_of

    for attribute, flag, what in OTHER_OPTIONS:
        if getattr(args, attribute, None) not in (None, []):
            raise InputError(f"{flag}: not taken by bbcor ({what}); give --bat and --ball")
    if args.bat is None:
        raise InputError("--bat: missing; bbcor needs a bat: a preset (baseball-wood-34in, "
                         "baseball-aluminium-bbcor-34in) or a bat file")
    if args.ball is None:
        raise InputError("--ball: missing; a ball preset or file, or hc:MASS_KG:STIFFNESS:"
                         "DAMPING_S_M")
    result = bbcor_certification(args.bat, ball_of(args.ball), ball_model=args.ball_model,
                                 allow=args.allow, progress=True)
    if not args.json:
        print_bbcor(result)
    if not result["meets_limit"]:  # a certification the bat fails: exit 3, the result printed
        raise CheckFailed(f"BBCOR {result['bbcor']:.4f} exceeds the limit "
                          f"{result['limit']:.3f} ({result['designation']})", result)
    return result


def print_bbcor(out: dict[str, Any]) -> None:
    """The BBCOR and the limit, the test's figures, the law, the scan."""
    verdict = "meets it" if out["meets_limit"] else "EXCEEDS it"
    model = "FE ball" if out["ball"].get("model") == "fe" else "ball law"
    print(f"{out['designation']} of {out['bat']} with {out['ball']['name']} ({model}): BBCOR "
          f"{out['bbcor']:.4f} (limit {out['limit']:.3f}: {verdict})")
    print(f"  ball {out['speed_m_s']:.4g} m/s ({out['ball_speed_mph']:.0f} mph) at the bat at "
          f"rest, pinned {out['pivot_m']:g} m ({out['pivot_in']:g} in) from the knob; I pivot "
          f"{out['moi_pivot_kg_m2']:.4f} kg m^2, ball {out['ball_mass_kg']:.4g} kg")
    print(f"  largest BBCOR at {out['impact_m']:.4f} m from the knob "
          f"({out['from_barrel_end_m']:.4f} m, {out['from_barrel_end_in']:.2f} in from the barrel "
          f"end): e_A {out['collision_efficiency']:.4f}, r {out['r']:.4f}; a rigid bat "
          f"(the ball's COR on a rigid plane) {out['rigid_bbcor']:.4f}")
    print("  scan, in from the barrel end: "
          + ", ".join(f"{p['from_barrel_end_in']:.1f} {p['bbcor']:.4f}" for p in out["scan"]))
