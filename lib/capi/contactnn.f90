! contactnn.f90: module contactnn, the Fortran 2008 interface of contactnn's run-time local search, over the
! C interface (contactnn/contactnn.h, whose comments are the full contract) with iso_c_binding.
!
! Compile this file with your own code (any Fortran 2008 compiler; the module file it makes belongs to that
! compiler) and link libcontactnn_c: with CMake, find_package(contactnn) gives its path as
! ${contactnn_FORTRAN_MODULE} and the library as contactnn::c.
!
! Layout: Fortran arrays are column-major, so one query's values are one column:
!   raw(15, n)    bilinear: ax ay az bx by bz cx cy cz dx dy dz sx sy sz (SPEC 6 order), world coordinates
!   raw(27, n)    Gregory: the same 15, then the node normals nax nay naz ... ndx ndy ndz (any positive length)
!   param(2, n)   (xi, eta) in [-1, 1]^2 (bilinear) or (u, v) in [0, 1]^2 (Gregory) of the closest point;
!                 intent(inout): the method start+newton:K reads each query's start from it first
!   status(n)     CONTACTNN_STATUS_* per query
!   gap(n)        optional: signed distance along the unit normal at the reported point (< 0: penetration;
!                 four_triangles: +-|S - P|, the sign of (S - P).(C - A)x(D - B))
!   iterations(n) optional: Newton steps taken
! which is the C interface's row-major n x 15 / n x 2: nothing is copied for contiguous arrays. Every array
! of a call must have the extent n = size(raw, 2) (param: 2 x n); real(c_double) or real(c_float) arrays,
! one kind per call.
!
! Errors: every procedure that can fail has an integer ierr, CONTACTNN_SUCCESS (0) or a CONTACTNN_ERROR_*
! code; contactnn_last_error() then returns the message. Nothing stops the program.
!
! Sample use:
!   use contactnn
!   type(contactnn_search) :: search
!   call contactnn_create(search, CONTACTNN_SURFACE_BILINEAR, 'network+newton:2', ierr, network='bilinear-8.h5')
!   if (ierr /= CONTACTNN_SUCCESS) print *, contactnn_last_error()
!   call contactnn_run(search, raw, param, status, ierr, gap=gap)
!   call contactnn_destroy(search)
! A scene plan (scene-study's DIR/plan.toml, SPEC 7) gives the surface, the method and the network in one file:
!   call contactnn_create_from_plan(search, 'study/plan.toml', ierr)
!   if (contactnn_surface(search) == CONTACTNN_SURFACE_GREGORY) ...   ! raw(27, n) rather than raw(15, n)
module contactnn
  use, intrinsic :: iso_c_binding, only: c_int, c_double, c_float, c_size_t, c_char, c_ptr, c_null_ptr, &
                                         c_null_char, c_associated, c_f_pointer, c_loc
  implicit none
  private

  ! Return codes (contactnn_return_code).
  integer, parameter, public :: CONTACTNN_SUCCESS = 0, CONTACTNN_ERROR_INTERNAL = 1, &
                                CONTACTNN_ERROR_INVALID_ARGUMENT = 2, CONTACTNN_ERROR_FORMAT = 3, &
                                CONTACTNN_ERROR_IO = 4, CONTACTNN_ERROR_NUMERICAL = 5, &
                                CONTACTNN_ERROR_OUT_OF_MEMORY = 6
  ! Per-query statuses (contactnn_status, the values of contactnn::Status).
  integer(c_int), parameter, public :: CONTACTNN_STATUS_OK = 0, CONTACTNN_STATUS_OUTSIDE = 1, &
                                       CONTACTNN_STATUS_NO_CONVERGENCE = 2, CONTACTNN_STATUS_DEGENERATE = 3, &
                                       CONTACTNN_STATUS_INVALID = 4, CONTACTNN_STATUS_OUT_OF_DOMAIN = 5, &
                                       CONTACTNN_STATUS_NO_SEGMENT = 6
  ! Surface kinds (contactnn_surface).
  integer, parameter, public :: CONTACTNN_SURFACE_BILINEAR = 0, CONTACTNN_SURFACE_GREGORY = 1
  !> The other faces of SPEC 9 (FaceSearch): raw(12, n), raw(21, n), raw(27, n); nodes in SPEC 9's order, then S.
  integer, parameter, public :: CONTACTNN_SURFACE_TRI3 = 2, CONTACTNN_SURFACE_TRI6 = 3, CONTACTNN_SURFACE_QUAD8 = 4

  !> The C struct contactnn_options, field for field: get the defaults from contactnn_default_options().
  type, bind(C), public :: contactnn_options
    integer(c_int) :: threads             ! OpenMP threads per run; <= 0: OpenMP's default
    integer(c_int) :: check_domain        ! network methods: /= 0 flags out_of_domain queries
    integer(c_int) :: max_iterations      ! "newton": iteration limit, 1 to 1000
    integer(c_int) :: max_halvings        ! hybrids: step halvings before no_convergence, 0 to 60
    real(c_double) :: tol_param           ! "newton": step tolerance, parameter units, 0 to 1
    real(c_double) :: domain_margin       ! ok versus outside: slack, parameter units, 0 to 1
    real(c_double) :: gregory_box_margin  ! hybrids, Gregory: box margin in domain widths, 0 to 1
    real(c_double) :: bilinear_box_margin ! hybrids, bilinear: box margin in domain widths, 0 to 1
    real(c_double) :: max_step_widths     ! hybrids: longest step in domain widths, > 0 and <= 1
    integer(c_size_t) :: min_parallel_count ! below this many queries a run uses one thread
  end type contactnn_options

  !> A search (one method on one surface kind); create with contactnn_create, free with contactnn_destroy.
  !> A copy (b = a) shares a's search: destroy one of them only, once (no reference count, no finaliser).
  type, public :: contactnn_search
    private
    type(c_ptr) :: handle = c_null_ptr
    integer :: columns = 0
  end type contactnn_search

  public :: contactnn_create, contactnn_run, contactnn_destroy, contactnn_default_options, &
            contactnn_last_error, contactnn_version, contactnn_status_name
  public :: contactnn_create_from_plan, contactnn_surface, contactnn_method

  !> call contactnn_run(search, raw, param, status, ierr [, gap] [, iterations]): double or single precision.
  interface contactnn_run
    module procedure run_double, run_float
  end interface contactnn_run

  interface
    function c_version(major, minor, patch) bind(C, name='contactnn_version')
      import :: c_ptr, c_int
      integer(c_int), intent(out) :: major, minor, patch
      type(c_ptr) :: c_version
    end function c_version

    function c_last_error() bind(C, name='contactnn_last_error')
      import :: c_ptr
      type(c_ptr) :: c_last_error
    end function c_last_error

    function c_set_last_error(code, message) bind(C, name='contactnn_set_last_error')
      import :: c_int, c_char
      integer(c_int), value :: code
      character(kind=c_char), intent(in) :: message(*)
      integer(c_int) :: c_set_last_error
    end function c_set_last_error

    function c_status_name(status) bind(C, name='contactnn_status_name')
      import :: c_int, c_ptr
      integer(c_int), value :: status
      type(c_ptr) :: c_status_name
    end function c_status_name

    function c_raw_columns(surface) bind(C, name='contactnn_raw_columns')
      import :: c_int
      integer(c_int), value :: surface
      integer(c_int) :: c_raw_columns
    end function c_raw_columns

    function c_options_init(options) bind(C, name='contactnn_options_init')
      import :: c_int, contactnn_options
      type(contactnn_options), intent(out) :: options
      integer(c_int) :: c_options_init
    end function c_options_init

    function c_search_create(search, surface, method, network_file, options) bind(C, name='contactnn_search_create')
      import :: c_int, c_char, c_ptr, contactnn_options
      type(c_ptr), intent(out) :: search
      integer(c_int), value :: surface
      character(kind=c_char), intent(in) :: method(*), network_file(*)
      type(contactnn_options), intent(in) :: options
      integer(c_int) :: c_search_create
    end function c_search_create

    subroutine c_search_destroy(search) bind(C, name='contactnn_search_destroy')
      import :: c_ptr
      type(c_ptr), value :: search
    end subroutine c_search_destroy

    function c_search_run(search, count, raw, param, gap, status, iterations) bind(C, name='contactnn_search_run')
      import :: c_int, c_size_t, c_ptr
      type(c_ptr), value :: search
      integer(c_size_t), value :: count
      type(c_ptr), value :: raw, param, gap, status, iterations
      integer(c_int) :: c_search_run
    end function c_search_run

    function c_search_run_float(search, count, raw, param, gap, status, iterations) &
        bind(C, name='contactnn_search_run_float')
      import :: c_int, c_size_t, c_ptr
      type(c_ptr), value :: search
      integer(c_size_t), value :: count
      type(c_ptr), value :: raw, param, gap, status, iterations
      integer(c_int) :: c_search_run_float
    end function c_search_run_float

    function c_search_create_from_plan(search, plan_file, options) bind(C, name='contactnn_search_create_from_plan')
      import :: c_int, c_char, c_ptr, contactnn_options
      type(c_ptr), intent(out) :: search
      character(kind=c_char), intent(in) :: plan_file(*)
      type(contactnn_options), intent(in) :: options
      integer(c_int) :: c_search_create_from_plan
    end function c_search_create_from_plan

    function c_search_surface(search) bind(C, name='contactnn_search_surface')
      import :: c_int, c_ptr
      type(c_ptr), value :: search
      integer(c_int) :: c_search_surface
    end function c_search_surface

    function c_search_method(search) bind(C, name='contactnn_search_method')
      import :: c_ptr
      type(c_ptr), value :: search
      type(c_ptr) :: c_search_method
    end function c_search_method

    function c_strlen(s) bind(C, name='strlen')
      import :: c_ptr, c_size_t
      type(c_ptr), value :: s
      integer(c_size_t) :: c_strlen
    end function c_strlen
  end interface

  ! ---------------------------------------------------------------------------------------------------------------
  ! The contact search handle (contactnn.h's contactnn_contact_*, issue 38): the whole surface search of SPEC 9 for
  ! an FE code, tracking inside. Face types (contactnn_face_type) and locations (contactnn_location):
  integer, parameter, public :: CONTACTNN_FACE_QUAD4 = 0, CONTACTNN_FACE_QUAD8 = 1, CONTACTNN_FACE_TRI3 = 2, &
                                CONTACTNN_FACE_TRI6 = 3
  integer, parameter, public :: CONTACTNN_LOCATION_FACE = 0, CONTACTNN_LOCATION_EDGE = 1, CONTACTNN_LOCATION_VERTEX = 2

  !> The C struct contactnn_contact_options: get the defaults from contactnn_default_contact_options().
  type, bind(C), public :: contactnn_contact_options
    real(c_double) :: capture_distance ! world units; <= 0: one largest face size
    integer(c_int) :: quad4_surface    ! CONTACTNN_SURFACE_BILINEAR or CONTACTNN_SURFACE_GREGORY
    integer(c_int) :: threads          ! OpenMP threads of an update; <= 0: OpenMP's default
    integer(c_int) :: tracking         ! /= 0: reuse the previous increment's candidates (the same answers)
    ! The face-interior method as C strings (contactnn.h): give them as contactnn_contact_create's method=,
    ! network= and plan= instead; these stay null (the exact search) unless a caller sets them with c_loc.
    type(c_ptr) :: method, network_file, plan_file
  end type contactnn_contact_options

  !> A contact search; create with contactnn_contact_create, free with contactnn_contact_destroy. A copy shares the
  !> handle: destroy one of them only.
  type, public :: contactnn_contact
    private
    type(c_ptr) :: handle = c_null_ptr
    integer :: nodes = 0, slaves = 0
    logical :: free = .false.
  end type contactnn_contact

  public :: contactnn_contact_create, contactnn_contact_update, contactnn_contact_destroy, &
            contactnn_default_contact_options

  interface
    function c_contact_options_init(options) bind(C, name='contactnn_contact_options_init')
      import :: c_int, contactnn_contact_options
      type(contactnn_contact_options), intent(out) :: options
      integer(c_int) :: c_contact_options_init
    end function c_contact_options_init

    function c_contact_create(contact, n_faces, face_types, connectivity, n_nodes, node_ids, id_base, n_slaves, &
                              slave_node_ids, options) bind(C, name='contactnn_contact_create')
      import :: c_int, c_size_t, c_ptr, contactnn_contact_options
      type(c_ptr), intent(out) :: contact
      integer(c_size_t), value :: n_faces, n_nodes, n_slaves
      type(c_ptr), value :: face_types, connectivity, node_ids, slave_node_ids
      integer(c_int), value :: id_base
      type(contactnn_contact_options), intent(in) :: options
      integer(c_int) :: c_contact_create
    end function c_contact_create

    subroutine c_contact_destroy(contact) bind(C, name='contactnn_contact_destroy')
      import :: c_ptr
      type(c_ptr), value :: contact
    end subroutine c_contact_destroy

    function c_contact_update(contact, n_nodes, coords, n_slaves, slave_points, status, face, location, param, &
                              point, gap, normal) bind(C, name='contactnn_contact_update')
      import :: c_int, c_size_t, c_ptr
      type(c_ptr), value :: contact
      integer(c_size_t), value :: n_nodes, n_slaves
      type(c_ptr), value :: coords, slave_points, status, face, location, param, point, gap, normal
      integer(c_int) :: c_contact_update
    end function c_contact_update
  end interface

contains

  !> `text` without its trailing blanks as a C string (an array of characters ending in c_null_char).
  subroutine to_c_chars(text, chars)
    character(len=*), intent(in) :: text
    character(kind=c_char), allocatable, intent(out) :: chars(:)
    integer :: i, n
    n = len_trim(text)
    allocate (chars(n + 1))
    do i = 1, n
      chars(i) = text(i:i)
    end do
    chars(n + 1) = c_null_char
  end subroutine to_c_chars

  !> A Fortran string from a C string (empty for a null pointer).
  function from_c_string(p) result(s)
    type(c_ptr), intent(in) :: p
    character(len=:), allocatable :: s
    character(kind=c_char), pointer :: chars(:)
    integer :: i, n
    if (.not. c_associated(p)) then
      s = ''
      return
    end if
    n = int(c_strlen(p))
    call c_f_pointer(p, chars, [n])
    allocate (character(len=n) :: s)
    do i = 1, n
      s(i:i) = chars(i)
    end do
  end function from_c_string

  !> The message of the most recent failing call on this thread ('' when none has).
  function contactnn_last_error() result(message)
    character(len=:), allocatable :: message
    message = from_c_string(c_last_error())
  end function contactnn_last_error

  !> The library's version as 'MAJOR.MINOR.PATCH'.
  function contactnn_version() result(version)
    character(len=:), allocatable :: version
    integer(c_int) :: major, minor, patch
    version = from_c_string(c_version(major, minor, patch))
  end function contactnn_version

  !> The CSV spelling of a status ('ok', 'outside', ..., 'unknown' for other values).
  function contactnn_status_name(status) result(name)
    integer, intent(in) :: status
    character(len=:), allocatable :: name
    name = from_c_string(c_status_name(int(status, c_int)))
  end function contactnn_status_name

  !> The library's default options (then change the fields you need and pass them to contactnn_create).
  function contactnn_default_options() result(options)
    type(contactnn_options) :: options
    integer(c_int) :: ierr
    ierr = c_options_init(options)  ! cannot fail: the argument is never null
  end function contactnn_default_options

  !> Creates a search: surface CONTACTNN_SURFACE_BILINEAR or _GREGORY (or a face of SPEC 9: _TRI3, _TRI6,
  !> _QUAD8, FaceSearch's methods, a face network file of scene-study --face); method 'network', 'newton:K',
  !> 'newton', 'closed_form', 'network+newton:K', 'closed_form+newton:K', 'start+newton:K' (K from 0 to
  !> 1000; param holds the starts when contactnn_run is called) or, bilinear only, 'four_triangles' (after
  !> OpenRadioss's type 7 contact: the nearest point of the four triangles about the segment's centroid, no
  !> iteration; its gap is +-|S - P|); network: a train-net network file (required by the network
  !> methods); options: contactnn_default_options() when absent. On failure search holds no handle and
  !> ierr /= CONTACTNN_SUCCESS. A search that already holds one is destroyed first.
  subroutine contactnn_create(search, surface, method, ierr, network, options)
    type(contactnn_search), intent(inout) :: search
    integer, intent(in) :: surface
    character(len=*), intent(in) :: method
    integer, intent(out) :: ierr
    character(len=*), intent(in), optional :: network
    type(contactnn_options), intent(in), optional :: options
    type(contactnn_options) :: effective
    type(c_ptr) :: handle

    call contactnn_destroy(search)
    if (present(options)) then
      effective = options
    else
      effective = contactnn_default_options()
    end if
    if (present(network)) then
      ierr = c_search_create(handle, int(surface, c_int), trim(method)//c_null_char, trim(network)//c_null_char, &
                             effective)
    else
      ! An empty file name is the C interface's "no network".
      ierr = c_search_create(handle, int(surface, c_int), trim(method)//c_null_char, c_null_char, effective)
    end if
    if (ierr /= CONTACTNN_SUCCESS) return
    search%handle = handle
    search%columns = c_raw_columns(int(surface, c_int))
  end subroutine contactnn_create

  !> Frees a search (nothing happens for one that holds no handle).
  subroutine contactnn_destroy(search)
    type(contactnn_search), intent(inout) :: search
    if (c_associated(search%handle)) call c_search_destroy(search%handle)
    search%handle = c_null_ptr
    search%columns = 0
  end subroutine contactnn_destroy

  !> ierr for arrays that do not fit the search: CONTACTNN_ERROR_INVALID_ARGUMENT with the message set.
  function check_shapes(search, raw_rows, n, param_rows, param_cols, status_size, gap_size, iterations_size) &
      result(ierr)
    type(contactnn_search), intent(in) :: search
    integer, intent(in) :: raw_rows, n, param_rows, param_cols, status_size, gap_size, iterations_size
    integer :: ierr
    character(len=200) :: message
    ierr = CONTACTNN_SUCCESS
    if (.not. c_associated(search%handle)) then
      message = 'contactnn_run: the search was not created (or was destroyed)'
    else if (raw_rows /= search%columns) then
      write (message, '(a,i0,a,i0,a)') 'contactnn_run: raw has ', raw_rows, ' rows, the search expects ', &
        search%columns, ' (raw(15, n) bilinear, raw(27, n) Gregory or quad8, raw(12, n) tri3, raw(21, n) tri6)'
    else if (param_rows /= 2 .or. param_cols /= n) then
      write (message, '(a,i0,a,i0,a,i0,a)') 'contactnn_run: param is ', param_rows, ' x ', param_cols, &
        ', expected 2 x ', n, ' (n = size(raw, 2))'
    else if (status_size /= n) then
      write (message, '(a,i0,a,i0)') 'contactnn_run: status has ', status_size, ' elements, expected ', n
    else if (gap_size >= 0 .and. gap_size /= n) then
      write (message, '(a,i0,a,i0)') 'contactnn_run: gap has ', gap_size, ' elements, expected ', n
    else if (iterations_size >= 0 .and. iterations_size /= n) then
      write (message, '(a,i0,a,i0)') 'contactnn_run: iterations has ', iterations_size, ' elements, expected ', n
    else
      return
    end if
    ierr = c_set_last_error(int(CONTACTNN_ERROR_INVALID_ARGUMENT, c_int), trim(message)//c_null_char)
  end function check_shapes

  subroutine run_double(search, raw, param, status, ierr, gap, iterations)
    type(contactnn_search), intent(in) :: search
    real(c_double), intent(in), contiguous, target :: raw(:, :)
    real(c_double), intent(inout), contiguous, target :: param(:, :)
    integer(c_int), intent(out), contiguous, target :: status(:)
    integer, intent(out) :: ierr
    real(c_double), intent(out), optional, contiguous, target :: gap(:)
    integer(c_int), intent(out), optional, contiguous, target :: iterations(:)
    type(c_ptr) :: gap_ptr, iterations_ptr
    integer :: gap_size, iterations_size

    gap_size = -1
    iterations_size = -1
    if (present(gap)) gap_size = size(gap)
    if (present(iterations)) iterations_size = size(iterations)
    ierr = check_shapes(search, size(raw, 1), size(raw, 2), size(param, 1), size(param, 2), size(status), &
                        gap_size, iterations_size)
    if (ierr /= CONTACTNN_SUCCESS .or. size(raw, 2) == 0) return
    gap_ptr = c_null_ptr
    iterations_ptr = c_null_ptr
    if (present(gap)) gap_ptr = c_loc(gap)
    if (present(iterations)) iterations_ptr = c_loc(iterations)
    ierr = c_search_run(search%handle, int(size(raw, 2), c_size_t), c_loc(raw), c_loc(param), gap_ptr, &
                        c_loc(status), iterations_ptr)
  end subroutine run_double

  subroutine run_float(search, raw, param, status, ierr, gap, iterations)
    type(contactnn_search), intent(in) :: search
    real(c_float), intent(in), contiguous, target :: raw(:, :)
    real(c_float), intent(inout), contiguous, target :: param(:, :)
    integer(c_int), intent(out), contiguous, target :: status(:)
    integer, intent(out) :: ierr
    real(c_float), intent(out), optional, contiguous, target :: gap(:)
    integer(c_int), intent(out), optional, contiguous, target :: iterations(:)
    type(c_ptr) :: gap_ptr, iterations_ptr
    integer :: gap_size, iterations_size

    gap_size = -1
    iterations_size = -1
    if (present(gap)) gap_size = size(gap)
    if (present(iterations)) iterations_size = size(iterations)
    ierr = check_shapes(search, size(raw, 1), size(raw, 2), size(param, 1), size(param, 2), size(status), &
                        gap_size, iterations_size)
    if (ierr /= CONTACTNN_SUCCESS .or. size(raw, 2) == 0) return
    gap_ptr = c_null_ptr
    iterations_ptr = c_null_ptr
    if (present(gap)) gap_ptr = c_loc(gap)
    if (present(iterations)) iterations_ptr = c_loc(iterations)
    ierr = c_search_run_float(search%handle, int(size(raw, 2), c_size_t), c_loc(raw), c_loc(param), gap_ptr, &
                              c_loc(status), iterations_ptr)
  end subroutine run_float

  !> Creates a search from a scene plan (scene-study's DIR/plan.toml, SPEC 7): the plan's surface, its method and,
  !> where the method uses one, its network file (relative to the plan's directory). options:
  !> contactnn_default_options() when absent. contactnn_surface(search) then tells raw(15, n) from raw(27, n). On
  !> failure search holds no handle and ierr /= CONTACTNN_SUCCESS (a malformed plan: CONTACTNN_ERROR_FORMAT, the
  !> message naming the file, the line and the key). A search that already holds one is destroyed first.
  subroutine contactnn_create_from_plan(search, plan, ierr, options)
    type(contactnn_search), intent(inout) :: search
    character(len=*), intent(in) :: plan
    integer, intent(out) :: ierr
    type(contactnn_options), intent(in), optional :: options
    type(contactnn_options) :: effective
    type(c_ptr) :: handle

    call contactnn_destroy(search)
    if (present(options)) then
      effective = options
    else
      effective = contactnn_default_options()
    end if
    ierr = c_search_create_from_plan(handle, trim(plan)//c_null_char, effective)
    if (ierr /= CONTACTNN_SUCCESS) return
    search%handle = handle
    search%columns = c_raw_columns(c_search_surface(handle))
  end subroutine contactnn_create_from_plan

  !> The surface of a search (CONTACTNN_SURFACE_BILINEAR or _GREGORY), or -1 when it holds no handle.
  function contactnn_surface(search) result(surface)
    type(contactnn_search), intent(in) :: search
    integer :: surface
    surface = -1
    if (c_associated(search%handle)) surface = int(c_search_surface(search%handle))
  end function contactnn_surface

  !> The method of a search ('network+newton:1', 'closed_form', ...), or '' when it holds no handle.
  function contactnn_method(search) result(method)
    type(contactnn_search), intent(in) :: search
    character(len=:), allocatable :: method
    method = ''
    if (c_associated(search%handle)) method = from_c_string(c_search_method(search%handle))
  end function contactnn_method

  ! ---------------------------------------------------------------------------------------------------------------
  ! The contact search handle.

  function contactnn_default_contact_options() result(options)
    type(contactnn_contact_options) :: options
    integer(c_int) :: ierr
    ierr = c_contact_options_init(options)  ! cannot fail: the argument is never null
  end function contactnn_default_contact_options

  !> Creates a contact search (contactnn.h's contactnn_contact_create).
  !>   face_types(n_faces)  CONTACTNN_FACE_*
  !>   connectivity(:)      the faces' node ids, concatenated (4, 8, 3 or 6 per face by its type; SPEC 9's order)
  !>   n_nodes              nodes of the coordinate array coords(3, n_nodes) of every update
  !>   slave_nodes(m)       slave node ids; or, absent, n_points free points (integration points) whose
  !>                        coordinates every update passes in points(3, n_points)
  !>   id_base              the id of coords(:, 1) (default 1); node_ids(n_nodes): each node's id (global ids)
  !>   options              contactnn_default_contact_options() when absent
  !>   method, network      the face-interior method ('closed_form+newton:2', 'newton:4', 'network+newton:1' with
  !>                        its network file; contactnn.h's options.method and .network_file); absent or '': the
  !>                        exact search
  !>   plan                 or a scene plan (scene-study's DIR/plan.toml): its method and network file
  !>                        (options.plan_file); its surface must be options%quad4_surface
  !> On failure contact holds no handle and ierr /= CONTACTNN_SUCCESS (contactnn_last_error() says why: a bad
  !> method CONTACTNN_ERROR_INVALID_ARGUMENT, a missing plan or network file CONTACTNN_ERROR_IO). A contact that
  !> already holds a handle is destroyed first.
  subroutine contactnn_contact_create(contact, face_types, connectivity, n_nodes, ierr, slave_nodes, n_points, &
                                      id_base, node_ids, options, method, network, plan)
    type(contactnn_contact), intent(inout) :: contact
    integer(c_int), intent(in), contiguous, target :: face_types(:), connectivity(:)
    integer, intent(in) :: n_nodes
    integer, intent(out) :: ierr
    integer(c_int), intent(in), optional, contiguous, target :: slave_nodes(:), node_ids(:)
    integer, intent(in), optional :: n_points, id_base
    type(contactnn_contact_options), intent(in), optional :: options
    character(len=*), intent(in), optional :: method, network, plan
    type(contactnn_contact_options) :: effective
    character(kind=c_char), allocatable, target :: method_c(:), network_c(:), plan_c(:)
    type(c_ptr) :: handle, ids_ptr, slaves_ptr
    integer :: base, m, expected, f
    logical :: known
    character(len=200) :: message

    call contactnn_contact_destroy(contact)
    effective = contactnn_default_contact_options()
    if (present(options)) effective = options
    base = 1
    if (present(id_base)) base = id_base
    message = ''
    expected = 0
    known = .true.  ! an unknown face type is the C interface's to name
    do f = 1, size(face_types)
      select case (face_types(f))
      case (CONTACTNN_FACE_QUAD4)
        expected = expected + 4
      case (CONTACTNN_FACE_QUAD8)
        expected = expected + 8
      case (CONTACTNN_FACE_TRI3)
        expected = expected + 3
      case (CONTACTNN_FACE_TRI6)
        expected = expected + 6
      case default
        known = .false.
      end select
    end do
    if (present(slave_nodes) .eqv. present(n_points)) then
      message = 'contactnn_contact_create: give slave_nodes or n_points, one of the two'
    else if (present(node_ids)) then
      if (size(node_ids) /= n_nodes) write (message, '(a,i0,a,i0)') 'contactnn_contact_create: node_ids has ', &
        size(node_ids), ' elements, expected n_nodes = ', n_nodes
    end if
    if (len_trim(message) == 0 .and. size(connectivity) /= expected .and. known) then
      write (message, '(a,i0,a,i0)') 'contactnn_contact_create: connectivity has ', size(connectivity), &
        ' node ids, the face types need ', expected
    end if
    if (len_trim(message) == 0 .and. n_nodes < 0) write (message, '(a,i0)') 'contactnn_contact_create: n_nodes = ', &
      n_nodes
    if (len_trim(message) == 0 .and. present(n_points)) then
      if (n_points < 0) write (message, '(a,i0)') 'contactnn_contact_create: n_points = ', n_points
    end if
    if (len_trim(message) /= 0) then
      ierr = c_set_last_error(int(CONTACTNN_ERROR_INVALID_ARGUMENT, c_int), trim(message)//c_null_char)
      return
    end if
    if (present(method)) then
      call to_c_chars(method, method_c)
      effective%method = c_loc(method_c)
    end if
    if (present(network)) then
      call to_c_chars(network, network_c)
      effective%network_file = c_loc(network_c)
    end if
    if (present(plan)) then
      call to_c_chars(plan, plan_c)
      effective%plan_file = c_loc(plan_c)
    end if
    ids_ptr = c_null_ptr
    slaves_ptr = c_null_ptr
    if (present(node_ids)) ids_ptr = c_loc(node_ids)
    if (present(slave_nodes)) then
      m = size(slave_nodes)
      if (m > 0) slaves_ptr = c_loc(slave_nodes)
    else
      m = n_points
    end if
    ierr = c_contact_create(handle, int(size(face_types), c_size_t), c_loc(face_types), c_loc(connectivity), &
                            int(n_nodes, c_size_t), ids_ptr, int(base, c_int), int(m, c_size_t), slaves_ptr, effective)
    if (ierr /= CONTACTNN_SUCCESS) return
    contact%handle = handle
    contact%nodes = n_nodes
    contact%slaves = m
    contact%free = .not. present(slave_nodes)
  end subroutine contactnn_contact_create

  !> One increment (contactnn.h's contactnn_contact_update): coords(3, n_nodes), points(3, m) for free points; per
  !> slave point status(m) (CONTACTNN_STATUS_OK or _NO_SEGMENT), face(m) the face's position in face_types FROM 1
  !> (0: none), optionally location(m) (CONTACTNN_LOCATION_*, -1: none), param(2, m), point(3, m), gap(m),
  !> normal(3, m). On failure nothing is written.
  subroutine contactnn_contact_update(contact, coords, ierr, status, face, location, param, point, gap, normal, points)
    type(contactnn_contact), intent(in) :: contact
    real(c_double), intent(in), contiguous, target :: coords(:, :)
    integer, intent(out) :: ierr
    integer(c_int), intent(inout), contiguous, target :: status(:), face(:)
    integer(c_int), intent(inout), optional, contiguous, target :: location(:)
    real(c_double), intent(inout), optional, contiguous, target :: param(:, :), point(:, :), normal(:, :)
    real(c_double), intent(inout), optional, contiguous, target :: gap(:)
    real(c_double), intent(in), optional, contiguous, target :: points(:, :)
    type(c_ptr) :: location_ptr, param_ptr, point_ptr, gap_ptr, normal_ptr, points_ptr
    character(len=200) :: message
    integer :: m

    m = contact%slaves
    message = ''
    if (.not. c_associated(contact%handle)) then
      message = 'contactnn_contact_update: the contact search was not created (or was destroyed)'
    else if (size(coords, 1) /= 3 .or. size(coords, 2) /= contact%nodes) then
      write (message, '(a,i0,a,i0,a,i0)') 'contactnn_contact_update: coords is ', size(coords, 1), ' x ', &
        size(coords, 2), ', expected 3 x ', contact%nodes
    else if (present(points) .neqv. contact%free) then
      message = 'contactnn_contact_update: points are given exactly for a search of free points'
    else if (size(status) /= m .or. size(face) /= m) then
      write (message, '(a,i0,a,i0,a,i0)') 'contactnn_contact_update: status and face have ', size(status), ' and ', &
        size(face), ' elements, expected ', m
    end if
    if (len_trim(message) == 0 .and. present(points)) then
      if (size(points, 1) /= 3 .or. size(points, 2) /= m) write (message, '(a,i0)') &
        'contactnn_contact_update: points must be 3 x ', m
    end if
    if (len_trim(message) == 0 .and. present(location)) then
      if (size(location) /= m) write (message, '(a,i0)') 'contactnn_contact_update: location must have m = ', m
    end if
    if (len_trim(message) == 0 .and. present(gap)) then
      if (size(gap) /= m) write (message, '(a,i0)') 'contactnn_contact_update: gap must have m = ', m
    end if
    if (len_trim(message) == 0 .and. present(param)) then
      if (size(param, 1) /= 2 .or. size(param, 2) /= m) write (message, '(a,i0)') &
        'contactnn_contact_update: param must be 2 x ', m
    end if
    if (len_trim(message) == 0 .and. present(point)) then
      if (size(point, 1) /= 3 .or. size(point, 2) /= m) write (message, '(a,i0)') &
        'contactnn_contact_update: point must be 3 x ', m
    end if
    if (len_trim(message) == 0 .and. present(normal)) then
      if (size(normal, 1) /= 3 .or. size(normal, 2) /= m) write (message, '(a,i0)') &
        'contactnn_contact_update: normal must be 3 x ', m
    end if
    if (len_trim(message) /= 0) then
      ierr = c_set_last_error(int(CONTACTNN_ERROR_INVALID_ARGUMENT, c_int), trim(message)//c_null_char)
      return
    end if
    location_ptr = c_null_ptr
    param_ptr = c_null_ptr
    point_ptr = c_null_ptr
    gap_ptr = c_null_ptr
    normal_ptr = c_null_ptr
    points_ptr = c_null_ptr
    if (present(location)) location_ptr = c_loc(location)
    if (present(param)) param_ptr = c_loc(param)
    if (present(point)) point_ptr = c_loc(point)
    if (present(gap)) gap_ptr = c_loc(gap)
    if (present(normal)) normal_ptr = c_loc(normal)
    if (present(points)) points_ptr = c_loc(points)
    ierr = c_contact_update(contact%handle, int(contact%nodes, c_size_t), c_loc(coords), int(m, c_size_t), &
                            points_ptr, c_loc(status), c_loc(face), location_ptr, param_ptr, point_ptr, gap_ptr, &
                            normal_ptr)
    if (ierr /= CONTACTNN_SUCCESS) return
    face = face + 1  ! Fortran counts faces from 1 (0: none)
  end subroutine contactnn_contact_update

  !> Frees a contact search (nothing happens for one that holds no handle).
  subroutine contactnn_contact_destroy(contact)
    type(contactnn_contact), intent(inout) :: contact
    if (c_associated(contact%handle)) call c_contact_destroy(contact%handle)
    contact%handle = c_null_ptr
    contact%nodes = 0
    contact%slaves = 0
    contact%free = .false.
  end subroutine contactnn_contact_destroy

end module contactnn
