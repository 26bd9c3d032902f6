"""The CalculiX cross-run shared by the export tests, the example and the benchmark: the
issue's elastic Mooney-Rivlin ball (C10 4.72 MPa, C01 -0.45 MPa, D1 = 0, 0.160 kg, 72 mm)."""

import math

ELASTIC_MR_BALL = {
    "name": "elastic-mooney-rivlin",
    "layers": [{"name": "ball", "outer_radius_m": 0.036,
                "density_kg_m3": 0.160 / (4.0 / 3.0 * math.pi * 0.036 ** 3),
                "material": {"model": "mooney_rivlin", "c10_pa": 4.72e6, "c01_pa": -0.45e6,
                             "d1_per_pa": 0.0}}],
}
