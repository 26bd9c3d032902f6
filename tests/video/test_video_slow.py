"""The issue's accuracy range for the video tracker: 5-40 m/s, 2,000-20,000 fps, default
synthetic recordings (a 48 px ball, motion blur, noise, textured background)."""

import pytest

from ballimpact.video import SyntheticImpact, measure, render, track


@pytest.mark.slow
@pytest.mark.parametrize("speed, fps", [(5.0, 2000.0), (5.0, 20000.0), (40.0, 2000.0),
                                        (40.0, 20000.0), (20.0, 5000.0)])
def test_speeds_within_1_percent_and_angles_within_half_a_degree(speed, fps):
    impact = SyntheticImpact(speed_m_s=speed, fps=fps, angle_deg=25.0, noise=5.0)
    detections = track(render(impact))
    truth = impact.truth()
    for scale in ({"scale_m_per_px": impact.scale_m_per_px},
                  {"ball_diameter_m": impact.ball_diameter_m}):
        s = measure(detections, fps, **scale).summary
        for key in ("impact_speed_m_s", "rebound_speed_m_s"):
            assert s[key] == pytest.approx(truth[key], rel=0.01), (key, scale)
        for key in ("impact_angle_deg", "rebound_angle_deg"):
            assert s[key] == pytest.approx(truth[key], abs=0.5), (key, scale)
