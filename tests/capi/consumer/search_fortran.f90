! search_fortran: module contactnn as a Fortran finite-element code calls it, on a file of queries.
!
! Usage: search_fortran bilinear|gregory METHOD NETWORK RAW.txt OUT.txt double|float
!   RAW.txt  the query count n on the first line, then n rows of 15 (bilinear) or 27 (Gregory) numbers
!   OUT.txt  one line per query: p0 p1 status gap iterations
! Also checks that arrays of the wrong shape are refused with a message (prints "shape check: ok"), and that
! the method 'start' hands back the starts it reads from param, intent(inout) (prints "warm start: ok").
! Exit status 0, or 1 with contactnn's message.
program search_fortran
  use, intrinsic :: iso_c_binding, only: c_double, c_float, c_int
  use contactnn
  implicit none

  character(len=4096) :: surface_name, method, network, raw_path, out_path, precision
  integer :: surface, columns, n, i, ierr, unit
  real(c_double), allocatable :: raw(:, :), param(:, :), gap(:)
  real(c_float), allocatable :: raw_f(:, :), param_f(:, :), gap_f(:)
  real(c_double), allocatable :: wrong_param(:, :), start(:, :)
  integer(c_int), allocatable :: status(:), iterations(:), start_status(:)
  type(contactnn_search) :: search, warm
  type(contactnn_options) :: options

  if (command_argument_count() /= 6) then
    print '(a)', 'usage: search_fortran bilinear|gregory METHOD NETWORK RAW.txt OUT.txt double|float'
    stop 2
  end if
  call get_command_argument(1, surface_name)
  call get_command_argument(2, method)
  call get_command_argument(3, network)
  call get_command_argument(4, raw_path)
  call get_command_argument(5, out_path)
  call get_command_argument(6, precision)
  surface = CONTACTNN_SURFACE_BILINEAR
  columns = 15
  if (trim(surface_name) == 'gregory') then
    surface = CONTACTNN_SURFACE_GREGORY
    columns = 27
  end if

  ! 1. The queries: one column each.
  open (newunit=unit, file=trim(raw_path), status='old', action='read')
  read (unit, *) n
  allocate (raw(columns, n), param(2, n), gap(n), status(n), iterations(n))
  do i = 1, n
    read (unit, *) raw(:, i)
  end do
  close (unit)

  ! 2. The search: two threads, every other option at its default.
  options = contactnn_default_options()
  options%threads = 2
  call contactnn_create(search, surface, trim(method), ierr, network=trim(network), options=options)
  if (ierr /= CONTACTNN_SUCCESS) call fail('contactnn_create')

  ! 3. Arrays that do not fit the search are refused, with a message, and nothing is run.
  allocate (wrong_param(2, n + 1))
  call contactnn_run(search, raw, wrong_param, status, ierr)
  if (ierr /= CONTACTNN_ERROR_INVALID_ARGUMENT .or. index(contactnn_last_error(), 'param is 2 x') == 0) then
    print '(a,i0,2a)', 'shape check: FAILED, ierr = ', ierr, ', message: ', contactnn_last_error()
    stop 1
  end if
  print '(a)', 'shape check: ok'

  ! 4. One batched call for all queries, in the precision asked for.
  if (trim(precision) == 'float') then
    allocate (raw_f(columns, n), param_f(2, n), gap_f(n))
    raw_f = real(raw, c_float)
    call contactnn_run(search, raw_f, param_f, status, ierr, gap=gap_f, iterations=iterations)
    param = real(param_f, c_double)
    gap = real(gap_f, c_double)
  else
    call contactnn_run(search, raw, param, status, ierr, gap=gap, iterations=iterations)
  end if
  if (ierr /= CONTACTNN_SUCCESS) call fail('contactnn_run')
  call contactnn_destroy(search)

  ! 5. A warm start ('start': no Newton step) gives back the starts in param wherever it answers ok or outside.
  call contactnn_create(warm, surface, 'start', ierr, options=options)
  if (ierr /= CONTACTNN_SUCCESS) call fail('contactnn_create start')
  allocate (start(2, n), start_status(n))
  start = param
  call contactnn_run(warm, raw, start, start_status, ierr)
  if (ierr /= CONTACTNN_SUCCESS) call fail('contactnn_run start')
  do i = 1, n
    if (start_status(i) <= CONTACTNN_STATUS_OUTSIDE .and. any(start(:, i) /= param(:, i))) then
      print '(a,i0)', 'warm start: FAILED at query ', i
      stop 1
    end if
  end do
  if (count(start_status <= CONTACTNN_STATUS_OUTSIDE) == 0) then
    print '(a)', 'warm start: FAILED, no query answered'
    stop 1
  end if
  print '(a)', 'warm start: ok'
  call contactnn_destroy(warm)

  ! 6. The results.
  open (newunit=unit, file=trim(out_path), status='replace', action='write')
  do i = 1, n
    write (unit, '(2(es26.17e3,1x),i0,1x,es26.17e3,1x,i0)') param(1, i), param(2, i), status(i), gap(i), iterations(i)
  end do
  close (unit)
  print '(4a,i0,2a)', 'search_fortran: contactnn ', contactnn_version(), ', ', 'queries ', n, ', ', trim(precision)

contains

  subroutine fail(what)
    character(len=*), intent(in) :: what
    print '(4a)', 'search_fortran: ', what, ': ', contactnn_last_error()
    stop 1
  end subroutine fail

end program search_fortran
