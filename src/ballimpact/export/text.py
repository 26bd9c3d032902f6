"""The text of an export, as `ballimpact export` prints it: the lines (without their line ends),
so that a Python user gets the command's text."""

from __future__ import annotations

from typing import Any


def export_lines(out: dict[str, Any]) -> list[str]:
    """`export_ball_spec`'s result: the file written, what it holds, its mesh and units."""
    what = "ball" if out["ball_only"] else "impact deck"
    return [f"wrote {out['out']}: {out['format']} {what} of {out['ball']} ({out['solver']}, "
            f"{out['nodes']} nodes, {out['elements']} elements, units {out['units']})"]


def note_lines(out: dict[str, Any]) -> list[str]:
    """The export's notes (every approximation the file's header states), a line each."""
    return [f"note: {note}" for note in out["notes"]]


__all__ = ["export_lines", "note_lines"]
