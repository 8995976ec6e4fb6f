! taper_nml -- run a taper scene file with Fortran's own namelist READ.
!
!   taper_nml SCENE.nml           run it: t_pass and v_peak next to the theory
!   taper_nml --dump SCENE.nml    print the resolved values (canonical form of
!                                 tests/bindings/scene_dump.c) and stop
!
! Our scene files (share/scenes/*.nml, docs/scene.md) are standard Fortran
! namelists.  This program reads every group of them with READ(unit,
! NML=...) and hands the library's settings (&chain, &ends, &striker,
! &losses, &solver) to libtaper by name through the iso_c_binding module
! `taper` (taper_chain_spec_set_option, taper_solver_spec_set_option): the
! library checks each value and names the setting it refuses, so this
! program keeps no bounds of its own, and the defaults, the names of the
! choices and the ranges of those settings are the library's (its table of
! settings, read at run time).
!
! The variables are not written by hand here.  Their declarations, each
! group's NAMELIST and READ, the defaults of the scene's own variables, the
! checks of what READ gave, --dump and the calls that hand each chain and
! solver value to the library are generated at build time from the scene's
! table (drivers/taper/scene/scene.c) and the library's table of settings
! by gen_namelists.c, into taper_nml_scene.inc (declarations) and
! taper_nml_groups.inc (procedures), which this file INCLUDEs: a new
! setting of the library is a new variable of taper_nml at the next build.
! What is written here is the scene's own rules (a radii file, the
! piston's 'push' and 'steady', a custom chain's number of granules, &output
! units with &material) and the handling of files, errors and runs.
!
! Each group is read in its own generated subroutine (read_chain, ...)
! whose local variables are the group's keys, so that keys shared by
! several groups (x, y and k_max of &fit and &figure, name of &table and
! &figure, radius and density of &striker and &material) are distinct
! variables; the values are kept in `sv` under each variable's unique name
! (its keyword: fit_x, striker_radius), as the C scene keeps them.
!
! A list of values for a real or an integer the scene sweeps (s, q,
! exponent, n_granules, seed, rtol, ...) is a sweep, run as taper runs it:
! every combination (the variable later in the table varying fastest) or,
! with &sweep mode = 'zip', the i-th values together.  &material (real
! units, mixed materials) is read and checked but not run (refused, naming
! the group: taper runs it); &sensors' time series are not written (the
! pass times are the same to rounding; said on stderr).  The analysis
! groups &fit, &table and &figure are read too, so that --dump proves every
! group of a scene is a real Fortran namelist and resolves as in the C
! parser; the runs here do not use them.
!
! Held to the C driver's standard where both read the same input: a file that
! is not text (control bytes), or has no group at all (empty, comments only,
! garbage), is refused; NaN and infinities are refused (a NaN with a payload
! of its own marks a value left out, so that `s = nan` is not taken for "not
! given"); errors end with a message and the exit status alone (no
! ERROR STOP, whose gfortran backtrace looked like a crash).
!
! Exit status: 0 complete, 1 library failure, 2 bad input, 3 partial result
! (as taper's; taper_nml does not check conservation, so never 4).
program taper_nml
  use, intrinsic :: iso_c_binding
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_value, ieee_positive_inf
  use, intrinsic :: iso_fortran_env, only: error_unit, output_unit, int64
  use taper
  implicit none

  ! MAX_LIST: SCENE_MAX_LIST of the C parser (drivers/taper/scene/scene_impl.h),
  ! the values of one list; MAX_SWEEP: the values of one sweep here.
  integer, parameter :: MAX_SWEEP = 1000, MAX_LIST = 250000, LEN_STR = 1024
  ! SCENE_MAX_FILE of the C parser
  integer(int64), parameter :: MAX_FILE = 8388608_int64
  ! At most this many runs in one scene (SCENE_MAX_RUNS of the C scene).
  integer(int64), parameter :: MAX_RUNS = 10000000_int64
  ! Values left out.  A real: a quiet NaN with a payload no input produces (a
  ! NaN the file gives is the canonical one, and refused as not finite).  An
  ! integer: a value no input gives.  A string: a NUL, which no text file
  ! holds (screen_file refuses control bytes).
  integer(int64), parameter :: NOT_GIVEN = int(z'7FF80000DEADBEEF', int64)
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

  ! The scene's variables (type scene_values), its groups, N_VARS and
  ! N_SWEEPABLE: written from the tables at build time.
  include 'taper_nml_scene.inc'

  type(scene_values), allocatable :: sv   ! allocatable: released whole at the end
  logical :: given(N_VARS) = .false.   ! the file gave variable i (logicals: never known)
  type(real_values) :: file_radii      ! the radii a radii_file holds (not the scene's list)
  ! While locate_error re-reads part of a group (probing), check_read
  ! records the status in probe_ios instead of reporting it.
  logical :: probing = .false.
  integer :: probe_ios = 0

  character(len=LEN_STR) :: path, arg
  logical :: dump
  integer :: lens(N_SWEEPABLE), ix(N_SWEEPABLE)
  integer :: i, status, worst, arg_status
  integer(int64) :: n_runs, run
  real(c_double) :: nan

  dump = .false.
  path = ""
  do i = 1, command_argument_count()
     call get_command_argument(i, arg, status=arg_status)
     if (arg_status /= 0) then   ! -1: longer than arg, never cut silently
        write (error_unit, '(a,i0,a)') "taper_nml: argument ", i, " is longer than ", LEN_STR, &
             " characters"
        call quit(2)
     end if
     if (arg == "--dump") then
        dump = .true.
     else if (arg == "-h" .or. arg == "--help") then
        write (output_unit, '(a)') "usage: taper_nml [--dump] SCENE.nml"
        call quit(0)
     else
        path = arg
     end if
  end do
  if (path == "") then
     write (error_unit, '(a)') "usage: taper_nml [--dump] SCENE.nml"
     call quit(2)
  end if

  nan = transfer(NOT_GIVEN, nan)
  allocate (sv)
  call screen_file(path)
  call read_scene(path)     ! every group, with its defaults (the generated read_*)
  call check_values()       ! generated: lengths, choices, finite reals
  call resolve()            ! the scene's own rules
  if (dump) then
     call print_dump()
     call release()
     stop
  end if

  if (.not. runnable()) call quit(2)
  call sweep_lengths(lens)
  lens = max(lens, 1)        ! a real left out (no default) has one run: none
  n_runs = count_runs(lens)
  worst = 0
  do run = 0, n_runs - 1
     call point_indices(run, lens, ix)
     status = run_point(lens, ix)
     worst = max(worst, status)
  end do
  call release()
  if (worst /= 0) call quit(worst)

contains

  ! The file's generated procedures: read_<group> for every group,
  ! read_group, group_keys, var_place, var_index, check_values,
  ! print_dump, apply_chain, apply_solver, sweep_lengths, write_swept.
  include 'taper_nml_groups.inc'

  ! Main-program variables are implicitly SAVE'd: never deallocated for us
  ! (LeakSanitizer and valgrind report them once MAIN__ has returned).
  subroutine release()
    if (allocated(sv)) deallocate (sv)
    if (allocated(file_radii%v)) deallocate (file_radii%v)
  end subroutine release

  ! ---- what READ gives: values left out, defaults -------------------------------

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
    a = nan
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

  ! Whether the file gave the variable of this keyword.
  logical function was_given(keyword)
    character(len=*), intent(in) :: keyword
    integer :: k
    k = var_index(keyword)
    was_given = .false.
    if (k > 0) was_given = given(k)
  end function was_given

  ! ---- the scene's own rules ---------------------------------------------------------

  ! What the C scene resolves besides the values read (scene_check.c,
  ! scene_physics.c): the radii of a radii file; a custom chain's number of
  ! granules from its radii when the file leaves n_granules out; results in
  ! SI with &material unless &output units says otherwise; a piston's
  ! duration with 'push' and only with it.
  subroutine resolve()
    integer :: n, k
    call read_radii_file()
    n = merge(file_radii%n, sv%radii%n, file_radii%n > 0)
    if (trim(sv%profile) == "custom" .and. n > 0 .and. .not. was_given("n_granules")) then
       sv%n_granules%v = [int(n, int64)]
       sv%n_granules%n = 1
    end if
    if (material_on() .and. .not. was_given("units")) sv%units = "si"
    do k = 1, sv%piston_duration%n
       if (trim(sv%piston) == "push" .and. .not. sv%piston_duration%v(k) > 0) then
          write (error_unit, '(a)') trim(path)//": &striker piston_duration: piston = 'push' "// &
               "pushes for piston_duration > 0 ("//real_text(sv%piston_duration%v(k))// &
               " given); piston = 'steady' pushes for ever"
          call quit(2)
       end if
       if (trim(sv%piston) /= "push" .and. abs(sv%piston_duration%v(k)) > 0) then
          write (error_unit, '(a)') trim(path)//": &striker piston_duration: piston_duration = "// &
               real_text(sv%piston_duration%v(k))//" has no effect without piston = 'push' "// &
               "(a 'steady' piston pushes for ever): leave it at 0"
          call quit(2)
       end if
    end do
  end subroutine resolve

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

  ! &material is on when one of the five variables that set the units is
  ! given (the C scene's rule).
  logical function material_on()
    material_on = was_given("young") .or. was_given("poisson") .or. was_given("density") .or. &
         was_given("radius") .or. was_given("velocity")
  end function material_on

  ! &chain radii_file as the C parser reads it (drivers/taper/scene/
  ! scene_physics.c): custom profile only, not with inline radii; the path
  ! relative to the scene file's folder, made absolute; one radius per line,
  ! blank lines and '#' comments skipped, every radius finite and > 0, the
  ! first 1; the radii become the custom chain's.  Errors name FILE:LINE of
  ! the radii file, under &chain radii_file.
  subroutine read_radii_file()
    character(len=:), allocatable :: file, line, where
    character(len=4096) :: buffer
    real(c_double) :: x
    integer :: unit, ios, lineno, k, n
    interface
       function c_getcwd(buf, size) bind(C, name="getcwd") result(p)
         import :: c_ptr, c_char, c_size_t
         character(kind=c_char), intent(out) :: buf(*)
         integer(c_size_t), value :: size
         type(c_ptr) :: p
       end function c_getcwd
    end interface
    character(kind=c_char) :: cwd(4096)
    if (len_trim(sv%radii_file) == 0) return
    if (trim(sv%profile) /= "custom") then
       write (error_unit, '(a)') trim(path)//": &chain radii_file: radii_file is only used "// &
            "with profile = 'custom': remove it or set the profile"
       call quit(2)
    end if
    if (was_given("radii")) then
       write (error_unit, '(a)') trim(path)//": &chain radii_file: give the radii either "// &
            "inline (radii) or in a file (radii_file), not both"
       call quit(2)
    end if
    file = trim(sv%radii_file)
    if (file(1:1) /= "/") then
       k = index(trim(path), "/", back=.true.)
       if (k > 0) file = path(1:k)//file
       if (file(1:1) /= "/") then
          if (c_associated(c_getcwd(cwd, size(cwd, kind=c_size_t)))) then
             n = 0
             do while (n < size(cwd))
                if (cwd(n + 1) == c_null_char) exit
                n = n + 1
             end do
             file = transfer(cwd(1:n), repeat(" ", n))//"/"//file
          end if
       end if
    end if
    sv%radii_file = file            ! the dump names the file this run read
    where = trim(path)//": &chain radii_file: "//file
    open (newunit=unit, file=file, status="old", action="read", iostat=ios)
    if (ios /= 0) then
       write (error_unit, '(a)') where//": cannot open it"
       call quit(2)
    end if
    allocate (file_radii%v(1024))
    n = 0
    lineno = 0
    do
       read (unit, '(a)', iostat=ios) buffer
       if (ios /= 0) exit
       lineno = lineno + 1
       line = buffer
       k = index(line, "#")
       if (k > 0) line = line(1:k - 1)
       if (len_trim(line) == 0) cycle
       read (line, *, iostat=ios) x
       if (ios /= 0 .or. .not. ieee_is_finite(x) .or. .not. x > 0) then
          write (error_unit, '(a,i0,a)') where//":", lineno, ": '"//trim(adjustl(line))// &
               "': every radius must be a finite number > 0, one per line"
          call quit(2)
       end if
       if (n == 0 .and. abs(x - 1) > 0) then
          write (error_unit, '(a,i0,a)') where//":", lineno, ": the first radius must be 1 "// &
               "(R_1 is the unit of length; divide the file by it)"
          call quit(2)
       end if
       n = n + 1
       if (n > size(file_radii%v)) file_radii%v = [file_radii%v, file_radii%v]   ! doubled
       file_radii%v(n) = x
    end do
    close (unit)
    if (n == 0) then
       write (error_unit, '(a)') where//": holds no radius"
       call quit(2)
    end if
    file_radii%n = n
  end subroutine read_radii_file

  ! ---- reading the file ------------------------------------------------------------------

  subroutine read_scene(file)
    character(len=*), intent(in) :: file
    integer :: unit, ios, g
    character(len=512) :: msg
    open (newunit=unit, file=file, status="old", action="read", iostat=ios, iomsg=msg)
    if (ios /= 0) then
       write (error_unit, '(a)') trim(file)//": "//trim(msg)
       call quit(2)
    end if
    ! Each group is optional: rewind and look for it; end of file = absent.
    do g = 1, size(GROUPS)
       if (g > 1) rewind (unit)
       call read_group(file, unit, trim(GROUPS(g)))
    end do
    ! READ skips whatever is not a group: a file with none ran the default
    ! chain.  The C parser refuses it; so does this program.
    do g = 1, size(GROUPS)
       if (has_group(unit, trim(GROUPS(g)))) exit   ! one call per statement
    end do
    if (g > size(GROUPS)) then
       write (error_unit, '(a)') trim(file)//": empty scene: no &chain, &solver or &output group"
       call quit(2)
    end if
    close (unit)
  end subroutine read_scene

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

  subroutine check_length(group, name, value)
    character(len=*), intent(in) :: group, name, value
    if (len_trim(value) < len(value)) return
    write (error_unit, '(a,i0,a)') trim(path)//": &"//group//" "//name//": longer than ", &
         len(value) - 1, " characters, which taper_nml cannot hold"
    call quit(2)
  end subroutine check_length

  ! After READ(unit, NML=group): a syntax error fails with the file name; end
  ! of file means the group is absent -- unless the file has the group's
  ! header, then the file ended inside it (an unterminated string, a missing
  ! '/'), which is an error too.
  recursive subroutine check_read(file, unit, group, ios, msg)
    character(len=*), intent(in) :: file, group, msg
    integer, intent(in) :: unit, ios
    if (probing) then
       probe_ios = ios
       return
    end if
    if (ios > 0) then
       close (unit)    ! report_read_error reopens the file as a stream, and quits
       call report_read_error(file, group, msg)
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
  recursive subroutine report_read_error(file, group, msg)
    character(len=*), intent(in) :: file, group, msg
    character(len=*), parameter :: NO_MATCH = "Cannot match namelist object name "
    character(len=:), allocatable :: bytes, name, key
    integer(int64), allocatable :: starts(:)
    integer :: line, head, k
    character(len=16) :: line_text
    call file_lines(file, bytes, starts)
    head = header_line(bytes, starts, group)
    line = 0
    if (head > 0) line = locate_error(file, group, bytes, starts, head)
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
            ": unknown key"//suggestion(name, group_keys(group))//" (&"//group//" has: "// &
            group_keys(group)//")"
    else
       key = last_key(bytes, starts, head, line)
       if (len(key) > 0 .and. .not. is_key_of(key, group)) then
          ! After a list's values gfortran takes an unknown name for more
          ! data ("Bad data for namelist object rtol"): the name is the fault.
          write (error_unit, '(a)') trim(file)//":"//trim(line_text)//": &"//group//" "//key// &
               ": unknown key"//suggestion(key, group_keys(group))//" (&"//group//" has: "// &
               group_keys(group)//")"
       else if (len(key) > 0) then
          write (error_unit, '(a)') trim(file)//":"//trim(line_text)//": &"//group//" "//key// &
               ": "//trim(msg)
       else
          write (error_unit, '(a)') trim(file)//":"//trim(line_text)//": &"//group//": "//trim(msg)
       end if
    end if
    call quit(2)
  end subroutine report_read_error

  ! Whether key (any case) is a key of group.
  logical function is_key_of(key, group)
    character(len=*), intent(in) :: key, group
    is_key_of = index(", "//group_keys(group)//",", ", "//lower(key)//",") > 0
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
  recursive integer function locate_error(file, group, bytes, starts, head) result(j)
    character(len=*), intent(in) :: file, group, bytes
    integer(int64), intent(in) :: starts(:)
    integer, intent(in) :: head
    integer :: lo, hi, mid
    lo = head
    hi = size(starts) - 1
    if (.not. prefix_fails(file, group, bytes, starts, head, hi)) then
       j = 0
       return
    end if
    do while (lo < hi)
       mid = (lo + hi) / 2
       if (prefix_fails(file, group, bytes, starts, head, mid)) then
          hi = mid
       else
          lo = mid + 1
       end if
    end do
    j = lo
  end function locate_error

  ! Whether lines head..last, closed by '/', fail to read as &group (a
  ! scratch file, read by read_group with check_read only recording).
  recursive logical function prefix_fails(file, group, bytes, starts, head, last)
    character(len=*), intent(in) :: file, group, bytes
    integer(int64), intent(in) :: starts(:)
    integer, intent(in) :: head, last
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
    call read_group(file, unit, group)
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

  ! out/NAME for scene file .../NAME.nml (drivers/taper/scene/scene_new.c: derived_dir).
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

  function lower(str) result(l)
    character(len=*), intent(in) :: str
    character(len=len(str)) :: l
    integer :: k
    l = str
    do k = 1, len(str)
       if (l(k:k) >= "A" .and. l(k:k) <= "Z") l(k:k) = achar(iachar(l(k:k)) + 32)
    end do
  end function lower

  subroutine print_bits(x)
    real(c_double), intent(in) :: x
    write (output_unit, '(1x,z16.16)', advance="no") transfer(x, 0_int64)
  end subroutine print_bits

  ! ---- --dump: the canonical form of tests/bindings/scene_dump.c ---------------------

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

  ! ---- runs -------------------------------------------------------------------------------

  ! What the C driver does with a scene and taper_nml does not: real units
  ! and mixed materials (&material), refused before any run, naming the
  ! group, rather than run as something else; a scene's sampled time series
  ! (&sensors) are not written (said on stderr; the pass times are the same
  ! to rounding).  (--dump reads and prints them all.)
  logical function runnable()
    integer :: k
    logical :: material
    material = lower(sv%units) == "si"
    do k = 1, N_VARS
       if (given(k) .and. GROUP_OF(k) == "material") material = .true.
    end do
    runnable = .not. material
    if (material) then
       write (error_unit, '(a)') trim(path)//": &material: taper_nml runs in rescaled units "// &
            "with one material only; run the scene with taper"
       return
    end if
    ! Sampling does not stop the run (CVODE interpolates at the sample
    ! times): the pass times and peaks are the same to rounding (1e-14).
    if (any(sv%interval%v(1:sv%interval%n) > 0) .or. sv%spacetime) &
         write (error_unit, '(a)') trim(path)//": &sensors: not written by taper_nml "// &
         "(taper writes the time series); the pass times are the same"
  end function runnable

  ! The runs of the sweep: every combination of the swept variables' values,
  ! or (&sweep mode = 'zip') their i-th values together, which needs lists
  ! of one length.
  integer(int64) function count_runs(lens) result(n)
    integer, intent(in) :: lens(:)
    integer :: k, first
    character(len=:), allocatable :: group, key, first_key
    n = 1
    first = 0
    do k = 1, size(lens)
       if (lens(k) < 2) cycle
       if (trim(sv%sweep_mode) == "zip") then
          if (first == 0) then
             first = k
             n = lens(k)
          else if (lens(k) /= n) then
             call var_place(SWEPT_KEYWORDS(first), group, first_key)
             call var_place(SWEPT_KEYWORDS(k), group, key)
             write (error_unit, '(a,i0,a,i0,a)') trim(path)//": &"//group//" "//key//": ", &
                  lens(k), " values, but "//first_key//" has ", n, ": zipped lists (&sweep "// &
                  "mode = 'zip') need the same length (or mode = 'grid': every combination)"
             call quit(2)
          end if
       else
          if (n > MAX_RUNS / lens(k)) then
             call var_place(SWEPT_KEYWORDS(k), group, key)
             write (error_unit, '(a,i0,a)') trim(path)//": &"//group//" "//key// &
                  ": the grid has more than ", MAX_RUNS, " runs: split the sweep"
             call quit(2)
          end if
          n = n * lens(k)
       end if
    end do
  end function count_runs

  ! The index of each sweepable variable's value at run `run` (0-based):
  ! zip: the run's; grid: the variable later in the table fastest.
  subroutine point_indices(run, lens, ix)
    integer(int64), intent(in) :: run
    integer, intent(in) :: lens(:)
    integer, intent(out) :: ix(:)
    integer(int64) :: stride
    integer :: k
    stride = 1
    do k = size(lens), 1, -1
       if (trim(sv%sweep_mode) == "zip") then
          ix(k) = int(min(run, int(lens(k) - 1, int64))) + 1
       else
          ix(k) = int(mod(run / stride, int(lens(k), int64))) + 1
          stride = stride * lens(k)
       end if
    end do
  end subroutine point_indices

  ! A library refusal as the C driver reports it: the file, then the group
  ! and key of the variable the library names, then the library's message.
  ! A number of granules the radii gave is the radii's fault, and radii a
  ! file gave are the file's.
  subroutine report(e)
    type(taper_error), intent(in) :: e
    character(len=:), allocatable :: field, group, key
    field = taper_field(e)
    if (field == "n_granules" .and. .not. was_given("n_granules") .and. &
         trim(sv%profile) == "custom") field = "radii"
    if (field == "radii" .and. file_radii%n > 0) field = "radii_file"
    call var_place(field, group, key)
    if (len(group) > 0) then
       write (error_unit, '(a)') trim(path)//": &"//group//" "//key//": "//taper_message(e)
    else
       write (error_unit, '(a)') trim(path)//": "//taper_message(e)
    end if
  end subroutine report

  ! The chain of a run: every chain setting by name (apply_chain), then the
  ! scene's own rules on top -- the radii of a radii file, a 'steady'
  ! piston's infinite push; c_null_ptr after reporting why not.
  function make_chain(ix) result(c)
    integer, intent(in) :: ix(:)
    type(c_ptr) :: c, cs
    type(taper_error) :: e
    integer(c_int) :: st
    c = c_null_ptr
    cs = taper_chain_spec_alloc(e)
    if (.not. c_associated(cs)) then
       call report(e)
       return
    end if
    st = apply_chain(cs, ix, e)
    if (st == TAPER_OK .and. file_radii%n > 0) &
         st = taper_chain_spec_set_option(cs, "radii", file_radii%v(1:file_radii%n), e)
    if (st == TAPER_OK .and. trim(sv%piston) == "steady") st = taper_chain_spec_set_option(cs, &
         "piston_duration", ieee_value(1.0_c_double, ieee_positive_inf), e)
    if (st == TAPER_OK) c = taper_chain_alloc(cs, e)
    if (.not. c_associated(c)) call report(e)
    call taper_chain_spec_free(cs)
  end function make_chain

  ! The solver of a run, every solver setting by name; c_null_ptr after
  ! reporting why not.
  function make_solver(ix) result(ss)
    integer, intent(in) :: ix(:)
    type(c_ptr) :: ss
    type(taper_error) :: e
    ss = taper_solver_spec_alloc(e)
    if (.not. c_associated(ss)) then
       call report(e)
       return
    end if
    if (apply_solver(ss, ix, e) /= TAPER_OK) then
       call report(e)
       call taper_solver_spec_free(ss)
       ss = c_null_ptr
    end if
  end function make_solver

  ! One run of the scene: chain, dynamics (with the theory the sim computes
  ! once) or the theory alone; 0, 1 (failure), 2 (bad input) or 3 (partial).
  integer function run_point(lens, ix) result(rc)
    integer, intent(in) :: lens(:), ix(:)
    type(taper_error) :: e
    type(c_ptr) :: c, ss, sim
    real(c_double), allocatable, target :: v_buf(:), t_buf(:)
    real(c_double), pointer :: t_pass(:), v_peak(:), v_th(:), t_th(:)
    integer(c_int) :: st
    integer(c_size_t) :: n, k, step

    rc = 0
    c = make_chain(ix)
    if (.not. c_associated(c)) then
       rc = 2
       return
    end if
    n = taper_chain_size(c)
    sim = c_null_ptr
    if (sv%numerics) then
       ss = make_solver(ix)
       if (.not. c_associated(ss)) then
          call taper_chain_free(c)
          rc = 2
          return
       end if
       sim = taper_sim_alloc(c, ss, e)
       call taper_solver_spec_free(ss)
       if (.not. c_associated(sim)) then
          call report(e)
          call taper_chain_free(c)
          rc = merge(1, 2, e%status == TAPER_ERANGE .or. e%status == TAPER_ENOMEM)
          return
       end if
       v_th => taper_theory(sim, c, TAPER_THEORY_V)
       t_th => taper_theory(sim, c, TAPER_THEORY_T)
       t_pass => taper_observable(sim, c, TAPER_T_PASS)  ! filled by the run
       v_peak => taper_observable(sim, c, TAPER_V_PEAK)
    else
       allocate (v_buf(n), t_buf(n))
       if (taper_theory_compute(c, c_loc(v_buf), c_null_ptr, c_null_ptr, c_loc(t_buf), e) &
            /= TAPER_OK) then
          call report(e)
          call taper_chain_free(c)
          rc = 1
          return
       end if
       v_th => v_buf
       t_th => t_buf
       t_pass => t_buf   ! not printed without numerics; associated all the same
       v_peak => v_buf
    end if

    write (output_unit, '(5a,i0,a,g0.6)', advance="no") "# ", trim(path), ": ", &
         taper_profile_name(taper_chain_profile(c)), " N = ", n, "  n = ", taper_chain_exponent(c)
    call write_swept(lens, ix)
    write (output_unit, '()')
    if (sv%numerics) then
       st = taper_sim_run(sim, e)
       if (st /= TAPER_OK) then
          write (error_unit, '(a)') trim(path)//": "//taper_message(e)
          rc = merge(1, 3, st == TAPER_EINVAL .or. st == TAPER_ENOMEM)
       end if
       write (output_unit, '(a2,a8,4a16)') "# ", "k", "t_pass", "t_k theory", "v_peak", "v_k theory"
    else
       write (output_unit, '(a2,a8,2a16)') "# ", "k", "t_k theory", "v_k theory"
    end if
    step = max(1_c_size_t, (n - 1) / 10)
    k = 1
    do while (k < n)
       if (sv%numerics) then
          write (output_unit, '(2x,i8,4es16.8)') k, t_pass(k), t_th(k), v_peak(k), v_th(k)
       else
          write (output_unit, '(2x,i8,2es16.8)') k, t_th(k), v_th(k)
       end if
       if (k < 5) then
          k = k + 1
       else if (k + step >= n .and. k /= n - 1) then
          k = n - 1
       else
          k = k + step
       end if
    end do
    if (sv%numerics) then
       write (output_unit, '(a,i0,a,es9.2,a,l1)') "# steps ", &
            int(taper_sim_statistic(sim, TAPER_STAT_STEPS), int64), "  energy error ", &
            taper_sim_statistic(sim, TAPER_STAT_ENERGY_ERROR), "  complete ", &
            taper_sim_statistic(sim, TAPER_STAT_COMPLETE) > 0.5_c_double  ! 0 or 1
       call taper_sim_free(sim)
    end if
    call taper_chain_free(c)
  end function run_point

end program taper_nml
