!> Tessera's Fortran module (docs/fortran.md): Fortran 2008 over the C API of
!> <tessera/tessera.h> (docs/c-api.md), with iso_c_binding. Same functions, statuses and
!> lifetimes as in C; what it adds:
!>   * tessera_field_from(name, u, ...) describes a simulation array in place: the address of
!>     u's first element and its byte strides are taken from the array itself (address
!>     differences of neighbours), so an array section such as u(:, :, :, 2) or
!>     u(2:10:2, :, :) is read where it lies, without a copy;
!>   * strings are Fortran strings (trailing blanks dropped, as Fortran compares them), and
!>     tessera_last_error returns character(:), allocatable; a name or path holding a NUL
!>     character (achar(0)), which C would read as its end, is refused with a message instead
!>     of being passed on cut (the refusal's message is kept by the module, see `refused`);
!>   * a field's name is kept inside type(tessera_field); tessera_execute builds the C
!>     descriptors, with NUL-terminated names in its own storage, for the duration of the call.
!>   * several blocks per rank (domains), cell or vertex data and rectilinear axes:
!>     type(tessera_mesh), tessera_mesh_coords, tessera_domain_from and
!>     tessera_execute_domains (tessera_domains.inc);
!>   * a field given by its address (type(c_ptr): device memory from CUDA Fortran or OpenACC's
!>     use_device_ptr, or any memory the module cannot see as an array):
!>     tessera_field_from_ptr, never reading it; tessera_set_cuda_stream (docs/gpu_bindings.md);
!>   * curvilinear and unstructured (hex, tet) meshes: type(tessera_mesh_domain),
!>     tessera_curvilinear_from, tessera_unstructured_from and tessera_execute_mesh_domains
!>     (tessera_meshes.inc);
!>   * what C cannot check, the length of every array it would read, checked at every execute
!>     (the refinement ratios, each coordinate array against the mesh as it is then, each field
!>     against the array tessera_field_from measured); a refused call passes none of its
!>     arguments to C (tessera_execute_refused takes its place, see refuse_call).
!> Field memory is read only during tessera_execute / tessera_execute_final, and only when a
!> render fires; the array must stay allocated (not moved) from tessera_field_from until then.
module tessera
  use, intrinsic :: iso_c_binding, only: c_ptr, c_null_ptr, c_associated, c_loc, c_f_pointer, &
    c_char, c_null_char, c_int, c_int32_t, c_int64_t, c_intptr_t, c_size_t, c_double, c_float, &
    c_int8_t, c_int16_t
  implicit none
  private

  !> Statuses, as tessera_status in C.
  integer, parameter, public :: TESSERA_OK = 0, TESSERA_ERROR_CONFIG = 1, TESSERA_ERROR_DATA = 2, &
    TESSERA_ERROR_RENDER = 3, TESSERA_ERROR_IO = 4, TESSERA_ERROR_DISABLED = 5
  !> Element types, as tessera_dtype in C.
  integer, parameter, public :: TESSERA_UINT8 = 0, TESSERA_INT16 = 1, TESSERA_UINT16 = 2, &
    TESSERA_FLOAT32 = 3, TESSERA_FLOAT64 = 4
  !> The communicator argument of tessera_open for a run without MPI.
  integer, parameter, public :: TESSERA_NO_MPI = -1
  !> What an array element is, as tessera_association in C.
  integer, parameter, public :: TESSERA_VERTEX = 0, TESSERA_CELL = 1

  !> An adapter handle (opaque). Set by tessera_open; not changed by tessera_close, so that a
  !> call after the close is refused with "adapter was closed" as in C.
  type, public :: tessera_adapter
    type(c_ptr), private :: handle = c_null_ptr
  end type tessera_adapter

  !> Where this rank's real (non-ghost) vertices sit globally; the C struct itself.
  type, bind(C), public :: tessera_grid
    real(c_double) :: origin(3) = 0.0_c_double      !< world position of global vertex (0,0,0)
    real(c_double) :: spacing(3) = 1.0_c_double     !< > 0 and finite
    integer(c_int64_t) :: global_dims(3) = 0        !< vertices of the whole domain
    integer(c_int64_t) :: offset(3) = 0             !< global index of this rank's first real vertex
  end type tessera_grid

  !> One scalar field, never copied: what tessera_field_from fills in. The components mirror
  !> the C struct tessera_field (dims, byte strides, ghosts along i j k = the array's first,
  !> second and third index); data points into the simulation's array.
  type, public :: tessera_field
    character(len=:), allocatable :: name           !< kept here, passed to C by tessera_execute
    type(c_ptr) :: data = c_null_ptr                !< first element (ghosts included)
    integer :: dtype = -1                           !< TESSERA_UINT8 .. TESSERA_FLOAT64
    integer(c_int64_t) :: dims(3) = 0               !< extent incl. ghosts
    integer(c_int64_t) :: byte_strides(3) = 0       !< address differences of neighbours
    integer(c_int64_t) :: ghosts_lo(3) = 0          !< ghost layers at the low end of each axis
    integer(c_int64_t) :: ghosts_hi(3) = 0          !< ... and at the high end
    integer :: association = -1                     !< domains: TESSERA_VERTEX or TESSERA_CELL; -1: the mesh's
    ! What tessera_field_from measured of the array at data (checked at every execute, so that a
    ! descriptor changed since then never makes C read past the array): extent, byte strides,
    ! element size; 0 bytes: not made by tessera_field_from (read as given)
    type(c_ptr), private :: array_data = c_null_ptr
    integer(c_int64_t), private :: array_dims(3) = 0, array_strides(3) = 0
    integer, private :: array_bytes = 0
  end type tessera_field

  include 'tessera_domain_types.inc'

  include 'tessera_mesh_types.inc'

  !> The C layout of tessera_field (built inside tessera_execute only).
  type, bind(C) :: c_tessera_field
    type(c_ptr) :: name = c_null_ptr
    type(c_ptr) :: data = c_null_ptr
    integer(c_int) :: dtype = 0
    integer(c_int64_t) :: dims(3) = 0, byte_strides(3) = 0, ghosts_lo(3) = 0, ghosts_hi(3) = 0
  end type c_tessera_field

  !> f = tessera_field_from(name, u [, ghosts] [, ghosts_lo] [, ghosts_hi]) for u real(4),
  !> real(8) or integer(2) (TESSERA_INT16), dimension(:,:,:), u(i, j, k) = vertex (i, j, k); or
  !> dimension(:), one value per vertex or cell of a curvilinear or unstructured domain (dims
  !> (n, 1, 1), no ghosts).
  !> ghosts: layers at both ends of every axis (default 0); ghosts_lo(3) / ghosts_hi(3), when
  !> present, replace it at that end. u is read in place (see the module header).
  interface tessera_field_from
    module procedure field_from_r4, field_from_r8, field_from_i2, field_from_r4_1d, field_from_r8_1d, &
      field_from_i2_1d
  end interface tessera_field_from
  !> The unsigned dtypes, which have no Fortran kind: integer(1) read as TESSERA_UINT8 and
  !> integer(2) as TESSERA_UINT16, i.e. the bits as unsigned (a stored -1 is 255 / 65535).
  interface tessera_field_from_unsigned
    module procedure field_from_u8, field_from_u16, field_from_u8_1d, field_from_u16_1d
  end interface tessera_field_from_unsigned
  !> f = tessera_field_from_ptr(name, data, dtype, dims, byte_strides [, ghosts] [, ghosts_lo]
  !> [, ghosts_hi]): a field at the address `data` (type(c_ptr); host, device or managed
  !> memory, never read here), dtype TESSERA_UINT8 .. TESSERA_FLOAT64, dims(3) and
  !> byte_strides(3) integer(8) or default integer, ghosts as in tessera_field_from.
  interface tessera_field_from_ptr
    module procedure field_from_ptr_i8, field_from_ptr_i4
  end interface tessera_field_from_ptr
  !> st = tessera_execute(viz, step, time, grid, fields(:)); step integer(8) (or default
  !> integer), time real(8) (or real(4)). Renders whatever fires at this step (docs/c-api.md).
  interface tessera_execute
    module procedure execute_i8, execute_i4, execute_i8_r4, execute_i4_r4
  end interface tessera_execute
  !> As tessera_execute, for the last step (render_final_step: true renders every render).
  interface tessera_execute_final
    module procedure execute_final_i8, execute_final_i4, execute_final_i8_r4, execute_final_i4_r4
  end interface tessera_execute_final

  public :: tessera_field_from, tessera_field_from_unsigned, tessera_field_from_ptr, tessera_execute, &
    tessera_execute_final, tessera_set_cuda_stream, tessera_open, tessera_open_with_output_dir, tessera_close, &
    tessera_field_unchanged, tessera_mesh_unchanged, tessera_last_error, tessera_mesh_coords, tessera_domain_from, &
    tessera_domain_coords, tessera_execute_domains, tessera_execute_domains_final, &
    tessera_curvilinear_from, tessera_unstructured_from, tessera_execute_mesh_domains, &
    tessera_execute_mesh_domains_final

  !> The last argument the module itself refused (a NUL inside a name or path, an array shorter
  !> than its descriptor claims): its message,
  !> and the handle it belongs to (null for an open). tessera_last_error returns it for that
  !> handle until the next call with the handle. Module state, not per thread: like the rest
  !> of the module, call it from one thread at a time.
  logical :: refused = .false.
  type(c_ptr) :: refused_handle = c_null_ptr
  character(:), allocatable :: refused_message

  include 'tessera_c_api.inc'

contains

  ! ---- Adapter lifetime ---------------------------------------------------------------------

  !> Loads and validates the YAML config (tessera_open in C). comm: an MPI Fortran
  !> communicator handle (MPI_COMM_WORLD from `use mpi`, comm%MPI_VAL from `use mpi_f08`) or
  !> -1 (TESSERA_NO_MPI). output_dir, when present and not blank, replaces the config's
  !> tessera.output_dir (tessera_open_with_output_dir). On failure viz holds no adapter and
  !> tessera_last_error(viz) says why (FILE:LINE:COL: key.path: ... for a config error).
  integer function tessera_open(path, comm, viz, output_dir) result(st)
    character(*), intent(in) :: path
    integer, intent(in) :: comm
    type(tessera_adapter), intent(out) :: viz
    character(*), intent(in), optional :: output_dir
    character(:), allocatable :: fault
    call forget_refusal(c_null_ptr)
    fault = nul_fault('tessera_open: path', path)
    if (present(output_dir) .and. len(fault) == 0) fault = nul_fault('tessera_open: output_dir', output_dir)
    if (len(fault) > 0) then
      ! Collective: this rank still opens, with no config, so that every rank fails together
      st = c_open(c_string(''), int(comm, c_int), viz%handle)
      st = TESSERA_ERROR_CONFIG
      call refuse(c_null_ptr, fault)
    else if (present(output_dir)) then
      st = c_open_with_output_dir(c_string(path), int(comm, c_int), c_string(output_dir), viz%handle)
    else
      st = c_open(c_string(path), int(comm, c_int), viz%handle)
    end if
  end function tessera_open

  !> tessera_open_with_output_dir in C (argument order as there); "" = the config's output_dir.
  integer function tessera_open_with_output_dir(path, comm, output_dir, viz) result(st)
    character(*), intent(in) :: path, output_dir
    integer, intent(in) :: comm
    type(tessera_adapter), intent(out) :: viz
    st = tessera_open(path, comm, viz, output_dir)
  end function tessera_open_with_output_dir

  !> Releases the adapter (collective). viz keeps its (now closed) handle: a later call with it
  !> returns TESSERA_ERROR_CONFIG, "adapter was closed". A never-opened viz is TESSERA_OK.
  integer function tessera_close(viz) result(st)
    type(tessera_adapter), intent(in) :: viz
    call forget_refusal(viz%handle)
    st = c_close(viz%handle)
  end function tessera_close

  !> The adapter's last error message, "" after a success; for an adapter that failed to open
  !> (or was never opened) or with no argument, this thread's last tessera_open failure. An
  !> argument the module refused (a NUL in a name or path) gives the module's own message.
  function tessera_last_error(viz) result(msg)
    type(tessera_adapter), intent(in), optional :: viz
    character(:), allocatable :: msg
    type(c_ptr) :: h
    h = c_null_ptr
    if (present(viz)) h = viz%handle
    if (refused .and. same_handle(refused_handle, h)) then
      msg = refused_message
    else
      msg = from_c_string(c_last_error(h))
    end if
  end function tessera_last_error

  !> The promise that field `name` has the same values at the next execute as at the last one
  !> (tessera_field_unchanged in C; one-shot).
  integer function tessera_field_unchanged(viz, name) result(st)
    type(tessera_adapter), intent(in) :: viz
    character(*), intent(in) :: name
    character(:), allocatable :: fault
    call forget_refusal(viz%handle)
    fault = nul_fault('tessera_field_unchanged: name', name)
    if (len(fault) > 0) then
      st = TESSERA_ERROR_DATA
      call refuse(viz%handle, fault)
    else
      st = c_field_unchanged(viz%handle, c_string(name))
    end if
  end function tessera_field_unchanged

  !> The promise that the next tessera_execute_mesh_domains passes this rank's domains with the
  !> same geometry as the last one, only the values changed (tessera_mesh_unchanged in C;
  !> one-shot).
  integer function tessera_mesh_unchanged(viz) result(st)
    type(tessera_adapter), intent(in) :: viz
    call forget_refusal(viz%handle)
    st = c_mesh_unchanged(viz%handle)
  end function tessera_mesh_unchanged

  !> The CUDA stream (a cudaStream_t, as type(c_ptr)) on which the simulation computes its
  !> device arrays (tessera_set_cuda_stream in C): before reading device (or managed) memory
  !> given by tessera_field_from_ptr, Tessera waits for the work queued on it; c_null_ptr (the
  !> default): it synchronises the whole device first. Kept until set again. Not collective.
  !> A stream held as an integer handle (CUDA Fortran's integer(cuda_stream_kind)) is passed as
  !> transfer(handle, c_null_ptr) (docs/gpu_bindings.md).
  integer function tessera_set_cuda_stream(viz, stream) result(st)
    type(tessera_adapter), intent(in) :: viz
    type(c_ptr), value :: stream
    call forget_refusal(viz%handle)
    st = c_set_cuda_stream(viz%handle, stream)
  end function tessera_set_cuda_stream

  ! ---- Execute ------------------------------------------------------------------------------

  ! The specifics: step integer(8) or default integer, time real(8) or real(4)
  integer function execute_i8(viz, step, time, grid, fields) result(st)
    type(tessera_adapter), intent(in) :: viz
    integer(c_int64_t), intent(in) :: step
    real(c_double), intent(in) :: time
    type(tessera_grid), intent(in) :: grid
    type(tessera_field), intent(in) :: fields(:)
    st = run_execute(.false., viz, step, time, grid, fields)
  end function execute_i8

  integer function execute_i4(viz, step, time, grid, fields) result(st)
    type(tessera_adapter), intent(in) :: viz
    integer(c_int32_t), intent(in) :: step
    real(c_double), intent(in) :: time
    type(tessera_grid), intent(in) :: grid
    type(tessera_field), intent(in) :: fields(:)
    st = run_execute(.false., viz, int(step, c_int64_t), time, grid, fields)
  end function execute_i4

  integer function execute_i8_r4(viz, step, time, grid, fields) result(st)
    type(tessera_adapter), intent(in) :: viz
    integer(c_int64_t), intent(in) :: step
    real(c_float), intent(in) :: time
    type(tessera_grid), intent(in) :: grid
    type(tessera_field), intent(in) :: fields(:)
    st = run_execute(.false., viz, step, real(time, c_double), grid, fields)
  end function execute_i8_r4

  integer function execute_i4_r4(viz, step, time, grid, fields) result(st)
    type(tessera_adapter), intent(in) :: viz
    integer(c_int32_t), intent(in) :: step
    real(c_float), intent(in) :: time
    type(tessera_grid), intent(in) :: grid
    type(tessera_field), intent(in) :: fields(:)
    st = run_execute(.false., viz, int(step, c_int64_t), real(time, c_double), grid, fields)
  end function execute_i4_r4

  integer function execute_final_i8(viz, step, time, grid, fields) result(st)
    type(tessera_adapter), intent(in) :: viz
    integer(c_int64_t), intent(in) :: step
    real(c_double), intent(in) :: time
    type(tessera_grid), intent(in) :: grid
    type(tessera_field), intent(in) :: fields(:)
    st = run_execute(.true., viz, step, time, grid, fields)
  end function execute_final_i8

  integer function execute_final_i4(viz, step, time, grid, fields) result(st)
    type(tessera_adapter), intent(in) :: viz
    integer(c_int32_t), intent(in) :: step
    real(c_double), intent(in) :: time
    type(tessera_grid), intent(in) :: grid
    type(tessera_field), intent(in) :: fields(:)
    st = run_execute(.true., viz, int(step, c_int64_t), time, grid, fields)
  end function execute_final_i4

  integer function execute_final_i8_r4(viz, step, time, grid, fields) result(st)
    type(tessera_adapter), intent(in) :: viz
    integer(c_int64_t), intent(in) :: step
    real(c_float), intent(in) :: time
    type(tessera_grid), intent(in) :: grid
    type(tessera_field), intent(in) :: fields(:)
    st = run_execute(.true., viz, step, real(time, c_double), grid, fields)
  end function execute_final_i8_r4

  integer function execute_final_i4_r4(viz, step, time, grid, fields) result(st)
    type(tessera_adapter), intent(in) :: viz
    integer(c_int32_t), intent(in) :: step
    real(c_float), intent(in) :: time
    type(tessera_grid), intent(in) :: grid
    type(tessera_field), intent(in) :: fields(:)
    st = run_execute(.true., viz, int(step, c_int64_t), real(time, c_double), grid, fields)
  end function execute_final_i4_r4

  !> Builds the C descriptors (names NUL-terminated in a local buffer that lives until the C
  !> call returns) and calls tessera_execute or tessera_execute_final. A field the module
  !> refuses (fields_fault: a name holding a NUL, a descriptor reaching past its array) never
  !> reaches C: see refuse_call.
  integer function run_execute(final, viz, step, time, grid, fields) result(st)
    logical, intent(in) :: final
    type(tessera_adapter), intent(in) :: viz
    integer(c_int64_t), intent(in) :: step
    real(c_double), intent(in) :: time
    type(tessera_grid), intent(in) :: grid
    type(tessera_field), intent(in) :: fields(:)
    type(c_tessera_field), allocatable, target :: cf(:)
    character(kind=c_char), allocatable, target :: names(:)
    type(c_ptr) :: first
    integer :: n, pos
    character(:), allocatable :: fault

    call forget_refusal(viz%handle)
    fault = fields_fault(fields, 'fields')
    if (len(fault) > 0) then
      st = refuse_call(viz, step, time, 0, final, fault)
      return
    end if

    n = size(fields)
    allocate(cf(n), names(names_length(fields)))
    pos = 1
    call pack_fields(fields, cf, 1, names, pos)
    first = c_null_ptr
    if (n > 0) first = c_loc(cf(1))
    if (final) then
      st = c_execute_final(viz%handle, step, time, grid, first, int(n, c_int))
    else
      st = c_execute(viz%handle, step, time, grid, first, int(n, c_int))
    end if
  end function run_execute

  !> Characters the NUL-terminated names of fields(:) take (at least 1).
  integer function names_length(fields) result(total)
    type(tessera_field), intent(in) :: fields(:)
    integer :: i
    total = 1
    do i = 1, size(fields)
      if (allocated(fields(i)%name)) total = total + len(fields(i)%name) + 1
    end do
  end function names_length

  !> The C descriptors of fields(:) into cf(at:), their names NUL-terminated into names(pos:)
  !> (pos advanced past them). An unset name stays NULL: C reports it. cf and names must stay
  !> in place until the C call that reads them returns.
  subroutine pack_fields(fields, cf, at, names, pos)
    type(tessera_field), intent(in) :: fields(:)
    type(c_tessera_field), intent(inout), target :: cf(:)
    integer, intent(in) :: at
    character(kind=c_char), intent(inout), target :: names(:)
    integer, intent(inout) :: pos
    integer :: i, j, c
    do i = 1, size(fields)
      c = at + i - 1
      cf(c)%name = c_null_ptr
      cf(c)%data = fields(i)%data
      cf(c)%dtype = int(fields(i)%dtype, c_int)
      cf(c)%dims = fields(i)%dims
      cf(c)%byte_strides = fields(i)%byte_strides
      cf(c)%ghosts_lo = fields(i)%ghosts_lo
      cf(c)%ghosts_hi = fields(i)%ghosts_hi
      if (allocated(fields(i)%name)) then
        do j = 1, len(fields(i)%name)
          names(pos + j - 1) = fields(i)%name(j:j)
        end do
        names(pos + len(fields(i)%name)) = c_null_char
        cf(c)%name = c_loc(names(pos))
        pos = pos + len(fields(i)%name) + 1
      end if
    end do
  end subroutine pack_fields

  include 'tessera_domains.inc'

  include 'tessera_meshes.inc'

  include 'tessera_fields.inc'

  ! ---- Strings and refusals -----------------------------------------------------------------

  !> "" if s holds no NUL character; else the message naming `what`, the position and the
  !> string C would see (cut at the NUL).
  function nul_fault(what, s) result(msg)
    character(*), intent(in) :: what, s
    character(:), allocatable :: msg
    character(len=16) :: at
    integer :: k
    k = index(s, c_null_char)
    if (k == 0) then
      msg = ''
      return
    end if
    write(at, '(i0)') k
    msg = what // ' contains a NUL character (achar(0)) at position ' // trim(at) // &
      ", which C would read as its end ('" // s(1:k - 1) // "'); names and paths must not contain one"
  end function nul_fault

  !> The call for an execute whose arguments the module refused with `fault`: nothing of them
  !> reaches C. tessera_execute_refused takes its place (collective, reads no descriptor):
  !> triggers are evaluated as in the call, and a render that fires fails on every rank with
  !> `fault` as its message and log line (another rank's names this one). Returns
  !> TESSERA_ERROR_DATA with `fault` as tessera_last_error(viz), or C's own status and message
  !> where the adapter refused the call itself (TESSERA_ERROR_CONFIG: not open, closed, the
  !> ranks disagree on the call).
  integer function refuse_call(viz, step, time, domains_call, final, fault) result(st)
    type(tessera_adapter), intent(in) :: viz
    integer(c_int64_t), intent(in) :: step
    real(c_double), intent(in) :: time
    integer, intent(in) :: domains_call  !< the call refused: 0 execute, 1 domains, 2 mesh domains
    logical, intent(in) :: final
    character(*), intent(in) :: fault
    st = c_execute_refused(viz%handle, step, time, int(domains_call, c_int), &
      merge(1_c_int, 0_c_int, final), fault // c_null_char)
    if (st == TESSERA_ERROR_CONFIG) return
    st = TESSERA_ERROR_DATA
    call refuse(viz%handle, fault)
  end function refuse_call

  subroutine refuse(handle, message)
    type(c_ptr), intent(in) :: handle
    character(*), intent(in) :: message
    refused = .true.
    refused_handle = handle
    refused_message = message
  end subroutine refuse

  !> A call with `handle` starts: an earlier refusal for it is no longer its last error.
  subroutine forget_refusal(handle)
    type(c_ptr), intent(in) :: handle
    if (refused .and. same_handle(refused_handle, handle)) refused = .false.
  end subroutine forget_refusal

  logical function same_handle(p, q)
    type(c_ptr), intent(in) :: p, q
    same_handle = address(p) == address(q)
  end function same_handle

  integer(c_intptr_t) function address(p)
    type(c_ptr), intent(in) :: p
    address = transfer(p, address)
  end function address

  !> n in decimal, no blanks.
  function int_text(n) result(text)
    integer(c_int64_t), intent(in) :: n
    character(:), allocatable :: text
    character(len=24) :: buffer
    write(buffer, '(i0)') n
    text = trim(buffer)
  end function int_text

  !> s without trailing blanks, NUL-terminated, for a character(kind=c_char) :: x(*) argument.
  function c_string(s) result(c)
    character(*), intent(in) :: s
    character(kind=c_char, len=:), allocatable :: c
    c = trim(s) // c_null_char
  end function c_string

  !> Copy of a NUL-terminated C string ("" for NULL).
  function from_c_string(p) result(s)
    type(c_ptr), intent(in) :: p
    character(:), allocatable :: s
    character(kind=c_char), pointer :: chars(:)
    integer :: i, n
    if (.not. c_associated(p)) then
      s = ""
      return
    end if
    n = int(c_strlen(p))
    call c_f_pointer(p, chars, [n])
    allocate(character(len=n) :: s)
    do i = 1, n
      s(i:i) = chars(i)
    end do
  end function from_c_string

end module tessera
