"""The one table from names to objects: models and their options.

Scene files and the string forms of `Scene(...)` (`model="xia2024", interaction="paper"`) name
choices; the library works with the objects. A new model is one new file in `models/` plus one
line in `MODELS` below (or `register_model(MyModel)` from user code).
"""

from __future__ import annotations

import dataclasses

from .models.base import AbstractContactModel
from .models.greenwood_williamson import GreenwoodWilliamson
from .models.jzz2010 import JZZ2010
from .models.persson import Persson
from .models.xia2024 import Xia2024
from .numerics.quadrature import Adaptive, GaussLegendre, PowerSeries
from .numerics.validate import InputError, check_choice
from .physics.distribution import MajumdarBhushan, WangKomvopoulos
from .physics.interaction import NoInteraction, PaperInteraction, SeriesInteraction
from .physics.spot_stiffness import FamilyDerivative, Sneddon

MODELS: dict[str, type[AbstractContactModel]] = {
    cls.name: cls
    for cls in (
        Xia2024,
        JZZ2010,
        GreenwoodWilliamson,
        Persson,
    )
}
INTERACTIONS = {cls.name: cls for cls in (NoInteraction, PaperInteraction, SeriesInteraction)}
DISTRIBUTIONS = {cls.name: cls for cls in (MajumdarBhushan, WangKomvopoulos)}
QUADRATURES = {cls.name: cls for cls in (PowerSeries, GaussLegendre, Adaptive)}
SPOT_STIFFNESSES = {cls.name: cls for cls in (FamilyDerivative, Sneddon)}


def register_model(cls: type[AbstractContactModel]) -> type[AbstractContactModel]:
    """Make a model known by its `name` to scene files and `Scene(model="...")`; returns `cls`."""
    if not (isinstance(cls, type) and issubclass(cls, AbstractContactModel)):
        raise InputError(f"register_model needs a subclass of AbstractContactModel, got {cls!r}")
    MODELS[cls.name] = cls
    return cls


def _option(name: str, value, table: dict):
    if isinstance(value, str):
        check_choice(name, value, tuple(table))
        return table[value]()
    return value


def build_model(
    model="xia2024",
    *,
    interaction=None,
    distribution=None,
    quadrature=None,
    quadrature_nodes=None,
    quadrature_tolerance=None,
    spot_stiffness=None,
) -> AbstractContactModel:
    """The model object that a name and its options ask for; a model object passes through.

    **Arguments:** `model`, a name of `MODELS` or an `AbstractContactModel`; the options, each a
    name or an object: `interaction` (`INTERACTIONS`), `distribution` (`DISTRIBUTIONS`),
    `quadrature` (`QUADRATURES`), with `quadrature_nodes` (Gauss–Legendre) and
    `quadrature_tolerance` (adaptive), `spot_stiffness` (`SPOT_STIFFNESSES`). Options that are
    None take the model's defaults.

    **Raises:** `ValueError` for an unknown name, or an option the model does not have.
    """
    given = {
        k: v
        for k, v in dict(
            interaction=interaction,
            distribution=distribution,
            quadrature=quadrature,
            quadrature_nodes=quadrature_nodes,
            quadrature_tolerance=quadrature_tolerance,
            spot_stiffness=spot_stiffness,
        ).items()
        if v is not None
    }
    if isinstance(model, AbstractContactModel):
        if given:
            raise InputError(f"{', '.join(given)} given beside the model object {model!r}: pass them to the model")
        return model
    check_choice("model", model, tuple(MODELS))
    cls = MODELS[model]
    fields = {f.name for f in dataclasses.fields(cls)}
    # Checked even where unused, so that a mistyped setting is never silently ignored.
    nodes = GaussLegendre(nodes=quadrature_nodes) if quadrature_nodes is not None else None
    adaptive = Adaptive(tolerance=quadrature_tolerance) if quadrature_tolerance is not None else None
    if "interaction" not in fields and interaction not in (None, "none"):
        raise InputError(
            f"interaction = {interaction!r} applies to models with interaction only; model "
            f"{model!r} has no interaction (use 'none' or leave it out)"
        )
    options = {}
    if "interaction" in fields and interaction is not None:
        options["interaction"] = _option("interaction", interaction, INTERACTIONS)
    if spot_stiffness is not None:
        options["spot_stiffness"] = _option("spot_stiffness", spot_stiffness, SPOT_STIFFNESSES)
    if distribution is not None:
        options["distribution"] = _option("distribution", distribution, DISTRIBUTIONS)
    if "quadrature" in fields:
        chosen = _option("quadrature", quadrature, QUADRATURES) if quadrature is not None else None
        if isinstance(chosen, GaussLegendre) and nodes is not None:
            chosen = nodes
        elif isinstance(chosen, Adaptive) and adaptive is not None:
            chosen = adaptive
        options["quadrature"] = chosen
    unknown = [k for k in options if k not in fields]
    if unknown:
        raise InputError(f"model {model!r} takes no {unknown[0]}")
    built = cls(**options)
    if (
        "quadrature" in fields
        and quadrature is None
        and nodes is not None
        and isinstance(built.quadrature, GaussLegendre)
    ):
        built = dataclasses.replace(built, quadrature=nodes)
    return built
