"""`ballimpact demo` from Python (`fe.demo`): the demo's impacts in order, their notes, and the
built-in sample identified (issue 24: identify's warnings about the package's own data become
notes; issue 39: the sample's contact time with the default processing)."""

import pytest

import ballimpact.fe
from ballimpact.universal.demo import (
    DEMO_IMPACTS,
    DEMO_NOTES,
    SAMPLE_CONTACT_TIME_S,
    demo_impacts,
    demo_summaries,
    identify_sample,
)


def test_demo_impacts_run_each_preset_at_its_speed(monkeypatch):
    runs, announced = [], []
    monkeypatch.setattr(ballimpact.fe, "simulate", lambda ball, speed: runs.append(
        (ball, speed)) or len(runs))
    assert demo_impacts(lambda name, speed: announced.append((name, speed))) == [1, 2]
    assert announced == list(DEMO_IMPACTS) == [("cricket-universal", 25.0),
                                               ("cricket-3layer", 20.8)]
    assert [speed for _, speed in runs] == [25.0, 20.8]
    # the universal ball's constants are those of its impact speed
    assert runs[0][0].to_dict() == ballimpact.fe.load_ball("cricket-universal",
                                                           impact_speed_m_s=25.0).to_dict()
    assert len(runs[1][0].layers) == 3


def test_demo_summaries_carry_the_three_layer_note():
    class Run:
        def __init__(self, cor):
            self.cor = cor

        def summary(self):
            return {"cor": self.cor}

    impacts = demo_summaries([Run(0.5), Run(0.9)])
    assert impacts[0] == {"cor": 0.5}
    assert impacts[1] == {"cor": 0.9, "note": DEMO_NOTES["cricket-3layer"]}
    assert "0.5-0.6" in impacts[1]["note"] and "docs/fe.md" in impacts[1]["note"]


def test_the_sample_is_identified_with_notes_not_warnings(recwarn):
    sample = identify_sample()
    assert sample.contact_time_s == pytest.approx(SAMPLE_CONTACT_TIME_S, rel=0.02)
    assert 0.0 < sample.contact_time_uncertainty_s < 0.05 * SAMPLE_CONTACT_TIME_S
    assert sample.peak_force_n == pytest.approx(11219.9, rel=0.02)
    assert any("training range" in note for note in sample.notes)
    assert not [w for w in recwarn if "training range" in str(w.message)]
    out = sample.to_dict()
    assert out["file"] == "sample_impact.csv (built-in, synthetic)"
    assert out["sample_exact_contact_time_s"] == SAMPLE_CONTACT_TIME_S
    assert out["sample_contact_time_s"] == sample.contact_time_s and out["notes"] == sample.notes
    assert out["verification"]["passed"] is False  # a Hunt-Crossley pulse, not a universal ball
    assert set(out["params"]) >= {"c10_pa", "c01_pa", "g1", "tau1_s"}
