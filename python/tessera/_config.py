"""A config given as a YAML file name or as a dict of the same schema."""
import json
import os

import numpy as np

from . import _checks
from ._errors import ConfigError

DICT_NAME = "config dict"
MAX_DEPTH = 64  # deeper than any config of the schema nests


def _refused(key_path, what):
    """The ConfigError of a dict value that cannot be turned into YAML, naming its key path."""
    where = f"{DICT_NAME}: {key_path}: " if key_path else f"{DICT_NAME}: "
    return ConfigError(where + what, file=DICT_NAME, key_path=key_path)


def _text(value, key_path, what):
    """A str without NUL, in UTF-8 (_checks.text) as a ConfigError naming the key path."""
    try:
        return _checks.text(value, what)
    except ValueError as e:
        raise ConfigError(str(e), file=DICT_NAME, key_path=key_path) from None


def _child(key_path, key):
    return f"{key_path}.{key}" if key_path else key


def _plain(value, key_path, depth, inside):
    """``value`` as plain data for JSON (dict, list, str, int, float, bool, None), checked on
    the way: every refusal names the key path (``renders[0].camera.fov``) and what is wrong.
    ``inside``: the ids of the containers being walked (a container inside itself)."""
    if isinstance(value, np.ndarray):
        value = value.tolist()
    elif isinstance(value, np.generic):
        value = value.item()
    if value is None or isinstance(value, bool):
        return value
    if isinstance(value, str):
        return _text(value, key_path, f"{DICT_NAME}: {key_path}" if key_path else DICT_NAME)
    if isinstance(value, int):
        try:
            float(value)
        except OverflowError:
            raise _refused(key_path, f"{_checks._shown(value)} is beyond the range of a float "
                                     f"(about +-1.8e308)") from None
        return value
    if isinstance(value, float):
        if value != value or value in (float("inf"), float("-inf")):
            raise _refused(key_path, f"{value} is not allowed (NaN and infinity have no YAML value here)")
        return value
    if not isinstance(value, (dict, list, tuple)):
        raise _refused(key_path, f"a value of type {type(value).__name__} is not allowed "
                                 f"(use numbers, strings, booleans, lists and dicts)")
    if id(value) in inside:
        raise _refused(key_path, "contains itself (a dict or list that refers back to itself)")
    if depth >= MAX_DEPTH:
        raise _refused(key_path, f"nested more than {MAX_DEPTH} levels deep")
    inside.add(id(value))
    if isinstance(value, dict):
        out = {}
        for key, item in value.items():
            if not isinstance(key, str):
                raise _refused(key_path, f"key {_checks._shown(key)} is not a str (keys are names)")
            key = _text(key, key_path, f"{DICT_NAME}: {key_path} key" if key_path else f"{DICT_NAME} key")
            out[key] = _plain(item, _child(key_path, key), depth + 1, inside)
    else:
        out = [_plain(item, f"{key_path}[{n}]", depth + 1, inside) for n, item in enumerate(value)]
    inside.discard(id(value))
    return out


def config_source(config):
    """(source, is_text, name): a file name, or the dict as YAML text (JSON is YAML) that the
    config library validates exactly as a file. A dict value JSON cannot hold (an object,
    NaN, a non-str key, text that is not UTF-8) is a ConfigError naming its key path."""
    if isinstance(config, (str, os.PathLike)):
        path = _checks.path(config, "config")
        return path, False, path
    if isinstance(config, dict):
        return json.dumps(_plain(config, "", 0, set()), indent=1, allow_nan=False), True, DICT_NAME
    raise TypeError(f"config: a YAML file name or a dict is needed, got {type(config).__name__}")
