! SPDX-License-Identifier: GPL-3.0-or-later
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
! The variables are not written by hand.  Their declarations, each group's
! NAMELIST and READ, the defaults of the scene's own variables, the checks
! of what READ gave, --dump and the calls that hand each chain and solver
! value to the library are generated at build time from the scene's table
! (drivers/scenes/scene/scene.c) and the library's table of settings by
! gen_namelists.c, as the module taper_nml_scene: a new setting of the
! library is a new variable of taper_nml at the next build.  What is
! written here is the scene's own rules (a radii file, the piston's 'push'
! and 'steady', a custom chain's number of granules, &output units with
! &material) and the runs; taper_nml_base.f90 holds what both share (the
! marks of a value left out, the library's defaults, the messages of a
! failed READ).
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
  use taper_nml_base
  use taper_nml_scene    ! generated: sv, GROUPS, read_group, check_values, print_dump, ...
  implicit none

  ! At most this many runs in one scene (SCENE_MAX_RUNS of the C scene).
  integer(int64), parameter :: MAX_RUNS = 10000000_int64

  type(real_values) :: file_radii      ! the radii a radii_file holds (not the scene's list)
  character(len=LEN_STR) :: arg
  logical :: dump
  integer :: lens(N_SWEEPABLE), ix(N_SWEEPABLE)
  integer :: i, status, worst, arg_status
  integer(int64) :: n_runs, run

  dump = .false.
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

  ! Main-program variables are implicitly SAVE'd: never deallocated for us
  ! (LeakSanitizer and valgrind report them once MAIN__ has returned).
  subroutine release()
    if (allocated(sv)) deallocate (sv)
    if (allocated(file_radii%v)) deallocate (file_radii%v)
  end subroutine release

  ! ---- the scene's own rules ---------------------------------------------------------

  ! Whether the file gave the variable of this keyword.
  logical function was_given(keyword)
    character(len=*), intent(in) :: keyword
    integer :: k
    k = var_index(keyword)
    was_given = .false.
    if (k > 0) was_given = given(k)
  end function was_given

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

  ! &material is on when one of the five variables that set the units is
  ! given (the C scene's rule).
  logical function material_on()
    material_on = was_given("young") .or. was_given("poisson") .or. was_given("density") .or. &
         was_given("radius") .or. was_given("velocity")
  end function material_on

  ! &chain radii_file as the C parser reads it (drivers/scenes/scene/
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
