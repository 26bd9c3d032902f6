"""`ballimpact balls`: the built-in ball presets."""

from __future__ import annotations

import argparse
from typing import Any
from .common import add_json, print_lines


def add_parser(verbs) -> None:
    balls = verbs.add_parser("balls", help="list the built-in ball presets",
                             description="The built-in ball presets usable with --ball.")
    add_json(balls)


def run_balls(args: argparse.Namespace) -> dict[str, Any]:
    from ..balls.text import presets_lines
    from ..fe import describe_presets

    presets = describe_presets()
    if not args.json:
        print_lines(presets_lines(presets))
    return {"balls": presets}
