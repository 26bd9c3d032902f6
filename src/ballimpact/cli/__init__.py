"""The `ballimpact` command (README "Command line").

Exit codes: 0 success, 2 bad input (one line on stderr naming the problem), 1 failed run,
3 a check the user asked for failed (`CheckFailed`: the result is still printed), 130 interrupted
(Ctrl-C: one line; a verb that can resume puts how in `args.resume_hint`). Run as the program
(`main()` without arguments: the console script, `python -m ballimpact.cli`), an interrupt ends
the process with `os._exit(130)` once the line is out: the interpreter's shutdown would race with
XLA's compiler threads and end in a segmentation fault about half the time. Outside the verb's
run (imports, printing the result) SIGINT exits at once with the same line; during it, it
raises `KeyboardInterrupt` so that the verb's clean-up and checkpoints run first (one raised
where exceptions are only printed, as in JAX's garbage-collection callback, ends it there).
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
import signal
import sys
import warnings


def _interrupted(hint: str | None = None) -> str:
    """The line of an interrupt, on a line of its own (a progress bar may have left one open)."""
    from ..progress import line_open

    return "\n" * line_open() + "error: interrupted" + (f"; {hint}" if hint else "")


def _exit_interrupted(hint: str | None = None) -> None:
    """Ctrl-C in the program: one line on stderr, then the process ends with exit code 130
    without the interpreter's shutdown (XLA's threads may still be compiling)."""
    line = _interrupted(hint)
    try:
        signal.signal(signal.SIGINT, signal.SIG_IGN)  # a second Ctrl-C: the same end
    except ValueError:  # not the main thread
        pass
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except Exception:  # noqa: BLE001 - a closed pipe: nothing more can reach it
            pass
    try:
        sys.stderr.write(line + "\n")
        sys.stderr.flush()
    except Exception:  # noqa: BLE001
        pass
    os._exit(130)


def _exit_running() -> None:
    """`_exit_interrupted` with the running verb's resume hint, if any."""
    _exit_interrupted(getattr(_running[-1], "resume_hint", None) if _running else None)


def _interrupt_at_once(signum, frame) -> None:
    """The SIGINT handler of the program outside a verb's run: nothing to clean up."""
    _exit_interrupted()


#: Seconds a verb's clean-up has after Ctrl-C before the program ends regardless: an interrupt
#: that lands where an exception is swallowed (a library's broad `except`) must still end it.
CLEAN_UP_DEADLINE_S = 3.0


def _interrupt_with_deadline(signum, frame) -> None:
    """The SIGINT handler during a verb's run: KeyboardInterrupt for its clean-up, and a timer
    that ends the program with exit 130 if it is still running `CLEAN_UP_DEADLINE_S` later."""
    import threading

    timer = threading.Timer(CLEAN_UP_DEADLINE_S, _exit_running)
    timer.daemon = True
    timer.start()
    raise KeyboardInterrupt


def _set_sigint(handler) -> None:
    """Install `handler` for SIGINT unless SIGINT is ignored (a shell's background job, nohup)."""
    try:
        if signal.getsignal(signal.SIGINT) is not signal.SIG_IGN:
            signal.signal(signal.SIGINT, handler)
    except ValueError:  # not the main thread: Python's default stays
        pass


#: the running command's arguments (for the resume hint of an interrupt that ends it at once)
_running: list = []


def _unraisable(hook):
    """A `sys.unraisablehook` that does not let Ctrl-C be lost: a KeyboardInterrupt raised where
    exceptions are only printed (JAX's garbage-collection callback, a `__del__`) would let the
    run go on; it ends the program there instead (exit 130, the line and the verb's hint)."""
    def unraisable(info):
        if isinstance(info.exc_value, KeyboardInterrupt) or info.exc_type is KeyboardInterrupt:
            _exit_running()
        hook(info)
    return unraisable


def _is_program() -> bool:
    """Whether this process is the `ballimpact` console script (known before `main` runs)."""
    return bool(sys.argv) and os.path.basename(sys.argv[0]) in ("ballimpact", "ballimpact.exe")


if _is_program():  # as early as this package allows: the imports below take a while
    _set_sigint(_interrupt_at_once)

from .. import __version__  # noqa: E402
from ..errors import CheckFailed, InputError, SimulationError  # noqa: E402
from ..fileio import json_safe  # noqa: E402
from ..progress import announce_waits  # noqa: E402
from .common import Parser  # noqa: E402
from .simulate import SolverDefaults  # noqa: E402

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
         "compare": ("compare", "run"), "data": ("data", "run"), "bat": ("bat", "run")}


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
    """The command line: `argv` (default `sys.argv[1:]`) -> the exit code. Without `argv` this
    process is the program: Ctrl-C ends it with `os._exit(130)` (module docstring)."""
    program = argv is None
    if program:
        announce_waits()  # a compilation's silent seconds get a line (`progress.Waiting`)
        _set_sigint(_interrupt_at_once)
        sys.unraisablehook = _unraisable(sys.unraisablehook)
    try:
        code = _main(argv, program)
        sys.stdout.flush()  # a closed pipe shows here rather than at the interpreter's exit
    except KeyboardInterrupt:  # outside the verb's run (a handler of one's own, or none)
        if program:
            _exit_interrupted()
        raise
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


def _main(argv: list[str] | None, program: bool = False) -> int:
    args = None
    failed_check = None
    try:
        if program:  # the verb's run: KeyboardInterrupt, so that its clean-up runs
            _set_sigint(_interrupt_with_deadline)
        argv = sys.argv[1:] if argv is None else argv
        args = build_parser(argv[0] if argv else None).parse_args(argv)
        if program:
            _running.append(args)
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
        if program:  # the verb's clean-up has run: end here, before the interpreter's shutdown
            _exit_interrupted(hint)
        print(_interrupted(hint), file=sys.stderr)
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
    finally:
        if program:  # from here on nothing to clean up: SIGINT exits at once
            _set_sigint(_interrupt_at_once)
    for note in notes:
        print(f"warning: {note}", file=sys.stderr)
    result["warnings"] = notes
    if args.json:
        print(json.dumps(json_safe(result), indent=2))
    if failed_check is not None:
        print(f"error: check failed: {failed_check}", file=sys.stderr)
        return failed_check.exit_code
    return 0

