! contact_search.f90: the contact search handle of contactnn from Fortran, as an FE code calls it (module contactnn,
! contactnn.f90, compiled with the program).
!
! The mesh of contact_search.c: a plate [0, 4] x [0, 4] x [-1, 0] of 4 x 4 cells (the left half hexahedra with
! quad4 top faces, the right half two wedges per cell with tri3 top faces) under a faceted spherical cap of 61
! nodes, which moves down into the plate and slides over ten increments while the plate sags. Each increment
! passes the coordinates, coords(3, n) column-major, to the handle and prints every slave node within reach of
! the plate: its face (from 1), where on the face, the signed gap (< 0: penetration), the closest point, the normal.
program contact_search
  use, intrinsic :: iso_c_binding, only: c_int, c_double
  use contactnn
  implicit none
  integer, parameter :: cells = 4, grid = cells + 1, plate_nodes = 2 * grid * grid, rings = 4
  integer, parameter :: cap_nodes = 1 + 3 * rings * (rings + 1), n_nodes = plate_nodes + cap_nodes
  integer, parameter :: increments = 10
  real(c_double), parameter :: pi = 3.14159265358979323846_c_double
  character(len=6), parameter :: location_name(0:2) = ['face  ', 'edge  ', 'vertex']
  integer(c_int), allocatable :: types(:), connectivity(:)
  integer(c_int) :: slaves(cap_nodes), status(cap_nodes), face(cap_nodes), location(cap_nodes)
  real(c_double) :: x(3, n_nodes), point(3, cap_nodes), gap(cap_nodes), normal(3, cap_nodes)
  type(contactnn_contact) :: contact
  integer :: ierr, k, i

  call build_faces(types, connectivity)
  slaves = [(plate_nodes + i, i = 1, cap_nodes)]
  ! Node ids from 1 (the default id_base), the slave points are nodes, the default options.
  call contactnn_contact_create(contact, types, connectivity, n_nodes, ierr, slave_nodes=slaves)
  if (ierr /= CONTACTNN_SUCCESS) then
    print '(2a)', 'contactnn_contact_create: ', contactnn_last_error()
    stop 1
  end if
  print '(a)', '# increment node face face_type location gap px py pz nx ny nz  (faces from 1, as the elements)'
  do k = 0, increments
    call place_nodes(k, x)
    call contactnn_contact_update(contact, x, ierr, status, face, location=location, point=point, gap=gap, &
                                  normal=normal)
    if (ierr /= CONTACTNN_SUCCESS) then
      print '(2a)', 'contactnn_contact_update: ', contactnn_last_error()
      stop 1
    end if
    print '(a,i0,a,i0,a,i0,a)', '# increment ', k, ': ', count(status == CONTACTNN_STATUS_OK), ' of ', cap_nodes, &
      ' slave nodes within reach'
    do i = 1, cap_nodes
      if (status(i) /= CONTACTNN_STATUS_OK) cycle
      print '(i0,1x,i0,1x,i0,1x,a,1x,a,7(1x,es24.16e3))', k, slaves(i), face(i), &
        merge('quad4', 'tri3 ', types(face(i)) == CONTACTNN_FACE_QUAD4), trim(location_name(location(i))), &
        gap(i), point(:, i), normal(:, i)
    end do
  end do
  call contactnn_contact_destroy(contact)
  deallocate (types, connectivity)

contains

  integer function top(i, j)
    integer, intent(in) :: i, j
    top = 1 + i + grid * j
  end function top

  ! The faces in the order of the elements that own them: a quad4 per hexahedron, two tri3 per wedge pair.
  subroutine build_faces(types, connectivity)
    integer(c_int), allocatable, intent(out) :: types(:), connectivity(:)
    integer :: i, j, a, b, c, d
    allocate (types(0), connectivity(0))
    do j = 0, cells - 1
      do i = 0, cells - 1
        a = top(i, j)
        b = top(i + 1, j)
        c = top(i + 1, j + 1)
        d = top(i, j + 1)
        if (i < cells / 2) then
          types = [types, CONTACTNN_FACE_QUAD4]
          connectivity = [connectivity, a, b, c, d]
        else
          types = [types, CONTACTNN_FACE_TRI3, CONTACTNN_FACE_TRI3]
          connectivity = [connectivity, a, b, c, a, c, d]
        end if
      end do
    end do
  end subroutine build_faces

  ! The node coordinates at increment k (0: the start).
  subroutine place_nodes(k, x)
    integer, intent(in) :: k
    real(c_double), intent(out) :: x(:, :)
    real(c_double), parameter :: radius = 3
    real(c_double) :: centre(3), polar, azimuth
    integer :: i, j, r, q, n, ring
    centre = [1.7_c_double + 0.06_c_double * k, 1.9_c_double + 0.03_c_double * k, &
              radius + 0.05_c_double - 0.02_c_double * k]
    n = 0
    do j = 0, grid - 1
      do i = 0, grid - 1
        n = n + 1
        x(:, n) = [real(i, c_double), real(j, c_double), &
                   -0.002_c_double * k * sin(pi * i / cells) * sin(pi * j / cells)]
      end do
    end do
    do j = 0, grid - 1
      do i = 0, grid - 1
        n = n + 1
        x(:, n) = [real(i, c_double), real(j, c_double), -1.0_c_double]
      end do
    end do
    do r = 0, rings
      polar = r * 8.0_c_double * pi / 180.0_c_double
      ring = max(1, 6 * r)
      do q = 0, ring - 1
        n = n + 1
        azimuth = 2.0_c_double * pi * q / ring
        x(:, n) = centre + radius * [sin(polar) * cos(azimuth), sin(polar) * sin(azimuth), -cos(polar)]
      end do
    end do
  end subroutine place_nodes

end program contact_search
