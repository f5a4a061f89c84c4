! test_faces_fortran: the faces of SPEC 9 through the Fortran module: a quad8 whose mid-side nodes are raised
! by 0.2 above the square [-1, 1]^2, S on its axis at (0, 0, 2): the closest point is the centre (0, 0, 0.4),
! gap 1.6; a flat tri6, S over (0.4, 0.6): (r, s) = (0.2, 0.3); a row count that is not the search's refused.
! Exit status 0 when every check holds.
program test_faces_fortran
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use contactnn
  use fortran_checks, only: expect, finish
  implicit none
  type(contactnn_search) :: search
  real(c_double) :: quad(27, 1), tri(21, 1), param(2, 1), gap(1), wrong(15, 1)
  integer(c_int) :: status(1)
  integer :: ierr

  quad(:, 1) = [-1d0, -1d0, 0d0, 1d0, -1d0, 0d0, 1d0, 1d0, 0d0, -1d0, 1d0, 0d0, &
                0d0, -1d0, 0.2d0, 1d0, 0d0, 0.2d0, 0d0, 1d0, 0.2d0, -1d0, 0d0, 0.2d0, 0d0, 0d0, 2d0]
  call contactnn_create(search, CONTACTNN_SURFACE_QUAD8, 'newton', ierr)
  call expect(ierr == CONTACTNN_SUCCESS, 'create quad8 newton')
  call expect(contactnn_surface(search) == CONTACTNN_SURFACE_QUAD8, 'the surface is quad8')
  call contactnn_run(search, quad, param, status, ierr, gap=gap)
  call expect(ierr == CONTACTNN_SUCCESS .and. status(1) == CONTACTNN_STATUS_OK, 'quad8 run')
  call expect(abs(param(1, 1)) < 1d-12 .and. abs(param(2, 1)) < 1d-12 .and. abs(gap(1) - 1.6d0) < 1d-12, &
              'quad8: the centre, gap 1.6')
  wrong = 0
  call contactnn_run(search, wrong, param, status, ierr)
  call expect(ierr == CONTACTNN_ERROR_INVALID_ARGUMENT, 'raw(15, n) refused for a quad8 search')
  call contactnn_destroy(search)

  tri(:, 1) = [0d0, 0d0, 0d0, 2d0, 0d0, 0d0, 0d0, 2d0, 0d0, 1d0, 0d0, 0d0, 1d0, 1d0, 0d0, 0d0, 1d0, 0d0, &
               0.4d0, 0.6d0, 0.5d0]
  call contactnn_create(search, CONTACTNN_SURFACE_TRI6, 'closed_form+newton:1', ierr)
  call expect(ierr == CONTACTNN_SUCCESS, 'create tri6')
  call contactnn_run(search, tri, param, status, ierr, gap=gap)
  call expect(ierr == CONTACTNN_SUCCESS .and. status(1) == CONTACTNN_STATUS_OK, 'tri6 run')
  call expect(abs(param(1, 1) - 0.2d0) < 1d-12 .and. abs(param(2, 1) - 0.3d0) < 1d-12 .and. &
              abs(gap(1) - 0.5d0) < 1d-12, 'tri6: (0.2, 0.3), gap 0.5')
  call contactnn_destroy(search)

  call finish('PASS: the Fortran module searches every face type')
end program test_faces_fortran
