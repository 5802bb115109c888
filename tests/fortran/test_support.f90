!> Helpers shared by the Fortran test programs (tests/fortran/CMakeLists.txt compiles this module
!> once into tessera_fortran_test_support): checks counted in `failures` and reported by
!> `finish`, files written, read and compared byte for byte, and one render of domains.
module test_support
  use, intrinsic :: iso_fortran_env, only: error_unit, real64
  use tessera
  implicit none
  private
  public :: failures, check, finish, exists, remove, write_text, contents, same_file, render_domains

  !> Checks that failed so far in this program.
  integer :: failures = 0

contains

  !> Counts a failed check and names it on standard error; the program goes on.
  subroutine check(ok, what)
    logical, intent(in) :: ok
    character(*), intent(in) :: what
    if (.not. ok) then
      write(error_unit, '(2a)') 'FAILED: ', what
      failures = failures + 1
    end if
  end subroutine check

  !> Ends the checks of program `name`: error stop 1 if any failed, else says all passed.
  subroutine finish(name)
    character(*), intent(in) :: name
    if (failures > 0) then
      write(error_unit, '(i0, a)') failures, ' check(s) failed'
      error stop 1
    end if
    print '(2a)', name, ': all checks passed'
  end subroutine finish

  logical function exists(path)
    character(*), intent(in) :: path
    inquire(file=path, exist=exists)
  end function exists

  !> Deletes the file `path` if there is one.
  subroutine remove(path)
    character(*), intent(in) :: path
    integer :: u
    if (.not. exists(path)) return
    open(newunit=u, file=path, status='old')
    close(u, status='delete')
  end subroutine remove

  !> Writes exactly the bytes of `text` to `path` (no newline added), replacing the file.
  subroutine write_text(path, text)
    character(*), intent(in) :: path, text
    integer :: u
    open(newunit=u, file=path, access='stream', form='unformatted', status='replace')
    write(u) text
    close(u)
  end subroutine write_text

  !> The bytes of the file `path`; empty if it is missing, empty or unreadable.
  function contents(path) result(text)
    character(*), intent(in) :: path
    character(len=:), allocatable :: text
    integer :: u, n, ios
    logical :: there
    inquire(file=path, exist=there, size=n)
    if (.not. there .or. n <= 0) then
      text = ''
      return
    end if
    allocate(character(len=n) :: text)
    open(newunit=u, file=path, access='stream', form='unformatted', status='old', iostat=ios)
    if (ios == 0) read(u, iostat=ios) text
    close(u)
    if (ios /= 0) text = ''
  end function contents

  !> Whether both files exist, are not empty and hold the same bytes.
  logical function same_file(p, q)
    character(*), intent(in) :: p, q
    character(len=:), allocatable :: x, y
    x = contents(p)
    y = contents(q)
    same_file = len(x) > 0 .and. len(x) == len(y) .and. x == y
  end function same_file

  !> Opens an adapter on `config` writing under `dir`, renders `domains` of `m` at step 0 (one
  !> process) and closes it; a failed open or render is a failed check naming the message.
  subroutine render_domains(config, dir, m, domains)
    character(*), intent(in) :: config, dir
    type(tessera_mesh), intent(in) :: m
    type(tessera_domain), intent(in) :: domains(:)
    type(tessera_adapter) :: viz
    integer :: st
    st = tessera_open(config, TESSERA_NO_MPI, viz, dir)
    call check(st == TESSERA_OK, 'open: ' // tessera_last_error(viz))
    st = tessera_execute_domains(viz, 0, 0.0_real64, m, domains)
    call check(st == TESSERA_OK, dir // ': ' // tessera_last_error(viz))
    st = tessera_close(viz)
  end subroutine render_domains

end module test_support
