"""Error types shared by the package.

`InputError` is raised for anything a user can fix (a bad file, a value out of range); the command
line turns it into exit code 2 and one line on stderr. Anything else is a failed run (exit code 1).
"""


class InputError(ValueError):
    """Bad user input: the message names the field and what is allowed."""


class InputWarning(UserWarning):
    """A result was computed but a check on the input failed (e.g. the impulse-momentum check)."""


class SimulationError(RuntimeError):
    """A run that could not produce a result (no separation, non-finite state): exit code 1."""


class CheckFailed(Exception):
    """A run that finished but failed a check the user asked for (e.g. `identify --max-nrmse`):
    exit code 3. `result` is the verb's JSON object, still printed with `--json`."""

    exit_code = 3

    def __init__(self, message: str, result: dict | None = None) -> None:
        super().__init__(message)
        self.result = result if result is not None else {}
