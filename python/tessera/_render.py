"""tessera.render: one image of a numpy array, as tessera-render makes it."""
import warnings

from . import _tessera
from . import _checks
from ._arrays import field_descriptor, uses_device_protocol
from ._config import config_source
from ._errors import TesseraWarning

# Test hook: the address of the first vertex the renderer read in the last render() call
_last_field_address = None


def render(volume, config, render=None, spacing=None, origin=None, step=0):
    """Renders the 3D array ``volume`` in place and returns a float32 array of shape
    (height, width, 4): linear RGBA, the pixels tessera-render writes to its EXR for the same
    data and render (bit for bit).

    volume: numpy array of uint8, int16, uint16, float32 or float64 (native byte order), any
        strides (views, transposes, negative steps, Fortran order: never copied).
        ``volume[i, j, k]`` is vertex (i, j, k) along x, y, z: pass a C-ordered (nz, ny, nx)
        array as ``volume.T``. An object with ``__cuda_array_interface__`` or a DLPack tensor
        is read through its protocol; device memory is refused (DataError: the render job
        reads the volume on the host; tessera.Adapter reads device arrays in place).
    config: a YAML file name or a dict of the same schema; a ``volume:`` block, if any, is
        used for its spacing and origin only.
    render: the render's name or index in ``renders`` (default: the first).
    spacing, origin: world spacing and position of vertex (0, 0, 0), a number or 3 numbers;
        default: the config's ``volume:`` block, else (1, 1, 1) and (0, 0, 0).
    step: render as the adapter does at this simulation step (its random numbers), as
        ``tessera-render --step``; default 0.

    Every argument is checked, never converted: TypeError or ValueError naming the argument
    for a step that is not an integer, a spacing that is not numbers, a NUL in a name or path,
    a name or path that is not UTF-8, an empty render name, a masked array (docs/python.md,
    "Arguments").

    Raises ConfigError (a ValueError, with the key path), TypeError (dtype), DataError,
    RenderError. Warnings about the image (e.g. a transfer-function range that misses the data)
    are issued as TesseraWarning. The GIL is released while rendering.
    """
    global _last_field_address
    source, is_text, name = config_source(config)
    array, address, code, dims, strides = field_descriptor(volume)
    if render is None:
        render_name, render_index = "", -1
    elif isinstance(render, str):
        render_name, render_index = _checks.name(render, "render"), -1
    else:
        try:
            render_name, render_index = "", _checks.integer(render, "render")
        except TypeError:
            raise TypeError(f"render: a render name or an index >= 0 is needed, got "
                            f"{type(render).__name__} {render!r}") from None
        if render_index < 0:
            raise ValueError(f"render: a render name or an index >= 0 is needed, got {render_index}")
    spacing = None if spacing is None else _checks.real_triple(spacing, "spacing")
    origin = None if origin is None else _checks.real_triple(origin, "origin")
    step = _checks.integer(step, "step")
    image, messages, seen = _tessera.render_array(source, is_text, name, render_name, render_index,
                                                  address, code, dims, strides, spacing, origin, step,
                                                  uses_device_protocol([array]))
    del array  # held until here: the renderer read it in place
    _last_field_address = seen
    for m in messages:
        warnings.warn(m, TesseraWarning, stacklevel=2)
    return image
