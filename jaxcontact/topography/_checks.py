"""Checks on a characterisation: the two methods against each other, and values no instrument measures."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

# A G (W-M, m) beyond this is an extrapolation no band supports (machined surfaces: 1e-14 to 1e-8 m).
G_RANGE = (1e-20, 1e-3)


def widened(covariance: np.ndarray, bias: float) -> np.ndarray:
    """`covariance` of (D, ln G) plus a systematic shift `bias` of D, with ln G along its regression on D."""
    direction = np.array([1.0, covariance[0, 1] / covariance[0, 0]])
    return covariance + bias**2 * np.outer(direction, direction)


def with_covariance(c, covariance: np.ndarray, note: str, power_law=None):
    """`c` with its intervals from `covariance` (and the power law's, if given) and `note` among its
    diagnostics."""
    from ._result import intervals

    return dataclasses.replace(
        c,
        **intervals(c.D, c.G, covariance, c.dof),
        covariance=covariance,
        diagnostics=c.diagnostics + (note,),
        power_law=c.power_law if power_law is None else power_law,
    )


def compared(psd, structure_function):
    """The PSD characterisation, with a diagnostic naming both D values and intervals widened by half
    their difference where the two methods disagree beyond 2 standard errors of the difference."""
    difference = psd.D - structure_function.D
    spread = math.hypot(psd.stderr["D"], structure_function.stderr["D"])
    if not abs(difference) > 2 * spread:
        return psd
    note = (
        f"the two methods disagree: the PSD gives D = {psd.D:.3f} ± {psd.stderr['D']:.3f}, the structure function "
        f"D = {structure_function.D:.3f} ± {structure_function.stderr['D']:.3f} (over "
        f"{structure_function.band[0]:.3g}-{structure_function.band[1]:.3g} m); the surface is not one power law over "
        "both bands, and the PSD's intervals include half the difference"
    )
    power_law = None
    if psd.power_law is not None:
        # The slope is -(6 - 2D) or -(5 - 2D): a shift of D by b moves it by 2b.
        slope, intercept, native = psd.power_law
        power_law = (slope, intercept, widened(native, difference))
    return with_covariance(psd, widened(psd.covariance, difference / 2), note, power_law)


# A D interval wider than this (standard error) says the band hardly determines D.
POOR_D = 0.1


def implausible(rms: float, c) -> tuple[str, ...]:
    """Diagnostics for an rms height or a G outside what instruments measure (a unit mistaken?), and
    for a D the band hardly determines."""
    from ._read import TYPICAL_RMS_HEIGHT as RMS_RANGE

    notes = []
    if c.stderr["D"] > POOR_D:
        notes.append(
            f"D is poorly determined (± {c.stderr['D']:.2g}): the power-law band is short or its position uncertain; "
            "psd.png shows the local slope"
        )
    if not RMS_RANGE[0] <= rms <= RMS_RANGE[1]:
        notes.append(
            f"the rms height is {rms:.3g} m, outside the {RMS_RANGE[0]:g}-{RMS_RANGE[1]:g} m that roughness "
            "instruments measure: are the heights in another unit? (give it: --unit, or read(..., unit=))"
        )
    low, high = c.ci95["G"]
    if not (G_RANGE[0] <= c.G <= G_RANGE[1]) or high > G_RANGE[1] or low < G_RANGE[0]:
        notes.append(
            f"G = {c.G:.3g} m with 95 % interval [{low:.3g}, {high:.3g}] m reaches beyond {G_RANGE[0]:g}-"
            f"{G_RANGE[1]:g} m: G is extrapolated far from the band (to q = 1 rad/m) and is poorly determined here"
        )
    return tuple(notes)


def widened_for_filling(covariance, filled: float, held: bool):
    """The covariance of (D, ln G) with the bias that filling `filled` of the points can cause
    (`read`'s `FILL_BIAS_PER_FRACTION`, D low and ln G along its regression on D) added as a
    systematic term; and the diagnostic that says so."""
    from ._read import FILL_BIAS_PER_FRACTION

    bias = FILL_BIAS_PER_FRACTION * filled
    if held:
        return covariance, f"{100 * filled:.2g} % of the points were filled by interpolation: G may be low"
    return widened(covariance, bias), (
        f"{100 * filled:.2g} % of the points were filled by interpolation, which can bias D low by up to "
        f"{bias:.2g} (and G with it): the intervals include that"
    )
