"""The `ballimpact` command (README "Command line").

Exit codes: 0 success, 2 bad input (one line on stderr naming the problem), 1 failed run,
3 a check the user asked for failed (`CheckFailed`: the result is still printed), 130 interrupted
(Ctrl-C: one line; a verb that can resume puts how in `args.resume_hint`).
With `--json` one JSON object goes to stdout; warnings and progress go to stderr. A reader that
closes stdout early (`| head -1`) ends the command quietly with exit code 1 (Python's "Note on
SIGPIPE").
One module per verb (or verb group) adds its parser and runs it; this module owns the
conventions: the error-to-exit-code mapping, the warnings list and the JSON output.
"""

from __future__ import annotations

import argparse
import importlib
import json
import os
import sys
import warnings

from .. import __version__
from ..errors import CheckFailed, InputError, SimulationError
from ..fileio import json_safe
from ..progress import line_open
from .common import Parser
from .simulate import SolverDefaults

__all__ = ["SolverDefaults", "build_parser", "main"]

#: verb -> (module of this package that adds its parser, its runner); each runner returns the
#: JSON object of the verb. Modules are imported only when a command needs them: a command names
#: one verb, and importing every verb's libraries took a second of a one-second `simulate`.
VERBS = {"features": ("features", "run"), "fit": ("fit", "run_fit"),
         "models": ("fit", "run_models"), "simulate": ("simulate", "run_simulate"),
         "balls": ("balls", "run_balls"), "demo": ("demo", "run_demo"),
         "universal": ("universal", "run"), "identify": ("identify", "run"),
         "calibrate": ("calibrate", "run"), "export": ("export", "run_export"),
         "import-material": ("export", "run_import"), "video": ("video", "run"),
         "report": ("report", "run"), "material": ("material", "run"),
         "compress": ("compress", "run"), "standard": ("standard", "run"),
         "compare": ("compare", "run")}


def _module(name: str):
    return importlib.import_module(f"{__name__}.{name}")


def build_parser(verb: str | None = None) -> argparse.ArgumentParser:
    """The parser of every verb; with `verb` (a known one), of only its module's verbs."""
    parser = Parser(prog="ballimpact", description="Sports-ball impact modelling (SI units).")
    parser.add_argument("--version", action="version", version=f"ballimpact {__version__}")
    verbs = parser.add_subparsers(dest="verb", required=True, metavar="VERB")
    modules = [VERBS[verb][0]] if verb in VERBS else dict.fromkeys(m for m, _ in VERBS.values())
    for name in modules:
        _module(name).add_parser(verbs)
    return parser


def main(argv: list[str] | None = None) -> int:
    try:
        code = _main(argv)
        sys.stdout.flush()  # a closed pipe shows here rather than at the interpreter's exit
    except BrokenPipeError:
        # Python docs, "Note on SIGPIPE": the reader has gone; point stdout at devnull so that
        # the interpreter's final flush does not fail again, and exit quietly
        try:
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, sys.stdout.fileno())
        except (AttributeError, OSError, ValueError):  # stdout replaced by an object without a file
            pass
        return 1
    return code


def _main(argv: list[str] | None) -> int:
    args = None
    failed_check = None
    try:
        argv = sys.argv[1:] if argv is None else argv
        args = build_parser(argv[0] if argv else None).parse_args(argv)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                module, runner = VERBS[args.verb]
                result = getattr(_module(module), runner)(args)
            except CheckFailed as error:
                result, failed_check = error.result, error
        notes = list(dict.fromkeys(str(w.message) for w in caught))
    except KeyboardInterrupt:
        hint = getattr(args, "resume_hint", None)
        # a progress bar may have left its line unfinished: the message starts a line of its own
        print("\n" * line_open() + "error: interrupted"
              + (f"; {hint}" if hint else ""), file=sys.stderr)
        return 130
    except InputError as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    except BrokenPipeError:
        raise
    except SimulationError as error:
        print(f"error: failed run: {error}", file=sys.stderr)
        return 1
    except Exception as error:  # noqa: BLE001 - a failed run, reported in one line
        print(f"error: failed run: {type(error).__name__}: {error}", file=sys.stderr)
        return 1
    for note in notes:
        print(f"warning: {note}", file=sys.stderr)
    result["warnings"] = notes
    if args.json:
        print(json.dumps(json_safe(result), indent=2))
    if failed_check is not None:
        print(f"error: check failed: {failed_check}", file=sys.stderr)
        return failed_check.exit_code
    return 0

