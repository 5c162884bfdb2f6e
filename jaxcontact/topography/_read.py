"""Reading instrument files into metres, through SurfaceTopography (40+ formats)."""

from __future__ import annotations

import contextlib
import io
import logging
import math
import pathlib
import warnings

import numpy as np

from ..numerics._validate import InputError, PlausibilityWarning, assigned, optional_import, spelled
from ._conventions import check_positive
from ._text import check_text_table

# Height and length units a file without its own may be given in.
UNITS = ("m", "mm", "µm", "um", "nm")
# Extensions that several formats (or any text file) use: a file read by another format than the
# one its extension names is accepted only for these.
GENERIC_EXTENSIONS = frozenset({"txt", "csv", "dat", "asc", "xyz"})
# Filling undefined points by interpolation replaces their short wavelengths by smooth ones: on
# synthetic maps of D = 1.2-1.8 (1024², points or 32² blocks missing) D came out low by up to
# 0.18 x the filled fraction. Above this fraction that is no longer small beside D's interval,
# and a map is refused rather than filled.
MAX_FILLED_FRACTION = 0.15
FILL_BIAS_PER_FRACTION = 0.2
# The rms height of a measured engineering surface, m: outside it, a unit mistake is likelier.
TYPICAL_RMS_HEIGHT = (1e-11, 1e-3)


@contextlib.contextmanager
def _quiet():
    """Silence what readers print or log while formats are tried (raw bytes of a damaged file)."""
    previous = logging.root.manager.disable
    logging.disable(logging.CRITICAL)
    try:
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            yield
    finally:
        logging.disable(previous)


def _first_line(exc: Exception) -> str:
    """An exception's message as one printable line."""
    lines = [line.strip() for line in str(exc).splitlines() if line.strip()]
    text = lines[0] if lines else type(exc).__name__
    text = "".join(c if c.isprintable() else "?" for c in text)
    return text if len(text) <= 200 else text[:197] + "..."


def _open(path: pathlib.Path):
    """The reader of `path`: by content, checked against the format its extension names."""
    SurfaceTopography = optional_import("SurfaceTopography", "reading a topography file")
    readers = optional_import("SurfaceTopography.IO", "reading a topography file").readers

    suffix = path.suffix.lower().lstrip(".")
    named = [r for r in readers if suffix in (r.file_extensions() or ())]
    with _quiet():
        try:
            reader = SurfaceTopography.open_topography(str(path))
        except Exception:  # the readers raise many kinds; each means "not a file this reader reads"
            reader = None
        if reader is not None and (not named or type(reader) in named or suffix in GENERIC_EXTENSIONS):
            return reader
        failures = []
        for candidate in named:
            try:
                return SurfaceTopography.open_topography(str(path), format=candidate.format())
            except Exception as exc:
                failures.append((candidate, exc))
    if failures:
        candidate, exc = failures[0]
        raise InputError(
            f"topography file {str(path)!r} cannot be read as {candidate.name()} (the format of .{suffix} files): "
            f"{_first_line(exc)}"
        )
    raise InputError(
        f"topography file {str(path)!r} cannot be read: none of the formats SurfaceTopography reads recognises it"
        + (f" (and .{suffix} is not the extension of any)" if suffix else "")
    )


def from_heights(heights, sizes, *, periodic: bool = False, unit: str = "m", info: dict | None = None):
    """A SurfaceTopography line scan (1-D `heights`) or map (2-D) over the physical `sizes`."""
    st = optional_import("SurfaceTopography", "building a topography")
    options = dict(periodic=periodic, unit=unit, info={} if info is None else info)
    if np.ndim(heights) == 1:
        return st.UniformLineScan(heights, sizes[0], **options)
    return st.Topography(heights, tuple(sizes), **options)


def _npy_topography(path: pathlib.Path, kwargs):
    """What SurfaceTopography's NPY reader gives (`kwargs` as its `topography`), the array read by numpy:
    its serial path copies the array element by element (15 s for a 2048² map)."""
    heights = np.load(path, allow_pickle=False)
    return from_heights(heights, kwargs["physical_sizes"], unit=kwargs["unit"], info=kwargs.get("info", {}))


def _rebuilt(topography, sizes, filled: float):
    """The same heights (m) with the physical sizes `sizes` (m), and the fraction of them `filled`."""
    info = {**topography.info, "filled_fraction": filled}
    return from_heights(topography.heights(), sizes, periodic=topography.is_periodic, info=info)


def read(path, *, size=None, unit=None, tip_radius=None, fill_undefined: bool = False):
    """A topography file as a detrended SurfaceTopography object in metres.

    **Arguments:**

    - `path`: any file SurfaceTopography reads (line scans and areal maps; the format is detected
      from the content and checked against the one the extension names). A plain two-column
      text file is an x–z profile.
    - `size`: physical size in m (a number for a line scan, `(Lx, Ly)` for a map). It overrides
      the file's own; a file that does not say its size needs it.
    - `unit`: the unit of heights (and of lengths, for an x–z profile) where the file does not
      say one: "m" (the default), "mm", "µm" (or "um"), "nm".
    - `tip_radius`: the stylus tip radius in m, where the file lacks it: it sets the short
      reliability cutoff below which the instrument does not resolve the surface.
    - `fill_undefined`: fill undefined (NaN or masked) points by harmonic interpolation
      (SurfaceTopography's `interpolate_undefined_data`) instead of refusing the file. At most
      `MAX_FILLED_FRACTION` (15 %) of the points are filled; `characterise` widens D's and G's
      intervals by the bias that filling can cause.

    **Returns:** a `UniformLineScan` or `Topography`, heights in m, tilt removed (`detrend("center")`);
    `info["filled_fraction"]` is the fraction of points filled.

    **Raises:** `ValueError` naming the problem in one line: unreadable or unknown file (with the
    format expected and what is wrong), no physical size, undefined points, non-positive size or
    tip radius, an unknown unit. **Warns:** `PlausibilityWarning` when the rms height is outside
    0.01 nm–1 mm (heights in another unit than assumed).
    """
    check_positive("tip_radius", tip_radius)
    check_positive("size", size)
    if unit is not None and unit not in UNITS:
        raise InputError(f"unit = {unit!r} is not one of {', '.join(map(repr, UNITS))}")
    path = pathlib.Path(path)
    if not path.is_file():
        raise InputError(f"topography file {str(path)!r} {'is a directory' if path.is_dir() else 'does not exist'}")
    not_utf8 = check_text_table(path) if path.suffix.lower().lstrip(".") in GENERIC_EXTENSIONS else None
    try:
        reader = _open(path)
    except InputError as exc:
        if not_utf8 is None:
            raise
        raise InputError(f"{exc} ({not_utf8}: save the file as UTF-8)") from None
    try:
        channel = reader.default_channel
    except Exception:  # a reader that found the format's header and no data behind it
        raise InputError(
            f"topography file {str(path)!r} is a {reader.name()} file without a readable data channel "
            "(cut short or damaged?)"
        ) from None
    sizes = None if size is None else tuple(float(s) for s in np.atleast_1d(np.asarray(size, dtype=float)))
    if sizes is not None and len(sizes) != len(channel.nb_grid_pts):
        shown = spelled(repr(size), " ".join(f"{s:g}" for s in sizes))
        raise InputError(f"{assigned('size', shown)} m must have {len(channel.nb_grid_pts)} value(s) for this file")
    if channel.unit is not None and unit is not None and channel.unit not in (unit, "µm" if unit == "um" else unit):
        raise InputError(
            f"{assigned('unit', spelled(repr(unit), unit))}, but topography file {str(path)!r} says its unit is "
            f"{channel.unit!r}: leave the unit out"
        )
    kwargs = {}
    if channel.unit is None:
        kwargs["unit"] = unit or "m"
    if channel.physical_sizes is None:
        if sizes is None:
            raise InputError(
                f"topography file {str(path)!r} does not say its physical size: give "
                + spelled("size (m)", "--size L for a line scan or --size LX LY for a map, in m")
            )
        units = optional_import("SurfaceTopography.Support.UnitConversion", "reading a topography file")
        in_unit = units.get_unit_conversion_factor("m", kwargs.get("unit") or channel.unit)
        kwargs["physical_sizes"] = tuple(s * in_unit for s in sizes)
    if tip_radius is not None:
        info = dict(channel.info)
        info["instrument"] = {"parameters": {"tip_radius": {"value": float(tip_radius), "unit": "m"}}}
        kwargs["info"] = info
    try:
        with _quiet():
            topography = _npy_topography(path, kwargs) if reader.format() == "npy" else reader.topography(**kwargs)
            if not topography.is_uniform:
                spacing = np.min(np.diff(topography.positions()))
                topography = topography.to_uniform(nb_points=int(math.ceil(topography.physical_sizes[0] / spacing)))
            if topography.unit != "m":
                topography = topography.to_unit("m")
            # Readers decode lazily: a damaged header (an unknown unit) fails only when the heights are asked for.
            topography.heights()
    except Exception as exc:
        raise InputError(f"topography file {str(path)!r} cannot be read: {_first_line(exc)}") from None
    filled = 0.0
    if topography.has_undefined_data:
        heights = topography.heights()
        filled = float(np.mean(np.ma.getmaskarray(heights) | ~np.isfinite(np.ma.getdata(heights))))
        if filled > MAX_FILLED_FRACTION:
            raise InputError(
                f"topography file {str(path)!r} has {100 * filled:.3g} % undefined (NaN or missing) points: more "
                f"than {100 * MAX_FILLED_FRACTION:g} % cannot be filled without inventing the surface's short "
                "wavelengths (D would come out low); crop the measurement to a part without them"
            )
        if not fill_undefined:
            raise InputError(
                f"topography file {str(path)!r} has undefined (NaN or missing) points ({100 * filled:.2g} %): "
                f"fill them by interpolation with {spelled('fill_undefined=True', '--fill-undefined')}"
            )
        topography = topography.interpolate_undefined_data()
    heights = topography.heights()
    if not np.all(np.isfinite(heights)):
        raise InputError(f"topography file {str(path)!r} has NaN or infinite heights")
    if not np.ptp(heights) > 0:
        what = "map" if heights.ndim == 2 else "profile"
        raise InputError(f"the {what} is flat: every height is the same, so it has no roughness to characterise")
    topography = _rebuilt(topography, sizes or topography.physical_sizes, filled)
    rms = float(np.std(topography.heights()))
    low, high = TYPICAL_RMS_HEIGHT
    if rms > 0 and not low <= rms <= high:
        warnings.warn(
            f"topography file {str(path)!r}: its rms height {rms:.3g} m is outside what instruments measure "
            f"({low:g}-{high:g} m): are its heights in another unit? (give {spelled('unit', '--unit')})",
            PlausibilityWarning,
            stacklevel=2,
        )
    return topography.detrend("center")
