"""Helpers for the report command's tests."""

import ballimpact.report.build as build


def fail_model(monkeypatch, error, name=None):
    """Make the report's runs of the model `name` (every model if None) raise `error`; the other
    models run as usual."""
    original = build.run_model

    def run_model(spec, test, **options):
        if name is None or spec.name == name:
            raise error
        return original(spec, test, **options)

    monkeypatch.setattr(build, "run_model", run_model)
