"""`corner.png` (the posterior's marginals and pairs) and `posterior_band.png` (K(F) from the samples)."""

from __future__ import annotations

import numpy as np

from ..quantities import PARAMETERS
from ..studies._plotting import figure, save_figure, subplots


def corner(posterior, path) -> str:
    """Histograms of each parameter on the diagonal, the samples of each pair below it (a scale on a log axis)."""
    names = posterior.params
    n = len(names)
    fig = figure((2.4 * n + 1.0, 2.4 * n + 0.6), rows=n, columns=n)
    axes = np.asarray(fig.subplots(n, n, squeeze=False))
    flat = {k: np.ravel(posterior.samples[k]) for k in names}
    shown = {k: np.log10(v) if PARAMETERS[k].log else v for k, v in flat.items()}
    label = {k: f"log10 {k}" if PARAMETERS[k].log else k for k in names}
    for i, row in enumerate(names):
        for j, column in enumerate(names):
            ax = axes[i, j]
            if j > i:
                ax.set_visible(False)
            elif i == j:
                ax.hist(shown[row], bins=40, color="C0", alpha=0.7)
                lo, hi = posterior.ci95[row]
                for edge in (lo, hi):
                    ax.axvline(np.log10(edge) if PARAMETERS[row].log else edge, color="k", ls=":", lw=1)
                ax.set_yticks([])
            else:
                ax.plot(shown[column], shown[row], ".", ms=1, alpha=0.3, color="C0")
            if i == n - 1:
                ax.set_xlabel(label[column])
            if j == 0 and i > 0:
                ax.set_ylabel(label[row])
    if not posterior.describes_data:
        fig.suptitle(REJECTED, fontsize=9, color="C3")
    return save_figure(fig, path)


# The caveat on a posterior plot of a model the least-squares fit rejected.
REJECTED = "the model does not describe these data: a posterior of a rejected model"


def posterior_band(posterior, loads, stiffness, path) -> str:
    """The data and the 95 % band of K predicted by the posterior's samples."""
    fig, ax = subplots()
    band_loads, lower, median, upper = posterior.band
    ax.loglog(loads, stiffness, "o", ms=3, label="data")
    ax.loglog(band_loads, median, "-", color="C1", label="posterior median")
    ax.fill_between(band_loads, lower, upper, color="C1", alpha=0.3, label="95 % of the posterior's curves")
    ax.set(xlabel="load F (N)", ylabel="stiffness K (N/m)")
    if not posterior.describes_data:
        ax.set_title(REJECTED, fontsize=9, color="C3")
    ax.legend(fontsize=8)
    return save_figure(fig, path)
