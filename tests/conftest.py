import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent))  # tests import shared closed forms from each other


@pytest.fixture
def bad_input(capsys):
    """`bad_input(argv, *fragments)`: run the command line in this process and check the contract
    for bad input (exit code 2, exactly one stderr line starting with 'error:', no traceback, no
    progress line before it, nothing on stdout); every fragment must appear in that line
    (case-insensitive). Returns the line."""
    from ballimpact.cli import main

    def check(argv, *fragments):
        capsys.readouterr()  # drop what earlier steps printed
        code = main([str(arg) for arg in argv])
        out, err = capsys.readouterr()
        lines = [line for line in err.replace("\r", "\n").splitlines() if line.strip()]
        assert code == 2, f"exit {code}, stderr: {err}"
        assert len(lines) == 1, f"expected one stderr line, got: {err!r}"
        assert lines[0].startswith("error: "), lines[0]
        assert "Traceback" not in err and out == "", (out, err)
        for fragment in fragments:
            assert fragment.lower() in lines[0].lower(), f"{fragment!r} not in {lines[0]!r}"
        return lines[0]

    return check
