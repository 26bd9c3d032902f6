"""`ballimpact balls`: the built-in ball presets."""

from __future__ import annotations

import argparse
from typing import Any
from .common import add_json


def add_parser(verbs) -> None:
    balls = verbs.add_parser("balls", help="list the built-in ball presets",
                             description="The built-in ball presets usable with --ball.")
    add_json(balls)


def run_balls(args: argparse.Namespace) -> dict[str, Any]:
    from ..fe import describe_presets

    presets = describe_presets()
    if not args.json:
        for preset in presets:
            print(f"{preset['name']}: {preset['description']}")
            if preset.get("source"):
                print(f"    source: {preset['source']}")
    return {"balls": presets}
