"""Reading instrument files into metres, through SurfaceTopography (40+ formats)."""

from __future__ import annotations

import math
import pathlib

import numpy as np

from ..numerics.validate import InputError
from .conventions import check_positive


def read(path, *, size=None, tip_radius=None, fill_undefined: bool = False):
    """A topography file as a detrended SurfaceTopography object in metres.

    **Arguments:**

    - `path`: any file SurfaceTopography reads (line scans and areal maps; the format is detected).
    - `size`: physical size in m (a number for a line scan, `(Lx, Ly)` for a map), where the file
      lacks it; it overrides the file's.
    - `tip_radius`: the stylus tip radius in m, where the file lacks it: it sets the short
      reliability cutoff below which the instrument does not resolve the surface.
    - `fill_undefined`: fill undefined (NaN or masked) points by harmonic interpolation
      (SurfaceTopography's `interpolate_undefined_data`) instead of refusing the file.

    **Returns:** a `UniformLineScan` or `Topography`, heights in m, tilt removed (`detrend("center")`).

    **Raises:** `ValueError` naming the problem: unreadable or unknown file, no physical size,
    undefined (NaN or masked) points, non-positive size or tip radius.
    """
    import SurfaceTopography

    check_positive("tip_radius", tip_radius)
    check_positive("size", size)
    path = pathlib.Path(path)
    if not path.is_file():
        raise InputError(f"topography file {str(path)!r} {'is a directory' if path.is_dir() else 'does not exist'}")
    try:
        reader = SurfaceTopography.open_topography(str(path))
    except Exception as exc:  # the readers raise many kinds; each means "not a file we can read"
        raise InputError(f"topography file {str(path)!r} cannot be read: {exc}") from None
    channel = reader.default_channel
    kwargs = {}
    if size is not None:
        sizes = np.atleast_1d(np.asarray(size, dtype=float))
        if sizes.size != len(channel.nb_grid_pts):
            raise InputError(f"size = {size!r} m must have {len(channel.nb_grid_pts)} value(s) for this file")
        kwargs["physical_sizes"] = tuple(sizes)
        kwargs["unit"] = "m"
    elif channel.physical_sizes is None or channel.unit is None:
        raise InputError(f"topography file {str(path)!r} does not say its physical size: give size (m)")
    if tip_radius is not None:
        info = dict(channel.info)
        info["instrument"] = {"parameters": {"tip_radius": {"value": float(tip_radius), "unit": "m"}}}
        kwargs["info"] = info
    try:
        topography = reader.topography(**kwargs)
    except Exception as exc:
        raise InputError(f"topography file {str(path)!r} cannot be read: {exc}") from None
    if topography.has_undefined_data:
        heights = topography.heights()
        fraction = float(np.mean(np.ma.getmaskarray(heights) | ~np.isfinite(np.ma.getdata(heights))))
        if not fill_undefined:
            raise InputError(
                f"topography file {str(path)!r} has undefined (NaN or missing) points ({100 * fraction:.2g} %): "
                "fill them by interpolation with fill_undefined=True (--fill-undefined)"
            )
        topography = topography.interpolate_undefined_data()
    heights = topography.heights()
    if not np.all(np.isfinite(heights)):
        raise InputError(f"topography file {str(path)!r} has NaN or infinite heights")
    if not topography.is_uniform:
        spacing = np.min(np.diff(topography.positions()))
        topography = topography.to_uniform(nb_points=int(math.ceil(topography.physical_sizes[0] / spacing)))
    if topography.unit != "m":
        topography = topography.to_unit("m")
    return topography.detrend("center")
