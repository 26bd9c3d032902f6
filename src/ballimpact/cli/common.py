"""Conventions shared by every verb: the parser that fails in one line, the record and processing
options, plot-path checks, the JSON clean-up and JAX's compilation cache."""

from __future__ import annotations

import argparse
import difflib
import math
import os
import sys
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any, TextIO

from ..errors import InputError
from ..records.features import DEFAULT_IMPULSE_TOLERANCE, METHODS
from ..records.filters import FILTER_NAMES
from ..records.options import LOADING_FIELDS, RecordOptions
from ..records.pipeline import DEFAULT_DAMPING_RATIO
from ..checks import CHECKS
from ..records.repeats import DEFAULT_SPEED_TOLERANCE


#: Flags that mean the same in every verb: each is accepted wherever the other is (one name
#: everywhere for the user; the verbs keep the name they were written with as `dest`).
FLAG_ALIASES = (("--impact-speed-m-s", "--speed-m-s"),)


def finite_float(text: str) -> float:
    """argparse type of every `type=float` flag: a finite number (NaN and inf are refused)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"{text!r} is not a finite number")
    return value


class Parser(argparse.ArgumentParser):
    """The command's parser (subparsers are of the same class): errors are one line and exit 2
    (no usage dump), `type=float` flags refuse NaN and inf, an unknown flag names the nearest
    known one, and the flags of `FLAG_ALIASES` are aliases of each other."""

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.register("type", float, finite_float)  # argparse looks `type=float` up here

    def error(self, message: str) -> None:  # one line, exit 2, no usage dump
        raise InputError(f"{self.prog}: {message}{self._nearest_flag()}")

    def parse_known_args(self, args=None, namespace=None):
        if self._subparsers is not None and not getattr(self, "_aliases_added", False):
            for parser in _parsers(self):  # once, when the whole tree has been built
                _add_aliases(parser)
            self._aliases_added = True
        self._given = list(sys.argv[1:] if args is None else args)  # for `_nearest_flag`
        parsed, extras = super().parse_known_args(args, namespace)
        if extras:  # refused by the parser that knows the verb's flags, to name the nearest
            self.error(f"unrecognized arguments: {' '.join(extras)}")
        return parsed, extras

    def _nearest_flag(self) -> str:
        """' (did you mean --x?)' for the first flag given that this parser does not know (a
        typo also shows as a missing required flag), else ''."""
        known = [s for s in self._option_string_actions if s.startswith("--")]
        for token in getattr(self, "_given", []):
            name = token.split("=", 1)[0]
            if not name.startswith("--") or any(k.startswith(name) for k in known):
                continue
            nearest = difflib.get_close_matches(name, known, n=1, cutoff=0.6)
            if nearest:
                return f" ({name}: did you mean {nearest[0]}?)"
        return ""


def _parsers(parser: argparse.ArgumentParser):
    """`parser` and every parser below it."""
    yield parser
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub in dict.fromkeys(action.choices.values()):
                yield from _parsers(sub)


def _add_aliases(parser: argparse.ArgumentParser) -> None:
    for names in FLAG_ALIASES:
        action = next((parser._option_string_actions[n] for n in names
                       if n in parser._option_string_actions), None)
        if action is None:
            continue
        for name in names:
            if name not in parser._option_string_actions:
                action.option_strings.append(name)
                parser._option_string_actions[name] = action


def add_record_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--mass-kg", type=float, help="ball mass (kg)")
    parser.add_argument("--impact-speed-m-s", type=float, help="impact speed (m/s)")
    parser.add_argument("--rebound-speed-m-s", type=float,
                        help="measured rebound speed (m/s); from the impulse if not given")
    parser.add_argument("--sensitivity-v-per-n", type=float,
                        help="WAV, or a CSV force column in volts: load-cell sensitivity (V/N)")
    parser.add_argument("--amplifier-gain", type=float,
                        help="WAV, or a CSV in volts: amplifier gain (default 1)")
    parser.add_argument("--full-scale-v", type=float,
                        help="WAV: volts at digital full scale (default 1)")
    parser.add_argument("--channel", type=int, help="WAV: channel index (default 0)")
    parser.add_argument("--time-column", metavar="NAME|N",
                        help="CSV: the time column, by header name or 0-based position (as "
                             "--channel), where several could be")
    parser.add_argument("--force-column", metavar="NAME|N",
                        help="CSV: the force column (N, kN, lbf, kgf, or volts with "
                             "--sensitivity-v-per-n), by header name or 0-based position; the "
                             "other channels are left out with a warning")


def add_processing(parser: argparse.ArgumentParser) -> None:
    """The flags of the verbs that load and process records: `add_record_options`,
    `add_filtering`, `--json` and `--plot`."""
    add_record_options(parser)
    add_filtering(parser)
    add_json(parser)
    parser.add_argument("--plot", type=Path, help="write force-time and force-displacement PNG")


def add_filtering(parser: argparse.ArgumentParser) -> None:
    """The processing flags of `record_options`: filter, its window, resampling, the pulse's
    method, the load cell, impulse tolerance, pulse, `--allow`."""
    parser.add_argument("--filter", default="none",
                        help=f"one of {', '.join(FILTER_NAMES)}, or cfc<N> (default none)")
    parser.add_argument("--filter-window-s", type=float,
                        help="window of savgol/lowess/loess (s); default 10%% of contact time")
    parser.add_argument("--resample-hz", type=float, help="resample to this uniform rate first")
    parser.add_argument("--pulse-method", choices=METHODS, default="fit",
                        help="fit: the contact's start and end fitted with the shape a contact "
                             "must have, smoothed between them, with uncertainties (default); "
                             "samples: piecewise linear through the samples, ends from the "
                             "noise threshold (the pulse as described before issue 39; a "
                             "ringing load cell is divided out all the same)")
    parser.add_argument("--load-cell-hz", type=float, metavar="HZ",
                        help="the load cell's mounted resonance (Hz): divided out of the record "
                             "(default: found from the record's own ringing, in and after "
                             "the contact)")
    parser.add_argument("--load-cell-damping", type=float, default=DEFAULT_DAMPING_RATIO,
                        metavar="ZETA", help=f"its damping ratio (default {DEFAULT_DAMPING_RATIO})")
    parser.add_argument("--impulse-tolerance", type=float, default=DEFAULT_IMPULSE_TOLERANCE,
                        help="relative misfit allowed between impulse and m(v_in + v_out) "
                             f"(default {DEFAULT_IMPULSE_TOLERANCE})")
    parser.add_argument("--pulse", type=int, metavar="N",
                        help="a record with several pulses (a bounce, a double hit): take pulse "
                             "N, 1 for the first")
    add_allow(parser)


def parsed(parse: Callable[[str], Any], text: str) -> Any:
    """`parse(text)` of a library parser, in an argparse type: its `InputError` becomes
    argparse's error (one line naming the flag, exit 2)."""
    try:
        return parse(text)
    except InputError as error:
        raise argparse.ArgumentTypeError(str(error)) from None


def speed_list(text: str) -> list[float]:
    """argparse type of --speeds: speeds in m/s separated by commas (`sweep.parse_speeds`; that
    they are positive is `repeats.check_nominal`'s)."""
    from ..fe.sweep import parse_speeds

    return list(parsed(parse_speeds, text))


def add_speed_grouping(parser: argparse.ArgumentParser) -> None:
    """`--speeds` and `--speed-tolerance`: how several records group into repeats by speed."""
    parser.add_argument("--speeds", type=speed_list, metavar="V1,V2,...",
                        help="nominal impact speeds (m/s) to group the records to, e.g. 5,10,20; "
                             "default: cluster the measured speeds (docs/features.md, repeated "
                             "tests)")
    parser.add_argument("--speed-tolerance", type=float, metavar="TOL",
                        default=DEFAULT_SPEED_TOLERANCE,
                        help="relative speed tolerance of the grouping: a record within this "
                             "fraction of a nominal speed; without --speeds, a speed more than "
                             "this fraction above its group's lowest starts a new group "
                             f"(default {DEFAULT_SPEED_TOLERANCE})")


def add_json(parser: argparse.ArgumentParser) -> None:
    """`--json`: the result as one JSON object on stdout (every verb has it)."""
    parser.add_argument("--json", action="store_true", help="print one JSON object")


def add_allow(parser: argparse.ArgumentParser) -> None:
    """`--allow NAME`: a plausibility check whose failure becomes a warning (docs/features.md)."""
    parser.add_argument("--allow", action="append", default=[], metavar="CHECK",
                        help="go on when this plausibility check fails, with a warning "
                             f"(repeatable): {', '.join(CHECKS)}; see docs/features.md")


def record_options(args: argparse.Namespace) -> RecordOptions:
    """The record flags (`add_record_options`, `add_filtering`) as one `RecordOptions`; a
    loading flag the verb does not have (`standard` has few) is None, the loader's default."""
    loading = {name: getattr(args, name, None) for name in LOADING_FIELDS}
    return RecordOptions(
        **loading, filter=args.filter, window_s=args.filter_window_s,
        resample_hz=args.resample_hz, impulse_tolerance=args.impulse_tolerance, pulse=args.pulse,
        allow=tuple(args.allow), resonance_hz=args.load_cell_hz, method=args.pulse_method,
        uncertainty=args.pulse_method == "fit", damping_ratio=args.load_cell_damping)


def print_lines(lines: Iterable[str], file: TextIO | None = None) -> None:
    """Print the lines of a result's text (the library's `*_lines` functions) to stdout, or to
    `file`."""
    for line in lines:
        print(line, file=file)


def assignments(items: list[str], flag: str, *, bounds: bool) -> dict[str, Any]:
    """Parse NAME=VALUE (or NAME=LOW:HIGH) flags into a dict of floats (or float pairs)."""
    parsed: dict[str, Any] = {}
    given: dict[str, str] = {}
    for item in items:
        name, sep, value = item.partition("=")
        if name in given:
            raise InputError(f"{flag}: {name} given twice ({given[name]} and {item})")
        given[name] = item
        try:
            if not sep or not name:
                raise ValueError
            parsed[name] = (tuple(float(x) for x in value.split(":", 1)) if bounds
                            else float(value))
            if bounds and len(parsed[name]) != 2:
                raise ValueError
        except ValueError:
            form = "NAME=LOW:HIGH" if bounds else "NAME=VALUE"
            raise InputError(f"{flag}: expected {form} with numbers in SI, got {item!r}") from None
    return parsed


def use_compilation_cache() -> None:
    """Keep JAX's compiled programs between runs of the command (about 2 s saved per run after
    the first), and the FE kernels' traced programs beside them in programs/ (`fe.programs`,
    0.8 s more): in $BALLIMPACT_CACHE_DIR, else ~/.cache/ballimpact/jax. Set for this process by
    the command only; the library leaves JAX's configuration alone."""
    import jax

    from ..fe import programs

    folder = os.environ.get("BALLIMPACT_CACHE_DIR") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.expanduser("~/.cache"), "ballimpact", "jax")
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError:
        return  # no writable cache: compile every time
    jax.config.update("jax_compilation_cache_dir", folder)
    jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.0)
    programs.use_folder(os.path.join(folder, "programs"))
