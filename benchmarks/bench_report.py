"""Cost of the comparison report on this machine, printed as JSON.

The demo report: the built-in SYNTHETIC multi-speed set (4 tests) against the single-element and
three-element lumped models, the universal FE model and the generating three-layer FE ball. Per
model: the identification per test and one compiled run (the report's cost table). The reference
measured in the same run is one single-element lumped run; the thesis' anchors (figure 7-5 and
section 7.2: 25 s a universal FE run, 87 s a detailed FE run, on a 2008 PC) are quoted as ratios.

    python benchmarks/bench_report.py
"""

from __future__ import annotations

import json
import os
import platform
import tempfile
import time
from pathlib import Path

from ballimpact.records.pipeline import process
from ballimpact.records.loaders import load_record
from ballimpact.report import build_report, builtin_files, parse_models
from ballimpact.report.inputs import builtin_ball, label_tests
from ballimpact.universal.model import load_model

THESIS_RUN_S = {"universal FE": 25.0, "FE synthetic-3layer": 87.0}


def main() -> None:
    files = builtin_files("speeds")
    tests = label_tests([str(f) for f in files], [process(load_record(f)) for f in files])
    models = parse_models(f"single_element,three_element,universal,{builtin_ball('speeds')}")
    started = time.perf_counter()
    with tempfile.TemporaryDirectory() as folder:
        report = build_report(tests, models, Path(folder) / "report", universal_model=load_model(),
                              progress=False)
    total = time.perf_counter() - started
    cost = {row[0]: {"identification_s_per_test": row[2], "run_s": row[3], "total_s": row[4]}
            for row in report["tables"]["cost"]["rows"]}
    reference = cost["single_element"]["run_s"]
    for model, figures in cost.items():
        figures["run_over_single_element_run"] = figures["run_s"] / reference
        if model in THESIS_RUN_S:
            figures["thesis_run_s"] = THESIS_RUN_S[model]
            figures["speedup_over_thesis"] = THESIS_RUN_S[model] / figures["run_s"]
    print(json.dumps({
        "machine": {"platform": platform.platform(), "cpus": os.cpu_count()},
        "tests": len(tests), "models": len(models), "report_wall_s": total,
        "cost": cost}, indent=2))


if __name__ == "__main__":
    main()
