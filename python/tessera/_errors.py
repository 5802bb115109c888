"""The exceptions and warnings the tessera package raises (docs/python.md, "Errors")."""


class TesseraError(Exception):
    """Base class of every error Tessera raises."""


class ConfigError(TesseraError, ValueError):
    """A config that failed to load: ``str(e)`` reads ``FILE:LINE:COL: KEY.PATH: what is wrong``
    (for a dict: ``config dict: KEY.PATH: ...``). Attributes: file, line and column (0 when
    unknown), key_path (``renders[0].camera.fov``; "" when unknown)."""

    def __init__(self, message, file="", line=0, column=0, key_path=""):
        super().__init__(message)
        self.file = file
        self.line = line
        self.column = column
        self.key_path = key_path


class DataError(TesseraError, ValueError):
    """An array or grid that cannot be rendered (overlapping strides, empty after ghosts, ...)."""


class RenderError(TesseraError, RuntimeError):
    """Preparing or rendering failed (camera inside the data, time or memory limit, MPI, ...)."""


class OutputError(TesseraError, OSError):
    """An output the config asks for could not be written."""


class DisabledError(RenderError):
    """``on_error: disable``: the render failed ``max_failures`` times in a row and is off."""


class TesseraWarning(UserWarning):
    """What may be wrong with an image although it rendered (range missing the data, ...), and
    an Adapter render that failed under ``on_error: warn`` or ``disable``."""
