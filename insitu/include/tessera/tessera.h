/* Tessera in situ C API (docs/c-api.md).
 *
 * A simulation opens an adapter once with a YAML config, calls tessera_execute once per
 * step with descriptors of its own arrays, and closes it at the end. Field memory is read in
 * place, only during tessera_execute / tessera_execute_final, and only when a render fires:
 * a call where no trigger fires returns without touching it. No function lets an exception,
 * a signal or an abort out, whatever the input; with `on_error: abort` a failure makes every
 * later tessera_execute return that error.
 *
 * Thread safety: calls on one adapter never race. tessera_close while another thread is
 * inside a call waits for that call to return; calls that arrive during a close, or while
 * another thread's call is inside, are refused (TESSERA_ERROR_CONFIG, nothing done, the
 * message in that thread's tessera_last_error(adapter)). Distinct adapters are independent.
 * With MPI every call except tessera_last_error and tessera_field_unchanged is collective
 * over the communicator given to tessera_open (or tessera_open_with_output_dir).
 *
 * C99-compatible; usable from C++ (extern "C"). */
#ifndef TESSERA_TESSERA_H
#define TESSERA_TESSERA_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct tessera_adapter tessera_adapter; /* opaque */

typedef enum {
  TESSERA_OK = 0,
  TESSERA_ERROR_CONFIG,   /* the YAML config failed to load (file:line:col: key: fault) */
  TESSERA_ERROR_DATA,     /* a field or grid descriptor is invalid */
  TESSERA_ERROR_RENDER,   /* preparing or rendering failed (camera, envmap, MPI, ...) */
  TESSERA_ERROR_IO,       /* an output could not be written */
  TESSERA_ERROR_DISABLED  /* on_error: disable: a render failed max_failures times in a row */
} tessera_status;

typedef enum {
  TESSERA_UINT8,
  TESSERA_INT16,
  TESSERA_UINT16,
  TESSERA_FLOAT32,
  TESSERA_FLOAT64,
  TESSERA_INT32, /* index arrays only (connectivity of a curvilinear or unstructured mesh) */
  TESSERA_INT64  /*   ... likewise */
} tessera_dtype;

/* One scalar field on a uniform grid, never copied. Vertex-centred: element (i, j, k) of the
 * array, ghosts included, lies at data + i*byte_strides[0] + j*byte_strides[1] +
 * k*byte_strides[2]; i need not be the fastest axis (any positive or negative strides whose
 * elements do not overlap). */
typedef struct {
  const char*   name;
  const void*   data;             /* first element of the array as the simulation holds it */
  tessera_dtype dtype;
  int64_t       dims[3];          /* local array extent incl. ghosts, i j k */
  int64_t       byte_strides[3];  /* distance in bytes between neighbours along i j k */
  int64_t       ghosts_lo[3];     /* ghost layers to skip at the low end of each axis */
  int64_t       ghosts_hi[3];     /*   ... and at the high end */
} tessera_field;

/* Where this rank's real (non-ghost) vertices sit globally. */
typedef struct {
  double  origin[3];              /* world position of global vertex (0,0,0) */
  double  spacing[3];             /* > 0 and finite */
  int64_t global_dims[3];         /* vertices of the whole domain */
  int64_t offset[3];              /* global index of this rank's first real vertex */
} tessera_grid;

/* ---- Several blocks per rank: a mesh and its domains (docs/data-model.md) ----------------
 * The terms follow Conduit's Mesh Blueprint: a *domain* is one block of the mesh with its own
 * arrays; a rank holds zero, one or many. tessera_execute is tessera_execute_domains with one
 * vertex-centred, uniform, single-level domain. */

/* What an array element is: a vertex (the value sits on the grid point) or a cell (the value
 * sits at the cell's centre and the medium fills the cell's whole box). */
typedef enum { TESSERA_VERTEX = 0, TESSERA_CELL = 1 } tessera_association;

/* The whole mesh; the same on every rank (the ranks compare it, coordinates included, at each
 * call where a render fires). */
typedef struct {                      /* the whole mesh; the same on every rank */
  tessera_association association;    /* what an array element is: a vertex or a cell */
  double        origin[3];            /* world position of level 0's element (0,0,0): the vertex,
                                         or the low corner of the cell */
  double        spacing[3];           /* level 0 spacing (uniform axes) */
  const double* coords[3];            /* per axis: NULL = uniform; else the level-0 vertex
                                         coordinates along that axis, increasing (rectilinear):
                                         global_dims[a] values for vertex data, + 1 for cell data */
  int64_t       global_dims[3];       /* level-0 elements (vertices or cells) of the whole mesh */
  int           nlevels;              /* 1 = single level; AMR: levels 0 (coarsest) .. nlevels-1 */
  const int*    refinement;           /* nlevels-1 ratios (2 or 4): level l+1 splits each level-l
                                         cell (or interval) into ratio^3 (NULL when nlevels = 1) */
  int           axes_from_domains;    /* bit a (1, 2, 4 for i, j, k) set: axis a is rectilinear and
                                         its coordinates come in pieces from the domains
                                         (tessera_domain coords[a]); coords[a] then NULL and
                                         spacing[a] ignored. 0 (zero-initialised): none */
} tessera_mesh;
/* Notes on tessera_mesh:
 * - A rectilinear axis (coords[a] non-NULL) is read in place, never copied; its values must be
 *   finite and strictly increasing, and spacing[a] is then ignored. A uniform axis needs a
 *   finite spacing[a] > 0. origin must be finite.
 * - Refinement levels: nlevels in [1, 8]; with nlevels > 1, refinement points to nlevels - 1
 *   ratios, each 2 or 4, and every axis is uniform (rectilinear axes with levels: not yet,
 *   TESSERA_ERROR_DATA). Level l has (global_dims - 1) * R + 1 vertices (vertex data) or
 *   global_dims * R cells (cell data) per axis, R the product of refinement[0 .. l-1]. Level 0's
 *   domains cover the mesh; each finer level's domains lie inside the region of the level below
 *   and do not overlap one another. A point takes the finest level whose interpolation stencil
 *   lies in real elements of that level, so the image does not depend on how a level is cut
 *   into domains or spread over ranks, in replicated and in distributed mode. */

/* One block this rank holds, never copied. */
typedef struct {                      /* one block this rank holds, never copied */
  int                  level;         /* 0 for single-level data */
  int64_t              offset[3];     /* global index, at its level, of its first real element */
  const tessera_field* fields;        /* its arrays, as in tessera_execute (dims incl. ghosts) */
  int                  nfields;
  const tessera_association* associations; /* NULL: every field has the mesh's association;
                                         else nfields entries: fields[f] is vertex or cell data
                                         (Blueprint's per-field association) */
  const double*        coords[3];     /* axes_from_domains: this domain's piece of axis a, read in
                                         place: coords_count[a] vertex coordinates (ghosts may be
                                         included), the first at global level-0 vertex index
                                         coords_start[a]; NULL: this domain gives none */
  int64_t              coords_start[3];
  int64_t              coords_count[3];
} tessera_domain;
/* Notes on tessera_domain:
 * - Every domain of every rank publishes the same fields: the same names with the same
 *   dtypes and associations (in any order); strides and ghosts may differ from domain to
 *   domain.
 * - Mixed associations (Blueprint's vertex and element fields on one topology): a field's
 *   association says how it sits on the mesh's points and cells. The mesh's global_dims count
 *   elements of the mesh's own association; a field of the other association has one element
 *   more (vertex data on a cell mesh) or one less (cell data on a vertex mesh) per axis, on the
 *   same origin, spacing and coordinates, and its domain's offset and dims count its own
 *   elements. A client that zero-initialises the struct (associations NULL) is unchanged.
 * - Per-domain coordinates (Blueprint's rectilinear coordset per domain): with bit a of the
 *   mesh's axes_from_domains set, the ranks gather every domain's piece of axis a (vertex
 *   indices outside the mesh are ignored) and assemble the global axis: every vertex must be
 *   covered, and pieces that overlap (ghosts) must agree bit for bit; otherwise
 *   TESSERA_ERROR_DATA naming the rank, domain, axis and index. Single-level meshes only.
 *   Collective at each call where a render fires: every rank's pieces travel to every rank.
 * - Ghost layers are skipped: the renderer reads every value from the domain that owns it
 *   (replica or brick cache), so ghosts are never needed and never read.
 * - Real (non-ghost) elements of all domains of one level over all ranks may not overlap;
 *   level 0's must cover the whole mesh. offset and the arrays count elements of the
 *   domain's level. */

/* The most domains one rank may pass in one call (a larger ndomains is TESSERA_ERROR_DATA).
 * Checking how the domains of all ranks fit together costs O(N log N) time and about 128
 * bytes per domain (N: domains over all ranks), on every rank, at each call that renders. */
#define TESSERA_MAX_DOMAINS 1048576

/* Loads and validates the config (errors name file:line:column and key path), creates
 * output_dir and writes output_dir/tessera_effective_config.yaml (rank 0). mpi_comm_f: a
 * Fortran communicator handle (MPI_Comm_c2f(comm)) or -1 for no MPI. On failure *out is set
 * to NULL and tessera_last_error(NULL) describes the fault. */
tessera_status tessera_open(const char* yaml_path, int mpi_comm_f, tessera_adapter** out);

/* As tessera_open, with output_dir replacing the config's tessera.output_dir once the config
 * has loaded and validated: images, Cinema databases and tessera_effective_config.yaml (which
 * shows the override) go under it. Kept as given (a relative directory is relative to the
 * process's working directory, not to the YAML file). NULL or "" = the config's output_dir.
 * Every rank passes the same value. Same statuses and error reporting as tessera_open. */
tessera_status tessera_open_with_output_dir(const char* yaml_path, int mpi_comm_f,
                                            const char* output_dir, tessera_adapter** out);

/* Evaluates every render's trigger for this step and renders those that fire. Returns at
 * once, touching no field data (nor the descriptors), when none fires. The descriptors and
 * the memory they point at need only be valid during the call. Returns TESSERA_OK, else the
 * status of the first render that failed (with on_error warn or disable the other renders
 * still run), else TESSERA_ERROR_DISABLED if a render that fired has been disabled (after
 * max_failures consecutive failures; once every render is, at once). */
tessera_status tessera_execute(tessera_adapter* adapter, int64_t step, double time,
                               const tessera_grid* grid, const tessera_field* fields,
                               int nfields);

/* As tessera_execute, for the simulation's last step: with the global option
 * render_final_step: true every render fires, whatever its trigger; otherwise the same as
 * tessera_execute. (Field memory is not valid at tessera_close, so the final render happens
 * here.) */
tessera_status tessera_execute_final(tessera_adapter* adapter, int64_t step, double time,
                                     const tessera_grid* grid, const tessera_field* fields,
                                     int nfields);

/* As tessera_execute, for data held as several blocks per rank (zero included): `mesh`
 * describes the whole mesh (the same on every rank), `domains` this rank's ndomains blocks.
 * Everything tessera_execute says holds (triggers, statuses, descriptors valid only during the
 * call, field memory read only when a render fires). TESSERA_ERROR_DATA, on every rank alike
 * and before anything is rendered or written, with a message naming the rank, domain, field
 * and axis, for: a NULL mesh; NULL domains with ndomains > 0; ndomains < 0 or above
 * TESSERA_MAX_DOMAINS; NULL fields with nfields > 0; domains whose field lists differ in names
 * or dtypes; nlevels outside [1, 8], a refinement ratio other than 2 or 4, a domain level
 * outside [0, nlevels), rectilinear axes with levels (not yet); a non-finite origin; a uniform
 * axis whose spacing is not finite and > 0; rectilinear coordinates that are not finite and
 * strictly increasing; a mesh that differs between ranks; ghosts that leave no real element;
 * a domain outside the mesh; real elements of two domains (of any ranks) that overlap, or
 * that leave part of the mesh uncovered. The image does not depend on how the same data is
 * cut into domains or spread over ranks: it is bit-identical. */
tessera_status tessera_execute_domains(tessera_adapter* adapter, int64_t step, double time,
                                       const tessera_mesh* mesh,
                                       const tessera_domain* domains, int ndomains);

/* As tessera_execute_domains, for the simulation's last step (see tessera_execute_final). */
tessera_status tessera_execute_domains_final(tessera_adapter* adapter, int64_t step, double time,
                                             const tessera_mesh* mesh,
                                             const tessera_domain* domains, int ndomains);

/* ---- Curvilinear and unstructured meshes (docs/data-model.md) ------------------------------
 * Blueprint's other topologies: `explicit` coordinate sets with a `structured` topology (a
 * curvilinear grid: a logical i, j, k grid whose vertices have explicit x, y, z) or an
 * `unstructured` one (an element list of one shape). */

typedef enum { TESSERA_HEX = 0, TESSERA_TET = 1, TESSERA_WEDGE = 2, TESSERA_PYRAMID = 3 } tessera_shape;

typedef struct {                      /* explicit vertex coordinates, read in place */
  const void*   x;                    /* vertex v's x at x + v * byte_stride; likewise y, z */
  const void*   y;
  const void*   z;
  tessera_dtype dtype;                /* TESSERA_FLOAT32 or TESSERA_FLOAT64 */
  int64_t       byte_stride;          /* between consecutive vertices (the same for x, y, z) */
  int64_t       count;                /* vertices */
} tessera_coordset;

typedef struct {                      /* one curvilinear or unstructured domain this rank holds */
  tessera_association  association;   /* the fields' values per vertex or per cell */
  tessera_coordset     coords;
  int64_t              dims[3];       /* curvilinear: vertices per logical axis (i fastest in
                                         coords; count = dims[0]*dims[1]*dims[2]); unstructured: 0 */
  tessera_shape        shape;         /* unstructured: the element shape */
  const void*          connectivity;  /* unstructured: ncells x (8 hex, 4 tet, 6 wedge, 5 pyramid)
                                         vertex indices, in Blueprint's (VTK's) order */
  tessera_dtype        index_dtype;   /* TESSERA_INT32 or TESSERA_INT64 */
  int64_t              ncells;        /* unstructured: elements; curvilinear: ignored */
  const tessera_field* fields;        /* per vertex (coords.count values) or per cell (ncells, or
                                         the logical cells of a curvilinear domain); a 1-D array
                                         has dims {n, 1, 1} and its stride in byte_strides[0] */
  int                  nfields;
  const char*          ghost_field;   /* NULL, or a TESSERA_UINT8 cell field: nonzero = a ghost
                                         cell, never sampled */
} tessera_mesh_domain;
/* Notes on tessera_mesh_domain:
 * - The mesh is the union of every rank's domains; a rank may pass none. Every domain publishes
 *   the same fields (names and dtypes). Real cells of different domains may not overlap (ghost
 *   cells may); the image does not depend on how the cells are cut into domains or spread over
 *   ranks: bit-identical for any decomposition, thread count and rank count.
 * - Vertex data: barycentric on tetrahedra, trilinear in the element's parametric coordinates
 *   on hexahedra and curvilinear cells; cell data is constant over the cell. Outside every
 *   element the medium is empty.
 * - Hexahedra and tetrahedra are rendered; wedges and pyramids are refused (not yet). Every
 *   element must be positively oriented in VTK's order (a curvilinear grid may be of either
 *   handedness, the same throughout). A field's ghosts_lo / ghosts_hi must be 0 (a ghost
 *   cell is marked by ghost_field).
 * - Under MPI every rank receives every rank's domains at each call that renders (replicated
 *   mode: a copy per rank, counted against tessera.memory_limit_mb); distributed mode is
 *   refused for these meshes (not yet). */

/* As tessera_execute_domains, for curvilinear and unstructured domains. TESSERA_ERROR_DATA, on
 * every rank alike and before anything is rendered or written, with a message naming the rank,
 * domain and element, for: NULL domains with ndomains > 0; ndomains < 0 or above
 * TESSERA_MAX_DOMAINS; NULL fields with nfields > 0; domains whose field lists differ in names
 * or dtypes; a dtype or shape out of range; an index out of range; negative counts; counts
 * times strides that overflow; NaN or infinite coordinates; a degenerate or inverted element; a
 * field or ghost field of the wrong length or dtype; no domain on any rank. */
tessera_status tessera_execute_mesh_domains(tessera_adapter* adapter, int64_t step, double time,
                                            const tessera_mesh_domain* domains, int ndomains);
/* As tessera_execute_mesh_domains, for the simulation's last step (see tessera_execute_final). */
tessera_status tessera_execute_mesh_domains_final(tessera_adapter* adapter, int64_t step,
                                                  double time, const tessera_mesh_domain* domains,
                                                  int ndomains);

/* For language bindings (the Fortran module): stands for one tessera_execute (domains_call 0),
 * tessera_execute_domains (domains_call 1) or tessera_execute_mesh_domains (domains_call 2) call, tessera_execute_final /
 * tessera_execute_domains_final with final_step 1, whose descriptors the binding refused on
 * this rank before they reached the library (an array shorter than its descriptor claims,
 * which C cannot see). Collective like that call, whose place it takes on this rank; reads no
 * descriptor. Triggers are evaluated as in that call; a render that fires fails on every rank
 * with TESSERA_ERROR_DATA, this rank's message (and log line) being `reason` (NULL or "": a
 * generic one), the other ranks' naming this rank and quoting it. Returns as that call would. */
tessera_status tessera_execute_refused(tessera_adapter* adapter, int64_t step, double time, int domains_call,
                                       int final_step, const char* reason);
/* The simulation's promise that the values of the field named field_name (its tessera_field
 * name) at the next tessera_execute / tessera_execute_final are bit-for-bit those it had at
 * the last one. That call then reuses what the adapter derived from the values (the field
 * summary behind the majorant grid and `range: auto`) instead of reading them again.
 * One-shot: it applies to the next execute call only, whether a render fires in it or not;
 * without it the next render reads the field again. The adapter still compares the field's
 * layout (data pointer, dtype, dims, strides, ghosts, global placement) and reads it again
 * when that differs. The promise itself is not checked: values that did change give
 * majorants that may be too low, i.e. a biased image. With MPI not collective: the summary is
 * reused only if every rank made this call before the execute (they agree inside it).
 * Returns TESSERA_OK; TESSERA_ERROR_CONFIG for a NULL adapter (tessera_last_error(NULL) says
 * so); TESSERA_ERROR_DATA for a NULL field_name or a name no render of the config can use
 * (tessera_last_error(adapter) says which). */
tessera_status tessera_field_unchanged(tessera_adapter* adapter, const char* field_name);

/* The simulation's promise that at the next tessera_execute_mesh_domains (or its final form)
 * this rank passes the same domains, in the same order, with bit-for-bit the same coordinates,
 * connectivity, dims, shapes and ghost fields as at the last such call: only field values may
 * differ. That call then reuses the mesh's lookup structure (the elements' canonical order,
 * boxes and location lists: about 200 to 480 bytes and an O(n log n) sort per cell) and checks
 * the descriptors, every cell's vertex indices and its vertices' coordinates (finite), not the
 * cells' shapes, instead of building and checking every element again; the image is
 * bit-identical. One-shot, like tessera_field_unchanged; with MPI not collective: the
 * structure is reused only if every rank made this call (they agree inside the execute). The
 * adapter still compares the domains' counts and shapes and builds again when they differ (a
 * broken promise gives a wrong image, never a read outside the arrays). Without the promise,
 * a mesh whose geometry hashes as the one the structure was built over (two independent
 * 64-bit hashes of the coordinates, connectivity and ghost flags: one pass, on the GPU for a
 * mesh in device memory on one rank) is reused the same way; the promise saves that pass.
 * Within one execute call every render after the first reuses the structure anyway. "The
 * last such call" is the last one whether a render fired at it or not: after a call that
 * moved the mesh without the promise and rendered nothing, the structure is of an older
 * geometry, so the next promise does not carry it (the hash decides instead); a promise at
 * every call, rendering or not, carries it throughout.
 * Returns TESSERA_OK, or TESSERA_ERROR_CONFIG for a NULL or closed adapter. */
tessera_status tessera_mesh_unchanged(tessera_adapter* adapter);

/* The CUDA stream (a cudaStream_t, passed as void* so that this header needs no CUDA) on which
 * the simulation computes its device arrays. Device (or managed) memory in a field's data is
 * recognised (cudaPointerGetAttributes) and, with `tessera.device: auto` or `cuda`, read in
 * place on the GPU (docs/gpu.md). Before reading device arrays Tessera waits for the work
 * queued on this stream; with none set (NULL, the default) it synchronises the whole device
 * first. Every execute call returns only when the GPU no longer reads the arrays, so the
 * simulation may overwrite them at once. Kept until set again. Not collective. Returns
 * TESSERA_OK, or TESSERA_ERROR_CONFIG for a NULL or closed adapter. */
tessera_status tessera_set_cuda_stream(tessera_adapter* adapter, void* cuda_stream);

/* Releases the adapter (NULL is allowed and returns TESSERA_OK). Handles are validated: a
 * second tessera_close of the same handle, or tessera_execute / tessera_execute_final /
 * tessera_field_unchanged after its close, returns TESSERA_ERROR_CONFIG and
 * tessera_last_error(adapter) says "adapter was closed ..." (the library keeps a 16-byte
 * tombstone per closed handle, so its address never names a newer adapter); a pointer that
 * tessera_open never returned is refused the same way ("not an adapter returned by
 * tessera_open"). A close while another thread is inside a call on the adapter waits for
 * that call to return; calls meanwhile return TESSERA_ERROR_CONFIG ("adapter is being
 * closed"); a second close at the same time waits, then finds the adapter closed. With MPI
 * collective: the ranks check that every one of them is closing; a rank still inside a call
 * that renders (tessera_execute_final on some ranks only) makes that call and this close
 * return TESSERA_ERROR_CONFIG ("ranks disagree on the call: ..."), the adapter released all
 * the same and the message kept for tessera_last_error(adapter). */
tessera_status tessera_close(tessera_adapter* adapter);

/* The adapter's last error message, or "" if the last call succeeded; with NULL, the calling
 * thread's last tessera_open (or tessera_open_with_output_dir) failure. For an adapter, a
 * copy for the calling thread, valid until this thread's next tessera_last_error on the same
 * adapter, even across tessera_close (a call refused on this thread shows its own message, to
 * this thread only); for NULL, valid until the next open on this thread. Never NULL.
 * tessera_field_unchanged(NULL, ...) also sets the NULL message. */
const char* tessera_last_error(const tessera_adapter* adapter);

#ifdef __cplusplus
} /* extern "C" */
#endif

#endif /* TESSERA_TESSERA_H */
