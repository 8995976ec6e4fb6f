! taper_nml -- run a taper scene file with Fortran's own namelist READ.
!
!   taper_nml SCENE.nml           run it: t_pass and v_peak next to the theory
!   taper_nml --dump SCENE.nml    print the resolved values (canonical form of
!                                 tests/bindings/scene_dump.c) and stop
!
! Our scene files (share/scenes/*.nml, docs/scene.md) are standard Fortran
! namelists with the groups &chain, &solver, &output, &fit, &table, &figure, &sweep,
! and (issue 15) &ends, &striker, &losses, &material, &sensors; this program
! reads them with READ(unit, NML=...) and hands the values of &chain,
! &solver, &ends, &striker and &losses to libtaper through the iso_c_binding
! module `taper`
! (src/bindings/fortran/taper.f90), one setter per variable: the library
! checks each value and names the variable it refuses, so this program keeps
! no bounds of its own, and the names of profiles, methods and fit models
! are the library's (taper_profile_name, ...).  The variables are those of
! the table in drivers/taper/scene/scene.c; the defaults of &chain and
! &solver come from the library itself (a fresh taper_chain_spec and
! taper_solver_spec), as in the C driver.
! A list of values for s, q or seed is a sweep: each value is run in turn.
! &material (real units, mixed materials) is read and checked but not run
! (refused, naming the group: taper runs it); &sensors' time series are not
! written (the pass times are the same to rounding; said on stderr).  The
! analysis groups &fit, &table and &figure (the C driver's fits, tables and
! figures) are read too, so that --dump proves every group of a scene is a
! real Fortran namelist and resolves as in the C parser; the runs here do not
! use them.  Their variables share names across groups (x, y, k_max, name),
! which one scoping unit cannot hold twice: each of these groups is read in
! its own internal subroutine (read_fit, read_table, read_figure).
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

  ! MAX_RADII: SCENE_MAX_LIST of the C parser (drivers/taper/scene/scene_impl.h)
  integer, parameter :: MAX_SWEEP = 1000, MAX_RADII = 250000, LEN_STR = 1024
  ! SCENE_MAX_FILE of the C parser
  integer(int64), parameter :: MAX_FILE = 8388608_int64
  ! A value left out: a quiet NaN with a payload no input produces (a NaN
  ! the file gives is the canonical one, and refused as not finite).
  integer(int64), parameter :: NOT_GIVEN = int(z'7FF80000DEADBEEF', int64)
  ! A seed left out of the list (seeds are >= 0).
  integer(int64), parameter :: NOT_GIVEN_SEED = -huge(0_int64)

  ! &chain
  character(len=LEN_STR) :: profile
  integer(int64) :: n_granules
  real(c_double) :: s(MAX_SWEEP), q(MAX_SWEEP), exponent
  real(c_double), allocatable, target :: radii(:)
  ! &chain, beyond the paper (issue 15)
  character(len=LEN_STR) :: radii_file, disorder
  real(c_double), allocatable, target :: pattern(:)
  real(c_double) :: disorder_amplitude, load
  integer(int64) :: seed(MAX_SWEEP)   ! a list of seeds: an ensemble, run in turn
  ! &ends, &striker, &losses, &material, &sensors (read by read_ends, ...;
  ! the group's prefix added to each name where two groups share one)
  character(len=LEN_STR) :: ends_left, ends_right
  real(c_double) :: ends_left_compliance, ends_right_compliance
  real(c_double) :: striker_radius, striker_density, striker_compliance
  character(len=LEN_STR) :: striker_piston
  real(c_double) :: striker_piston_duration, striker_piston_compliance
  real(c_double) :: losses_damping, losses_drag
  real(c_double) :: material_young, material_poisson, material_density, material_radius, &
       material_velocity
  real(c_double) :: material_other_young(MAX_SWEEP), material_other_poisson(MAX_SWEEP), &
       material_other_density(MAX_SWEEP), material_sequence(MAX_SWEEP)
  integer(int64) :: material_wall, material_striker
  real(c_double) :: sensors_interval, sensors_granules(MAX_SWEEP)
  logical :: sensors_spacetime
  integer(int64) :: sensors_spacetime_granules, sensors_spacetime_times
  ! &solver
  character(len=LEN_STR) :: method
  real(c_double) :: rtol, atol, t_max, t_end
  logical :: window, numerics
  integer(int64) :: last_granule, max_steps
  ! &output
  character(len=LEN_STR) :: dir, columns
  logical :: progress
  integer(int64) :: threads      ! parallel sweeps of the C driver; unused here
  integer(int64) :: every        ! granules.tsv of the C driver; unused here
  real(c_double) :: max_energy_error, max_momentum_error
  character(len=LEN_STR) :: units
  ! &fit, &table, &figure (read by read_fit, read_table, read_figure; the
  ! group's prefix added to each name)
  character(len=LEN_STR) :: fit_model, fit_x, fit_y, fit_report, fit_label, fit_theory
  integer(int64) :: fit_k_min, fit_k_max
  real(c_double) :: fit_p, fit_factor
  character(len=LEN_STR) :: table_name, table_caption
  integer(int64) :: table_digits
  real(c_double) :: table_paper_theory(MAX_SWEEP), table_paper_numerics(MAX_SWEEP)
  character(len=LEN_STR) :: figure_name, figure_title, figure_x, figure_y, figure_curves, &
       figure_x_label, figure_y_label
  logical :: figure_log_x, figure_log_y, figure_inset
  integer(int64) :: figure_every, figure_k_max
  real(c_double) :: figure_inset_reference
  ! &sweep (read by read_sweep): how the C driver combines lists; unused here
  character(len=LEN_STR) :: sweep_mode

  ! Allowed strings of the driver's own analysis groups
  ! (drivers/taper/scene/scene.c); the C parser stores their canonical
  ! spelling.  Profiles, methods and fit models are the library's.
  character(len=*), parameter :: QUANTITIES(6) = [character(len=7) :: "k", "v", "T_res", "t", &
       "t_reach", "t_peak"]
  character(len=*), parameter :: FIT_PARAMS(6) = [character(len=1) :: "a", "b", "c", "m", "p", "f"]
  character(len=*), parameter :: THEORIES(4) = [character(len=4) :: "fit", "rate", "f", "b"]
  character(len=*), parameter :: CURVES(3) = [character(len=8) :: "both", "theory", "numerics"]
  character(len=*), parameter :: SWEEP_MODES(2) = [character(len=4) :: "grid", "zip"]
  character(len=*), parameter :: UNITS_CHOICES(2) = [character(len=8) :: "rescaled", "si"]
  character(len=*), parameter :: PISTONS(3) = [character(len=6) :: "none", "push", "steady"]

  namelist /chain/ profile, n_granules, s, q, exponent, radii, radii_file, pattern, disorder, &
       disorder_amplitude, seed, load
  namelist /solver/ method, rtol, atol, window, last_granule, t_max, max_steps, t_end, numerics
  namelist /output/ dir, progress, threads, columns, every, max_energy_error, &
       max_momentum_error, units
  ! The keys of every group, for the message on an unknown key (the
  ! namelists above and in read_fit, read_table, read_figure, read_sweep).
  character(len=*), parameter :: KEYS_CHAIN = "profile, n_granules, s, q, exponent, radii, " // &
       "radii_file, pattern, disorder, disorder_amplitude, seed, load", &
       KEYS_SOLVER = "method, rtol, atol, window, last_granule, t_max, max_steps, t_end, " // &
       "numerics", &
       KEYS_OUTPUT = "dir, progress, threads, columns, every, max_energy_error, " // &
       "max_momentum_error, units", &
       KEYS_ENDS = "left, right, left_compliance, right_compliance", &
       KEYS_STRIKER = "radius, density, compliance, piston, piston_duration, " // &
       "piston_compliance", &
       KEYS_LOSSES = "damping, drag", &
       KEYS_MATERIAL = "young, poisson, density, radius, velocity, other_young, " // &
       "other_poisson, other_density, sequence, wall, striker", &
       KEYS_SENSORS = "interval, granules, spacetime, spacetime_granules, spacetime_times", &
       KEYS_FIT = "model, x, y, k_min, k_max, p, report, factor, label, theory", &
       KEYS_TABLE = "name, caption, digits, paper_theory, paper_numerics", &
       KEYS_FIGURE = "name, title, x, y, curves, log_x, log_y, every, k_max, x_label, " // &
       "y_label, inset, inset_reference", &
       KEYS_SWEEP = "mode"
  ! While locate_error re-reads part of a group (probing), check_read
  ! records the status in probe_ios instead of reporting it.
  logical :: probing = .false.
  integer :: probe_ios = 0

  character(len=LEN_STR) :: path, arg
  logical :: dump, n_given
  integer :: n_s, n_q, n_radii, n_pattern, n_seed, n_sweep, i, status, worst, arg_status
  real(c_double) :: nan
  type(c_ptr) :: chain_defaults, solver_defaults
  type(taper_error) :: err

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

  ! Defaults: those of fresh library specs (the table of
  ! drivers/taper/scene/scene.c takes them from there too).
  nan = transfer(NOT_GIVEN, nan)
  chain_defaults = taper_chain_spec_alloc(err)
  solver_defaults = taper_solver_spec_alloc(err)
  if (.not. c_associated(chain_defaults) .or. .not. c_associated(solver_defaults)) then
     write (error_unit, '(a)') "taper_nml: "//taper_message(err)
     call quit(1)
  end if
  profile = taper_profile_name(taper_chain_spec_profile(chain_defaults))
  n_granules = -1            ! not given: the library's default, or the number of radii
  s = nan                    ! not given: the library's default
  q = nan
  exponent = taper_chain_spec_exponent(chain_defaults)
  allocate (radii(MAX_RADII))
  radii = nan
  radii_file = ""
  allocate (pattern(MAX_RADII))
  pattern = nan
  disorder = taper_disorder_name(taper_chain_spec_disorder(chain_defaults))
  disorder_amplitude = taper_chain_spec_disorder_amplitude(chain_defaults)
  seed = -1                  ! not given (a seed is >= 0): the library's default
  seed(1) = int(taper_chain_spec_disorder_seed(chain_defaults), int64)
  seed(2:) = NOT_GIVEN_SEED
  load = taper_chain_spec_load(chain_defaults)
  t_end = taper_solver_spec_t_end(solver_defaults)
  units = "rescaled"
  method = taper_method_name(taper_solver_spec_method(solver_defaults))
  rtol = taper_solver_spec_rtol(solver_defaults)
  atol = taper_solver_spec_atol(solver_defaults)
  window = taper_solver_spec_window(solver_defaults) /= 0
  last_granule = int(taper_solver_spec_last_granule(solver_defaults), int64)
  t_max = taper_solver_spec_t_max(solver_defaults)
  max_steps = int(taper_solver_spec_max_steps(solver_defaults), int64)
  numerics = .true.
  dir = default_dir(path)
  progress = .true.
  threads = 0
  columns = ""
  every = 1
  max_energy_error = 1e-3_c_double
  max_momentum_error = 1e-3_c_double

  ! Defaults of &fit, &table and &figure: set by read_fit, read_table and
  ! read_figure, which read_scene calls.
  call screen_file(path)
  call read_scene(path)
  ! Namelist READ cuts a string at its variable's length without a word: a
  ! value that fills the whole variable may have been cut, so it is refused.
  call check_length("chain", "profile", profile)
  call check_length("solver", "method", method)
  call check_length("output", "dir", dir)
  call check_length("output", "columns", columns)
  call check_length("fit", "model", fit_model)
  call check_length("fit", "x", fit_x)
  call check_length("fit", "y", fit_y)
  call check_length("fit", "report", fit_report)
  call check_length("fit", "label", fit_label)
  call check_length("fit", "theory", fit_theory)
  call check_length("table", "name", table_name)
  call check_length("table", "caption", table_caption)
  call check_length("figure", "name", figure_name)
  call check_length("figure", "title", figure_title)
  call check_length("figure", "x", figure_x)
  call check_length("figure", "y", figure_y)
  call check_length("figure", "curves", figure_curves)
  call check_length("figure", "x_label", figure_x_label)
  call check_length("figure", "y_label", figure_y_label)
  call check_length("sweep", "mode", sweep_mode)
  call check_length("chain", "radii_file", radii_file)
  call check_length("chain", "disorder", disorder)
  call check_length("ends", "left", ends_left)
  call check_length("ends", "right", ends_right)
  call check_length("striker", "piston", striker_piston)
  call check_length("output", "units", units)

  ! Allowed strings in their canonical spelling, as the C parser stores them:
  ! the library's names for profiles, methods and fit models.
  profile = library_name(profile, "profile")
  method = library_name(method, "method")
  if (lower(fit_model) == "none") then
     fit_model = "none"
  else
     fit_model = library_name(fit_model, "fit_model")
  end if
  fit_x = canonical(fit_x, QUANTITIES)
  fit_y = canonical(fit_y, QUANTITIES)
  fit_report = canonical(fit_report, FIT_PARAMS)
  fit_theory = canonical(fit_theory, THEORIES)
  figure_x = canonical(figure_x, QUANTITIES)
  figure_y = canonical(figure_y, QUANTITIES)
  figure_curves = canonical(figure_curves, CURVES)
  sweep_mode = canonical(sweep_mode, SWEEP_MODES)
  disorder = library_name(disorder, "disorder")
  ends_left = library_name(ends_left, "boundary")
  ends_right = library_name(ends_right, "boundary")
  units = canonical(units, UNITS_CHOICES)
  striker_piston = canonical(striker_piston, PISTONS)

  ! Resolve: a sweep is the list given; nothing given is the library's default.
  n_s = count_given(s)
  n_q = count_given(q)
  n_radii = count_given(radii)
  n_pattern = count_given(pattern)
  n_seed = 1
  do while (n_seed < MAX_SWEEP)
     if (seed(n_seed + 1) == NOT_GIVEN_SEED) exit
     n_seed = n_seed + 1
  end do
  if (any(seed(1:n_seed) < 0)) then
     write (error_unit, '(a)') trim(path)//": &chain seed: a seed is an integer >= 0"
     call quit(2)
  end if
  call read_radii_file()
  ! Every real given must be a number (READ takes nan and inf).
  call check_finite("chain", "s", s(1:n_s))
  call check_finite("chain", "q", q(1:n_q))
  call check_finite("chain", "radii", radii(1:n_radii))
  call check_finite("chain", "exponent", [exponent])
  call check_finite("solver", "rtol", [rtol])
  call check_finite("solver", "atol", [atol])
  call check_finite("solver", "t_max", [t_max])
  call check_finite("output", "max_energy_error", [max_energy_error])
  call check_finite("output", "max_momentum_error", [max_momentum_error])
  call check_finite("chain", "pattern", pattern(1:n_pattern))
  call check_finite("chain", "disorder_amplitude", [disorder_amplitude])
  call check_finite("chain", "load", [load])
  call check_finite("ends", "left_compliance", [ends_left_compliance])
  call check_finite("ends", "right_compliance", [ends_right_compliance])
  call check_finite("striker", "radius", [striker_radius])
  call check_finite("striker", "density", [striker_density])
  call check_finite("striker", "compliance", [striker_compliance])
  call check_finite("striker", "piston_duration", [striker_piston_duration])
  call check_finite("striker", "piston_compliance", [striker_piston_compliance])
  if ((trim(striker_piston) == "push") .neqv. (abs(striker_piston_duration) > 0)) then
     write (error_unit, '(a)') trim(path)//": &striker piston_duration: piston = 'push' "// &
          "pushes for piston_duration > 0, and only it has one ('steady' pushes for ever)"
     call quit(2)
  end if
  call check_finite("losses", "damping", [losses_damping])
  call check_finite("losses", "drag", [losses_drag])
  call check_finite("solver", "t_end", [t_end])
  call check_finite("sensors", "interval", [sensors_interval])
  call check_finite("sensors", "granules", sensors_granules(1:count_given(sensors_granules)))
  if (is_given(material_young)) call check_finite("material", "young", [material_young])
  if (is_given(material_poisson)) call check_finite("material", "poisson", [material_poisson])
  if (is_given(material_density)) call check_finite("material", "density", [material_density])
  if (is_given(material_radius)) call check_finite("material", "radius", [material_radius])
  if (is_given(material_velocity)) call check_finite("material", "velocity", [material_velocity])
  call check_finite("material", "other_young", &
       material_other_young(1:count_given(material_other_young)))
  call check_finite("material", "other_poisson", &
       material_other_poisson(1:count_given(material_other_poisson)))
  call check_finite("material", "other_density", &
       material_other_density(1:count_given(material_other_density)))
  call check_finite("material", "sequence", material_sequence(1:count_given(material_sequence)))
  call check_finite("fit", "factor", [fit_factor])
  if (is_given(fit_p)) call check_finite("fit", "p", [fit_p])
  if (is_given(figure_inset_reference)) &
       call check_finite("figure", "inset_reference", [figure_inset_reference])
  call check_finite("table", "paper_theory", table_paper_theory(1:count_given(table_paper_theory)))
  call check_finite("table", "paper_numerics", &
       table_paper_numerics(1:count_given(table_paper_numerics)))
  if (n_s == 0) then
     s(1) = taper_chain_spec_s(chain_defaults)
     n_s = 1
  end if
  if (n_q == 0) then
     q(1) = taper_chain_spec_q(chain_defaults)
     n_q = 1
  end if
  n_given = n_granules >= 0
  if (.not. n_given) n_granules = int(taper_chain_spec_n_granules(chain_defaults), int64)
  call taper_chain_spec_free(chain_defaults)
  call taper_solver_spec_free(solver_defaults)
  if (lower(profile) == "custom" .and. n_radii > 0) then
     if (n_given .and. n_granules /= n_radii) then
        write (error_unit, '(a,i0,a,i0,a)') trim(path)//": n_granules = ", n_granules, &
             " but ", n_radii, " radii are given"
        call quit(2)
     end if
     n_granules = n_radii
  end if
  if (count([n_s > 1, n_q > 1, n_seed > 1]) > 1) then
     write (error_unit, '(a)') trim(path)//": only one of s, q and seed may be swept"
     call quit(2)
  end if

  if (dump) then
     call print_dump()
     deallocate (radii, pattern)
     stop
  end if

  if (.not. runnable()) call quit(2)
  n_sweep = max(n_s, n_q, n_seed)
  worst = 0
  do i = 1, n_sweep
     status = run_point(min(i, n_s), min(i, n_q), min(i, n_seed))
     worst = max(worst, status)
  end do
  ! Main-program variables are implicitly SAVE'd: never deallocated for us
  ! (LeakSanitizer and valgrind report them once MAIN__ has returned).
  deallocate (radii, pattern)
  if (worst /= 0) call quit(worst)

contains

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

  ! Refuses NaN and infinities among the values given for group/name.
  subroutine check_finite(group, name, values)
    character(len=*), intent(in) :: group, name
    real(c_double), intent(in) :: values(:)
    integer :: k
    do k = 1, size(values)
       if (ieee_is_finite(values(k))) cycle
       write (error_unit, '(a)') trim(path)//": &"//group//" "//name// &
            ": not a finite number (nan and inf are refused)"
       call quit(2)
    end do
  end subroutine check_finite

  ! False for the NaN that marks a value left out (NOT_GIVEN).
  logical function is_given(x)
    real(c_double), intent(in) :: x
    is_given = transfer(x, 0_int64) /= NOT_GIVEN
  end function is_given

  ! &chain radii_file as the C parser reads it (drivers/taper/scene/
  ! scene_physics.c): the path relative to the scene file's folder, made
  ! absolute; one radius per line, blank lines and '#' comments skipped,
  ! every radius finite and > 0, the first 1; the radii become the custom
  ! chain's and n_granules their number.  Errors name FILE:LINE of the radii
  ! file, under &chain radii_file.
  subroutine read_radii_file()
    character(len=:), allocatable :: file, line, where
    character(len=4096) :: buffer
    real(c_double), allocatable :: grown(:)
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
    if (len_trim(radii_file) == 0) return
    file = trim(radii_file)
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
    radii_file = file            ! the dump names the file this run read
    where = trim(path)//": &chain radii_file: "//file
    open (newunit=unit, file=file, status="old", action="read", iostat=ios)
    if (ios /= 0) then
       write (error_unit, '(a)') where//": cannot open it"
       call quit(2)
    end if
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
       if (n > size(radii)) then
          allocate (grown(2 * size(radii)))
          grown = nan
          grown(1:size(radii)) = radii
          call move_alloc(grown, radii)
       end if
       radii(n) = x
    end do
    close (unit)
    if (n == 0) then
       write (error_unit, '(a)') where//": holds no radius"
       call quit(2)
    end if
    n_radii = n
  end subroutine read_radii_file

  subroutine read_scene(file)
    character(len=*), intent(in) :: file
    character(len=*), parameter :: GROUPS(12) = [character(len=8) :: "chain", "solver", "output", &
         "fit", "table", "figure", "sweep", "ends", "striker", "losses", "material", "sensors"]
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

  ! READ(unit, NML=group) of one group, checked by check_read.  Recursive:
  ! check_read's locate_error calls it again on part of the file.
  recursive subroutine read_group(file, unit, group)
    character(len=*), intent(in) :: file, group
    integer, intent(in) :: unit
    integer :: ios
    character(len=512) :: msg
    select case (group)
    case ("chain")
       read (unit, nml=chain, iostat=ios, iomsg=msg)
       call check_read(file, unit, group, ios, msg)
    case ("solver")
       read (unit, nml=solver, iostat=ios, iomsg=msg)
       call check_read(file, unit, group, ios, msg)
    case ("output")
       read (unit, nml=output, iostat=ios, iomsg=msg)
       call check_read(file, unit, group, ios, msg)
    case ("fit")
       call read_fit(file, unit)
    case ("table")
       call read_table(file, unit)
    case ("figure")
       call read_figure(file, unit)
    case ("sweep")
       call read_sweep(file, unit)
    case ("ends")
       call read_ends(file, unit)
    case ("striker")
       call read_striker(file, unit)
    case ("losses")
       call read_losses(file, unit)
    case ("material")
       call read_material(file, unit)
    case ("sensors")
       call read_sensors(file, unit)
    end select
  end subroutine read_group

  ! &ends with the library's defaults (free ends, rigid walls); copied to ends_*.
  recursive subroutine read_ends(file, unit)
    character(len=*), intent(in) :: file
    integer, intent(in) :: unit
    character(len=LEN_STR) :: left, right
    real(c_double) :: left_compliance, right_compliance
    namelist /ends/ left, right, left_compliance, right_compliance
    integer :: ios
    character(len=512) :: msg
    left = taper_boundary_name(taper_chain_spec_end(chain_defaults, TAPER_LEFT))
    right = taper_boundary_name(taper_chain_spec_end(chain_defaults, TAPER_RIGHT))
    left_compliance = taper_chain_spec_end_compliance(chain_defaults, TAPER_LEFT)
    right_compliance = taper_chain_spec_end_compliance(chain_defaults, TAPER_RIGHT)
    read (unit, nml=ends, iostat=ios, iomsg=msg)
    call check_read(file, unit, "ends", ios, msg)
    ends_left = left
    ends_right = right
    ends_left_compliance = left_compliance
    ends_right_compliance = right_compliance
  end subroutine read_ends

  ! &striker with the library's defaults (none: radius 0); copied to striker_*.
  recursive subroutine read_striker(file, unit)
    character(len=*), intent(in) :: file
    integer, intent(in) :: unit
    real(c_double) :: radius, density, compliance, piston_duration, piston_compliance
    character(len=LEN_STR) :: piston
    namelist /striker/ radius, density, compliance, piston, piston_duration, piston_compliance
    integer :: ios
    character(len=512) :: msg
    radius = taper_chain_spec_striker_radius(chain_defaults)
    density = taper_chain_spec_striker_density(chain_defaults)
    compliance = taper_chain_spec_striker_compliance(chain_defaults)
    piston = "none"   ! the library's default: duration 0
    piston_duration = taper_chain_spec_piston_duration(chain_defaults)
    piston_compliance = taper_chain_spec_piston_compliance(chain_defaults)
    read (unit, nml=striker, iostat=ios, iomsg=msg)
    call check_read(file, unit, "striker", ios, msg)
    striker_radius = radius
    striker_density = density
    striker_compliance = compliance
    striker_piston = piston
    striker_piston_duration = piston_duration
    striker_piston_compliance = piston_compliance
  end subroutine read_striker

  ! &losses with the library's defaults (elastic, no drag); copied to losses_*.
  recursive subroutine read_losses(file, unit)
    character(len=*), intent(in) :: file
    integer, intent(in) :: unit
    real(c_double) :: damping, drag
    namelist /losses/ damping, drag
    integer :: ios
    character(len=512) :: msg
    damping = taper_chain_spec_damping(chain_defaults)
    drag = taper_chain_spec_drag(chain_defaults)
    read (unit, nml=losses, iostat=ios, iomsg=msg)
    call check_read(file, unit, "losses", ios, msg)
    losses_damping = damping
    losses_drag = drag
  end subroutine read_losses

  ! &material with the table's defaults (nothing given: rescaled units, one
  ! material, rigid walls, the striker of material 1); copied to material_*.
  recursive subroutine read_material(file, unit)
    character(len=*), intent(in) :: file
    integer, intent(in) :: unit
    real(c_double) :: young, poisson, density, radius, velocity
    real(c_double) :: other_young(MAX_SWEEP), other_poisson(MAX_SWEEP), &
         other_density(MAX_SWEEP), sequence(MAX_SWEEP)
    integer(int64) :: wall, striker
    namelist /material/ young, poisson, density, radius, velocity, other_young, other_poisson, &
         other_density, sequence, wall, striker
    integer :: ios
    character(len=512) :: msg
    young = nan              ! no defaults: left out
    poisson = nan
    density = nan
    radius = nan
    velocity = nan
    other_young = nan        ! empty lists
    other_poisson = nan
    other_density = nan
    sequence = nan
    wall = 0
    striker = 1
    read (unit, nml=material, iostat=ios, iomsg=msg)
    call check_read(file, unit, "material", ios, msg)
    material_young = young
    material_poisson = poisson
    material_density = density
    material_radius = radius
    material_velocity = velocity
    material_other_young = other_young
    material_other_poisson = other_poisson
    material_other_density = other_density
    material_sequence = sequence
    material_wall = wall
    material_striker = striker
  end subroutine read_material

  ! &sensors with the table's defaults (no sampling); copied to sensors_*.
  recursive subroutine read_sensors(file, unit)
    character(len=*), intent(in) :: file
    integer, intent(in) :: unit
    real(c_double) :: interval, granules(MAX_SWEEP)
    logical :: spacetime
    integer(int64) :: spacetime_granules, spacetime_times
    namelist /sensors/ interval, granules, spacetime, spacetime_granules, spacetime_times
    integer :: ios
    character(len=512) :: msg
    interval = 0
    granules = nan           ! an empty list
    spacetime = .false.
    spacetime_granules = 200
    spacetime_times = 500
    read (unit, nml=sensors, iostat=ios, iomsg=msg)
    call check_read(file, unit, "sensors", ios, msg)
    sensors_interval = interval
    sensors_granules = granules
    sensors_spacetime = spacetime
    sensors_spacetime_granules = spacetime_granules
    sensors_spacetime_times = spacetime_times
  end subroutine read_sensors

  ! &fit with its table defaults, if the file has it; copied to fit_*.
  recursive subroutine read_fit(file, unit)
    character(len=*), intent(in) :: file
    integer, intent(in) :: unit
    character(len=LEN_STR) :: model, x, y, report, label, theory
    integer(int64) :: k_min, k_max
    real(c_double) :: p, factor
    namelist /fit/ model, x, y, k_min, k_max, p, report, factor, label, theory
    integer :: ios
    character(len=512) :: msg
    model = "none"
    x = "k"
    y = "v"
    k_min = 1
    k_max = 0
    p = nan                  ! no default: left out
    report = "b"
    factor = 1
    label = ""
    theory = "fit"
    read (unit, nml=fit, iostat=ios, iomsg=msg)
    call check_read(file, unit, "fit", ios, msg)
    fit_model = model
    fit_x = x
    fit_y = y
    fit_k_min = k_min
    fit_k_max = k_max
    fit_p = p
    fit_report = report
    fit_factor = factor
    fit_label = label
    fit_theory = theory
  end subroutine read_fit

  ! &table with its table defaults, if the file has it; copied to table_*.
  recursive subroutine read_table(file, unit)
    character(len=*), intent(in) :: file
    integer, intent(in) :: unit
    character(len=LEN_STR) :: name, caption
    integer(int64) :: digits
    real(c_double) :: paper_theory(MAX_SWEEP), paper_numerics(MAX_SWEEP)
    namelist /table/ name, caption, digits, paper_theory, paper_numerics
    integer :: ios
    character(len=512) :: msg
    name = ""
    caption = ""
    digits = 4
    paper_theory = nan       ! no default: empty lists
    paper_numerics = nan
    read (unit, nml=table, iostat=ios, iomsg=msg)
    call check_read(file, unit, "table", ios, msg)
    table_name = name
    table_caption = caption
    table_digits = digits
    table_paper_theory = paper_theory
    table_paper_numerics = paper_numerics
  end subroutine read_table

  ! &sweep with its table default, if the file has it; copied to sweep_mode.
  recursive subroutine read_sweep(file, unit)
    character(len=*), intent(in) :: file
    integer, intent(in) :: unit
    character(len=LEN_STR) :: mode
    namelist /sweep/ mode
    integer :: ios
    character(len=512) :: msg
    mode = "grid"
    read (unit, nml=sweep, iostat=ios, iomsg=msg)
    call check_read(file, unit, "sweep", ios, msg)
    sweep_mode = mode
  end subroutine read_sweep

  ! &figure with its table defaults, if the file has it; copied to figure_*.
  recursive subroutine read_figure(file, unit)
    character(len=*), intent(in) :: file
    integer, intent(in) :: unit
    character(len=LEN_STR) :: name, title, x, y, curves, x_label, y_label
    logical :: log_x, log_y, inset
    integer(int64) :: every, k_max
    real(c_double) :: inset_reference
    namelist /figure/ name, title, x, y, curves, log_x, log_y, every, k_max, x_label, &
         y_label, inset, inset_reference
    integer :: ios
    character(len=512) :: msg
    name = ""
    title = ""
    x = "k"
    y = "v"
    curves = "both"
    log_x = .false.
    log_y = .false.
    every = 1
    k_max = 0
    x_label = ""
    y_label = ""
    inset = .false.
    inset_reference = nan    ! no default: no line
    read (unit, nml=figure, iostat=ios, iomsg=msg)
    call check_read(file, unit, "figure", ios, msg)
    figure_name = name
    figure_title = title
    figure_x = x
    figure_y = y
    figure_curves = curves
    figure_log_x = log_x
    figure_log_y = log_y
    figure_every = every
    figure_k_max = k_max
    figure_x_label = x_label
    figure_y_label = y_label
    figure_inset = inset
    figure_inset_reference = inset_reference
  end subroutine read_figure

  ! The library's spelling of a profile, method or fit model name (any
  ! case), or str itself if the library does not know it (the run then
  ! reports the library's message).
  function library_name(str, kind) result(c)
    character(len=*), intent(in) :: str, kind
    character(len=len(str)) :: c
    type(taper_error) :: e
    integer(c_int) :: code
    c = str
    select case (kind)
    case ("profile")
       if (taper_profile_from_name(str, code, e) == TAPER_OK) c = taper_profile_name(code)
    case ("method")
       if (taper_method_from_name(str, code, e) == TAPER_OK) c = taper_method_name(code)
    case ("fit_model")
       if (taper_fit_model_from_name(str, code, e) == TAPER_OK) c = taper_fit_model_name(code)
    case ("disorder")
       if (taper_disorder_from_name(str, code, e) == TAPER_OK) c = taper_disorder_name(code)
    case ("boundary")
       if (taper_boundary_from_name(str, code, e) == TAPER_OK) c = taper_boundary_name(code)
    end select
  end function library_name

  subroutine check_length(group, name, value)
    character(len=*), intent(in) :: group, name, value
    if (len_trim(value) < len(value)) return
    write (error_unit, '(a,i0,a)') trim(path)//": &"//group//" "//name//": longer than ", &
         len(value) - 1, " characters, which taper_nml cannot hold"
    call quit(2)
  end subroutine check_length

  ! The allowed string that str spells (case-insensitive), or str itself.
  function canonical(str, choices) result(c)
    character(len=*), intent(in) :: str
    character(len=*), intent(in) :: choices(:)
    character(len=len(str)) :: c
    integer :: k
    c = str
    do k = 1, size(choices)
       if (lower(str) == lower(choices(k))) then
          c = choices(k)
          return
       end if
    end do
  end function canonical

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
       if (len(key) > 0) then
          write (error_unit, '(a)') trim(file)//":"//trim(line_text)//": &"//group//" "//key// &
               ": "//trim(msg)
       else
          write (error_unit, '(a)') trim(file)//":"//trim(line_text)//": &"//group//": "//trim(msg)
       end if
    end if
    call quit(2)
  end subroutine report_read_error

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

  ! The keys of a group, as listed in the messages.
  function group_keys(group) result(keys)
    character(len=*), intent(in) :: group
    character(len=:), allocatable :: keys
    select case (group)
    case ("chain")
       keys = KEYS_CHAIN
    case ("solver")
       keys = KEYS_SOLVER
    case ("output")
       keys = KEYS_OUTPUT
    case ("fit")
       keys = KEYS_FIT
    case ("table")
       keys = KEYS_TABLE
    case ("figure")
       keys = KEYS_FIGURE
    case ("ends")
       keys = KEYS_ENDS
    case ("striker")
       keys = KEYS_STRIKER
    case ("losses")
       keys = KEYS_LOSSES
    case ("material")
       keys = KEYS_MATERIAL
    case ("sensors")
       keys = KEYS_SENSORS
    case default
       keys = KEYS_SWEEP
    end select
  end function group_keys

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

  ! Whether the file has a header &group (or $group), as gfortran looks for
  ! one: '&' or '$' outside comments, the name in any case, then a separator.
  logical function has_group(unit, group)
    integer, intent(in) :: unit
    character(len=*), intent(in) :: group
    character(len=LEN_STR) :: line
    integer :: ios, k, n, e
    has_group = .false.
    rewind (unit)
    do
       read (unit, '(a)', iostat=ios) line
       if (ios /= 0) exit
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
          has_group = .true.
          return
       end do
    end do
  end function has_group

  ! Leading entries of a NaN-initialised namelist array that the file set.
  integer function count_given(a)
    real(c_double), intent(in) :: a(:)
    count_given = 0
    do while (count_given < size(a))
       if (.not. is_given(a(count_given + 1))) exit
       count_given = count_given + 1
    end do
  end function count_given

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

  subroutine print_real(name, x)
    character(len=*), intent(in) :: name
    real(c_double), intent(in) :: x
    write (output_unit, '(a)', advance="no") name//" ="
    call print_bits(x)
    write (output_unit, '()')
  end subroutine print_real

  ! A real without a default: nothing after " =" when left out (NaN).
  subroutine print_optional(name, x)
    character(len=*), intent(in) :: name
    real(c_double), intent(in) :: x
    write (output_unit, '(a)', advance="no") name//" ="
    if (is_given(x)) call print_bits(x)
    write (output_unit, '()')
  end subroutine print_optional

  subroutine print_list(name, a, n)
    character(len=*), intent(in) :: name
    real(c_double), intent(in) :: a(:)
    integer, intent(in) :: n
    integer :: k
    write (output_unit, '(a,1x,i0)', advance="no") name//" =", n
    do k = 1, n
       call print_bits(a(k))
    end do
    write (output_unit, '()')
  end subroutine print_list

  ! The canonical form of tests/bindings/scene_dump.c, in the order of the table.
  subroutine print_dump()
    write (output_unit, '(a)') "chain.profile = "//trim(profile)
    write (output_unit, '(a,i0)') "chain.n_granules = ", n_granules
    call print_list("chain.s", s, n_s)
    call print_list("chain.q", q, n_q)
    call print_real("chain.exponent", exponent)
    ! the radii a radii_file gave are not the scene's list (scene_dump echoes neither)
    call print_list("chain.radii", radii, merge(0, n_radii, len_trim(radii_file) > 0))
    write (output_unit, '(a)') "chain.radii_file = "//trim(radii_file)
    call print_list("chain.pattern", pattern, n_pattern)
    write (output_unit, '(a)') "chain.disorder = "//trim(disorder)
    call print_real("chain.disorder_amplitude", disorder_amplitude)
    write (output_unit, '(a,i0)') "chain.seed = ", seed(1)   ! a list: its first, as scene_dump
    call print_real("chain.load", load)
    write (output_unit, '(a)') "ends.left = "//trim(ends_left)
    write (output_unit, '(a)') "ends.right = "//trim(ends_right)
    call print_real("ends.left_compliance", ends_left_compliance)
    call print_real("ends.right_compliance", ends_right_compliance)
    call print_real("striker.radius", striker_radius)
    call print_real("striker.density", striker_density)
    call print_real("striker.compliance", striker_compliance)
    write (output_unit, '(a)') "striker.piston = "//trim(striker_piston)
    call print_real("striker.piston_duration", striker_piston_duration)
    call print_real("striker.piston_compliance", striker_piston_compliance)
    call print_real("losses.damping", losses_damping)
    call print_real("losses.drag", losses_drag)
    call print_optional("material.young", material_young)
    call print_optional("material.poisson", material_poisson)
    call print_optional("material.density", material_density)
    call print_optional("material.radius", material_radius)
    call print_optional("material.velocity", material_velocity)
    call print_list("material.other_young", material_other_young, count_given(material_other_young))
    call print_list("material.other_poisson", material_other_poisson, &
         count_given(material_other_poisson))
    call print_list("material.other_density", material_other_density, &
         count_given(material_other_density))
    call print_list("material.sequence", material_sequence, count_given(material_sequence))
    write (output_unit, '(a,i0)') "material.wall = ", material_wall
    write (output_unit, '(a,i0)') "material.striker = ", material_striker
    write (output_unit, '(a)') "solver.method = "//trim(method)
    call print_real("solver.rtol", rtol)
    call print_real("solver.atol", atol)
    write (output_unit, '(a,l1)') "solver.window = ", window
    write (output_unit, '(a,i0)') "solver.last_granule = ", last_granule
    call print_real("solver.t_max", t_max)
    write (output_unit, '(a,i0)') "solver.max_steps = ", max_steps
    call print_real("solver.t_end", t_end)
    write (output_unit, '(a,l1)') "solver.numerics = ", numerics
    call print_real("sensors.interval", sensors_interval)
    call print_list("sensors.granules", sensors_granules, count_given(sensors_granules))
    write (output_unit, '(a,l1)') "sensors.spacetime = ", sensors_spacetime
    write (output_unit, '(a,i0)') "sensors.spacetime_granules = ", sensors_spacetime_granules
    write (output_unit, '(a,i0)') "sensors.spacetime_times = ", sensors_spacetime_times
    write (output_unit, '(a)') "output.dir = "//trim(dir)
    write (output_unit, '(a,l1)') "output.progress = ", progress
    write (output_unit, '(a,i0)') "output.threads = ", threads
    write (output_unit, '(a)') "output.columns = "//trim(columns)
    write (output_unit, '(a,i0)') "output.every = ", every
    call print_real("output.max_energy_error", max_energy_error)
    call print_real("output.max_momentum_error", max_momentum_error)
    write (output_unit, '(a)') "output.units = "//trim(units)
    write (output_unit, '(a)') "fit.model = "//trim(fit_model)
    write (output_unit, '(a)') "fit.x = "//trim(fit_x)
    write (output_unit, '(a)') "fit.y = "//trim(fit_y)
    write (output_unit, '(a,i0)') "fit.k_min = ", fit_k_min
    write (output_unit, '(a,i0)') "fit.k_max = ", fit_k_max
    call print_optional("fit.p", fit_p)
    write (output_unit, '(a)') "fit.report = "//trim(fit_report)
    call print_real("fit.factor", fit_factor)
    write (output_unit, '(a)') "fit.label = "//trim(fit_label)
    write (output_unit, '(a)') "fit.theory = "//trim(fit_theory)
    write (output_unit, '(a)') "table.name = "//trim(table_name)
    write (output_unit, '(a)') "table.caption = "//trim(table_caption)
    write (output_unit, '(a,i0)') "table.digits = ", table_digits
    call print_list("table.paper_theory", table_paper_theory, count_given(table_paper_theory))
    call print_list("table.paper_numerics", table_paper_numerics, &
         count_given(table_paper_numerics))
    write (output_unit, '(a)') "figure.name = "//trim(figure_name)
    write (output_unit, '(a)') "figure.title = "//trim(figure_title)
    write (output_unit, '(a)') "figure.x = "//trim(figure_x)
    write (output_unit, '(a)') "figure.y = "//trim(figure_y)
    write (output_unit, '(a)') "figure.curves = "//trim(figure_curves)
    write (output_unit, '(a,l1)') "figure.log_x = ", figure_log_x
    write (output_unit, '(a,l1)') "figure.log_y = ", figure_log_y
    write (output_unit, '(a,i0)') "figure.every = ", figure_every
    write (output_unit, '(a,i0)') "figure.k_max = ", figure_k_max
    write (output_unit, '(a)') "figure.x_label = "//trim(figure_x_label)
    write (output_unit, '(a)') "figure.y_label = "//trim(figure_y_label)
    write (output_unit, '(a,l1)') "figure.inset = ", figure_inset
    call print_optional("figure.inset_reference", figure_inset_reference)
    write (output_unit, '(a)') "sweep.mode = "//trim(sweep_mode)
  end subroutine print_dump

  ! A library refusal, as the C driver reports it: the file, the group and
  ! the variable the library names (every setter is named as its scene
  ! variable), then the library's message.
  subroutine report(group, e)
    character(len=*), intent(in) :: group
    type(taper_error), intent(in) :: e
    if (len(taper_field(e)) > 0) then
       write (error_unit, '(a)') trim(path)//": &"//group//" "//taper_field(e)//": "// &
            taper_message(e)
    else
       write (error_unit, '(a)') trim(path)//": "//taper_message(e)
    end if
  end subroutine report

  ! A count of the scene as the library's size_t: a negative one cannot be
  ! passed (it would wrap around), so it is refused here, naming it.
  logical function count_ok(group, name, value)
    character(len=*), intent(in) :: group, name
    integer(int64), intent(in) :: value
    count_ok = value >= 0
    if (.not. count_ok) write (error_unit, '(a,i0,a)') trim(path)//": &"//group//" "//name// &
         ": ", value, " is negative"
  end function count_ok

  ! The chain of sweep point (is, iq), built through the setters; c_null_ptr
  ! after reporting why not.  (One call per statement: Fortran may skip a
  ! function reference in a logical expression whose value is known.)
  function make_chain(is, iq, iseed) result(c)
    integer, intent(in) :: is, iq, iseed
    type(c_ptr) :: c, cs
    type(taper_error) :: e
    integer(c_int) :: p, st, d, b
    c = c_null_ptr
    if (.not. count_ok("chain", "n_granules", n_granules)) return
    cs = taper_chain_spec_alloc(e)
    if (.not. c_associated(cs)) then
       call report("chain", e)
       return
    end if
    st = taper_profile_from_name(profile, p, e)
    if (st == TAPER_OK) st = taper_chain_spec_set_profile(cs, p, e)
    if (st == TAPER_OK) st = taper_chain_spec_set_n_granules(cs, int(n_granules, c_size_t), e)
    if (st == TAPER_OK) st = taper_chain_spec_set_s(cs, s(is), e)
    if (st == TAPER_OK) st = taper_chain_spec_set_q(cs, q(iq), e)
    if (st == TAPER_OK) st = taper_chain_spec_set_exponent(cs, exponent, e)
    if (st == TAPER_OK .and. n_radii > 0) &
         st = taper_chain_spec_set_radii(cs, c_loc(radii(1)), int(n_radii, c_size_t), e)
    ! Beyond the paper (issue 15): each through its setter, defaults the library's.
    if (st == TAPER_OK .and. n_pattern > 0) &
         st = taper_chain_spec_set_pattern(cs, c_loc(pattern(1)), int(n_pattern, c_size_t), e)
    if (st == TAPER_OK) st = taper_disorder_from_name(disorder, d, e)
    if (st == TAPER_OK) st = taper_chain_spec_set_disorder(cs, d, disorder_amplitude, &
         int(seed(iseed), c_int64_t), e)
    if (st == TAPER_OK) st = taper_chain_spec_set_load(cs, load, e)
    if (st == TAPER_OK) st = taper_boundary_from_name(ends_left, b, e)
    if (st == TAPER_OK) st = taper_chain_spec_set_end(cs, TAPER_LEFT, b, ends_left_compliance, e)
    if (st == TAPER_OK) st = taper_boundary_from_name(ends_right, b, e)
    if (st == TAPER_OK) st = taper_chain_spec_set_end(cs, TAPER_RIGHT, b, ends_right_compliance, e)
    if (st == TAPER_OK) st = taper_chain_spec_set_striker(cs, striker_radius, striker_density, &
         striker_compliance, e)
    ! piston 'steady': an infinite duration; 'none': the duration given,
    ! so that one without a piston is refused by name (the C driver's rule)
    if (st == TAPER_OK) then
       select case (trim(striker_piston))
       case ("steady")
          st = taper_chain_spec_set_piston(cs, ieee_value(1.0_c_double, ieee_positive_inf), &
               striker_piston_compliance, e)
       case ("push")
          st = taper_chain_spec_set_piston(cs, striker_piston_duration, &
               striker_piston_compliance, e)
       case default
          st = taper_chain_spec_set_piston(cs, 0.0_c_double, striker_piston_compliance, e)
       end select
    end if
    if (st == TAPER_OK) st = taper_chain_spec_set_damping(cs, losses_damping, e)
    if (st == TAPER_OK) st = taper_chain_spec_set_drag(cs, losses_drag, e)
    if (st == TAPER_OK) c = taper_chain_alloc(cs, e)
    if (.not. c_associated(c)) call report_chain(e)
    call taper_chain_spec_free(cs)
  end function make_chain

  ! A refusal of a chain setting under the group and key of the scene that
  ! holds it (the library names its setters: left_end is &ends left, ...).
  subroutine report_chain(e)
    type(taper_error), intent(in) :: e
    character(len=:), allocatable :: field
    field = taper_field(e)
    select case (field)
    case ("left_end", "right_end", "left_wall_compliance", "right_wall_compliance")
       if (field(1:4) == "left") then
          field = "left"//merge("_compliance", "           ", index(field, "wall") > 0)
       else
          field = "right"//merge("_compliance", "           ", index(field, "wall") > 0)
       end if
       write (error_unit, '(a)') trim(path)//": &ends "//trim(field)//": "//taper_message(e)
    case ("striker_radius", "striker_density", "striker_compliance")
       write (error_unit, '(a)') trim(path)//": &striker "//field(9:)//": "//taper_message(e)
    case ("piston_duration", "piston_compliance")
       write (error_unit, '(a)') trim(path)//": &striker "//field//": "//taper_message(e)
    case ("damping", "drag")
       write (error_unit, '(a)') trim(path)//": &losses "//field//": "//taper_message(e)
    case default
       call report("chain", e)
    end select
  end subroutine report_chain

  ! What the C driver does with a scene and taper_nml does not: real units
  ! and mixed materials (&material), refused before any run, naming the
  ! group, rather than run as something else; a scene's sampled time series
  ! (&sensors) are not written (said on stderr; the pass times are the same
  ! to rounding).  (--dump reads and prints them all.)
  logical function runnable()
    runnable = .false.
    if (is_given(material_young) .or. is_given(material_poisson) .or. &
         is_given(material_density) .or. is_given(material_radius) .or. &
         is_given(material_velocity) .or. count_given(material_sequence) > 0 .or. &
         count_given(material_other_young) > 0 .or. lower(units) == "si") then
       write (error_unit, '(a)') trim(path)//": &material: taper_nml runs in rescaled units "// &
            "with one material only; run the scene with taper"
    else
       ! Sampling does not stop the run (CVODE interpolates at the sample
       ! times): the pass times and peaks are the same to rounding (1e-14).
       if (sensors_interval > 0 .or. sensors_spacetime) write (error_unit, '(a)') trim(path)// &
            ": &sensors: not written by taper_nml (taper writes the time series); "// &
            "the pass times are the same"
       runnable = .true.
    end if
  end function runnable

  ! The solver settings of the scene through the setters; c_null_ptr after
  ! reporting why not.
  function make_solver() result(ss)
    type(c_ptr) :: ss
    type(taper_error) :: e
    integer(c_int) :: m, st
    ss = c_null_ptr
    if (.not. count_ok("solver", "last_granule", last_granule)) return
    ss = taper_solver_spec_alloc(e)
    if (.not. c_associated(ss)) then
       call report("solver", e)
       return
    end if
    st = taper_method_from_name(method, m, e)
    if (st == TAPER_OK) st = taper_solver_spec_set_method(ss, m, e)
    if (st == TAPER_OK) st = taper_solver_spec_set_rtol(ss, rtol, e)
    if (st == TAPER_OK) st = taper_solver_spec_set_atol(ss, atol, e)
    if (st == TAPER_OK) st = taper_solver_spec_set_window(ss, merge(1_c_int, 0_c_int, window), e)
    if (st == TAPER_OK) &
         st = taper_solver_spec_set_last_granule(ss, int(last_granule, c_size_t), e)
    if (st == TAPER_OK) st = taper_solver_spec_set_t_max(ss, t_max, e)
    if (st == TAPER_OK) st = taper_solver_spec_set_max_steps(ss, int(max_steps, c_long), e)
    if (st == TAPER_OK) st = taper_solver_spec_set_t_end(ss, t_end, e)
    if (st /= TAPER_OK) then
       call report("solver", e)
       call taper_solver_spec_free(ss)
       ss = c_null_ptr
    end if
  end function make_solver

  ! One point of the scene: chain, dynamics (with the theory the sim computes
  ! once) or the theory alone; 0, 1 (failure), 2 (bad input) or 3 (partial).
  integer function run_point(is, iq, iseed) result(rc)
    integer, intent(in) :: is, iq, iseed
    type(taper_error) :: e
    type(c_ptr) :: c, ss, sim
    real(c_double), allocatable, target :: v_buf(:), t_buf(:)
    real(c_double), pointer :: t_pass(:), v_peak(:), v_th(:), t_th(:)
    integer(c_int) :: st
    integer(c_size_t) :: n, k, step

    rc = 0
    c = make_chain(is, iq, iseed)
    if (.not. c_associated(c)) then
       rc = 2
       return
    end if
    n = taper_chain_size(c)
    sim = c_null_ptr
    if (numerics) then
       ss = make_solver()
       if (.not. c_associated(ss)) then
          call taper_chain_free(c)
          rc = 2
          return
       end if
       sim = taper_sim_alloc(c, ss, e)
       call taper_solver_spec_free(ss)
       if (.not. c_associated(sim)) then
          call report("solver", e)
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
          call report("chain", e)
          call taper_chain_free(c)
          rc = 1
          return
       end if
       v_th => v_buf
       t_th => t_buf
       t_pass => t_buf   ! not printed without numerics; associated all the same
       v_peak => v_buf
    end if

    write (output_unit, '(5a,i0,3(a,g0.6))') "# ", trim(path), ": ", &
         taper_profile_name(taper_chain_profile(c)), " N = ", n, "  s = ", s(is), "  q = ", q(iq), &
         "  n = ", taper_chain_exponent(c)
    if (numerics) then
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
       if (numerics) then
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
    if (numerics) then
       write (output_unit, '(a,i0,a,es9.2,a,l1)') "# steps ", &
            int(taper_sim_statistic(sim, TAPER_STAT_STEPS), int64), "  energy error ", &
            taper_sim_statistic(sim, TAPER_STAT_ENERGY_ERROR), "  complete ", &
            taper_sim_statistic(sim, TAPER_STAT_COMPLETE) > 0.5_c_double  ! 0 or 1
       call taper_sim_free(sim)
    end if
    call taper_chain_free(c)
  end function run_point

end program taper_nml
