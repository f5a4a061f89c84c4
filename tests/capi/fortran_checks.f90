! fortran_checks.f90: module fortran_checks, what the Fortran tests of this folder check alike: a failure count,
! expect(), and the end of a test (the count and exit status 1, or the line that says it passed). Compiled before
! each test by contactnn_add_fortran_capi_test (tests/capi/CMakeLists.txt).
module fortran_checks
  implicit none
  private
  integer, public :: failures = 0
  public :: expect, finish

contains

  subroutine expect(condition, what)
    logical, intent(in) :: condition
    character(len=*), intent(in) :: what
    if (.not. condition) then
      print '(2a)', 'FAIL: ', what
      failures = failures + 1
    end if
  end subroutine expect

  !> Stops with exit status 1 after printing how many checks failed, or prints `pass`.
  subroutine finish(pass)
    character(len=*), intent(in) :: pass
    if (failures > 0) then
      print '(i0,a)', failures, ' check(s) failed'
      stop 1
    end if
    print '(a)', pass
  end subroutine finish

end module fortran_checks
