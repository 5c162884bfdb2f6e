"""Where the library's compiled programs live: in this process (the default: `jax.jit`, compiled for a
short compile time where that is asked for), or in the store a caller puts them in for a while
(`kept_in`). The command line keeps them on disk between processes (`jaxcontact.cli`), so that a new
process need not trace them; the library knows only this interface.
"""

from __future__ import annotations

import abc
import contextlib
from collections.abc import Callable

import jax

from ._compiling import FastCompile


class AbstractProgramStore(abc.ABC):
    """Builds the callable of a program: `program(name, static, function, args, closed_over,
    fast_compile)` and `executable(...)` (the same, compiled for a short compile time, its executable
    kept where the store can).

    `name` and `static` describe the program (`static`: everything `function` closes over that changes
    it), `args` are arguments like those it will be called with, `closed_over` the tree structures it
    closes over. **Attributes:** `short_compile_below`, the load count below which a top-level solve
    is compiled for a short compile time (0: never; a store for processes that make few calls per
    program sets it).
    """

    short_compile_below: int = 0

    @abc.abstractmethod
    def program(
        self, name: str, static: str, function: Callable, args, closed_over=(), fast_compile: bool = True
    ) -> Callable:
        """The callable of `function` for arguments like `args`."""

    @abc.abstractmethod
    def executable(self, name: str, static: str, function: Callable, args, closed_over=()) -> Callable:
        """As `program`, compiled for a short compile time, its executable kept where the store can."""

    @abc.abstractmethod
    def close(self) -> None:
        """Finish what is being kept (on leaving `kept_in`)."""


class InProcess(AbstractProgramStore):
    """Programs compiled in this process and kept by `jax.jit` for its lifetime."""

    def program(self, name, static, function, args, closed_over=(), fast_compile=True):
        return FastCompile(function) if fast_compile else jax.jit(function)

    def executable(self, name, static, function, args, closed_over=()):
        return FastCompile(function)

    def close(self) -> None:
        pass  # nothing outlives the process


_IN_PROCESS = InProcess()
_stores: list[AbstractProgramStore] = [_IN_PROCESS]


def current_store() -> AbstractProgramStore:
    """The store programs are built in now (`InProcess` unless a `kept_in` context is active)."""
    return _stores[-1]


def keeping() -> bool:
    """Whether a store other than this process's own is active."""
    return current_store() is not _IN_PROCESS


@contextlib.contextmanager
def kept_in(store: AbstractProgramStore | None):
    """Build programs in `store` while the context is active (`None`: in this process); on leaving it,
    the store finishes what it is keeping (`close`)."""
    _stores.append(_IN_PROCESS if store is None else store)
    try:
        yield
    finally:
        _stores.pop().close()


def program(name: str, static: str, function: Callable, args, closed_over=(), fast_compile: bool = True) -> Callable:
    """The current store's callable of `function` (`AbstractProgramStore.program`)."""
    return current_store().program(name, static, function, args, closed_over, fast_compile)


def executable(name: str, static: str, function: Callable, args, closed_over=()) -> Callable:
    """The current store's short-compile callable of `function` (`AbstractProgramStore.executable`)."""
    return current_store().executable(name, static, function, args, closed_over)
