"""Ctrl-C at any moment of a cold run ends with exit 130 and one line (README "Command line").

Runs `ballimpact simulate` and `ballimpact calibrate` (a small search) as separate processes,
each with an empty JAX compilation cache (a fresh $BALLIMPACT_CACHE_DIR, so the first
compilation is under way for seconds), sends SIGINT after a delay spread over 0.5..6 s, and
tallies the exit codes. A try passes when the exit code is 130, stderr's last line is
'error: interrupted...', and stderr holds no traceback, no 'Segmentation fault' or core dump.
A run that ends before its signal arrives counts as 'finished' (exit 0), not a failure.

    python benchmarks/ctrl_c_check.py                 # 20 tries, 10 per verb
    python benchmarks/ctrl_c_check.py --tries 4 --verbs simulate

Prints one JSON object; exit code 1 when any try fails.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

#: the commands, each with what it needs written in `folder` first
_VERBS = ("simulate", "calibrate")


def _record(folder: Path) -> Path:
    """A half-sine test of a 0.16 kg ball at 20 m/s (COR 0.6, 0.45 ms), with its side file."""
    t = np.arange(0.0, 2e-3, 1e-5)
    contact = 4.5e-4
    peak = 0.16 * 20.0 * 1.6 * np.pi / (2 * contact)
    inside = (t > 2e-4) & (t < 2e-4 + contact)
    force = np.where(inside, peak * np.sin(np.pi * (t - 2e-4) / contact), 0.0)
    csv = folder / "ball.csv"
    np.savetxt(csv, np.column_stack([t, force]), delimiter=",", header="time_s,force_n",
               comments="")
    (folder / "ball.json").write_text(json.dumps({"mass_kg": 0.16, "impact_speed_m_s": 20.0}))
    return csv


def command(verb: str, folder: Path) -> list[str]:
    script = Path(sys.executable).parent / "ballimpact"  # the console script, as users run it
    exe = [str(script)] if script.is_file() else [sys.executable, "-m", "ballimpact.cli"]
    if verb == "simulate":
        return [*exe, "simulate", "--ball", "cricket-3layer", "--speed-m-s", "20", "--json"]
    record = _record(folder)
    return [*exe, "calibrate", "--ball", "cricket-universal", "--test", str(record),
            "--free", "layers.ball.material.c10_pa=3e6:7e6", "--population", "4",
            "--generations", "3", "--seed", "2", "--element-size-m", "4e-3",
            "--out", str(folder / "cal"), "--json"]


def _default_sigint() -> None:
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def one_try(verb: str, delay_s: float, timeout_s: float = 120.0) -> dict:
    folder = Path(tempfile.mkdtemp(prefix="ctrl-c-"))
    try:
        env = {**os.environ, "BALLIMPACT_CACHE_DIR": str(folder / "cache"),
               "PYTHONFAULTHANDLER": ""}
        argv = command(verb, folder)
        start = time.perf_counter()
        # a shell's background job starts with SIGINT ignored, and so would the command:
        # give it the default disposition, as a terminal's foreground job has
        proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env,
                                cwd=folder, preexec_fn=_default_sigint)
        sent = False
        try:
            proc.wait(timeout=delay_s)
        except subprocess.TimeoutExpired:
            proc.send_signal(signal.SIGINT)
            sent = True
        try:
            out, err = proc.communicate(timeout=timeout_s)
        except subprocess.TimeoutExpired:
            proc.kill()
            out, err = proc.communicate()
        wall = time.perf_counter() - start
        err_text = err.decode(errors="replace")
        lines = [line for line in err_text.replace("\r", "\n").splitlines() if line.strip()]
        code = proc.returncode
        crashed = any(word in err_text for word in ("Segmentation fault", "core dumped",
                                                    "Fatal Python error", "Traceback"))
        if not sent:
            ok, outcome = code == 0, "finished"
        else:
            ok = (code == 130 and not crashed and bool(lines)
                  and lines[-1].startswith("error: interrupted"))
            outcome = "interrupted"
        return {"verb": verb, "delay_s": round(delay_s, 2), "exit_code": code,
                "outcome": outcome, "ok": ok, "wall_s": round(wall, 2),
                "last_line": lines[-1][:160] if lines else "",
                **({"stderr_tail": err_text[-600:]} if not ok else {})}
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tries", type=int, default=20, help="tries in all (default 20)")
    parser.add_argument("--verbs", default=",".join(_VERBS), help="simulate,calibrate")
    parser.add_argument("--min-delay-s", type=float, default=0.5)
    parser.add_argument("--max-delay-s", type=float, default=6.0)
    args = parser.parse_args()
    verbs = [v for v in args.verbs.split(",") if v]
    delays = np.linspace(args.min_delay_s, args.max_delay_s, max(1, args.tries // len(verbs)))
    tries = []
    for k in range(args.tries):
        verb = verbs[k % len(verbs)]
        delay = float(delays[(k // len(verbs)) % len(delays)])
        tries.append(one_try(verb, delay))
        print(json.dumps(tries[-1]), file=sys.stderr, flush=True)
    codes: dict[str, int] = {}
    for t in tries:
        codes[str(t["exit_code"])] = codes.get(str(t["exit_code"]), 0) + 1
    result = {"tries": len(tries), "interrupted": sum(t["outcome"] == "interrupted" for t in tries),
              "finished_before_the_signal": sum(t["outcome"] == "finished" for t in tries),
              "failed": sum(not t["ok"] for t in tries), "exit_codes": codes,
              "python": sys.version.split()[0], "runs": tries}
    print(json.dumps(result, indent=2))
    return 1 if result["failed"] else 0


if __name__ == "__main__":
    sys.exit(main())
