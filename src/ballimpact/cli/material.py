"""`ballimpact material fit|check`: material tests to constants (placeholder, being written)."""

from __future__ import annotations

import argparse
from typing import Any


def add_parser(verbs) -> None:
    material = verbs.add_parser("material", help="fit material constants to material tests")
    material.add_argument("--json", action="store_true", help="print one JSON object")


def run(args: argparse.Namespace) -> dict[str, Any]:
    raise NotImplementedError("material: being written")
