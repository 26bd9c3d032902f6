"""Protective equipment: head-injury criteria of a backing's acceleration, computed from a sampled
acceleration history (time in s, acceleration in m/s^2): the peak acceleration in g, the Head
Injury Criterion (HIC, with the 15 ms and 36 ms windows of HIC15 and HIC36) and the Gadd Severity
Index (`injury`). NumPy and SciPy only."""

from .injury import (HIC15_WINDOW_S, HIC36_WINDOW_S, HicResult, gadd_severity_index, hic, hic15,
                     hic36, peak_acceleration_g)

__all__ = ["HIC15_WINDOW_S", "HIC36_WINDOW_S", "HicResult", "gadd_severity_index", "hic", "hic15",
           "hic36", "peak_acceleration_g"]
