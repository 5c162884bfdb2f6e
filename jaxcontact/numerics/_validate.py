"""Checks of configuration values that are known at construction time.

Values that are JAX tracers (inside `jit`, `grad`, `vmap`) cannot be checked here; the model
reports value-dependent failures per point through `Solution.status` instead.
"""

from __future__ import annotations

import contextlib
import contextvars
import importlib
import math
from collections.abc import Sequence

import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import ArrayLike, Float

# What a function of loads takes: an array (JAX or NumPy), a number, or a list of numbers.
LoadsLike = Float[ArrayLike, "*loads"] | Sequence[float]


class InputError(ValueError):
    """A value given to jaxcontact that it does not accept. The message names the parameter, the
    value and what is allowed; the command line reports it in one line (exit status 2)."""


# The command line's option for each argument name while a command runs (None from Python): errors
# then say `--band SHORT LONG` where a Python caller reads `band=(short, long)`.
_COMMAND_LINE_OPTIONS: contextvars.ContextVar[dict | None] = contextvars.ContextVar("jaxcontact_cli", default=None)


@contextlib.contextmanager
def command_line_spelling(options: dict[str, str]):
    """Within this context, messages name arguments as the command line's `options` ({name: "--opt"})."""
    token = _COMMAND_LINE_OPTIONS.set(dict(options))
    try:
        yield
    finally:
        _COMMAND_LINE_OPTIONS.reset(token)


@contextlib.contextmanager
def file_spelling():
    """Within this context, messages name values as a file (a scene file's keys) does: by their Python
    names, also while a command runs."""
    token = _COMMAND_LINE_OPTIONS.set(None)
    try:
        yield
    finally:
        _COMMAND_LINE_OPTIONS.reset(token)


def spelled(python: str, command_line: str) -> str:
    """`python` (how a Python caller writes an argument), or `command_line` while a command runs."""
    return python if _COMMAND_LINE_OPTIONS.get() is None else command_line


def assigned(name: str, value: str, meaning: str = "") -> str:
    """`name (meaning) = value` from Python; `--option value (meaning)` for a command's own option."""
    options = _COMMAND_LINE_OPTIONS.get() or {}
    what = f" ({meaning})" if meaning else ""
    return f"{options[name]} {value}{what}" if name in options else f"{name}{what} = {value}"


# The optional packages, and the extra of jaxcontact that installs each (`pyproject.toml`).
EXTRAS = {"SurfaceTopography": "surface", "ContactMechanics": "bem", "mpmath": "studies", "blackjax": "bayes"}


class MissingExtraError(ImportError):
    """An optional package is not installed; the message names the extra that installs it."""


def optional_import(module: str, purpose: str):
    """`module` (of one of the packages of `EXTRAS`), or a `MissingExtraError` naming its extra."""
    package = module.split(".")[0]
    try:
        return importlib.import_module(module)
    except ModuleNotFoundError as exc:
        if (exc.name or "").split(".")[0] != package:
            raise
        extra = EXTRAS[package]
        raise MissingExtraError(
            f"{purpose} needs {package}, which jaxcontact's {extra!r} extra installs: "
            f"pip install 'jaxcontact[{extra}]'",
            name=package,
        ) from None


class JaxcontactWarning(UserWarning):
    """A warning of jaxcontact's own: a value that is valid but probably not what was meant, or a
    result recomputed because what was stored was not valid. The command line shows each in one line."""


class PlausibilityWarning(JaxcontactWarning):
    """A parameter outside what engineering surfaces and instruments have: most likely a unit mistake."""


def as_array(value):
    """Numbers and arrays become JAX arrays (pytree leaves that `eqx.filter_grad`, `filter_jit`
    and `filter_vmap` treat as parameters); tracers pass through.

    A Python number stays weakly typed, so that it takes the working precision of the solve
    (float32, or float64 under `jax_enable_x64`) instead of fixing one at construction.
    """
    if isinstance(value, bool):
        raise InputError(f"expected a number, got the boolean {value!r}")
    if isinstance(value, jax.core.Tracer):
        return value
    if isinstance(value, (int, np.integer)):
        value = float(value)
    try:
        array = jnp.asarray(value)
    except (TypeError, ValueError) as exc:
        raise InputError(f"expected a number or an array of numbers, got {value!r}") from exc
    if not jnp.issubdtype(array.dtype, jnp.number) or jnp.issubdtype(array.dtype, jnp.complexfloating):
        raise InputError(f"expected a real number, got {value!r}")
    return array if jnp.issubdtype(array.dtype, jnp.floating) else array.astype(float)


def concrete(value) -> np.ndarray | None:
    """The value as a float64 numpy array, or None while it is being traced."""
    if isinstance(value, jax.core.Tracer):
        return None
    try:
        return np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputError(f"expected a number, got {value!r}") from exc


def _describe(values: np.ndarray) -> str:
    if values.ndim == 0:
        return f"{float(values):.6g}"
    return f"{np.array2string(values, precision=6, threshold=6)}"


def check_range(
    name: str,
    value,
    low: float = -math.inf,
    high: float = math.inf,
    *,
    low_open: bool = True,
    high_open: bool = True,
    meaning: str = "",
) -> None:
    """Raise `ValueError` unless every element of a concrete `value` lies in the interval."""
    values = concrete(value)
    if values is None:
        return
    ok = np.isfinite(values)
    ok &= (values > low) if low_open else (values >= low)
    ok &= (values < high) if high_open else (values <= high)
    if not np.all(ok):
        left = "(" if low_open else "["
        right = ")" if high_open else "]"
        interval = f"{left}{low:g}, {high:g}{right}"
        raise InputError(f"{assigned(name, _describe(values), meaning)} is outside its valid range {interval}")


def check_positive(name: str, value, unit: str, noun: str) -> None:
    """Raise `InputError` naming the first element of a concrete `value` that is not finite and > 0,
    e.g. "loads[3] = nan N is not a valid load: loads must be finite and > 0 (valid range (0, inf) N)".
    Traced values are not checked."""
    values = concrete(value)
    if values is None:
        return
    # Two reductions decide the common case; NaN fails `> 0` and falls through to the search.
    if values.size and values.min() > 0 and values.max() < np.inf:
        return
    bad = ~(np.isfinite(values) & (values > 0))
    if np.any(bad):
        where = np.argwhere(bad)[0]
        index = f"[{', '.join(map(str, where))}]" if values.ndim else ""
        raise InputError(
            f"{name}{index} = {float(values[tuple(where)])!r} {unit} is not a valid {noun}: "
            f"{name} must be finite and > 0 (valid range (0, inf) {unit})"
        )


def check_choice(name: str, value, choices: tuple[str, ...]) -> None:
    if value not in choices:
        allowed = ", ".join(repr(c) for c in choices)
        raise InputError(f"{assigned(name, repr(value))} is not one of {allowed}")


def check_instance(name: str, value, kind: type) -> None:
    """Raise `ValueError` unless `value` is a `kind` (a model's choice passed as an object)."""
    if not isinstance(value, kind):
        raise InputError(f"{name} = {value!r} must be a {kind.__name__} (see jaxcontact.{kind.__name__})")


def check_strategy(name: str, value, base: type, names: dict[str, type], face: str) -> None:
    """Raise `ValueError` unless `value` is a `base` (a strategy passed as an object); a name of
    `names` (the command line's) is refused with the object it stands for, `face.Class()`."""
    if isinstance(value, base):
        return
    if isinstance(value, str) and value in names:
        raise InputError(
            f"{name} = {value!r}: give the object, {face}.{names[value].__name__}() (names are for the command line)"
        )
    options = " or ".join(f"{face}.{kind.__name__}()" for kind in dict.fromkeys(names.values()))
    raise InputError(f"{name} = {value!r} must be {options}")


def decoded_text(data: bytes) -> tuple[str, str | None]:
    """A text file's bytes as text: UTF-8 (a byte-order mark dropped), else Latin-1, which instrument and
    lab software writes ("µm", "é" in a comment); and where it is not UTF-8 ("line 4 has the byte
    0xb5, which is not UTF-8"), or None."""
    try:
        return data.decode("utf-8-sig"), None
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        return data.decode("latin-1"), f"line {line} has the byte 0x{data[exc.start]:02x}, which is not UTF-8"


def float_array(name: str, value, ndim: int | None = None) -> np.ndarray:
    """`value` as a float64 numpy array, or `InputError` naming `name`: text, complex numbers, ragged
    nesting, or (with `ndim`) another number of dimensions."""
    try:
        array = np.asarray(value)
        if np.iscomplexobj(array):
            raise TypeError
        array = array.astype(np.float64)
    except (TypeError, ValueError):
        raise InputError(f"{name} = {_shown(value)} must be real numbers (an array of one shape)") from None
    if ndim is not None and array.ndim != ndim:
        raise InputError(f"{name} has {array.ndim} dimension(s), shape {array.shape}: it needs {ndim}")
    return array


def _shown(value) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."
