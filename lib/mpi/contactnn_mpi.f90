! contactnn_mpi.f90: module contactnn_mpi, the Fortran 2008 interface of the contact search across MPI ranks
! (issue 41) over the C interface (contactnn/contactnn_mpi.h, whose comments are the full contract).
!
! Compile this file after contactnn.f90 (module contactnn: return codes, face types, contactnn_contact_options,
! contactnn_last_error) with your own compiler, and link libcontactnn_mpi_c and libcontactnn_c: with CMake,
! find_package(contactnn COMPONENTS mpi) gives its path as ${contactnn_MPI_FORTRAN_MODULE} and the library as
! contactnn::mpi_c. The communicator is a Fortran handle (an INTEGER, such as MPI_COMM_WORLD of `use mpi`); the
! library converts it with MPI_Comm_f2c, duplicates it and never calls MPI_Init.
!
! Global ids are integer(c_long) (face ids, node ids, the faces' connectivity, the face answered). Per slave node
! i: status(i), face(i) (the global face id, -1: none), optionally owner(i) (the rank that passed the face),
! location(i), param(2, i), point(3, i), gap(i), normal(3, i). Every procedure but contactnn_mpi_bytes_sent is
! collective; an error on any rank gives every rank the same ierr and contactnn_last_error().
!
! Sample use:
!   use mpi
!   use contactnn
!   use contactnn_mpi
!   type(contactnn_mpi_contact) :: c
!   call contactnn_mpi_contact_create(c, MPI_COMM_WORLD, face_ids, face_types, connectivity, node_ids, &
!                                     slave_ids, ierr)
!   call contactnn_mpi_contact_update(c, coords, ierr, status, face, owner=owner, gap=gap)
!   call contactnn_mpi_contact_destroy(c)
module contactnn_mpi
  use, intrinsic :: iso_c_binding, only: c_int, c_long, c_double, c_size_t, c_ptr, c_null_ptr, c_associated, c_loc
  use contactnn, only: contactnn_contact_options, contactnn_default_contact_options
  implicit none
  private

  !> A distributed contact search; create with contactnn_mpi_contact_create, free (collectively) with
  !> contactnn_mpi_contact_destroy. A copy shares the handle: destroy one of them only.
  type, public :: contactnn_mpi_contact
    private
    type(c_ptr) :: handle = c_null_ptr
    integer :: nodes = 0, slaves = 0
  end type contactnn_mpi_contact

  public :: contactnn_mpi_contact_create, contactnn_mpi_contact_update, contactnn_mpi_contact_destroy, &
            contactnn_mpi_bytes_sent

  interface
    function c_create(contact, comm, n_faces, face_ids, face_types, connectivity, n_nodes, node_ids, n_slaves, &
                      slave_ids, options) bind(C, name='contactnn_mpi_contact_create_f')
      import :: c_int, c_size_t, c_ptr, contactnn_contact_options
      type(c_ptr), intent(out) :: contact
      integer(c_int), value :: comm
      integer(c_size_t), value :: n_faces, n_nodes, n_slaves
      type(c_ptr), value :: face_ids, face_types, connectivity, node_ids, slave_ids
      type(contactnn_contact_options), intent(in) :: options
      integer(c_int) :: c_create
    end function c_create

    function c_update(contact, n_nodes, coords, n_slaves, status, face, owner, location, param, point, gap, &
                      normal) bind(C, name='contactnn_mpi_contact_update')
      import :: c_int, c_size_t, c_ptr
      type(c_ptr), value :: contact
      integer(c_size_t), value :: n_nodes, n_slaves
      type(c_ptr), value :: coords, status, face, owner, location, param, point, gap, normal
      integer(c_int) :: c_update
    end function c_update

    subroutine c_destroy(contact) bind(C, name='contactnn_mpi_contact_destroy')
      import :: c_ptr
      type(c_ptr), value :: contact
    end subroutine c_destroy

    function c_bytes_sent(contact) bind(C, name='contactnn_mpi_contact_bytes_sent')
      import :: c_ptr, c_long
      type(c_ptr), value :: contact
      integer(c_long) :: c_bytes_sent
    end function c_bytes_sent
  end interface

contains

  !> A pointer to an array's first element, or null for an empty one.
  function first_long(a) result(p)
    integer(c_long), intent(in), contiguous, target :: a(:)
    type(c_ptr) :: p
    p = c_null_ptr
    if (size(a) > 0) p = c_loc(a)
  end function first_long

  !> Collective (contactnn_mpi.h's contactnn_mpi_contact_create): this rank's faces (face_ids, face_types
  !> CONTACTNN_FACE_*, connectivity: 4, 8, 3 or 6 global node ids per face), the global ids of the nodes of every
  !> update's coords(3, n), this rank's slave node ids; options: contactnn_default_contact_options() when absent.
  !> A contact that already holds a handle is destroyed first (collectively).
  subroutine contactnn_mpi_contact_create(contact, comm, face_ids, face_types, connectivity, node_ids, slave_ids, &
                                          ierr, options)
    type(contactnn_mpi_contact), intent(inout) :: contact
    integer, intent(in) :: comm
    integer(c_long), intent(in), contiguous, target :: face_ids(:), connectivity(:), node_ids(:), slave_ids(:)
    integer(c_int), intent(in), contiguous, target :: face_types(:)
    integer, intent(out) :: ierr
    type(contactnn_contact_options), intent(in), optional :: options
    type(contactnn_contact_options) :: effective
    type(c_ptr) :: handle, types_ptr

    call contactnn_mpi_contact_destroy(contact)
    effective = contactnn_default_contact_options()
    if (present(options)) effective = options
    types_ptr = c_null_ptr
    if (size(face_types) > 0) types_ptr = c_loc(face_types)
    ! A face_ids of another length than face_types: the C interface sees a count that does not fit (on every rank).
    ierr = c_create(handle, int(comm, c_int), int(size(face_ids), c_size_t), first_long(face_ids), types_ptr, &
                    first_long(connectivity), int(size(node_ids), c_size_t), first_long(node_ids), &
                    int(size(slave_ids), c_size_t), first_long(slave_ids), effective)
    if (ierr /= 0) return
    contact%handle = handle
    contact%nodes = size(node_ids)
    contact%slaves = size(slave_ids)
  end subroutine contactnn_mpi_contact_create

  !> Collective. One increment (contactnn_mpi_contact_update): coords(3, n_nodes) in the order of node_ids. An
  !> array of the wrong extent (status, face, owner, location, gap: m; param 2 x m; point, normal 3 x m; coords
  !> 3 x n_nodes) fails on every rank, and nothing is written on any.
  subroutine contactnn_mpi_contact_update(contact, coords, ierr, status, face, owner, location, param, point, gap, &
                                          normal)
    type(contactnn_mpi_contact), intent(in) :: contact
    real(c_double), intent(in), contiguous, target :: coords(:, :)
    integer, intent(out) :: ierr
    integer(c_int), intent(inout), contiguous, target :: status(:)
    integer(c_long), intent(inout), contiguous, target :: face(:)
    integer(c_int), intent(inout), optional, contiguous, target :: owner(:), location(:)
    real(c_double), intent(inout), optional, contiguous, target :: param(:, :), point(:, :), normal(:, :)
    real(c_double), intent(inout), optional, contiguous, target :: gap(:)
    type(c_ptr) :: owner_ptr, location_ptr, param_ptr, point_ptr, gap_ptr, normal_ptr
    integer :: m
    logical :: fits

    m = contact%slaves
    fits = size(coords, 1) == 3 .and. size(coords, 2) == contact%nodes .and. size(status) == m .and. size(face) == m
    if (present(owner)) fits = fits .and. size(owner) == m
    if (present(location)) fits = fits .and. size(location) == m
    if (present(param)) fits = fits .and. size(param, 1) == 2 .and. size(param, 2) == m
    if (present(point)) fits = fits .and. size(point, 1) == 3 .and. size(point, 2) == m
    if (present(gap)) fits = fits .and. size(gap) == m
    if (present(normal)) fits = fits .and. size(normal, 1) == 3 .and. size(normal, 2) == m
    ! The optional arrays go only where every array fits and there are slave nodes: no arrays for no slave nodes;
    ! arrays that do not fit go as none at all, which the C++ class refuses on every rank (the other ranks must
    ! take part in the collective error).
    owner_ptr = c_null_ptr
    location_ptr = c_null_ptr
    param_ptr = c_null_ptr
    point_ptr = c_null_ptr
    gap_ptr = c_null_ptr
    normal_ptr = c_null_ptr
    if (fits .and. m > 0) then
      if (present(owner)) owner_ptr = c_loc(owner)
      if (present(location)) location_ptr = c_loc(location)
      if (present(param)) param_ptr = c_loc(param)
      if (present(point)) point_ptr = c_loc(point)
      if (present(gap)) gap_ptr = c_loc(gap)
      if (present(normal)) normal_ptr = c_loc(normal)
      ierr = c_update(contact%handle, int(contact%nodes, c_size_t), c_loc(coords), int(m, c_size_t), c_loc(status), &
                      c_loc(face), owner_ptr, location_ptr, param_ptr, point_ptr, gap_ptr, normal_ptr)
    else if (fits .and. size(coords) > 0) then
      ierr = c_update(contact%handle, int(contact%nodes, c_size_t), c_loc(coords), 0_c_size_t, c_null_ptr, &
                      c_null_ptr, c_null_ptr, c_null_ptr, c_null_ptr, c_null_ptr, c_null_ptr, c_null_ptr)
    else
      ierr = c_update(contact%handle, int(contact%nodes, c_size_t), c_null_ptr, int(m, c_size_t), c_null_ptr, &
                      c_null_ptr, c_null_ptr, c_null_ptr, c_null_ptr, c_null_ptr, c_null_ptr, c_null_ptr)
    end if
  end subroutine contactnn_mpi_contact_update

  !> Collective (frees the duplicate communicator). A contact without a handle is left alone.
  subroutine contactnn_mpi_contact_destroy(contact)
    type(contactnn_mpi_contact), intent(inout) :: contact
    if (c_associated(contact%handle)) call c_destroy(contact%handle)
    contact%handle = c_null_ptr
    contact%nodes = 0
    contact%slaves = 0
  end subroutine contactnn_mpi_contact_destroy

  !> The bytes this rank sent in the last update (-1 without a handle). Local.
  function contactnn_mpi_bytes_sent(contact) result(bytes)
    type(contactnn_mpi_contact), intent(in) :: contact
    integer(c_long) :: bytes
    bytes = -1
    if (c_associated(contact%handle)) bytes = c_bytes_sent(contact%handle)
  end function contactnn_mpi_bytes_sent
end module contactnn_mpi
