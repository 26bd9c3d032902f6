"""The text of the records' results, as `ballimpact features` and `ballimpact data list` print
it: each function returns the lines (without their line ends), so that a Python user gets the
command's text."""

from __future__ import annotations

import math
from typing import Any

from .features import FEATURE_NAMES
from .pipeline import ProcessedImpact
from .repeats import MAIN_COLUMNS


def features_lines(result: dict[str, Any], processed: list[ProcessedImpact]) -> list[str]:
    """The text of `summaries.features_of_files`' result: the speed groups of several records
    (`groups_lines`), or the features of one (`impact_lines`)."""
    return groups_lines(result) if len(processed) > 1 else impact_lines(processed[0])


def groups_lines(result: dict[str, Any]) -> list[str]:
    """Records grouped by speed (`repeats.summarise_repeats`): per group the mean +- SD of the
    main features, in aligned columns; the table written, if any."""
    grouping = result["grouping"]
    rule = ("to the nominal speeds" if grouping["rule"] == "nominal"
            else "clustered: a group spans at most the tolerance above its lowest speed")
    lines = [f"{len(result['records'])} records in {len(result['groups'])} speed groups ({rule}; "
             f"tolerance {grouping['speed_tolerance']:.0%}); mean ± SD (ddof 1)"]
    rows = [["speed (m/s)", "n", "impact speed (m/s)", "COR", "peak force (N)",
             "contact time (ms)", "dyn. stiffness (N/m)"]]
    for group in result["groups"]:
        cells = [f"{group['speed_m_s']:.4g}", str(group["count"])]
        for name in MAIN_COLUMNS:
            scale = 1e3 if name == "contact_time_s" else 1.0
            mean, sd = group["mean"][name] * scale, group["sd"][name] * scale
            cells.append(f"{mean:.5g} ± {sd:.2g}" if math.isfinite(sd) else f"{mean:.5g}")
        rows.append(cells)
    widths = [max(map(len, column)) for column in zip(*rows)]
    lines += ["  " + "  ".join(cell.ljust(width) for cell, width in zip(row, widths)).rstrip()
              for row in rows]
    if "table_csv" in result:
        lines.append(f"table (a row per record): {result['table_csv']}")
    return lines


def impact_lines(processed: ProcessedImpact) -> list[str]:
    """One processed record: the processing, the 19 features with their uncertainties, the
    impulse check and the derived values."""
    f = processed.features
    u = f.uncertainty or {}
    lines = [f"filter: {processed.filtered.metadata.get('filter', 'none')}   pulse: {f.method}   "
             f"baseline offset removed: "
             f"{processed.raw.metadata.get('baseline_offset_n', 0.0):.4g} N"]
    resonance = processed.filtered.metadata.get("load_cell_resonance")
    if resonance:
        lines.append(f"  load-cell resonance {resonance['frequency_hz']:.0f} Hz (damping ratio "
                     f"{resonance['damping_ratio']:.3f}) divided out")
    if u:
        lines.append("  (+/- the standard uncertainty from the record's noise; 90% interval: "
                     "+/- 1.645 of it)")
    for key, name in FEATURE_NAMES.items():
        spread = f"  +/- {u[key]:.2g}" if u.get(key) else ""
        lines.append(f"  {key:>4}  {name:<42} {f.values[key]:.6g}{spread}")
    check = f.impulse_check_passed
    status = "not checked (rebound speed from impulse)" if check is None else (
        f"{f.impulse_relative_error:+.2%} ({'ok' if check else 'FAILED'}, "
        f"tolerance {f.impulse_tolerance:.1%})")
    spread = f" +/- {u['impulse_n_s']:.2g}" if u.get("impulse_n_s") else ""
    return lines + [
        f"  rebound speed source: {f.rebound_speed_source}",
        f"  impulse {f.impulse_n_s:.5g}{spread} N s; impulse check: {status}",
        f"  impulse COR {f.impulse_cor:.4f}; max compression {f.max_compression_m * 1e3:.4g} "
        f"mm; energy lost {f.energy_lost_j:.4g} J; dynamic stiffness "
        f"{f.dynamic_stiffness_n_m:.4g} N/m"]


def datasets_lines(sets: list[dict[str, Any]]) -> list[str]:
    """The built-in data sets (`datasets.DataSet.to_dict` each): name, kind, description,
    source, files and an example."""
    lines = []
    for d in sets:
        lines += [f"{d['argument']} ({d['kind']}): {d['description']}",
                  f"    source: {d['source']}",
                  f"    files:  {', '.join(d['files'])}",
                  f"    e.g.    {d['usage']}"]
    return lines


__all__ = ["datasets_lines", "features_lines", "groups_lines", "impact_lines"]
