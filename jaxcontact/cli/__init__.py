"""The `jaxcontact` command line, scene files, result tables and plots."""

from ._main import console, main

__all__ = ["console", "main"]
