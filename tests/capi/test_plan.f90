! test_plan_fortran: a scene plan loaded through the Fortran module (contactnn_create_from_plan): the plan's
! surface and method, results bit for bit those of contactnn_create with the same surface, method and network,
! and a malformed plan refused with CONTACTNN_ERROR_FORMAT and a message naming the line and the key.
!
! Usage: test_plan_fortran SOURCE_DIR   (data/weights of SOURCE_DIR; the plans are written in the working
! directory). Exit status 0 when every check holds.
program test_plan_fortran
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use contactnn
  use fortran_checks, only: expect, finish
  implicit none
  character(len=4096) :: source

  if (command_argument_count() /= 1) then
    print '(a)', 'usage: test_plan_fortran SOURCE_DIR'
    stop 2
  end if
  call get_command_argument(1, source)

  call write_plan('closed.toml', 'bilinear', 'closed_form+newton:1', '', '')
  call check_plan('closed.toml', CONTACTNN_SURFACE_BILINEAR, 'closed_form+newton:1', '')
  call write_plan('network.toml', 'gregory', 'network+newton:2', trim(source)//'/data/weights/gregory-48.h5', '')
  call check_plan('network.toml', CONTACTNN_SURFACE_GREGORY, 'network+newton:2', &
                  trim(source)//'/data/weights/gregory-48.h5')
  call write_plan('unknown.toml', 'bilinear', 'newton:2', '', 'colour = "blue"')
  call check_refused('unknown.toml', "'unknown.toml':7: unknown key 'colour' in [plan]")

  call finish('PASS: the Fortran module loads scene plans')

contains

  !> A plan in the format of lib/io/plan_file.hpp; `extra` (if not blank) goes on line 7, inside [plan].
  subroutine write_plan(path, surface, method, network, extra)
    character(len=*), intent(in) :: path, surface, method, network, extra
    integer :: unit
    open (newunit=unit, file=path, status='replace', action='write')
    write (unit, '(a)') '# written by test_plan_fortran'
    write (unit, '(a)') '[plan]'
    write (unit, '(a)') 'schema_version = 1'
    write (unit, '(3a)') 'surface = "', surface, '"'
    write (unit, '(3a)') 'method = "', method, '"'
    write (unit, '(3a)') 'network = "', network, '"'
    if (len_trim(extra) > 0) write (unit, '(a)') extra
    write (unit, '(a)') 'target = 0.0025'
    write (unit, '(a)') 'margin = 0.8'
    write (unit, '(a)') 'reached = true'
    write (unit, '(a)') '[domain]'
    write (unit, '(a)') 'deck = "deck.inp"'
    write (unit, '(a)') 'pair = 0'
    write (unit, '(a)') 'deformation = 0.1'
    write (unit, '(a)') 'capture = 0.5'
    write (unit, '(a)') 'normal_tilt_tangent = 0.1'
    write (unit, '(a)') 'boundary_fraction = 0.2'
    write (unit, '(a)') 'heldout_count = 100'
    write (unit, '(a)') 'heldout_seed = 1001'
    close (unit)
  end subroutine write_plan

  !> The plan's search against the same search made by contactnn_create: equal bits.
  subroutine check_plan(path, surface, method, network)
    character(len=*), intent(in) :: path, method, network
    integer, intent(in) :: surface
    type(contactnn_search) :: from_plan, direct
    real(c_double), allocatable :: raw(:, :)
    real(c_double) :: p1(2, 8), p2(2, 8), g1(8), g2(8)
    integer(c_int) :: s1(8), s2(8)
    integer :: ierr, i, columns

    columns = 15
    if (surface == CONTACTNN_SURFACE_GREGORY) columns = 27
    allocate (raw(columns, 8))
    do i = 1, 8
      raw(1:15, i) = [0d0, 0d0, 0d0, 1d0, 0.05d0, 0.02d0, 1.1d0, 0.95d0, 0.01d0 * i, 0.02d0, 1d0, 0.01d0, &
                      0.1d0 * i, 0.8d0 - 0.05d0 * i, 0.1d0]
      if (columns == 27) raw(16:27, i) = [0.02d0, -0.01d0, 1d0, -0.03d0, 0.02d0, 1d0, 0.01d0, 0.04d0, 1d0, &
                                          0d0, -0.02d0, 1d0]
    end do
    call contactnn_create_from_plan(from_plan, path, ierr)
    if (ierr /= CONTACTNN_SUCCESS) print '(2a)', 'contactnn_create_from_plan: ', contactnn_last_error()
    call expect(ierr == CONTACTNN_SUCCESS, 'create from '//path)
    call expect(contactnn_surface(from_plan) == surface, path//': the plan''s surface')
    call expect(contactnn_method(from_plan) == method, path//': the plan''s method')
    if (len(network) > 0) then
      call contactnn_create(direct, surface, method, ierr, network=network)
    else
      call contactnn_create(direct, surface, method, ierr)
    end if
    call expect(ierr == CONTACTNN_SUCCESS, 'create directly')
    p1 = 0
    p2 = 0
    call contactnn_run(from_plan, raw, p1, s1, ierr, gap=g1)
    call expect(ierr == CONTACTNN_SUCCESS, 'run the plan''s search')
    call contactnn_run(direct, raw, p2, s2, ierr, gap=g2)
    call expect(all(p1 == p2) .and. all(g1 == g2) .and. all(s1 == s2), path//': the same results as contactnn_create')
    call expect(s1(1) == CONTACTNN_STATUS_OK .or. s1(1) == CONTACTNN_STATUS_OUT_OF_DOMAIN, path//': a usable answer')
    call contactnn_destroy(from_plan)
    call contactnn_destroy(direct)
    call expect(contactnn_surface(from_plan) == -1, 'no surface once destroyed')
  end subroutine check_plan

  subroutine check_refused(path, says)
    character(len=*), intent(in) :: path, says
    type(contactnn_search) :: search
    integer :: ierr
    call contactnn_create_from_plan(search, path, ierr)
    print '(3a)', path, ': ', contactnn_last_error()
    call expect(ierr == CONTACTNN_ERROR_FORMAT, path//': refused as malformed')
    call expect(index(contactnn_last_error(), says) > 0, path//': the message names the line and the key')
    call expect(contactnn_surface(search) == -1, path//': no handle')
  end subroutine check_refused

end program test_plan_fortran
