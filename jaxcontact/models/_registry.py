"""The one table from names to objects: models and their options.

Scene files and the string forms of `Scene(...)` (`model="xia2024", interaction="paper"`) name
choices; the library works with the objects. A new model is one new file in `models/` plus one
line in `MODELS` below (or `register_model(MyModel)` from user code).
"""

from __future__ import annotations

import dataclasses

from ..numerics import Adaptive, GaussLegendre, InputError, NewtonBisection, PowerSeries, check_choice
from ..physics import (
    FamilyDerivative,
    MajumdarBhushan,
    NoInteraction,
    PaperInteraction,
    SeriesInteraction,
    Sneddon,
    WangKomvopoulos,
)
from ._base import AbstractContactModel
from ._greenwood_williamson import GreenwoodWilliamson
from ._jzz2010 import JZZ2010
from ._persson import Persson
from ._xia2024 import Xia2024

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


def _option(name: str, value, table: dict, **settings):
    if isinstance(value, str):
        check_choice(name, value, tuple(table))
        return table[value](**settings)
    return value


def _quadrature(quadrature, nodes, tolerance):
    """The quadrature that the names ask for, or None for the interaction's default. A node count
    or a tolerance alone picks its rule; each is checked even where the rule does not use it, so
    that a mistyped setting is never silently ignored."""
    gauss = GaussLegendre(nodes=nodes) if nodes is not None else None
    adaptive = Adaptive(tolerance=tolerance) if tolerance is not None else None
    settings = {"gauss-legendre": gauss, "adaptive": adaptive}
    if isinstance(quadrature, str):
        check_choice("quadrature", quadrature, tuple(QUADRATURES))
        return settings.get(quadrature) or QUADRATURES[quadrature]()
    return quadrature if quadrature is not None else gauss or adaptive


def _interaction(interaction, rule, cls):
    """The interaction the names ask for, with the quadrature `rule` (None: its default)."""
    if not isinstance(interaction, (str, type(None))):
        if rule is not None:
            raise InputError("quadrature given beside the interaction object: pass it to the interaction")
        return interaction
    name = interaction if interaction is not None else cls().interaction.name
    check_choice("interaction", name, tuple(INTERACTIONS))
    if rule is None:
        return INTERACTIONS[name]()
    if "quadrature" not in {f.name for f in dataclasses.fields(INTERACTIONS[name])}:
        raise InputError(
            f"quadrature = {rule.name!r} applies to the interactions 'paper' and 'series'; interaction "
            f"{name!r} has no integral to do"
        )
    return INTERACTIONS[name](quadrature=rule)


def build_model(
    model="xia2024",
    *,
    interaction=None,
    distribution=None,
    quadrature=None,
    quadrature_nodes=None,
    quadrature_tolerance=None,
    spot_stiffness=None,
    max_steps=None,
    solver_tolerance=None,
) -> AbstractContactModel:
    """The model object that a name and its options ask for.

    **Arguments:** `model`, a name of `MODELS`; the options, each a name or an object: `interaction`
    (`INTERACTIONS`), `distribution` (`DISTRIBUTIONS`), `spot_stiffness` (`SPOT_STIFFNESSES`), and the
    interaction's `quadrature` (`QUADRATURES`), with `quadrature_nodes` (Gauss–Legendre) and
    `quadrature_tolerance` (adaptive); `max_steps` and `solver_tolerance`, the model's root finder
    (`NewtonBisection`). Options that are None take the model's defaults.

    **Raises:** `ValueError` for an unknown name, or an option the model does not have.
    """
    check_choice("model", model, tuple(MODELS))
    cls = MODELS[model]
    fields = {f.name for f in dataclasses.fields(cls)}
    rule = _quadrature(quadrature, quadrature_nodes, quadrature_tolerance)
    options = {}
    if interaction is not None or rule is not None:
        if "interaction" not in fields:
            if interaction not in (None, "none") or rule is not None:
                raise InputError(
                    f"interaction = {interaction!r} applies to models with interaction only; model "
                    f"{model!r} has no interaction (use 'none' or leave it out)"
                )
        else:
            options["interaction"] = _interaction(interaction, rule, cls)
    if spot_stiffness is not None:
        options["spot_stiffness"] = _option("spot_stiffness", spot_stiffness, SPOT_STIFFNESSES)
    if distribution is not None:
        options["distribution"] = _option("distribution", distribution, DISTRIBUTIONS)
    if max_steps is not None or solver_tolerance is not None:
        if "root_finder" not in fields:
            given = "max_steps" if max_steps is not None else "solver_tolerance"
            raise InputError(
                f"{given} applies to models that solve for each load's state (xia2024, jzz2010, gw); model {model!r} "
                "finds none (a closed form, or an iteration of its own): leave it out"
            )
        options["root_finder"] = NewtonBisection(64 if max_steps is None else max_steps, solver_tolerance)
    unknown = [k for k in options if k not in fields]
    if unknown:
        raise InputError(f"model {model!r} takes no {unknown[0]}")
    return cls(**options)
