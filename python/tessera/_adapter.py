"""tessera.Adapter: the in situ adapter (C API, docs/c-api.md) for simulations in Python."""
import warnings

from . import _checks, _tessera
from ._arrays import field_descriptor
from ._config import config_source
from ._errors import TesseraError, TesseraWarning

MAX_LEVELS = 8  # the most refinement levels a mesh may have


class Adapter:
    """Opens the adapter at construction (collective over ``comm``), renders in execute(),
    releases everything in close(); also a context manager.

    config: a YAML file name or a dict of the same schema; checked at once (ConfigError with
        the key path).
    comm: an mpi4py communicator (every rank of it constructs, executes and closes together)
        or None for one process.
    output_dir: replaces the config's ``tessera.output_dir`` (None: the config's).
    quiet: no per-render log line on stderr (failures are still reported).
    """

    def __init__(self, config, comm=None, output_dir=None, quiet=False):
        self._impl = None
        source, is_text, name = config_source(config)
        if comm is not None and not callable(getattr(comm, "py2f", None)):
            raise TypeError(f"comm: an mpi4py communicator or None is needed, got {type(comm).__name__}")
        out = "" if output_dir is None else _checks.path(output_dir, "output_dir")
        quiet = _checks.flag(quiet, "quiet")
        comm_f = -1 if comm is None else int(comm.py2f())
        self._comm = comm  # kept alive while the adapter uses its duplicate
        self._impl = _tessera.Adapter(source, is_text, name, comm_f, out, quiet)
        self.last_status = 0
        self.last_error = ""
        self.results = []

    def execute(self, step, time, fields=None, *, spacing=1.0, origin=0.0, global_dims=None, offset=0,
                ghosts=0, ghosts_hi=None, final=False, domains=None, association="vertex", coords=None,
                nlevels=1, refinement=None):
        """Renders what the triggers fire at ``step`` and returns ``{render name: image}``:
        float32 (height, width, 4) linear RGBA arrays of the renders that succeeded, on rank 0
        (an empty dict on other ranks and when nothing fired). The outputs the config asks for
        are written too.

        fields: ``{name: 3D array}``, each read in place during this call only (any dtype and
            strides of tessera.render; ``u[i, j, k]`` is vertex (i, j, k), ghosts included).
        spacing, origin: the grid (a number or 3); origin is global vertex (0, 0, 0).
        global_dims: vertices of the whole domain (default: this rank's real vertices, i.e.
            one process owns everything); offset: global index of this rank's first real vertex.
        ghosts: ghost layers at the low end of each axis (and the high end unless ghosts_hi).
        final: the simulation's last step (``render_final_step`` renders every render).

        Several blocks per rank (docs/data-model.md): instead of ``fields``, ``domains`` is a
        list (empty allowed) of dicts ``{"fields": {name: 3D array}, "offset": (i, j, k),
        "ghosts": g, "ghosts_hi": g}`` (offset, ghosts default 0, ghosts_hi defaults to ghosts),
        one per block this rank holds; ``global_dims`` (required), ``spacing`` and ``origin``
        then describe the whole mesh, the same on every rank; ``association`` is "vertex" or
        "cell"; ``coords`` None or three entries, each None (a uniform axis) or a 1-D
        contiguous float64 array of the axis' increasing coordinates (global_dims[a] values,
        + 1 for cell data), read in place. Every domain publishes the same field names and
        dtypes; their real elements tile the mesh.

        Refinement levels (AMR, docs/data-model.md): ``nlevels`` levels (1 .. 8), level 0 the
        mesh above; ``refinement`` a list of nlevels - 1 integer ratios (2 or 4), level l + 1
        splitting each level-l cell into ``refinement[l]`` parts per axis; each domain's
        ``"level"`` (default 0) says its level, its ``"offset"`` is then an index of that
        level. Only with ``domains``.

        A failing render follows the config's ``on_error``: ``warn`` and ``disable`` issue a
        TesseraWarning and go on (last_status, last_error and results say what failed);
        ``abort`` raises (DataError, RenderError, OutputError, DisabledError).

        Arguments are checked, never converted (docs/python.md, "Arguments"): step an integer,
        time a real number, ghosts / global_dims / offset integers, spacing / origin finite
        numbers, field names str without NUL; TypeError or ValueError naming the argument.
        """
        impl = self._impl  # another thread's close() may clear self._impl meanwhile
        if impl is None:
            raise TesseraError("execute: the adapter is closed")
        try:
            step_i = _checks.integer(step, "step")
            time_f = _checks.real(time, "time")
            final_b = _checks.flag(final, "final")
            if domains is not None:
                if fields is not None:
                    raise TypeError("fields and domains: give one of them, not both")
                call = self._domains_call(domains, spacing, origin, global_dims, association, coords, nlevels,
                                          refinement)
            elif nlevels != 1 or refinement is not None:
                raise TypeError("nlevels and refinement: refinement levels need domains (each with its level)")
            elif not isinstance(fields, dict):
                raise TypeError(f"fields: a dict {{name: array}} is needed, got {type(fields).__name__}")
            if domains is None:
                call = self._fields_call(fields, spacing, origin, global_dims, offset, ghosts, ghosts_hi)
        except Exception:
            if self._comm is not None:
                self._enter_without_fields(impl, step, time, final)
            raise
        held, args = call
        if domains is None:
            status = impl.execute(step_i, time_f, *args, final_b)
        else:
            status = impl.execute_domains(step_i, time_f, *args, final_b)
        del held  # the arrays were read in place during the call
        return self._outcome(impl, status, step)

    @staticmethod
    def _fields_call(fields, spacing, origin, global_dims, offset, ghosts, ghosts_hi):
        """(arrays held, the binding's execute arguments but step, time, final)."""
        lo = _checks.integer_triple(ghosts, "ghosts")
        hi = lo if ghosts_hi is None else _checks.integer_triple(ghosts_hi, "ghosts_hi")
        held, descs = [], []
        for fname, array in fields.items():
            fname = _checks.name(fname, "fields key")
            a, address, code, dims, strides = field_descriptor(array, f"fields['{fname}']")
            held.append(a)
            descs.append((fname, address, code, dims, strides, lo, hi))
        if global_dims is None:
            first = descs[0][3] if descs else (1, 1, 1)
            global_dims = tuple(first[a] - lo[a] - hi[a] for a in range(3))
        grid = (_checks.real_triple(origin, "origin"), _checks.real_triple(spacing, "spacing"),
                _checks.integer_triple(global_dims, "global_dims"), _checks.integer_triple(offset, "offset"))
        return held, (*grid, descs)

    @staticmethod
    def _domains_call(domains, spacing, origin, global_dims, association, coords, nlevels, refinement):
        """(arrays held, the binding's execute_domains arguments but step, time, final)."""
        levels = _checks.integer(nlevels, "nlevels", bits=32)
        if not 1 <= levels <= MAX_LEVELS:
            raise ValueError(f"nlevels: 1 .. {MAX_LEVELS} levels are allowed, got {levels}")
        if refinement is None:
            if levels > 1:
                raise TypeError(f"refinement: {levels - 1} ratio(s) are needed for nlevels = {levels} (a list "
                                f"of 2s or 4s), got None")
            ratios = []
        else:
            if not isinstance(refinement, (list, tuple)):
                raise TypeError(f"refinement: a list of {levels - 1} integer ratio(s) is needed, got "
                                f"{type(refinement).__name__}")
            if len(refinement) != levels - 1:
                raise ValueError(f"refinement: nlevels - 1 = {levels - 1} ratio(s) are needed, got "
                                 f"{len(refinement)}")
            ratios = [_checks.integer(r, f"refinement[{n}]", bits=32) for n, r in enumerate(refinement)]
        if association not in ("vertex", "cell"):
            raise ValueError(f"association: 'vertex' or 'cell' is needed, got {association!r}")
        if global_dims is None:
            raise TypeError("global_dims: required with domains (the whole mesh's elements)")
        dims = _checks.integer_triple(global_dims, "global_dims")
        if not isinstance(domains, (list, tuple)):
            raise TypeError(f"domains: a list of dicts is needed, got {type(domains).__name__}")
        held, addresses = [], [0, 0, 0]
        if coords is not None:
            if not isinstance(coords, (list, tuple)) or len(coords) != 3:
                raise TypeError("coords: None or three entries (None or a 1-D float64 array each) are needed")
            for a, c in enumerate(coords):
                if c is None:
                    continue
                n = dims[a] + (1 if association == "cell" else 0)
                ok = (getattr(c, "dtype", None) is not None and str(c.dtype) == "float64" and c.ndim == 1
                      and c.flags["C_CONTIGUOUS"] and c.shape[0] == n)
                if not ok:
                    raise ValueError(f"coords[{a}]: a 1-D contiguous float64 array of {n} values is needed "
                                     f"(global_dims[{a}] = {dims[a]}, {association} data)")
                held.append(c)
                addresses[a] = int(c.ctypes.data)
        known = {"fields", "offset", "ghosts", "ghosts_hi", "level"}
        blocks = []
        for d, dom in enumerate(domains):
            if not isinstance(dom, dict):
                raise TypeError(f"domains[{d}]: a dict is needed, got {type(dom).__name__}")
            unknown = sorted(set(dom) - known)
            if unknown:
                raise ValueError(f"domains[{d}]: unknown keys {unknown} (known: {sorted(known)})")
            fields = dom.get("fields")
            if not isinstance(fields, dict):
                raise TypeError(f"domains[{d}]['fields']: a dict {{name: array}} is needed")
            lo = _checks.integer_triple(dom.get("ghosts", 0), f"domains[{d}]['ghosts']")
            hi = lo if dom.get("ghosts_hi") is None else _checks.integer_triple(dom["ghosts_hi"], f"domains[{d}]['ghosts_hi']")
            descs = []
            for fname, array in fields.items():
                fname = _checks.name(fname, f"domains[{d}]['fields'] key")
                a, address, code, fdims, strides = field_descriptor(array, f"domains[{d}]['fields']['{fname}']")
                held.append(a)
                descs.append((fname, address, code, fdims, strides, lo, hi))
            level = _checks.integer(dom.get("level", 0), f"domains[{d}]['level']", bits=32)
            blocks.append((level, _checks.integer_triple(dom.get("offset", 0), f"domains[{d}]['offset']"), descs))
        args = (0 if association == "vertex" else 1, _checks.real_triple(origin, "origin"),
                _checks.real_triple(spacing, "spacing"), tuple(addresses), dims, levels, ratios, blocks)
        return held, args

    def _outcome(self, impl, status, step):
        """Records the call's status, warns, and returns rank 0's images."""
        self.last_status = status
        self.last_error = impl.last_error()
        self.results = impl.results()
        if status != 0:
            warnings.warn(f"tessera: step {step}: {self.last_error}", TesseraWarning, stacklevel=3)
        images = {}
        for r in self.results:
            for w in r["warnings"]:
                warnings.warn(f"render '{r['name']}' at step {step}: {w}", TesseraWarning, stacklevel=3)
            if r["image"] is not None:
                images[r["name"]] = r["image"]
        return images

    def _enter_without_fields(self, impl, step, time, final):
        """An argument this rank could not describe, under MPI: the other ranks are entering
        the collective call, so this rank enters it too, with no fields. A render that fires
        then fails on every rank (its field is missing here, and the ranks agree on failure
        before any collective) instead of leaving the others waiting; the caller then raises
        the argument's own error on this rank."""
        try:  # a step or time refused above is entered as its int / float if it has one
            impl.execute(int(step), float(time), (0.0, 0.0, 0.0), (1.0, 1.0, 1.0), (1, 1, 1), (0, 0, 0),
                         [], bool(final))
        except Exception:  # the argument error raised next says what is wrong
            pass

    def close(self):
        """Releases the adapter (collective); idempotent. Safe while another thread is inside
        execute(): close waits for that call to return, and calls made meanwhile are refused
        (their status is nonzero and last_error says "adapter is being closed"). With MPI, a
        rank that disagreed about the calls (execute(final=True) on some ranks only) is
        reported here as a TesseraWarning; everything is released all the same."""
        impl, self._impl = self._impl, None
        if impl is not None:
            status = impl.close()
            if status != 0:
                self.last_status = status
                self.last_error = impl.last_error()
                warnings.warn(f"tessera: close: {self.last_error}", TesseraWarning, stacklevel=2)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def __del__(self):
        # Not collective-safe under MPI: close() explicitly (or use `with`) there
        if getattr(self, "_impl", None) is not None and self._comm is None:
            self.close()
