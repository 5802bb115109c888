"""A config given as a YAML file name or as a dict of the same schema."""
import json
import os

import numpy as np

from . import _checks

DICT_NAME = "config dict"


def _plain(value):
    """numpy scalars and arrays as plain Python values, for JSON."""
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    raise TypeError(f"config dict: a value of type {type(value).__name__} is not allowed "
                    f"(use numbers, strings, booleans, lists and dicts)")


def config_source(config):
    """(source, is_text, name): a file name, or the dict as YAML text (JSON is YAML) that the
    config library validates exactly as a file."""
    if isinstance(config, (str, os.PathLike)):
        path = _checks.path(config, "config")
        return path, False, path
    if isinstance(config, dict):
        return json.dumps(config, default=_plain, indent=1, allow_nan=False), True, DICT_NAME
    raise TypeError(f"config: a YAML file name or a dict is needed, got {type(config).__name__}")
