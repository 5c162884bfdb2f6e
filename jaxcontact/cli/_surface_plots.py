"""`psd.png`: a measured spectrum against wavelength (the unit `--band` takes, q on the top axis),
with its local slope as D, the fitted band or a suggested one."""

from __future__ import annotations

import numpy as np

from ..studies._plotting import save_figure, subplots


def _reciprocal(x):
    """2π/x, the map between wavelength and q both ways (matplotlib probes it at 0 too)."""
    with np.errstate(divide="ignore"):
        return 2 * np.pi / np.asarray(x, dtype=float)


def psd_figure(spectrum, local, path, *, ylabel, fit=None, D=None, band=None, suggestion=None, cutoff=None) -> str:
    """Spectrum `(q, C)` and local D `(q, D)` against wavelength 2π/q (m); `fit` `(q, C)` over `band`
    (short, long wavelength, m), or a `suggestion` (short, long) where none was found."""
    fig, (ax, bx) = subplots(2, 1, figsize=(6, 6.4), sharex=True)
    q, C = spectrum
    keep = (q > 0) & (C > 0)
    ax.loglog(2 * np.pi / q[keep], C[keep], ".", ms=3, color="0.4", label="measured (binned)")
    if fit is not None:
        ax.loglog(2 * np.pi / fit[0], fit[1], "-", color="C3", label=f"fit: D = {D:.3f}")
    for ends, color, label in ((band, "C0", "fit band"), (suggestion, "C1", "suggested band")):
        if ends is not None:
            for axis in (ax, bx):
                axis.axvspan(*ends, color=color, alpha=0.15, label=label if axis is ax else None)
    if cutoff:
        for axis in (ax, bx):
            axis.axvline(cutoff, color="k", ls="--", lw=1, label="tip reliability cutoff" if axis is ax else None)
    ax.set_ylabel(ylabel)
    ax.legend(fontsize=8)
    top = ax.secondary_xaxis("top", functions=(_reciprocal, _reciprocal))
    top.set_xlabel("q (rad/m)")
    local_q, local_D = local
    finite = np.isfinite(local_D)
    bx.semilogx(2 * np.pi / local_q[finite], local_D[finite], "-", color="C2", label="local D (±¼ decade)")
    bx.axhspan(1.0, 2.0, color="0.92", zorder=0, label="self-affine: 1 < D < 2")
    bx.set_ylim(0.0, 3.0)
    bx.set_ylabel("local D from the slope")
    bx.set_xlabel("wavelength (m)")
    bx.legend(fontsize=8, loc="lower left")
    return save_figure(fig, path)


def spectrum_figure(c, ylabel, xlabel, path):
    """A structure function (or spectrum) with its fit, band and the tip's reliability cutoff."""
    fig, ax = subplots()
    x, y = c.spectrum
    keep = (x > 0) & (y > 0)
    ax.loglog(x[keep], y[keep], ".", ms=2, color="0.5", label="measured (mean of groups)")
    ax.loglog(*c.fit, "-", color="C3", label=f"fit: D = {c.D:.3f}")
    ax.axvspan(*c.band, color="C0", alpha=0.12, label="fit band")
    if c.reliability_cutoff:
        ax.axvline(c.reliability_cutoff, color="k", ls="--", lw=1, label="tip reliability cutoff")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.legend(fontsize=8)
    return save_figure(fig, path)


def plot_band(band, title, path, others=None, model: str = "") -> str:
    """K(F) with its 95 % band from the surface's (D, G) uncertainty, and other models' K as lines; a
    model without a positive K at any load is named on the plot instead of drawn."""
    fig, ax = subplots()
    positive = np.isfinite(band.stiffness) & (band.stiffness > 0)
    missing = []
    if positive.any():
        ax.loglog(
            band.load[positive], band.stiffness[positive], "-", color="C0", label=f"{model} at the surface's D, G"
        )
        ax.fill_between(
            band.load[positive], band.lower[positive], band.upper[positive], color="C0", alpha=0.25, label="95 % band"
        )
    else:
        missing.append(model)
    for k, (name, K) in enumerate((others or {}).items()):
        drawn = np.isfinite(K) & (K > 0)
        if drawn.any():
            ax.loglog(band.load[drawn], K[drawn], "--", color=f"C{k + 1}", lw=1, label=name)
        else:
            missing.append(name)
    ax.set_xscale("log")
    ax.set_yscale("log")
    if missing:
        ax.text(0.02, 0.02, "no positive K at any load: " + ", ".join(missing), transform=ax.transAxes, fontsize=8)
    ax.set_xlabel("F (N)")
    ax.set_ylabel("K (N/m)")
    ax.set_title(title, fontsize=8)
    ax.legend(fontsize=8)
    return save_figure(fig, path)


def psd_figure_stitched(c, path) -> str:
    """The joined spectrum of stitched measurements with its fit (no local slope)."""
    return psd_figure(
        c.spectrum,
        (c.spectrum[0], c.spectrum[0] * float("nan")),
        path,
        ylabel=c.kind.psd_label,
        fit=c.fit,
        D=c.D,
        band=c.band,
    )
