"""Material files: the JSON objects `material fit --out` writes (a ball layer's `material`), the
JSON `material fit --json` prints (the material under "material", a Prony fit's terms under
"prony"), read and written with errors that name the file."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from ..errors import InputError
from ..fileio import write_atomic


def read_json(path: Path, flag: str = "") -> Any:
    """The JSON in `path`; `InputError` starting with `flag` and the path when it cannot be
    read or is not JSON."""
    try:
        return json.loads(Path(path).read_text())
    except (OSError, UnicodeDecodeError) as error:
        raise InputError(f"{flag}{path}: cannot read ({error})") from None
    except json.JSONDecodeError as error:
        raise InputError(f"{flag}{path}: not JSON ({error.msg}, line {error.lineno})") from None


def read_material(path: Path) -> dict:
    """The material object in `path`: a material file, or the JSON `material fit --json`
    prints (its "material")."""
    data = read_json(path)
    if isinstance(data, dict) and isinstance(data.get("material"), dict):
        data = data["material"]  # the JSON `material fit --json` prints
    if not isinstance(data, dict):
        raise InputError(f"{path}: expected a material object ({{\"model\": ...}})")
    return data


def write_material(path: Path, material: dict) -> None:
    """`material` as indented JSON in `path`, written atomically (`fileio.write_atomic`)."""
    write_atomic(Path(path), json.dumps(material, indent=2) + "\n")


def read_prony_terms(path: Path) -> list[dict]:
    """The Prony terms ({"g", "k", "tau_s"}) in `path`: the JSON `material fit --model prony
    --json` prints, or a material with a "prony" list (errors name the flag --prony)."""
    path = Path(path)
    data = read_json(path, "--prony ")
    if isinstance(data, dict) and not isinstance(data.get("prony"), list) and isinstance(
            data.get("material"), dict):
        data = data["material"]
    terms = data.get("prony") if isinstance(data, dict) else None
    if not isinstance(terms, list) or not terms:
        raise InputError(f"--prony {path}: no 'prony' list (give the JSON `material fit --model "
                         "prony --json` prints, or a material with Prony terms)")
    return terms


__all__ = ["read_json", "read_material", "read_prony_terms", "write_material"]
