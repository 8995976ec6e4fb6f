! SPDX-License-Identifier: GPL-3.0-or-later
! taper_nml_base.f90 -- what the Fortran scene driver taper_nml (taper_nml.f90)
! and its generated module taper_nml_scene share: the marks of a value left
! out, the lists a scene gives, the library's defaults and choices, the
! checks of what READ gave, the --dump formats, and the messages of a READ
! that failed (FILE:LINE: &group key: ..., as the C driver's).
!
! A READ that fails is located by reading the group again on parts of the
! file (locate_error): the group's reader and its keys are passed in
! (procedure arguments), so that this module knows no group of its own.
module taper_nml_base
  use, intrinsic :: iso_c_binding
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use, intrinsic :: iso_fortran_env, only: error_unit, output_unit, int64
  use taper
  implicit none

  ! MAX_LIST: SCENE_MAX_LIST of the C parser (drivers/scenes/scene/scene_impl.h),
  ! the values of one list; MAX_SWEEP: the values of one sweep here.
  integer, parameter :: MAX_SWEEP = 1000, MAX_LIST = 250000, LEN_STR = 1024
  ! SCENE_MAX_FILE of the C parser
  integer(int64), parameter :: MAX_FILE = 8388608_int64
  ! Values left out.  A real: a quiet NaN with a payload no input produces (a
  ! NaN the file gives is the canonical one, and refused as not finite).  An
  ! integer: a value no input gives.  A string: a NUL, which no text file
  ! holds (screen_file refuses control bytes).
  integer(int64), parameter :: NOT_GIVEN = int(z'7FF80000DEADBEEF', int64)
  ! (A protected variable, not a parameter: a module file keeps a real
  ! parameter's value but not a NaN's payload.)
  real(c_double), protected :: NOT_GIVEN_REAL = transfer(NOT_GIVEN, 1.0_c_double)
  integer(int64), parameter :: NOT_GIVEN_INT = -huge(0_int64)
  character(len=*), parameter :: NOT_GIVEN_TEXT = achar(0)

  ! The values a scene gave a variable that takes a list: v(1:n).
  type :: real_values
     real(c_double), allocatable :: v(:)
     integer :: n = 0
  end type real_values
  type :: int_values
     integer(int64), allocatable :: v(:)
     integer :: n = 0
  end type int_values

  ! The scene file, as messages name it.
  character(len=LEN_STR) :: path = ""
  ! While locate_error re-reads part of a group (probing), check_read
  ! records the status in probe_ios instead of reporting it.
  logical :: probing = .false.
  integer :: probe_ios = 0

  abstract interface
     ! READ(unit, NML=group) of one group (recursive: check_read may call
     ! it again on part of the file).
     subroutine group_reader(file, unit, group)
       character(len=*), intent(in) :: file, group
       integer, intent(in) :: unit
     end subroutine group_reader
     ! The keys of a group, "a, b, c", as messages list them.
     function group_keys_of(group) result(keys)
       character(len=*), intent(in) :: group
       character(len=:), allocatable :: keys
     end function group_keys_of
  end interface

contains

  ! ---- the end of a run, a file that is not a scene ----------------------------------

  ! Ends the program with `code` and nothing else on stderr (ERROR STOP
  ! prints "ERROR STOP n" and a gfortran backtrace).  C's exit runs
  ! libgfortran's destructor, which flushes and closes every unit.
  subroutine quit(code)
    integer, intent(in) :: code
    interface
       subroutine c_exit(status) bind(c, name="exit")
         import :: c_int
         integer(c_int), value :: status
       end subroutine c_exit
    end interface
    flush (output_unit)
    flush (error_unit)
    call c_exit(int(code, c_int))
  end subroutine quit

  ! What the C parser refuses before any namelist syntax: a file too large,
  ! control bytes (binary data), and -- after reading -- no group at all.
  subroutine screen_file(file)
    character(len=*), intent(in) :: file
    character(len=:), allocatable :: bytes
    character(len=512) :: msg
    integer(int64) :: size, k
    integer :: unit, ios, line, c
    open (newunit=unit, file=file, access="stream", form="unformatted", status="old", &
         action="read", iostat=ios, iomsg=msg)
    if (ios /= 0) then
       write (error_unit, '(a)') trim(file)//": cannot open: "//trim(msg)
       call quit(2)
    end if
    inquire (unit=unit, size=size)
    if (size > MAX_FILE) then
       write (error_unit, '(a,i0,a)') trim(file)//": file larger than ", MAX_FILE, &
            " bytes: not a scene"
       call quit(2)
    end if
    allocate (character(len=max(size, 1_int64)) :: bytes)
    if (size > 0) read (unit, iostat=ios) bytes(1:size)
    close (unit)
    if (ios /= 0) then
       write (error_unit, '(a)') trim(file)//": read error (is it a directory?)"
       call quit(2)
    end if
    line = 1
    do k = 1, size
       c = iachar(bytes(k:k))
       if (c == 10) then
          line = line + 1
       else if ((c < 32 .and. c /= 9 .and. c /= 13) .or. c == 127) then
          write (error_unit, '(a,i0,a,z2.2,a)') trim(file)//":", line, ": binary data (byte 0x", &
               c, "): not a text scene file"
          call quit(2)
       end if
    end do
  end subroutine screen_file

  ! ---- what READ gives: values left out, defaults ----------------------------------

  ! False for the NaN that marks a real left out (NOT_GIVEN).
  logical function is_given(x)
    real(c_double), intent(in) :: x
    is_given = transfer(x, 0_int64) /= NOT_GIVEN
  end function is_given

  ! Leading entries of a NOT_GIVEN-initialised namelist array that the file set.
  integer function count_given(a)
    real(c_double), intent(in) :: a(:)
    count_given = 0
    do while (count_given < size(a))
       if (.not. is_given(a(count_given + 1))) exit
       count_given = count_given + 1
    end do
  end function count_given

  integer function count_given_ints(a) result(n)
    integer(int64), intent(in) :: a(:)
    n = 0
    do while (n < size(a))
       if (a(n + 1) == NOT_GIVEN_INT) exit
       n = n + 1
    end do
  end function count_given_ints

  ! A namelist array of n values, none given yet.
  subroutine fresh_reals(a, n)
    real(c_double), allocatable, intent(out) :: a(:)
    integer, intent(in) :: n
    allocate (a(n))
    a = NOT_GIVEN_REAL
  end subroutine fresh_reals

  subroutine fresh_ints(a, n)
    integer(int64), allocatable, intent(out) :: a(:)
    integer, intent(in) :: n
    allocate (a(n))
    a = NOT_GIVEN_INT
  end subroutine fresh_ints

  ! What READ left in a group's key, kept in the variable: the value, or the
  ! default if the file left it out (was_given says which).
  subroutine take_text(dst, src, default, was_given)
    character(len=*), intent(out) :: dst
    character(len=*), intent(in) :: src, default
    logical, intent(out) :: was_given
    was_given = src /= NOT_GIVEN_TEXT
    if (was_given) then
       dst = src
    else
       dst = default
    end if
  end subroutine take_text

  subroutine take_int(dst, src, default, was_given)
    integer(int64), intent(out) :: dst
    integer(int64), intent(in) :: src, default
    logical, intent(out) :: was_given
    was_given = src /= NOT_GIVEN_INT
    dst = merge(src, default, was_given)
  end subroutine take_int

  subroutine take_real(dst, src, default, was_given)
    real(c_double), intent(out) :: dst
    real(c_double), intent(in) :: src, default
    logical, intent(out) :: was_given
    was_given = is_given(src)
    dst = merge(src, default, was_given)
  end subroutine take_real

  subroutine take_ints(dst, src, default, was_given)
    type(int_values), intent(inout) :: dst
    integer(int64), intent(in) :: src(:), default(:)
    logical, intent(out) :: was_given
    integer :: n
    n = count_given_ints(src)
    was_given = n > 0
    if (was_given) then
       dst%v = src(1:n)
    else
       dst%v = default
    end if
    dst%n = size(dst%v)
  end subroutine take_ints

  subroutine take_reals(dst, src, default, was_given)
    type(real_values), intent(inout) :: dst
    real(c_double), intent(in) :: src(:), default(:)
    logical, intent(out) :: was_given
    integer :: n
    n = count_given(src)
    was_given = n > 0
    if (was_given) then
       dst%v = src(1:n)
    else
       dst%v = default
    end if
    dst%n = size(dst%v)
  end subroutine take_reals

  ! The library's row of a setting the generated code names: taper_nml and
  ! the library it runs with come from one build.
  function library_row(name) result(row)
    character(len=*), intent(in) :: name
    type(taper_setting), pointer :: row
    type(taper_error) :: e
    row => taper_setting_find(name, e)
    if (associated(row)) return
    write (error_unit, '(a)') "taper_nml: the library has no setting '"//name// &
         "' (taper_nml was built with another libtaper): "//taper_message(e)
    call quit(1)
  end function library_row

  ! The default of a library setting (a real, an integer, a logical as 0 or 1).
  real(c_double) function library_default(name)
    character(len=*), intent(in) :: name
    type(taper_setting), pointer :: row
    row => library_row(name)
    library_default = row%default_value
  end function library_default

  ! The default of a library choice, by name ("monodisperse", "adams").
  function library_choice(name) result(s)
    character(len=*), intent(in) :: name
    character(len=:), allocatable :: s
    type(taper_setting), pointer :: row
    row => library_row(name)
    s = taper_setting_choice_name(row, nint(row%default_value) + 1)
  end function library_choice

  ! The library's spelling of a choice written in any case, or the value
  ! itself (the library names it when it refuses it).
  function library_spelling(name, value) result(c)
    character(len=*), intent(in) :: name, value
    character(len=len(value)) :: c
    type(taper_setting), pointer :: row
    integer :: k, n
    row => library_row(name)
    c = value
    n = taper_setting_n_choices(row)
    do k = 1, n
       if (lower(value) == lower(taper_setting_choice_name(row, k))) then
          c = taper_setting_choice_name(row, k)
          return
       end if
    end do
  end function library_spelling

  ! ---- checks of what READ gave -------------------------------------------------------

  ! A choice of the scene's own in its spelling, or refused as the C parser
  ! refuses it.
  subroutine own_choice(group, name, value, choices)
    character(len=*), intent(in) :: group, name
    character(len=*), intent(inout) :: value
    character(len=*), intent(in) :: choices(:)
    character(len=:), allocatable :: allowed
    integer :: k
    do k = 1, size(choices)
       if (lower(value) == lower(choices(k))) then
          value = choices(k)
          return
       end if
    end do
    allowed = ""
    do k = 1, size(choices)
       allowed = allowed//merge(", ", "  ", k > 1)//"'"//trim(choices(k))//"'"
    end do
    write (error_unit, '(a)') trim(path)//": &"//group//" "//name//": '"//trim(value)// &
         "' is not allowed: use one of "//allowed(3:)
    call quit(2)
  end subroutine own_choice

  ! Refuses NaN and infinities among the values given for group/name (a
  ! real left out, NOT_GIVEN, has no value).
  subroutine check_finite(group, name, values)
    character(len=*), intent(in) :: group, name
    real(c_double), intent(in) :: values(:)
    integer :: k
    do k = 1, size(values)
       if (.not. is_given(values(k)) .or. ieee_is_finite(values(k))) cycle
       write (error_unit, '(a)') trim(path)//": &"//group//" "//name// &
            ": not a finite number (nan and inf are refused)"
       call quit(2)
    end do
  end subroutine check_finite

  subroutine check_length(group, name, value)
    character(len=*), intent(in) :: group, name, value
    if (len_trim(value) < len(value)) return
    write (error_unit, '(a,i0,a)') trim(path)//": &"//group//" "//name//": longer than ", &
         len(value) - 1, " characters, which taper_nml cannot hold"
    call quit(2)
  end subroutine check_length

  ! A short text of x that reads back to it, for messages: fixed point
  ! between 1e-4 and 1e15, else scientific, no trailing zeros.
  function real_text(x) result(text)
    real(c_double), intent(in) :: x
    character(len=:), allocatable :: text
    character(len=48) :: buffer, format
    real(c_double) :: y
    integer :: digits, ios
    logical :: fixed
    if (.not. abs(x) > 0) then
       text = "0"
       return
    end if
    fixed = abs(x) >= 1e-4_c_double .and. abs(x) < 1e15_c_double
    do digits = 1, 25
       if (fixed) then
          write (format, '(a,i0,a)') "(f40.", digits, ")"
       else
          write (format, '(a,i0,a)') "(es40.", min(digits, 17), ")"
       end if
       write (buffer, format) x
       read (buffer, *, iostat=ios) y
       if (ios == 0 .and. transfer(y, 0_int64) == transfer(x, 0_int64)) exit
    end do
    text = trim(adjustl(buffer))
    if (fixed) then
       do while (text(len(text):len(text)) == "0")
          text = text(1:len(text) - 1)
       end do
       if (text(len(text):len(text)) == ".") text = text(1:len(text) - 1)
    end if
  end function real_text

  function lower(str) result(l)
    character(len=*), intent(in) :: str
    character(len=len(str)) :: l
    integer :: k
    l = str
    do k = 1, len(str)
       if (l(k:k) >= "A" .and. l(k:k) <= "Z") l(k:k) = achar(iachar(l(k:k)) + 32)
    end do
  end function lower

  ! out/NAME for scene file .../NAME.nml (drivers/scenes/scene/scene_new.c: derived_dir).
  function default_dir(file) result(d)
    character(len=*), intent(in) :: file
    character(len=LEN_STR) :: d
    integer :: slash, n
    slash = index(file, "/", back=.true.)
    n = len_trim(file)
    if (n - slash > 4) then
       if (lower(file(n - 3:n)) == ".nml") n = n - 4
    end if
    if (n == slash) then
       d = "out/scene"
    else
       d = "out/"//file(slash + 1:n)
    end if
  end function default_dir

  ! ---- --dump: the canonical form of tests/bindings/scene_dump.c ---------------------

  subroutine print_bits(x)
    real(c_double), intent(in) :: x
    write (output_unit, '(1x,z16.16)', advance="no") transfer(x, 0_int64)
  end subroutine print_bits

  subroutine print_text(name, value)
    character(len=*), intent(in) :: name, value
    write (output_unit, '(a)') name//" = "//trim(value)
  end subroutine print_text

  ! A real without a default: nothing after " =" when left out.
  subroutine print_optional(name, x)
    character(len=*), intent(in) :: name
    real(c_double), intent(in) :: x
    write (output_unit, '(a)', advance="no") name//" ="
    if (is_given(x)) call print_bits(x)
    write (output_unit, '()')
  end subroutine print_optional

  ! A list, or a real a list sweeps: the number of values, then each.
  subroutine print_list(name, a)
    character(len=*), intent(in) :: name
    type(real_values), intent(in) :: a
    integer :: k
    write (output_unit, '(a,1x,i0)', advance="no") name//" =", a%n
    do k = 1, a%n
       call print_bits(a%v(k))
    end do
    write (output_unit, '()')
  end subroutine print_list

  ! An integer a list sweeps: the number of values, then each.
  subroutine print_ints(name, a)
    character(len=*), intent(in) :: name
    type(int_values), intent(in) :: a
    integer :: k
    write (output_unit, '(a,1x,i0)', advance="no") name//" =", a%n
    do k = 1, a%n
       write (output_unit, '(1x,i0)', advance="no") a%v(k)
    end do
    write (output_unit, '()')
  end subroutine print_ints

  ! ---- a READ that failed: where, and which key ------------------------------------

  ! After READ(unit, NML=group): a syntax error fails with the file name; end
  ! of file means the group is absent -- unless the file has the group's
  ! header, then the file ended inside it (an unterminated string, a missing
  ! '/'), which is an error too.
  recursive subroutine check_read(file, unit, group, ios, msg, reader, keys)
    character(len=*), intent(in) :: file, group, msg
    integer, intent(in) :: unit, ios
    procedure(group_reader) :: reader
    procedure(group_keys_of) :: keys
    if (probing) then
       probe_ios = ios
       return
    end if
    if (ios > 0) then
       close (unit)    ! report_read_error reopens the file as a stream, and quits
       call report_read_error(file, group, msg, reader, keys)
    end if
    if (ios < 0) then
       if (has_group(unit, group)) then
          write (error_unit, '(a)') trim(file)//": &"//group//": end of file inside the group "// &
               "(a string not closed, or no '/' at its end?): "//trim(msg)
          call quit(2)
       end if
    end if
  end subroutine check_read

  ! A READ of &group failed with gfortran's message msg: say where, as the C
  ! driver does (FILE:LINE: &group key: message, exit 2).  gfortran gives no
  ! line, and the file position after a failed READ is undefined, so the
  ! line is found by reading again: the first line j such that the group's
  ! text up to line j, closed by '/', fails too (binary search over
  ! prefixes; a prefix that fails contains the error).  The key is the name
  ! gfortran could not match, if it stands as a key on that line; else the
  ! last "name =" before the error.
  recursive subroutine report_read_error(file, group, msg, reader, keys)
    character(len=*), intent(in) :: file, group, msg
    procedure(group_reader) :: reader
    procedure(group_keys_of) :: keys
    character(len=*), parameter :: NO_MATCH = "Cannot match namelist object name "
    character(len=:), allocatable :: bytes, name, key, known
    integer(int64), allocatable :: starts(:)
    integer :: line, head, k
    character(len=16) :: line_text
    known = keys(group)
    call file_lines(file, bytes, starts)
    head = header_line(bytes, starts, group)
    line = 0
    if (head > 0) line = locate_error(file, group, bytes, starts, head, reader)
    name = ""
    k = index(msg, NO_MATCH)
    if (k > 0) name = trim(adjustl(msg(k + len(NO_MATCH):)))
    if (line == 0) then
       write (error_unit, '(a)') trim(file)//": &"//group//": "//trim(msg)
       call quit(2)
    end if
    ! gfortran may fail a line later than the value it could not match
    ! (exponent = 'abc' fails at the next key): blame the first line of the
    ! group, up to the failing one, where that token stands.
    if (len(name) > 0 .and. .not. is_key_on(line_of(bytes, starts, line), name)) then
       do k = head, line
          if (index(lower(line_of(bytes, starts, k)), lower(name)) > 0) then
             line = k
             exit
          end if
       end do
    end if
    write (line_text, '(i0)') line
    if (len(name) > 0 .and. is_key_on(line_of(bytes, starts, line), name)) then
       write (error_unit, '(a)') trim(file)//":"//trim(line_text)//": &"//group//" "//name// &
            ": unknown key"//suggestion(name, known)//" (&"//group//" has: "// &
            known//")"
    else
       key = last_key(bytes, starts, head, line)
       if (len(key) > 0 .and. .not. is_key_of(key, known)) then
          ! After a list's values gfortran takes an unknown name for more
          ! data ("Bad data for namelist object rtol"): the name is the fault.
          write (error_unit, '(a)') trim(file)//":"//trim(line_text)//": &"//group//" "//key// &
               ": unknown key"//suggestion(key, known)//" (&"//group//" has: "// &
               known//")"
       else if (len(key) > 0) then
          write (error_unit, '(a)') trim(file)//":"//trim(line_text)//": &"//group//" "//key// &
               ": "//trim(msg)
       else
          write (error_unit, '(a)') trim(file)//":"//trim(line_text)//": &"//group//": "//trim(msg)
       end if
    end if
    call quit(2)
  end subroutine report_read_error

  ! Whether key (any case) is one of keys ("a, b, c").
  logical function is_key_of(key, keys)
    character(len=*), intent(in) :: key, keys
    is_key_of = index(", "//keys//",", ", "//lower(key)//",") > 0
  end function is_key_of

  ! The whole file and the byte offset where each line starts (a last entry
  ! one past the end).
  subroutine file_lines(file, bytes, starts)
    character(len=*), intent(in) :: file
    character(len=:), allocatable, intent(out) :: bytes
    integer(int64), allocatable, intent(out) :: starts(:)
    integer(int64) :: size, k, n
    integer :: unit, ios
    open (newunit=unit, file=file, access="stream", form="unformatted", status="old", &
         action="read", iostat=ios)
    size = 0
    if (ios == 0) inquire (unit=unit, size=size)
    allocate (character(len=max(size, 0_int64)) :: bytes)
    if (ios == 0 .and. size > 0) read (unit, iostat=ios) bytes
    if (ios == 0) close (unit)
    n = 1
    do k = 1, size
       if (bytes(k:k) == achar(10)) n = n + 1
    end do
    allocate (starts(n + 1))
    starts(1) = 1
    n = 1
    do k = 1, size
       if (bytes(k:k) /= achar(10)) cycle
       n = n + 1
       starts(n) = k + 1
    end do
    starts(n + 1) = size + 2      ! so that line n ends at size (starts(n+1) - 2)
    if (size > 0) then
       if (bytes(size:size) == achar(10)) starts(n + 1) = size + 1
    end if
  end subroutine file_lines

  ! Line j without its newline.
  function line_of(bytes, starts, j) result(l)
    character(len=*), intent(in) :: bytes
    integer(int64), intent(in) :: starts(:)
    integer, intent(in) :: j
    character(len=:), allocatable :: l
    integer(int64) :: e
    e = min(starts(j + 1) - 2, int(len(bytes), int64))
    if (e >= starts(j) .and. j < size(starts)) then
       l = bytes(starts(j):e)
    else
       l = ""
    end if
  end function line_of

  ! The first line holding the header &group, 0 if none.
  integer function header_line(bytes, starts, group) result(j)
    character(len=*), intent(in) :: bytes, group
    integer(int64), intent(in) :: starts(:)
    do j = 1, size(starts) - 1
       if (header_in(line_of(bytes, starts, j), group)) return
    end do
    j = 0
  end function header_line

  ! The first line j >= head such that lines head..j, closed by '/', fail
  ! to read as &group; 0 if even the whole rest reads (no line to blame).
  recursive integer function locate_error(file, group, bytes, starts, head, reader) result(j)
    character(len=*), intent(in) :: file, group, bytes
    integer(int64), intent(in) :: starts(:)
    integer, intent(in) :: head
    procedure(group_reader) :: reader
    integer :: lo, hi, mid
    lo = head
    hi = size(starts) - 1
    if (.not. prefix_fails(file, group, bytes, starts, head, hi, reader)) then
       j = 0
       return
    end if
    do while (lo < hi)
       mid = (lo + hi) / 2
       if (prefix_fails(file, group, bytes, starts, head, mid, reader)) then
          hi = mid
       else
          lo = mid + 1
       end if
    end do
    j = lo
  end function locate_error

  ! Whether lines head..last, closed by '/', fail to read as &group (a
  ! scratch file, read by the group's reader with check_read only recording).
  recursive logical function prefix_fails(file, group, bytes, starts, head, last, reader)
    character(len=*), intent(in) :: file, group, bytes
    integer(int64), intent(in) :: starts(:)
    integer, intent(in) :: head, last
    procedure(group_reader) :: reader
    integer :: unit, ios
    integer(int64) :: e
    open (newunit=unit, status="scratch", access="stream", form="formatted", iostat=ios)
    if (ios /= 0) then
       prefix_fails = .false.
       return
    end if
    e = min(starts(last + 1) - 1, int(len(bytes), int64))
    write (unit, '(a)') bytes(starts(head):e)//new_line("a")//"/"
    rewind (unit)
    probing = .true.
    probe_ios = 0
    call reader(file, unit, group)
    probing = .false.
    close (unit)
    prefix_fails = probe_ios > 0
  end function prefix_fails

  ! Whether name stands as a key on line: a whole word followed by '=' or '('.
  logical function is_key_on(line, name)
    character(len=*), intent(in) :: line, name
    integer :: k, from, e
    is_key_on = .false.
    from = 1
    do
       k = index(lower(line(from:)), lower(name))
       if (k == 0) return
       k = from + k - 1
       e = k + len(name)
       from = k + 1
       if (k > 1) then
          if (is_name_char(line(k - 1:k - 1))) cycle
       end if
       do while (e <= len(line))
          if (line(e:e) /= " " .and. line(e:e) /= achar(9)) exit
          e = e + 1
       end do
       if (e > len(line)) cycle
       if (line(e:e) == "=" .or. line(e:e) == "(") then
          is_key_on = .true.
          return
       end if
    end do
  end function is_key_on

  logical function is_name_char(c)
    character, intent(in) :: c
    is_name_char = (c >= "a" .and. c <= "z") .or. (c >= "A" .and. c <= "Z") .or. &
         (c >= "0" .and. c <= "9") .or. c == "_"
  end function is_name_char

  ! The last "name =" (outside quotes and comments) on lines head..last.
  function last_key(bytes, starts, head, last) result(key)
    character(len=*), intent(in) :: bytes
    integer(int64), intent(in) :: starts(:)
    integer, intent(in) :: head, last
    character(len=:), allocatable :: key, l
    character :: quote
    integer :: j, k, b, e
    key = ""
    do j = head, last
       l = line_of(bytes, starts, j)
       quote = " "
       do k = 1, len(l)
          if (quote /= " ") then
             if (l(k:k) == quote) quote = " "
             cycle
          end if
          if (l(k:k) == "'" .or. l(k:k) == '"') then
             quote = l(k:k)
          else if (l(k:k) == "!") then
             exit
          else if (l(k:k) == "=") then
             e = k - 1
             do while (e >= 1)
                if (l(e:e) /= " " .and. l(e:e) /= achar(9)) exit
                e = e - 1
             end do
             if (e >= 1) then
                if (l(e:e) == ")") then      ! name(i) = ...
                   do while (e >= 1)
                      if (l(e:e) == "(") exit
                      e = e - 1
                   end do
                   e = e - 1
                end if
             end if
             b = e
             do while (b >= 1)
                if (.not. is_name_char(l(b:b))) exit
                b = b - 1
             end do
             if (e > b) key = l(b + 1:e)
          end if
       end do
    end do
  end function last_key

  ! ": did you mean KEY?" for the key of the list nearest to name (at most
  ! two edits away), as the C driver suggests; '' if none is that near.
  function suggestion(name, keys) result(s)
    character(len=*), intent(in) :: name, keys
    character(len=:), allocatable :: s, best, word
    integer :: k, e, d, best_d
    s = ""
    best = ""
    best_d = 3
    k = 1
    do while (k <= len(keys))
       e = index(keys(k:), ",")
       if (e == 0) then
          e = len(keys) + 1
       else
          e = k + e - 1
       end if
       word = trim(adjustl(keys(k:e - 1)))
       d = edit_distance(lower(name), word)
       if (d < best_d .and. d < len(name)) then
          best_d = d
          best = word
       end if
       k = e + 1
    end do
    if (len(best) > 0) s = ": did you mean "//best//"?"
  end function suggestion

  ! Levenshtein distance.
  integer function edit_distance(a, b) result(d)
    character(len=*), intent(in) :: a, b
    integer :: row(0:len(b)), prev, tmp, i, j
    do j = 0, len(b)
       row(j) = j
    end do
    do i = 1, len(a)
       prev = row(0)
       row(0) = i
       do j = 1, len(b)
          tmp = row(j)
          row(j) = min(row(j) + 1, row(j - 1) + 1, prev + merge(0, 1, a(i:i) == b(j:j)))
          prev = tmp
       end do
    end do
    d = row(len(b))
  end function edit_distance

  ! Whether a line holds the header &group (or $group), as gfortran looks for
  ! one: '&' or '$' outside comments, the name in any case, then a separator.
  logical function header_in(line, group)
    character(len=*), intent(in) :: line, group
    integer :: k, n, e
    header_in = .false.
    n = index(line, "!") - 1
    if (n < 0) n = len_trim(line)
    do k = 1, n
       if (line(k:k) /= "&" .and. line(k:k) /= "$") cycle
       e = k + len(group)
       if (e > n) cycle
       if (lower(line(k + 1:e)) /= lower(group)) cycle
       if (e < n) then     ! the name must end there
          if (index(" ,/;"//achar(9), line(e + 1:e + 1)) == 0) cycle
       end if
       header_in = .true.
       return
    end do
  end function header_in

  ! Whether the file has a header &group (or $group) on some line (header_in).
  logical function has_group(unit, group)
    integer, intent(in) :: unit
    character(len=*), intent(in) :: group
    character(len=LEN_STR) :: line
    integer :: ios
    has_group = .false.
    rewind (unit)
    do
       read (unit, '(a)', iostat=ios) line
       if (ios /= 0) return
       if (header_in(line, group)) exit
    end do
    has_group = .true.
  end function has_group
end module taper_nml_base
