"""`ballimpact compress`: the whole ball between two rigid platens (placeholder, being written)."""

from __future__ import annotations

import argparse
from typing import Any


def add_parser(verbs) -> None:
    compress = verbs.add_parser("compress", help="the ball squeezed between two rigid platens")
    compress.add_argument("--json", action="store_true", help="print one JSON object")


def run(args: argparse.Namespace) -> dict[str, Any]:
    raise NotImplementedError("compress: being written")
