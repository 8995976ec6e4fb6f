! taper_nml -- run a taper scene file with Fortran's own namelist READ.
!
!   taper_nml SCENE.nml           run it: t_pass and v_peak next to the theory
!   taper_nml --dump SCENE.nml    print the resolved values (canonical form of
!                                 tests/scene_dump.c) and stop
!
! Our scene files (share/scenes/*.nml, docs/scene.md) are standard Fortran
! namelists with the groups &chain, &solver and &output; this program reads
! them with READ(unit, NML=...) and hands the values to libtaper through the
! iso_c_binding module `taper` (share/fortran/taper.f90).  The variables and
! their defaults are those of the table in src/scene.c; the solver defaults
! come from the library itself (taper_solver_spec_init), as in the C driver.
! A list of values for s or q is a sweep: each value is run in turn.  Other
! groups of a scene (&fit, &table, &figure: the C driver's analysis) are
! skipped by the namelist READ, as Fortran does for groups it is not asked for.
!
! Exit status: 0 complete, 1 library failure, 2 bad input, 3 partial result.
program taper_nml
  use, intrinsic :: iso_c_binding
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_is_nan
  use, intrinsic :: iso_fortran_env, only: error_unit, output_unit, int64
  use taper
  implicit none

  integer, parameter :: MAX_SWEEP = 1000, MAX_RADII = 1000000, LEN_STR = 1024

  ! &chain
  character(len=LEN_STR) :: profile
  integer(int64) :: n_granules
  real(c_double) :: s(MAX_SWEEP), q(MAX_SWEEP), exponent
  real(c_double), allocatable, target :: radii(:)
  ! &solver
  character(len=LEN_STR) :: method
  real(c_double) :: rtol, atol, t_max
  logical :: window, numerics
  integer(int64) :: last_granule, max_steps
  ! &output
  character(len=LEN_STR) :: dir
  logical :: progress
  integer(int64) :: threads      ! parallel sweeps of the C driver; unused here

  namelist /chain/ profile, n_granules, s, q, exponent, radii
  namelist /solver/ method, rtol, atol, window, last_granule, t_max, max_steps, numerics
  namelist /output/ dir, progress, threads

  character(len=LEN_STR) :: path, arg
  logical :: dump, n_given
  integer :: n_s, n_q, n_radii, n_sweep, i, status, worst
  real(c_double) :: nan
  type(taper_solver_spec) :: defaults

  dump = .false.
  path = ""
  do i = 1, command_argument_count()
     call get_command_argument(i, arg)
     if (arg == "--dump") then
        dump = .true.
     else if (arg == "-h" .or. arg == "--help") then
        write (output_unit, '(a)') "usage: taper_nml [--dump] SCENE.nml"
        stop
     else
        path = arg
     end if
  end do
  if (path == "") then
     write (error_unit, '(a)') "usage: taper_nml [--dump] SCENE.nml"
     error stop 2
  end if

  ! Defaults: the table of src/scene.c; solver defaults from the library.
  nan = ieee_value(nan, ieee_quiet_nan)
  call taper_solver_spec_init(defaults)
  profile = "monodisperse"
  n_granules = -1            ! not given: 100, or the number of radii
  s = nan
  q = nan
  exponent = 2.5_c_double
  allocate (radii(MAX_RADII))
  radii = nan
  method = merge("bdf  ", "adams", defaults%method == TAPER_BDF)
  rtol = defaults%rtol
  atol = defaults%atol
  window = defaults%window /= 0
  last_granule = 0
  t_max = 0
  max_steps = 0
  numerics = .true.
  dir = default_dir(path)
  progress = .true.
  threads = 0

  call read_scene(path)

  ! Resolve: a sweep is the list given; nothing given is the default 0.
  n_s = count_given(s)
  n_q = count_given(q)
  n_radii = count_given(radii)
  if (n_s == 0) then
     s(1) = 0
     n_s = 1
  end if
  if (n_q == 0) then
     q(1) = 0
     n_q = 1
  end if
  n_given = n_granules >= 0
  if (.not. n_given) n_granules = 100
  if (lower(profile) == "custom" .and. n_radii > 0) then
     if (n_given .and. n_granules /= n_radii) then
        write (error_unit, '(a,i0,a,i0,a)') trim(path)//": n_granules = ", n_granules, &
             " but ", n_radii, " radii are given"
        error stop 2
     end if
     n_granules = n_radii
  end if
  if (n_s > 1 .and. n_q > 1) then
     write (error_unit, '(a)') trim(path)//": only one of s and q may be swept"
     error stop 2
  end if

  if (dump) then
     call print_dump()
     stop
  end if

  n_sweep = max(n_s, n_q)
  worst = 0
  do i = 1, n_sweep
     status = run_point(min(i, n_s), min(i, n_q))
     worst = max(worst, status)
  end do
  select case (worst)   ! F2008: STOP codes are constants
  case (1)
     error stop 1
  case (2)
     error stop 2
  case (3)
     error stop 3
  end select

contains

  subroutine read_scene(file)
    character(len=*), intent(in) :: file
    integer :: unit, ios
    character(len=512) :: msg
    open (newunit=unit, file=file, status="old", action="read", iostat=ios, iomsg=msg)
    if (ios /= 0) then
       write (error_unit, '(a)') trim(file)//": "//trim(msg)
       error stop 2
    end if
    ! Each group is optional: rewind and look for it; end of file = absent.
    read (unit, nml=chain, iostat=ios, iomsg=msg)
    call check_read(file, "chain", ios, msg)
    rewind (unit)
    read (unit, nml=solver, iostat=ios, iomsg=msg)
    call check_read(file, "solver", ios, msg)
    rewind (unit)
    read (unit, nml=output, iostat=ios, iomsg=msg)
    call check_read(file, "output", ios, msg)
    close (unit)
  end subroutine read_scene

  subroutine check_read(file, group, ios, msg)
    character(len=*), intent(in) :: file, group, msg
    integer, intent(in) :: ios
    if (ios > 0) then
       write (error_unit, '(a)') trim(file)//": &"//group//": "//trim(msg)
       error stop 2
    end if
  end subroutine check_read

  ! Leading entries of a NaN-initialised namelist array that the file set.
  integer function count_given(a)
    real(c_double), intent(in) :: a(:)
    count_given = 0
    do while (count_given < size(a))
       if (ieee_is_nan(a(count_given + 1))) exit
       count_given = count_given + 1
    end do
  end function count_given

  ! out/NAME for scene file .../NAME.nml (src/scene.c: derived_dir).
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

  ! The canonical form of tests/scene_dump.c, in the order of the table.
  subroutine print_dump()
    write (output_unit, '(a)') "chain.profile = "//trim(profile)
    write (output_unit, '(a,i0)') "chain.n_granules = ", n_granules
    call print_list("chain.s", s, n_s)
    call print_list("chain.q", q, n_q)
    call print_real("chain.exponent", exponent)
    call print_list("chain.radii", radii, n_radii)
    write (output_unit, '(a)') "solver.method = "//trim(method)
    call print_real("solver.rtol", rtol)
    call print_real("solver.atol", atol)
    write (output_unit, '(a,l1)') "solver.window = ", window
    write (output_unit, '(a,i0)') "solver.last_granule = ", last_granule
    call print_real("solver.t_max", t_max)
    write (output_unit, '(a,i0)') "solver.max_steps = ", max_steps
    write (output_unit, '(a,l1)') "solver.numerics = ", numerics
    write (output_unit, '(a)') "output.dir = "//trim(dir)
    write (output_unit, '(a,l1)') "output.progress = ", progress
    write (output_unit, '(a,i0)') "output.threads = ", threads
  end subroutine print_dump

  ! One point of the scene: chain, theory, dynamics; 0, 1 (failure) or 3 (partial).
  integer function run_point(is, iq) result(rc)
    integer, intent(in) :: is, iq
    type(taper_chain_spec) :: cs
    type(taper_solver_spec) :: ss
    type(taper_error) :: err
    type(c_ptr) :: c, sim
    real(c_double), allocatable, target :: v_th(:), t_th(:)
    real(c_double), pointer :: t_pass(:), v_peak(:)
    integer(c_int) :: p, st
    integer(c_size_t) :: n, k, step
    type(taper_stats) :: stats

    rc = 0
    call taper_chain_spec_init(cs)
    if (taper_profile_from_name(profile, p) /= TAPER_OK) then
       write (error_unit, '(a)') trim(path)//": &chain profile: unknown '"//trim(profile)//"'"
       rc = 2
       return
    end if
    cs%profile = p
    cs%n_granules = int(n_granules, c_size_t)
    cs%s = s(is)
    cs%q = q(iq)
    cs%exponent = exponent
    if (p == TAPER_CUSTOM .and. n_radii > 0) cs%radii = c_loc(radii(1))
    c = taper_chain_alloc(cs, err)
    if (.not. c_associated(c)) then
       write (error_unit, '(a)') trim(path)//": "//taper_message(err)
       rc = 2
       return
    end if
    n = taper_chain_size(c)
    allocate (v_th(n), t_th(n))
    if (taper_theory_compute(c, c_loc(v_th), c_null_ptr, c_null_ptr, c_loc(t_th), err) &
         /= TAPER_OK) then
       write (error_unit, '(a)') trim(path)//": theory: "//taper_message(err)
       call taper_chain_free(c)
       rc = 1
       return
    end if

    write (output_unit, '(5a,i0,3(a,g0.6))') "# ", trim(path), ": ", &
         taper_profile_name(p), " N = ", n, "  s = ", cs%s, "  q = ", cs%q, "  n = ", exponent
    sim = c_null_ptr
    if (numerics) then
       call taper_solver_spec_init(ss)
       ss%method = merge(TAPER_BDF, TAPER_ADAMS, lower(method) == "bdf")
       ss%rtol = rtol
       ss%atol = atol
       ss%window = merge(1, 0, window)
       ss%last_granule = int(last_granule, c_size_t)
       ss%t_max = t_max
       ss%max_steps = int(max_steps, c_long)
       sim = taper_sim_alloc(c, ss, err)
       if (.not. c_associated(sim)) then
          write (error_unit, '(a)') trim(path)//": "//taper_message(err)
          call taper_chain_free(c)
          rc = 2
          return
       end if
       st = taper_sim_run(sim, err)
       if (st /= TAPER_OK) then
          write (error_unit, '(a)') trim(path)//": "//taper_message(err)
          rc = merge(1, 3, st == TAPER_EINVAL .or. st == TAPER_ENOMEM)
       end if
       t_pass => taper_observable(sim, c, TAPER_T_PASS)
       v_peak => taper_observable(sim, c, TAPER_V_PEAK)
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
       call taper_sim_stats(sim, stats)
       write (output_unit, '(a,i0,a,es9.2,a,l1)') "# steps ", stats%steps, "  energy error ", &
            stats%energy_error, "  complete ", stats%complete /= 0
       call taper_sim_free(sim)
    end if
    call taper_chain_free(c)
  end function run_point

end program taper_nml
