"""The text of the ball presets, as `ballimpact balls` prints it: the lines (without their line
ends), so that a Python user gets the command's text."""

from __future__ import annotations

from typing import Any


def presets_lines(presets: list[dict[str, Any]]) -> list[str]:
    """The presets (`ball.describe_presets`): each name with its description and source."""
    lines = []
    for preset in presets:
        lines.append(f"{preset['name']}: {preset['description']}")
        if preset.get("source"):
            lines.append(f"    source: {preset['source']}")
    return lines


__all__ = ["presets_lines"]
