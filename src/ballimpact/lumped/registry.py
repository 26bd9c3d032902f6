"""The lumped models by name."""

from __future__ import annotations

from ..errors import InputError
from . import hertz, hunt_crossley, kelvin_voigt, lieberman_johnson, simon, single_element
from . import three_element
from .base import LumpedModel
from .thesis import SINGLE_ELEMENT_THESIS, THREE_ELEMENT_THESIS

MODELS: dict[str, LumpedModel] = {
    model.name: model
    for model in (
        single_element.MODEL,
        three_element.MODEL,
        hunt_crossley.MODEL,
        kelvin_voigt.MODEL,
        hertz.MODEL,
        lieberman_johnson.MODEL,
        simon.MODEL,
        SINGLE_ELEMENT_THESIS,
        THREE_ELEMENT_THESIS,
    )
}


def get_model(model: str | LumpedModel) -> LumpedModel:
    """A model from its registry name (or the model itself)."""
    if isinstance(model, LumpedModel):
        return model
    try:
        return MODELS[model]
    except KeyError:
        raise InputError(f"model: unknown {model!r}; one of {', '.join(MODELS)}") from None


def describe_models() -> list[dict]:
    """Name, summary, parameters with units, and whether each model is a reproduction."""
    return [
        {"name": m.name, "summary": m.summary, "reproduction": m.reproduction,
         "params": {p.name: {"unit": p.unit, "description": p.description,
                             **({"default": p.default} if p.fixed else {})}
                    for p in m.parameters}}
        for m in MODELS.values()
    ]
