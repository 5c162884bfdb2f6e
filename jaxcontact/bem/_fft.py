"""How the compliance's FFTs are laid out over devices: on whatever device holds the map
(`LocalFFT`), or as a distributed FFT over a mesh of devices, each holding a band of rows
(`DistributedFFT`).

The distributed transform is the textbook pencil (slab) decomposition: each device transforms its
rows along the columns, one all-to-all exchange hands every device whole columns of the half
spectrum, the column transforms, the kernel's product and their inverses are local, and a second
exchange returns the rows. Nothing is gathered: a device holds its band of the map and its share of
the spectrum. A free half-space's zero padding is added on each device (columns) and after the
first exchange (rows), never materialised as a padded map.
"""

from __future__ import annotations

import abc
import math
from collections.abc import Callable

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jax.sharding import Mesh, NamedSharding, PartitionSpec
from jaxtyping import Array, Complex, Float

from ..numerics import cached
from ..numerics._compat import complex_dtype
from ..numerics._validate import InputError

# A kernel given on the rfft2 grid's wavenumbers `values(kx, ky, xp)` (kx a column over every row,
# ky a row over the columns, rad per grid spacing), or at the pixel offsets `values(x, y, xp)` of
# the whole grid (its rfft2 is the kernel); `xp` numpy or jax.numpy.
Values = Callable


def _offsets(indices, rows: int, xp):
    """Pixel offsets of grid indices on a periodic grid of `rows`: 0..rows/2, then negative."""
    return xp.where(indices <= rows // 2, indices, indices - rows)


@cached
def _host_spectral(values: Values, rows: int) -> np.ndarray:
    k = np.fft.fftfreq(rows) * 2 * math.pi
    return values(k[:, None], np.fft.rfftfreq(rows)[None, :] * 2 * math.pi, np)


@cached
def _host_spatial(values: Values, rows: int) -> np.ndarray:
    x = _offsets(np.arange(rows), rows, np).astype(float)
    return np.fft.rfft2(values(x[:, None], x[None, :], np))


def _shard_map():
    # Public as `jax.shard_map` in newer JAX; `jax.experimental.shard_map` before that.
    public = getattr(jax, "shard_map", None)
    if public is not None:
        return public
    from jax.experimental.shard_map import shard_map

    return shard_map


def _times(spectrum, kernel):
    # The product that standard promotion would form (the real kernel made complex), written out so
    # that it holds under strict promotion too: the same program.
    return spectrum * kernel.astype(spectrum.dtype)


class AbstractFFT(eqx.Module):
    """Where the compliance's FFTs run. `convolve` is the whole use the solver makes of them."""

    @abc.abstractmethod
    def convolve(
        self, field: Float[Array, "n n"], kernel: Complex[Array, "rows columns"] | Float[Array, "rows columns"]
    ) -> Float[Array, "n n"]:
        """`irfft2(rfft2(field) · kernel)` on the kernel's grid (`rows × rows`; the kernel in this
        layout, `spectral_kernel`), with `field` zero-padded to it where it is larger (a free
        half-space), cut back to n × n."""

    @abc.abstractmethod
    def spectral_kernel(self, values: Values, rows: int, dtype) -> Array:
        """The kernel `values(kx, ky, xp)` on the rfft2 grid of `rows × rows`, in this layout."""

    @abc.abstractmethod
    def spatial_kernel(self, values: Values, rows: int, dtype) -> Array:
        """The rfft2 of `values(x, y, xp)` over the pixel offsets of `rows × rows`, in this layout."""

    @abc.abstractmethod
    def place(self, heights: Float[Array, "n n"]) -> Float[Array, "n n"]:
        """The heights laid out as the transform expects them (inside a trace too)."""

    @abc.abstractmethod
    def check(self, n: int) -> None:
        """Raise `ValueError` if an n × n map cannot be transformed so."""


class LocalFFT(AbstractFFT):
    """`jnp.fft` on the map as it is: one device, or heights that the user sharded themselves,
    which XLA's partitioner then spreads, gathering the FFTs' operands where it must."""

    def convolve(self, field, kernel):
        n, rows = field.shape[0], kernel.shape[0]
        spectrum = jnp.fft.rfft2(field, s=(rows, rows))  # zero-pads a free map
        return jnp.fft.irfft2(_times(spectrum, kernel), s=(rows, rows))[:n, :n]

    def spectral_kernel(self, values, rows, dtype):
        return jnp.asarray(_host_spectral(values, rows), dtype)

    def spatial_kernel(self, values, rows, dtype):
        return jnp.asarray(_host_spatial(values, rows), complex_dtype(dtype))

    def place(self, heights):
        return heights

    def check(self, n):
        del n


class DistributedFFT(AbstractFFT):
    """A distributed FFT over the devices of `mesh` along its axis `axis`, each device holding
    `n / devices` rows of the map (and of every field the solver forms from it).

    **Arguments:** `mesh`, a `jax.sharding.Mesh`; `axis`, the name of its axis that the rows are
    split over (the map's side must be a multiple of that axis's size). Works under `jit`, `grad`
    and `vmap`; the exchanges are two all-to-alls per transform pair.
    """

    mesh: Mesh = eqx.field(static=True)
    axis: str = eqx.field(static=True, default="rows")

    def __check_init__(self):
        if not isinstance(self.mesh, Mesh):
            raise InputError(f"mesh = {self.mesh!r} is not a jax.sharding.Mesh: give the mesh the rows are split over")
        if self.axis not in self.mesh.axis_names:
            names = tuple(self.mesh.axis_names)
            raise InputError(f"axis = {self.axis!r} is not an axis of the mesh: valid are {names}")

    @property
    def devices(self) -> int:
        return int(self.mesh.shape[self.axis])

    def check(self, n):
        if n % self.devices:
            raise InputError(
                f"the map's side n = {n} is not a multiple of the {self.devices} devices along {self.axis!r}: "
                "valid are multiples of the device count"
            )

    def place(self, heights):
        return jax.lax.with_sharding_constraint(heights, NamedSharding(self.mesh, PartitionSpec(self.axis, None)))

    def _width(self, rows: int) -> int:
        """The half spectrum's columns, `rows/2 + 1`, padded to split evenly over the devices."""
        return -(-(rows // 2 + 1) // self.devices) * self.devices

    def _forward(self, band, rows: int):
        """A device's band of rows (zero-padded to `rows × rows`) to its columns of the spectrum."""
        spectrum = jnp.fft.rfft(band, n=rows, axis=1)
        spectrum = jnp.pad(spectrum, ((0, 0), (0, self._width(rows) - spectrum.shape[1])))
        spectrum = jax.lax.all_to_all(spectrum, self.axis, split_axis=1, concat_axis=0, tiled=True)
        return jnp.fft.fft(spectrum, n=rows, axis=0)

    def _mapped(self, local, inputs, outputs):
        rows_spec, columns_spec = PartitionSpec(self.axis, None), PartitionSpec(None, self.axis)
        specs = {"rows": rows_spec, "columns": columns_spec}
        in_specs, out_specs = tuple(specs[i] for i in inputs), specs[outputs]
        return _shard_map()(local, mesh=self.mesh, in_specs=in_specs, out_specs=out_specs)

    def spectral_kernel(self, values, rows, dtype):
        half, block = rows // 2 + 1, self._width(rows) // self.devices
        k = jnp.asarray(np.fft.fftfreq(rows) * 2 * math.pi, dtype)

        def local():
            columns = jax.lax.axis_index(self.axis) * block + jnp.arange(block)
            kernel = values(k[:, None], (columns * (2 * math.pi / rows)).astype(dtype)[None, :], jnp)
            return jnp.where(columns[None, :] < half, kernel, 0.0).astype(dtype)

        return self._mapped(local, (), "columns")()

    def spatial_kernel(self, values, rows, dtype):
        band = rows // self.devices
        y = jnp.asarray(_offsets(np.arange(rows), rows, np), dtype)

        def local():
            x = _offsets(jax.lax.axis_index(self.axis) * band + jnp.arange(band), rows, jnp).astype(dtype)
            return self._forward(values(x[:, None], y[None, :], jnp), rows)

        return self._mapped(local, (), "columns")()

    def convolve(self, field, kernel):
        n, rows = field.shape[0], kernel.shape[0]

        def local(band, kernel_columns):
            spectrum = jnp.fft.ifft(_times(self._forward(band, rows), kernel_columns), axis=0)[:n]
            spectrum = jax.lax.all_to_all(spectrum, self.axis, split_axis=0, concat_axis=1, tiled=True)
            return jnp.fft.irfft(spectrum[:, : rows // 2 + 1], n=rows, axis=1)[:, :n]

        return self._mapped(local, ("rows", "columns"), "rows")(field, kernel)


def check_fft(fft, n: int) -> None:
    """Raise `ValueError` unless `fft` is an `AbstractFFT` that can transform an n × n map."""
    if not isinstance(fft, AbstractFFT):
        raise InputError(f"fft = {fft!r} must be bem.LocalFFT() or bem.DistributedFFT(mesh, axis)")
    fft.check(n)
