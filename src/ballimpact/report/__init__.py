"""The comparison report (thesis chapter 7): lumped, universal and FE models against tests at
several speeds, as one self-contained HTML page with its figures, a JSON file and CSV tables.

`build_report(tests, models, out)`; the tests come from `inputs` (files or a built-in set), the
models from `models.parse_models`; `browser.check_page` opens a report in headless Chromium.
"""

from .build import build_report as build_report
from .inputs import BUILTIN_SETS as BUILTIN_SETS, ReportTest as ReportTest
from .inputs import builtin_files as builtin_files
from .models import ModelRun as ModelRun, ModelSpec as ModelSpec, parse_models as parse_models
from .models import run_model as run_model
