"""The `jaxcontact` command line, scene files, result tables and plots."""

from .main import main

__all__ = ["main"]
