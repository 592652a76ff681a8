"""The ``jointplay`` command line.

Each command lives in its own module of this package and registers itself on
:data:`jointplay.cli._app.app`; every public module here is imported so its commands exist.
"""

from __future__ import annotations

import importlib
import pkgutil

from jointplay.cli._app import app, main, run

for _module in pkgutil.iter_modules(__path__):
    if not _module.name.startswith("_"):
        importlib.import_module(f"{__name__}.{_module.name}")

__all__ = ["app", "main", "run"]
