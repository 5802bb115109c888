"""Tessera: Monte Carlo volume rendering of numpy arrays, and in situ for Python simulations.

    image = tessera.render(volume, "scene.yaml")   # float32 (height, width, 4), linear RGBA
    with tessera.Adapter("viz.yaml", comm) as viz:
        viz.execute(step, t, {"temperature": u}, spacing=dx, ghosts=1, ...)

See docs/python.md.
"""
from . import _tessera
from ._adapter import Adapter
from ._mesh_domains import MeshDomain
from ._errors import (ConfigError, DataError, DisabledError, OutputError, RenderError,
                      TesseraError, TesseraWarning)
from ._render import render

__all__ = ["render", "Adapter", "MeshDomain", "TesseraError", "ConfigError", "DataError", "RenderError",
           "OutputError", "DisabledError", "TesseraWarning"]
__version__ = "0.1.0"

_tessera._set_error_types(ConfigError, DataError, RenderError, OutputError, DisabledError)
