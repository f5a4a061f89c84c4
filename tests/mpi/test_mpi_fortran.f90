! The distributed contact search from Fortran (module contactnn_mpi, lib/mpi/contactnn_mpi.f90), under mpirun -np 3
! (tests/mpi/CMakeLists.txt). A flat plate of 6 x 6 unit quad4 faces at z = 0, its columns of faces split over the
! ranks, and one slave node above the centre of each face, split over the ranks in the opposite order (so that
! most slave nodes' faces live on another rank), pressed down through three increments. Known in closed form: each
! slave node's face (id i*6 + j), its owner rank, the point below it and the gap. Then a face id given by two
! ranks: the same error code on every rank. Prints PASS on rank 0 when every check holds on every rank.
program test_mpi_fortran
  use, intrinsic :: iso_c_binding, only: c_int, c_long, c_double
  use mpi
  use contactnn
  use contactnn_mpi
  implicit none
  integer, parameter :: n = 6
  type(contactnn_mpi_contact) :: c, bad
  integer :: ierr, rank, nranks, i, j, k, m, increment, failures, total, low, high
  integer(c_long), allocatable :: face_ids(:), connectivity(:), node_ids(:), slave_ids(:), face(:)
  integer(c_int), allocatable :: face_types(:), status(:), owner(:), location(:)
  real(c_double), allocatable :: coords(:, :), point(:, :), gap(:), normal(:, :)
  logical, allocatable :: mine(:)
  real(c_double) :: drop, x, y

  call MPI_Init(ierr)
  call MPI_Comm_rank(MPI_COMM_WORLD, rank, ierr)
  call MPI_Comm_size(MPI_COMM_WORLD, nranks, ierr)
  allocate (face_ids(0), connectivity(0), slave_ids(0), face_types(0))
  allocate (mine(1000 + n * n))  ! node ids 1 .. (n + 1)**2, slave ids 1001 .. 1000 + n**2
  mine = .false.
  do i = 0, n - 1
    do j = 0, n - 1
      if (i * nranks / n == rank) then
        face_ids = [face_ids, int(i * n + j, c_long)]
        face_types = [face_types, int(CONTACTNN_FACE_QUAD4, c_int)]
        connectivity = [connectivity, plate(i, j), plate(i + 1, j), plate(i + 1, j + 1), plate(i, j + 1)]
        mine(plate(i, j)) = .true.
        mine(plate(i + 1, j)) = .true.
        mine(plate(i + 1, j + 1)) = .true.
        mine(plate(i, j + 1)) = .true.
      end if
      if ((n - 1 - i) * nranks / n == rank) then
        slave_ids = [slave_ids, slave(i, j)]
        mine(slave(i, j)) = .true.
      end if
    end do
  end do
  node_ids = pack([(int(k, c_long), k = 1, size(mine))], mine)
  m = int(size(slave_ids))
  allocate (status(m), face(m), owner(m), location(m), point(3, m), gap(m), normal(3, m))
  allocate (coords(3, size(node_ids)))

  call contactnn_mpi_contact_create(c, MPI_COMM_WORLD, face_ids, face_types, connectivity, node_ids, slave_ids, ierr)
  failures = 0
  if (ierr /= CONTACTNN_SUCCESS) then
    print *, 'rank', rank, ': create failed: ', contactnn_last_error()
    failures = failures + 1
  end if
  do increment = 0, 2
    drop = 0.25d0 - 0.05d0 * increment
    do k = 1, size(node_ids)
      coords(:, k) = position(node_ids(k), drop)
    end do
    call contactnn_mpi_contact_update(c, coords, ierr, status, face, owner=owner, location=location, point=point, &
                                      gap=gap, normal=normal)
    if (ierr /= CONTACTNN_SUCCESS) then
      print *, 'rank', rank, ': update failed: ', contactnn_last_error()
      failures = failures + 1
      cycle
    end if
    do k = 1, m
      i = int((slave_ids(k) - 1001) / n)
      j = int(mod(slave_ids(k) - 1001, int(n, c_long)))
      x = i + 0.5d0
      y = j + 0.5d0
      if (status(k) /= CONTACTNN_STATUS_OK .or. face(k) /= i * n + j .or. owner(k) /= i * nranks / n .or. &
          location(k) /= CONTACTNN_LOCATION_FACE .or. abs(gap(k) - drop) > 1d-12 .or. &
          maxval(abs(point(:, k) - [x, y, 0d0])) > 1d-12 .or. maxval(abs(normal(:, k) - [0d0, 0d0, 1d0])) > 1d-12) then
        failures = failures + 1
        if (failures <= 5) print *, 'rank', rank, ' slave', slave_ids(k), ': face', face(k), ' owner', owner(k), &
          ' gap', gap(k), ' expected face', i * n + j, ' gap', drop
      end if
    end do
  end do
  if (contactnn_mpi_bytes_sent(c) <= 0 .and. nranks > 1) failures = failures + 1
  call contactnn_mpi_contact_destroy(c)

  ! A face id given twice (rank size - 1 passes rank 0's first face id): the same error on every rank.
  if (rank == nranks - 1 .and. nranks > 1) face_ids(1) = 0
  call contactnn_mpi_contact_create(bad, MPI_COMM_WORLD, face_ids, face_types, connectivity, node_ids, slave_ids, ierr)
  call MPI_Allreduce(ierr, low, 1, MPI_INTEGER, MPI_MIN, MPI_COMM_WORLD, k)
  call MPI_Allreduce(ierr, high, 1, MPI_INTEGER, MPI_MAX, MPI_COMM_WORLD, k)
  if (nranks > 1 .and. (low /= CONTACTNN_ERROR_INVALID_ARGUMENT .or. high /= low)) then
    print *, 'rank', rank, ': a face id given twice gave', ierr, ' (', low, '..', high, ')'
    failures = failures + 1
  end if
  call contactnn_mpi_contact_destroy(bad)

  call MPI_Allreduce(failures, total, 1, MPI_INTEGER, MPI_SUM, MPI_COMM_WORLD, ierr)
  if (rank == 0 .and. total == 0) print '(a,i0,a)', 'PASS: the distributed contact search from Fortran on ', nranks, &
    ' ranks'
  if (rank == 0 .and. total /= 0) print '(a,i0,a)', 'FAIL: ', total, ' checks failed'
  call MPI_Finalize(ierr)

contains

  integer(c_long) function plate(i, j)
    integer, intent(in) :: i, j
    plate = int(i * (n + 1) + j + 1, c_long)
  end function plate

  integer(c_long) function slave(i, j)
    integer, intent(in) :: i, j
    slave = int(1001 + i * n + j, c_long)
  end function slave

  !> Node id's position: the plate's nodes at z = 0, the slave nodes `drop` above the faces' centres.
  function position(id, drop) result(p)
    integer(c_long), intent(in) :: id
    real(c_double), intent(in) :: drop
    real(c_double) :: p(3)
    if (id <= (n + 1) * (n + 1)) then
      p = [real((id - 1) / (n + 1), c_double), real(mod(id - 1, int(n + 1, c_long)), c_double), 0d0]
    else
      p = [real((id - 1001) / n, c_double) + 0.5d0, real(mod(id - 1001, int(n, c_long)), c_double) + 0.5d0, drop]
    end if
  end function position

end program test_mpi_fortran
