"""tessera.Adapter: the in situ adapter (C API, docs/c-api.md) for simulations in Python."""
import sys
import threading
import warnings

from . import _blueprint, _checks, _mesh_domains, _tessera
from ._arrays import coordinate_array, cuda_stream_address, field_descriptor, producer_stream
from ._config import config_source
from ._errors import (ConfigError, DataError, DisabledError, OutputError, RenderError, TesseraError,
                      TesseraWarning)

MAX_LEVELS = 8  # the most refinement levels a mesh may have
# The classes a rank's refusal of the constructor is raised as on the other ranks, by name
_REFUSALS = {c.__name__: c for c in (TypeError, ValueError, ConfigError, DataError, RenderError, OutputError,
                                     DisabledError, TesseraError)}


def _mpi_of(comm):
    """mpi4py's MPI module for an mpi4py communicator, checked to be usable (TypeError for
    anything else, RenderError once MPI is finalized: a call on it would abort the process)."""
    mpi = sys.modules.get("mpi4py.MPI")
    if mpi is None or not isinstance(comm, mpi.Comm):
        raise TypeError(f"comm: an mpi4py communicator or None is needed, got {type(comm).__name__}")
    if mpi.Is_finalized():
        raise RenderError("comm: MPI is finalized (MPI.Finalize() has run): the communicator cannot be used any "
                          "more; open, execute and close the adapter before MPI.Finalize()")
    if not mpi.Is_initialized():
        raise RenderError("comm: MPI is not initialized (mpi4py.rc.initialize = False?): call MPI.Init() first")
    if comm == mpi.COMM_NULL:
        raise ValueError("comm: MPI.COMM_NULL is not a communicator (a rank outside the group it was split from "
                         "does not open the adapter)")
    return mpi


def _agree_on_opening(comm, error):
    """Collective over ``comm``: every rank learns whether any rank refused its arguments or
    its config, so that all raise, or none, before the collective open. Returns the exception
    this rank raises: its own, else the first refusing rank's (same class, its rank named),
    else None."""
    mine = None
    if error is not None:
        mine = (type(error).__name__, str(error), getattr(error, "file", ""), getattr(error, "line", 0),
                getattr(error, "column", 0), getattr(error, "key_path", ""))
    every = comm.allgather(mine)
    if error is not None:
        return error
    for rank, refusal in enumerate(every):
        if refusal is not None:
            name, message, file, line, column, key_path = refusal
            cls = _REFUSALS.get(name, TesseraError)
            text = f"rank {rank} of {len(every)} refused to open the adapter: {message}"
            return cls(text, file, line, column, key_path) if cls is ConfigError else cls(text)
    return None


class _LastCall(threading.local):
    """What the calling thread's last call on an adapter left (each thread sees its own)."""

    def __init__(self):
        self.status = 0
        self.error = ""
        self.results = []


class Adapter:
    """Opens the adapter at construction (collective over ``comm``), renders in execute(),
    releases everything in close(); also a context manager.

    config: a YAML file name or a dict of the same schema; checked at once (ConfigError with
        the key path).
    comm: an mpi4py communicator (every rank of it constructs, executes and closes together)
        or None for one process. Under MPI the ranks agree before opening: when one rank
        refuses an argument or fails to load the config, every rank raises (the others the
        same class, naming that rank); none is left waiting.
    output_dir: replaces the config's ``tessera.output_dir`` (None: the config's).
    quiet: no per-render log line on stderr (failures are still reported).

    ``last_status``, ``last_error`` and ``results`` describe the calling thread's last call.
    """

    def __init__(self, config, comm=None, output_dir=None, quiet=False):
        self._impl = None
        self._last = _LastCall()
        self._comm = self._mpi = None
        self._stream_set = False  # set_cuda_stream was called: the fields' own streams are not used
        mpi = None if comm is None else _mpi_of(comm)  # not agreed: without a communicator there is no one to ask
        error = None
        try:
            source, is_text, name = config_source(config)
            out = "" if output_dir is None else _checks.path(output_dir, "output_dir")
            quiet = _checks.flag(quiet, "quiet")
            _tessera.check_config(source, is_text, name)  # a ConfigError with its key path
        except Exception as e:  # raised below on every rank, after the ranks agree
            error = e
        if mpi is not None:
            error = _agree_on_opening(comm, error)
        if error is not None:
            raise error
        comm_f = -1 if comm is None else int(comm.py2f())
        self._comm = comm  # kept alive while the adapter uses its duplicate
        self._mpi = mpi
        self._impl = _tessera.Adapter(source, is_text, name, comm_f, out, quiet)

    @property
    def last_status(self):
        """0 or the tessera_status of the calling thread's last call (execute or close)."""
        return self._last.status

    @property
    def last_error(self):
        """The message of the calling thread's last call; "" after one that succeeded."""
        return self._last.error

    @property
    def results(self):
        """One dict per render that fired in the calling thread's last execute()."""
        return self._last.results

    def execute(self, step, time, fields=None, *, spacing=1.0, origin=0.0, global_dims=None, offset=0,
                ghosts=0, ghosts_hi=None, final=False, domains=None, association="vertex", coords=None,
                nlevels=1, refinement=None):
        """Renders what the triggers fire at ``step`` and returns ``{render name: image}``:
        float32 (height, width, 4) linear RGBA arrays of the renders that succeeded, on rank 0
        (an empty dict on other ranks and when nothing fired). The outputs the config asks for
        are written too.

        fields: ``{name: 3D array}``, each read in place during this call only (any dtype and
            strides of tessera.render; ``u[i, j, k]`` is vertex (i, j, k), ghosts included).
            A device array (``__cuda_array_interface__``: CuPy, PyTorch, Numba; or DLPack on
            a CUDA device) is read in place too, on the GPU with ``tessera.device: auto`` or
            ``cuda`` (docs/gpu_bindings.md); its values are never touched from Python.
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
        dtypes; their real elements tile the mesh. A domain's ``"associations"``: ``{name:
        "vertex" | "cell"}`` for fields whose association is not the mesh's (one element more
        or fewer per axis, on the same points and cells).

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
        numbers, field names non-empty str in UTF-8 without NUL; TypeError or ValueError naming
        the argument. ``fields`` and ``domains`` are looked into only at a step where a render
        fires (Adapter::fires): a call where nothing fires costs the same for any number of
        domains, and checks only the few numbers around them.
        """
        impl = self._impl  # another thread's close() may clear self._impl meanwhile
        if impl is None:
            raise TesseraError("execute: the adapter is closed")
        if self._mpi is not None and self._mpi.Is_finalized():  # any MPI call now aborts the process
            raise RenderError("execute: MPI is finalized (MPI.Finalize() has run): the adapter's communicator "
                              "cannot be used any more; close the adapter before MPI.Finalize()")
        try:
            step_i = _checks.integer(step, "step")
            time_f = _checks.real(time, "time")
            final_b = _checks.flag(final, "final")
            if domains is not None:
                if fields is not None:
                    raise TypeError("fields and domains: give one of them, not both")
                mesh = self._mesh(spacing, origin, global_dims, association, coords, nlevels, refinement)
                if not isinstance(domains, (list, tuple)):
                    raise TypeError(f"domains: a list of dicts is needed, got {type(domains).__name__}")
            elif _checks.integer(nlevels, "nlevels", bits=32) != 1 or refinement is not None:
                raise TypeError("nlevels and refinement: refinement levels need domains (each with its level)")
            elif not isinstance(fields, dict):
                raise TypeError(f"fields: a dict {{name: array}} is needed, got {type(fields).__name__}")
            else:
                lo = _checks.integer_triple(ghosts, "ghosts")
                hi = lo if ghosts_hi is None else _checks.integer_triple(ghosts_hi, "ghosts_hi")
                grid = [_checks.real_triple(origin, "origin"), _checks.real_triple(spacing, "spacing"),
                        None if global_dims is None else _checks.integer_triple(global_dims, "global_dims"),
                        _checks.integer_triple(offset, "offset")]
            # The arrays are looked at only when a render fires (or may: `when`), as in the C
            # API: a call where nothing fires costs the same for one domain or a million
            fires = impl.fires(step_i, final_b)
            if domains is not None:
                held, blocks = self._blocks(domains, mesh[0]) if fires else ([], [])
            else:
                held, descs = self._descriptors(fields, lo, hi, "fields") if fires else ([], [])
                if grid[2] is None:  # this rank's real vertices
                    first = descs[0][3] if descs else (1, 1, 1)
                    grid[2] = tuple(first[a] - lo[a] - hi[a] for a in range(3))
        except Exception as e:
            if self._comm is not None:
                self._enter_without_fields(impl, step, time, final, 0 if domains is None else 1, e)
            raise
        stream = self._call_stream(held)
        if domains is None:
            outcome = impl.execute(step_i, time_f, *grid, descs, final_b, stream)
        else:
            outcome = impl.execute_domains(step_i, time_f, *mesh, blocks, final_b, stream)
        del held  # the arrays were read in place during the call
        return self._outcome(outcome, step)

    def execute_mesh_domains(self, step, time, domains, *, final=False):
        """execute() for curvilinear and unstructured domains (docs/python.md, "Curvilinear and
        unstructured meshes"; the C API's tessera_execute_mesh_domains): ``domains`` is a list
        (empty allowed) of this rank's domains, each a dict or a tessera.MeshDomain with
        ``coords`` (an (n, 3) array or three arrays x, y, z, float32 or float64, one dtype and
        one stride), ``dims`` (curvilinear: vertices along i, j, k, i fastest) or ``shape``
        ('hex' or 'tet') and ``connectivity`` (int32 or int64, (ncells, 8 | 4) or flat, 0-based,
        VTK's order), ``fields`` ``{name: array}`` (1-D, any stride; curvilinear also 3-D [i, j,
        k] held i fastest), ``association`` ('vertex', the default, or 'cell') or per field
        ``associations``, and ``ghost_field`` (a uint8 cell field, nonzero = ghost). Every array
        is read in place during this call only; the mesh is the union of every rank's domains.

        Returns, warns and raises as execute() does; faults in the arguments raise TypeError or
        ValueError naming the domain and key; an index out of range, an inverted element or
        NaN coordinates are the adapter's DataError naming the domain and element. Nothing is
        looked at where no render fires (final: the last step, as in execute()).
        """
        impl = self._impl
        if impl is None:
            raise TesseraError("execute_mesh_domains: the adapter is closed")
        if self._mpi is not None and self._mpi.Is_finalized():
            raise RenderError("execute_mesh_domains: MPI is finalized (MPI.Finalize() has run): the adapter's "
                              "communicator cannot be used any more; close the adapter before MPI.Finalize()")
        try:
            step_i = _checks.integer(step, "step")
            time_f = _checks.real(time, "time")
            final_b = _checks.flag(final, "final")
            if not isinstance(domains, (list, tuple)):
                raise TypeError(f"domains: a list of dicts or tessera.MeshDomain is needed, got "
                                f"{type(domains).__name__}")
            # As execute(domains=...): the arrays are looked at only when a render fires
            held, blocks = _mesh_domains.blocks(domains) if impl.fires(step_i, final_b) else ([], [])
        except Exception as e:
            if self._comm is not None:  # the other ranks' call fails too, with this reason
                self._enter_without_fields(impl, step, time, final, 2, e)
            raise
        outcome = impl.execute_mesh_domains(step_i, time_f, blocks, final_b, self._call_stream(held))
        del held  # the arrays were read in place during the call
        return self._outcome(outcome, step)

    def set_cuda_stream(self, stream):
        """The CUDA stream on which the simulation computes its device arrays (the C API's
        tessera_set_cuda_stream, docs/gpu_bindings.md): before reading them Tessera waits for the
        work queued on it; None (the default): it synchronises the whole device first. Kept
        until set again. ``stream``: None, an int (the raw cudaStream_t), or a stream object
        with ``.ptr`` (CuPy's Stream) or ``.cuda_stream`` (PyTorch's torch.cuda.Stream).

        Once called (None included), the stream a field names in its
        ``__cuda_array_interface__`` is no longer used for the call. Not collective. TypeError
        or ValueError for anything else; TesseraError on a closed adapter or while another
        thread is inside a call on it."""
        address = cuda_stream_address(stream)
        impl = self._impl
        if impl is None:
            raise TesseraError("set_cuda_stream: the adapter is closed")
        status, error = impl.set_cuda_stream(address)[:2]
        if status != 0:
            raise TesseraError(f"set_cuda_stream: {error}")
        self._stream_set = True

    def _call_stream(self, held):
        """The stream of one call: None (the adapter's own, set_cuda_stream's or none) once
        set_cuda_stream was called, else the one producer's stream the device fields name."""
        return None if self._stream_set else producer_stream(held)

    def execute_blueprint(self, step, time, mesh, *, final=False, topology=None,
                          ghost_field_name=_blueprint.GHOST_FIELDS):
        """execute() for a Conduit Mesh Blueprint hierarchy as nested dicts (docs/python.md,
        "Mesh Blueprint"): ``mesh`` is one domain ``{"coordsets": ..., "topologies": ...,
        "fields": ..., "state": ...}`` (Conduit's path keys ``"coordsets/coords/type"`` too), a
        list of them or a dict of named ones, numpy arrays as values (read in place). Uniform
        and rectilinear topologies, vertex or element fields, several domains per rank,
        refinement levels (``state/level_id``); the global mesh and each domain's offset are
        worked out from the coordinates of every rank's domains. ``topology``: the one to
        render where a domain has several; ``ghost_field_name``: the element field(s) marking
        ghost elements (nonzero), as whole layers at the faces. Nothing is looked at where
        no render fires; faults raise naming their path in the hierarchy, on every rank."""
        impl = self._impl
        if impl is None:
            raise TesseraError("execute_blueprint: the adapter is closed")
        if self._mpi is not None and self._mpi.Is_finalized():
            raise RenderError("execute_blueprint: MPI is finalized (MPI.Finalize() has run): the adapter's "
                              "communicator cannot be used any more; close the adapter before MPI.Finalize()")
        return _blueprint.execute(self, impl, step, time, mesh, final, topology, ghost_field_name)

    @staticmethod
    def _descriptors(fields, lo, hi, what):
        """(arrays held, the binding's field tuples) of a dict {name: array}."""
        held, descs = [], []
        for fname, array in fields.items():
            fname = _checks.name(fname, f"{what} key")
            a, address, code, dims, strides = field_descriptor(array, f"{what}[{fname!r}]")
            held.append(a)
            descs.append((fname, address, code, dims, strides, lo, hi))
        return held, descs

    @staticmethod
    def _mesh(spacing, origin, global_dims, association, coords, nlevels, refinement):
        """The binding's execute_domains arguments between time and the domains: everything
        but the domains, checked (a few numbers and the coordinate arrays, whatever the number
        of domains)."""
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
        if not isinstance(association, str) or association not in ("vertex", "cell"):
            raise ValueError(f"association: 'vertex' or 'cell' is needed, got {_checks._shown(association)}")
        if global_dims is None:
            raise TypeError("global_dims: required with domains (the whole mesh's elements)")
        dims = _checks.integer_triple(global_dims, "global_dims")
        axes = [None, None, None]
        if coords is not None:
            if not isinstance(coords, (list, tuple)) or len(coords) != 3:
                got = f"{len(coords)} entries" if isinstance(coords, (list, tuple)) else _checks._shown(coords)
                raise TypeError(f"coords: None or a list of three entries (None or a 1-D float64 array each) is "
                                f"needed, got {got}")
            extra = 1 if association == "cell" else 0
            for a, c in enumerate(coords):
                if c is not None:
                    axes[a] = coordinate_array(c, f"coords[{a}]", dims[a] + extra,
                                               f"global_dims[{a}] = {dims[a]}" + (" + 1, cell data" if extra else
                                                                                  ", vertex data"))
        return (0 if association == "vertex" else 1, _checks.real_triple(origin, "origin"),
                _checks.real_triple(spacing, "spacing"), axes, dims, levels, ratios)

    @classmethod
    def _blocks(cls, domains, association):
        """(arrays held, the binding's domain tuples (level, offset, fields, associations))."""
        known = {"fields", "offset", "ghosts", "ghosts_hi", "level", "associations"}
        held, blocks = [], []
        for d, dom in enumerate(domains):
            if not isinstance(dom, dict):
                raise TypeError(f"domains[{d}]: a dict is needed, got {type(dom).__name__}")
            unknown = [k for k in dom if k not in known]
            if unknown:
                raise ValueError(f"domains[{d}]: unknown keys {', '.join(map(repr, unknown))} (known: "
                                 f"{', '.join(sorted(known))})")
            fields = dom.get("fields")
            if not isinstance(fields, dict):
                raise TypeError(f"domains[{d}]['fields']: a dict {{name: array}} is needed")
            lo = _checks.integer_triple(dom.get("ghosts", 0), f"domains[{d}]['ghosts']")
            hi = lo if dom.get("ghosts_hi") is None else _checks.integer_triple(dom["ghosts_hi"], f"domains[{d}]['ghosts_hi']")
            a, descs = cls._descriptors(fields, lo, hi, f"domains[{d}]['fields']")
            held += a
            level = _checks.integer(dom.get("level", 0), f"domains[{d}]['level']", bits=32)
            blocks.append((level, _checks.integer_triple(dom.get("offset", 0), f"domains[{d}]['offset']"), descs,
                           cls._associations(dom.get("associations"), fields, association,
                                             f"domains[{d}]['associations']")))
        return held, blocks

    @staticmethod
    def _associations(given, fields, mesh, what):
        """The binding's per-field associations (0 vertex, 1 cell) of a domain's ``{name:
        "vertex" | "cell"}``; fields it does not name have the mesh's (code ``mesh``); [] when
        it names none (every field the mesh's)."""
        if given is None or not given:
            return []
        if not isinstance(given, dict):
            raise TypeError(f"{what}: a dict {{field name: 'vertex' or 'cell'}} is needed, got "
                            f"{_checks._shown(given)}")
        for name, a in given.items():
            if name not in fields:
                raise ValueError(f"{what}: {name!r} is not one of the domain's fields")
            if not isinstance(a, str) or a not in ("vertex", "cell"):
                raise ValueError(f"{what}[{name!r}]: 'vertex' or 'cell' is needed, got {_checks._shown(a)}")
        return [{"vertex": 0, "cell": 1}.get(given.get(name), mesh) for name in fields]

    def _outcome(self, outcome, step):
        """Records the call's own outcome (status, message, results: what this call left, not
        another thread's) for the calling thread, warns, and returns rank 0's images."""
        status, error, results = outcome
        last = self._last
        last.status, last.error, last.results = status, error, results
        if status != 0:
            warnings.warn(f"tessera: step {step}: {error}", TesseraWarning, stacklevel=3)
        images = {}
        for r in results:
            for w in r["warnings"]:
                warnings.warn(f"render '{r['name']}' at step {step}: {w}", TesseraWarning, stacklevel=3)
            if r["image"] is not None:
                images[r["name"]] = r["image"]
        return images

    def _enter_without_fields(self, impl, step, time, final, kind, error):
        """An argument this rank could not describe, under MPI: the other ranks are entering
        the collective call (`kind`: 0 execute, 1 execute with domains, 2 mesh domains), so
        this rank enters it too, as refused: a render that fires then fails on every rank with
        this rank's reason (the ranks agree on failure before any collective) instead of
        leaving the others waiting; the caller then raises the argument's own error here."""
        try:  # a step or time refused above is entered as its int / float if it has one
            impl.execute_refused(int(step), float(time), kind, f"{type(error).__name__}: {error}", bool(final))
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
            status, error = impl.close()
            if status != 0:
                self._last.status, self._last.error = status, error
                warnings.warn(f"tessera: close: {error}", TesseraWarning, stacklevel=2)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def __del__(self):
        # Not collective-safe under MPI: close() explicitly (or use `with`) there
        if getattr(self, "_impl", None) is not None and self._comm is None:
            self.close()
