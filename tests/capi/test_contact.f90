! test_contact.f90: the contact search handle through the Fortran module (contactnn_contact_create, _update,
! _destroy) on a flat surface of a quad4 and two tri3 faces at z = 0 with answers known in closed form: free points
! and slave nodes (1-based ids), faces counted from 1, coords(3, n) column-major, and refusals that write nothing;
! the face-interior method (method=, network=, plan=) against the local search's (check_method).
! Prints PASS when every check holds.
program test_contact
  use, intrinsic :: iso_c_binding, only: c_int, c_double
  use contactnn
  implicit none
  integer, parameter :: n_nodes = 8, m = 2
  integer(c_int) :: types(3) = [CONTACTNN_FACE_QUAD4, CONTACTNN_FACE_TRI3, CONTACTNN_FACE_TRI3]
  integer(c_int) :: conn(10) = [1, 2, 3, 4, 2, 5, 6, 2, 6, 3]
  integer(c_int) :: status(m), face(m), location(m), slaves(m) = [7, 8]
  real(c_double) :: coords(3, n_nodes), points(3, m), param(2, m), point(3, m), gap(m), normal(3, m)
  type(contactnn_contact) :: contact
  type(contactnn_contact_options) :: options
  integer :: ierr, failures

  failures = 0
  ! Nodes a (0,0) b (1,0) c (1,1) d (0,1) e (2,0) f (2,1); nodes 7 and 8 the slave nodes.
  coords = reshape([0d0, 0d0, 0d0, 1d0, 0d0, 0d0, 1d0, 1d0, 0d0, 0d0, 1d0, 0d0, 2d0, 0d0, 0d0, 2d0, 1d0, 0d0, &
                    0.25d0, 0.5d0, 0.2d0, 2.3d0, 0.5d0, 0.4d0], [3, n_nodes])
  points = coords(:, 7:8)
  options = contactnn_default_contact_options()
  options%capture_distance = 2d0

  ! Free points: above the quad4 (face 1, its interior) and beyond the tri3's outer edge (face 2, an edge).
  call contactnn_contact_create(contact, types, conn, n_nodes, ierr, n_points=m, options=options)
  call expect(ierr == CONTACTNN_SUCCESS, 'create with free points')
  call contactnn_contact_update(contact, coords, ierr, status, face, location=location, param=param, point=point, &
                                gap=gap, normal=normal, points=points)
  call expect(ierr == CONTACTNN_SUCCESS, 'update with free points')
  call check('free points')
  ! A refusal: a NaN coordinate; the arrays keep what they held.
  status = -9
  face = -9
  gap = -9d0
  coords(2, 3) = ieee_nan()
  call contactnn_contact_update(contact, coords, ierr, status, face, gap=gap, points=points)
  call expect(ierr == CONTACTNN_ERROR_NUMERICAL .and. all(status == -9) .and. all(face == -9) .and. all(gap == -9d0), &
              'a NaN coordinate refused, nothing written')
  call expect(index(contactnn_last_error(), 'node 3') > 0, 'the message names node 3')
  coords(2, 3) = 1d0
  call contactnn_contact_update(contact, coords(:, 1:7), ierr, status, face, points=points)
  call expect(ierr == CONTACTNN_ERROR_INVALID_ARGUMENT .and. all(status == -9), 'coords of the wrong size refused')
  call contactnn_contact_destroy(contact)

  ! Slave nodes 7 and 8 (1-based ids, the default).
  call contactnn_contact_create(contact, types, conn, n_nodes, ierr, slave_nodes=slaves, options=options)
  call expect(ierr == CONTACTNN_SUCCESS, 'create with slave nodes')
  call contactnn_contact_update(contact, coords, ierr, status, face, location=location, param=param, point=point, &
                                gap=gap, normal=normal)
  call expect(ierr == CONTACTNN_SUCCESS, 'update with slave nodes')
  call check('slave nodes')
  call contactnn_contact_destroy(contact)
  call contactnn_contact_update(contact, coords, ierr, status, face)
  call expect(ierr == CONTACTNN_ERROR_INVALID_ARGUMENT, 'a destroyed contact search refused')
  ! A face naming node 9 of 8.
  conn(6) = 9
  call contactnn_contact_create(contact, types, conn, n_nodes, ierr, slave_nodes=slaves)
  call expect(ierr == CONTACTNN_ERROR_INVALID_ARGUMENT .and. index(contactnn_last_error(), 'node 9') > 0, &
              'a face naming a node that does not exist refused')

  call check_method()

  if (failures == 0) print '(a)', 'PASS: the contact search handle from Fortran'

contains

  subroutine expect(condition, what)
    logical, intent(in) :: condition
    character(len=*), intent(in) :: what
    if (.not. condition) then
      failures = failures + 1
      print '(3a)', 'FAILED: ', what, ' ('//contactnn_last_error()//')'
    end if
  end subroutine expect

  subroutine check(what)
    character(len=*), intent(in) :: what
    call expect(all(status == CONTACTNN_STATUS_OK) .and. face(1) == 1 .and. face(2) == 2, what//': faces')
    call expect(location(1) == CONTACTNN_LOCATION_FACE .and. location(2) == CONTACTNN_LOCATION_EDGE, what//': locations')
    call expect(abs(gap(1) - 0.2d0) < 1d-12 .and. abs(gap(2) - 0.5d0) < 1d-12, what//': gaps')
    call expect(all(abs(point(:, 1) - [0.25d0, 0.5d0, 0d0]) < 1d-12) .and. &
                all(abs(point(:, 2) - [2d0, 0.5d0, 0d0]) < 1d-12), what//': points')
    call expect(all(abs(normal(:, 1) - [0d0, 0d0, 1d0]) < 1d-12) .and. &
                all(abs(normal(:, 2) - [0.6d0, 0d0, 0.8d0]) < 1d-12), what//': normals')
    call expect(all(abs(param(:, 1) - [-0.5d0, 0d0]) < 1d-12), what//': the quad4''s (xi, eta)')
  end subroutine check

  ! The face-interior method (method=, network=, plan=): on a twisted bilinear quad4, free points over its interior
  ! get the local search's newton:1 answers (contactnn_create / contactnn_run on the face's raw rows), not the exact
  ! search's; a network method runs with its network file; a bad method and a missing plan are refused, creating
  ! nothing.
  subroutine check_method()
    integer, parameter :: n = 12
    integer(c_int) :: quad(1) = [CONTACTNN_FACE_QUAD4], quad_conn(4) = [1, 2, 3, 4]
    integer(c_int) :: st(n), fc(n), loc(n), run_status(n)
    real(c_double) :: x(3, 4), p(3, n), raw(15, n), exact(2, n), by_method(2, n), run_param(2, n)
    type(contactnn_search) :: search
    character(len=4096) :: source
    integer :: i, compared, differ

    x = reshape([0d0, 0d0, 0d0, 1d0, 0d0, 0.4d0, 1d0, 1d0, 0d0, 0d0, 1d0, 0.4d0], [3, 4])
    do i = 1, n
      p(:, i) = [0.2d0 + 0.6d0 * mod(i - 1, 4) / 3d0, 0.25d0 + 0.5d0 * ((i - 1) / 4) / 2d0, 0.2d0 - 0.3d0 * mod(i, 2)]
      raw(1:12, i) = reshape(x, [12])
      raw(13:15, i) = p(:, i)
    end do
    call contactnn_contact_create(contact, quad, quad_conn, 4, ierr, n_points=n)
    call expect(ierr == CONTACTNN_SUCCESS, 'create the exact search')
    call contactnn_contact_update(contact, x, ierr, st, fc, param=exact, points=p)
    call contactnn_contact_destroy(contact)
    call contactnn_contact_create(contact, quad, quad_conn, 4, ierr, n_points=n, method='newton:1')
    call expect(ierr == CONTACTNN_SUCCESS, 'create with method newton:1')
    call contactnn_contact_update(contact, x, ierr, st, fc, location=loc, param=by_method, points=p)
    call expect(ierr == CONTACTNN_SUCCESS .and. all(st == CONTACTNN_STATUS_OK) .and. all(fc == 1), 'update newton:1')
    call contactnn_contact_destroy(contact)
    call contactnn_create(search, CONTACTNN_SURFACE_BILINEAR, 'newton:1', ierr)
    call contactnn_run(search, raw, run_param, run_status, ierr)
    call contactnn_destroy(search)
    compared = 0
    differ = 0
    do i = 1, n
      if (run_status(i) /= CONTACTNN_STATUS_OK) cycle
      compared = compared + 1
      call expect(loc(i) == CONTACTNN_LOCATION_FACE .and. all(abs(by_method(:, i) - run_param(:, i)) < 1d-12), &
                  'newton:1: the handle''s point is the local search''s')
      if (any(abs(by_method(:, i) - exact(:, i)) > 1d-6)) differ = differ + 1
    end do
    call expect(compared > n / 2, 'newton:1 answers most points')
    call expect(differ > n / 4, 'newton:1 is not the exact search on the twisted face')

    call get_command_argument(1, source)
    call contactnn_contact_create(contact, quad, quad_conn, 4, ierr, n_points=n, method='network+newton:1', &
                                  network=trim(source)//'/data/weights/bilinear-8.h5')
    call expect(ierr == CONTACTNN_SUCCESS, 'create with a network method and its network')
    call contactnn_contact_update(contact, x, ierr, st, fc, points=p)
    call expect(ierr == CONTACTNN_SUCCESS .and. all(st == CONTACTNN_STATUS_OK), 'update with the network method')
    call contactnn_contact_destroy(contact)

    call contactnn_contact_create(contact, quad, quad_conn, 4, ierr, n_points=n, method='newton:two')
    call expect(ierr == CONTACTNN_ERROR_INVALID_ARGUMENT .and. index(contactnn_last_error(), 'options.method') > 0 &
                .and. index(contactnn_last_error(), 'newton:two') > 0, 'a bad method refused, naming it')
    st = -9
    call contactnn_contact_update(contact, x, ierr, st, fc, points=p)
    call expect(ierr == CONTACTNN_ERROR_INVALID_ARGUMENT .and. all(st == -9), 'nothing was created for a bad method')
    call contactnn_contact_create(contact, quad, quad_conn, 4, ierr, n_points=n, plan='no-such-dir/plan.toml')
    call expect(ierr == CONTACTNN_ERROR_IO .and. index(contactnn_last_error(), 'options.plan_file') > 0 .and. &
                index(contactnn_last_error(), 'no-such-dir/plan.toml') > 0, 'a missing plan refused, naming it')
  end subroutine check_method

  function ieee_nan() result(x)
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
    real(c_double) :: x
    x = ieee_value(x, ieee_quiet_nan)
  end function ieee_nan

end program test_contact
