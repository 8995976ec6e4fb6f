! test_fortran_abi -- the Fortran module src/bindings/fortran/taper.f90
! against the library: the two bind(C) derived types it declares
! (taper_error, taper_progress) have the size and field offsets of the C
! structs (asked of the C compiler in fortran_abi.c); every other object is
! opaque, set and read through the interfaces, which are exercised here: the
! name lists, setters (a refusal names its setting and leaves the spec as
! it was), a run with a monitor written in Fortran, statistics by name, the
! sim's theory, taper_dynamics and a fit; every enum constant against the
! header's (fortran_abi.c); and issue 15's options: a right wall with t_end
! and a sampler written in Fortran (31 samples at t = 0..30), the wall's
! statistics, taper_sim_forces, taper_unit_scale and the new names.
module test_fortran_abi_monitor
  use, intrinsic :: iso_c_binding
  use taper, only: taper_progress
  implicit none
  integer, save :: calls = 0, samples = 0
  integer(c_size_t), save :: last_granule_seen = 0
  real(c_double), save :: last_sample_t = -1
contains
  ! A sampler: counts the samples and checks that the sim is at its time.
  function count_samples(sim, user) bind(C) result(stop)
    use taper, only: taper_sim_time
    type(c_ptr), value :: sim, user
    integer(c_int) :: stop
    if (c_associated(user)) continue
    samples = samples + 1
    last_sample_t = taper_sim_time(sim)
    stop = 0
  end function count_samples
  ! Stops the run at the third pulse event.
  function stop_at_third(progress, user) bind(C) result(stop)
    type(taper_progress), intent(in) :: progress
    type(c_ptr), value :: user
    integer(c_int) :: stop
    if (c_associated(user)) continue
    calls = calls + 1
    last_granule_seen = progress%granule
    stop = merge(1_c_int, 0_c_int, calls >= 3)
  end function stop_at_third
end module test_fortran_abi_monitor

program test_fortran_abi
  use, intrinsic :: iso_c_binding
  use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
  use taper
  use test_fortran_abi_monitor
  implicit none
  interface
     function layout(type, field) bind(C, name="taper_test_layout") result(n)
       import :: c_int, c_size_t
       integer(c_int), value :: type, field
       integer(c_size_t) :: n
     end function layout
     function c_enum(i) bind(C, name="taper_test_enum") result(v)
       import :: c_int, c_long
       integer(c_int), value :: i
       integer(c_long) :: v
     end function c_enum
     function c_n_enums() bind(C, name="taper_test_n_enums") result(n)
       import :: c_int
       integer(c_int) :: n
     end function c_n_enums
  end interface
  ! The module's constants in the order of fortran_abi.c's list of the C values.
  integer(c_long), parameter :: ENUMS(*) = [integer(c_long) :: &
       TAPER_MONODISPERSE, TAPER_BACKWARD_LINEAR, TAPER_FORWARD_LINEAR, TAPER_BACKWARD_EXPONENTIAL, &
       TAPER_FORWARD_EXPONENTIAL, TAPER_CUSTOM, TAPER_DECORATED, TAPER_N_PROFILES, &
       TAPER_DISORDER_RADIUS, TAPER_DISORDER_MASS, TAPER_N_DISORDERS, &
       TAPER_LEFT, TAPER_RIGHT, TAPER_N_ENDS, TAPER_END_FREE, TAPER_END_WALL, TAPER_N_BOUNDARIES, &
       TAPER_DIM_LENGTH, TAPER_DIM_TIME, TAPER_DIM_VELOCITY, TAPER_DIM_MASS, TAPER_DIM_FORCE, &
       TAPER_DIM_ENERGY, TAPER_DIM_IMPULSE, TAPER_N_DIMENSIONS, &
       TAPER_ADAMS, TAPER_BDF, TAPER_N_METHODS, &
       TAPER_T_PASS, TAPER_T_RES, TAPER_V_PEAK, TAPER_T_PEAK, TAPER_X_PASS, TAPER_N_OBSERVABLES, &
       TAPER_THEORY_V, TAPER_THEORY_MU, TAPER_THEORY_T_RES, TAPER_THEORY_T, &
       TAPER_N_THEORY_QUANTITIES, &
       TAPER_STAT_STEPS, TAPER_STAT_RHS_EVALS, TAPER_STAT_ROOT_EVALS, TAPER_STAT_JAC_EVALS, &
       TAPER_STAT_NONLIN_ITERS, TAPER_STAT_ERR_TEST_FAILS, TAPER_STAT_WINDOW_CHANGES, &
       TAPER_STAT_RESTARTS, TAPER_STAT_MAX_WINDOW, TAPER_STAT_GRANULE_REACHED, TAPER_STAT_T_FINAL, &
       TAPER_STAT_ENERGY_ERROR, TAPER_STAT_MOMENTUM_ERROR, TAPER_STAT_COMPLETE, &
       TAPER_STAT_ENERGY_INITIAL, TAPER_STAT_ENERGY_DISSIPATED, TAPER_STAT_ENERGY_TRANSMITTED, &
       TAPER_STAT_ENERGY_REFLECTED, TAPER_STAT_ENERGY_IN_CHAIN, TAPER_STAT_WALL_PEAK_FORCE_LEFT, &
       TAPER_STAT_WALL_PEAK_TIME_LEFT, TAPER_STAT_WALL_IMPULSE_LEFT, &
       TAPER_STAT_WALL_PEAK_FORCE_RIGHT, TAPER_STAT_WALL_PEAK_TIME_RIGHT, &
       TAPER_STAT_WALL_IMPULSE_RIGHT, TAPER_N_STATISTICS, &
       TAPER_FIT_POWER, TAPER_FIT_EXPONENTIAL, TAPER_FIT_DIVERGENCE_B, TAPER_FIT_DIVERGENCE_C, &
       TAPER_FIT_DIVERGENCE_M, TAPER_N_FIT_MODELS, &
       TAPER_OK, TAPER_EINVAL, TAPER_ENOMEM, TAPER_ERANGE, TAPER_ESOLVER, TAPER_EINTERRUPTED, &
       TAPER_ELIMIT, int(TAPER_MESSAGE_SIZE, c_long), TAPER_N_GRANULES_MIN, TAPER_N_GRANULES_MAX, &
       TAPER_MAX_ORDER_ADAMS, TAPER_MAX_ORDER_BDF]
  type(taper_error), target :: e
  type(taper_progress), target :: pr
  type(c_ptr) :: cs, ss, chain, sim, dyn, fs, fr, wchain, wsim
  real(c_double), allocatable :: force(:)
  real(c_double) :: x1, x2
  real(c_double), pointer :: t_pass(:), radius(:), t_th(:)
  real(c_double), allocatable :: y(:), ydot(:)
  real(c_double) :: energy, momentum
  real(c_double) :: x(4) = [1d0, 2d0, 4d0, 8d0], yf(4) = [1d0, 0.25d0, 0.0625d0, 0.015625d0]
  integer :: fails, i
  integer(c_int) :: status, p

  fails = 0
  call same(0, "taper_error", c_sizeof(e), [off(c_loc(e%status), c_loc(e)), &
       off(c_loc(e%field), c_loc(e)), off(c_loc(e%message), c_loc(e))])
  call same(1, "taper_progress", c_sizeof(pr), [off(c_loc(pr%granule), c_loc(pr)), &
       off(c_loc(pr%target), c_loc(pr)), off(c_loc(pr%t), c_loc(pr)), off(c_loc(pr%steps), c_loc(pr)), &
       off(c_loc(pr%window_lo), c_loc(pr)), off(c_loc(pr%window_hi), c_loc(pr))])

  ! Every enum value and count of the module is the header's.
  if (c_n_enums() /= size(ENUMS)) call fail("fortran_abi.c and ENUMS list different constants")
  do i = 1, min(size(ENUMS), int(c_n_enums()))
     if (ENUMS(i) /= c_enum(int(i - 1, c_int))) then
        print '(a,i0,a,i0,a,i0)', "FAIL: constant ", i, " of ENUMS is ", ENUMS(i), " in the module, ", &
             c_enum(int(i - 1, c_int)), " in taper.h"
        fails = fails + 1
     end if
  end do

  ! The library's names: each list ends in '' (NULL), and reads back.
  if (taper_version() /= TAPER_VERSION_STRING) call fail("version "//taper_version())
  ! (One impure call per statement: Fortran fixes no order of evaluation
  ! in an expression and may skip a reference whose value is not needed.)
  if (count_names(1) /= TAPER_N_PROFILES) call fail("profile names")
  if (count_names(2) /= TAPER_N_METHODS) call fail("method names")
  if (count_names(3) /= TAPER_N_FIT_MODELS) call fail("fit model names")
  if (count_names(4) /= TAPER_N_STATISTICS) call fail("statistic names")
  status = taper_profile_from_name("Backward_Linear", p, e)
  if (status /= TAPER_OK .or. p /= TAPER_BACKWARD_LINEAR) call fail("taper_profile_from_name")
  if (taper_profile_name(TAPER_FORWARD_EXPONENTIAL) /= "forward_exponential") call fail("profile_name")
  if (taper_statistic_name(TAPER_STAT_GRANULE_REACHED) /= "granule_reached") call fail("statistic_name")
  status = taper_method_from_name("rk4", p, e)
  call refused(status, "method")

  ! Settings: defaults, setters, a refusal that names its setting.
  cs = taper_chain_spec_alloc(e)
  if (.not. c_associated(cs)) call fail("chain spec: "//taper_message(e))
  if (taper_chain_spec_n_granules(cs) /= 100) call fail("chain spec default n_granules")
  if (abs(taper_chain_spec_exponent(cs) - 2.5_c_double) > 0) call fail("chain spec default exponent")
  if (taper_chain_spec_set_profile(cs, TAPER_BACKWARD_LINEAR, e) /= TAPER_OK) call fail("profile")
  if (taper_chain_spec_set_n_granules(cs, 30_c_size_t, e) /= TAPER_OK) call fail("n_granules")
  if (taper_chain_spec_set_s(cs, 0.1_c_double, e) /= TAPER_OK) call fail("s")
  status = taper_chain_spec_set_n_granules(cs, 1_c_size_t, e)
  call refused(status, "n_granules")
  if (taper_chain_spec_n_granules(cs) /= 30) call fail("a refusal changed n_granules")
  status = taper_chain_spec_set_s(cs, -1.0_c_double, e)
  call refused(status, "s")
  chain = taper_chain_alloc(cs, e)
  call taper_chain_spec_free(cs)
  if (.not. c_associated(chain)) call fail("chain: "//taper_message(e))
  if (e%status /= TAPER_OK .or. c_associated(e%field) .or. len(taper_message(e)) /= 0) &
       call fail("a success clears the error")
  radius => taper_chain_array(chain, taper_chain_radius(chain))
  if (size(radius) /= 30) call fail("radius size")
  if (abs(radius(30) - 3.9_c_double) > 1d-12) call fail("radius(30)")

  ! A run with the defaults, its theory and statistics.
  sim = taper_sim_alloc(chain, c_null_ptr, e)
  status = taper_sim_run(sim, e)
  if (status /= TAPER_OK) call fail("run: "//taper_message(e))
  t_pass => taper_observable(sim, chain, TAPER_T_PASS)
  t_th => taper_theory(sim, chain, TAPER_THEORY_T)
  if (abs(t_pass(10) / t_th(10) - 1) > 0.02_c_double .or. .not. ieee_is_nan(t_pass(30))) &
       call fail("t_pass vs theory")
  if (abs(taper_sim_statistic(sim, TAPER_STAT_COMPLETE) - 1) > 0) call fail("complete")
  if (abs(taper_sim_statistic(sim, TAPER_STAT_GRANULE_REACHED) - 29) > 0) call fail("granule_reached")
  if (.not. taper_sim_statistic(sim, TAPER_STAT_STEPS) > 0) call fail("steps")
  call taper_sim_free(sim)

  ! Solver settings that do not fit the chain name the setting; a monitor
  ! in Fortran stops the run.
  ss = taper_solver_spec_alloc(e)
  status = taper_solver_spec_set_rtol(ss, -1.0_c_double, e)
  call refused(status, "rtol")
  if (taper_solver_spec_set_last_granule(ss, 31_c_size_t, e) /= TAPER_OK) call fail("last_granule")
  sim = taper_sim_alloc(chain, ss, e)
  if (c_associated(sim)) call fail("last_granule > N accepted")
  call refused(e%status, "last_granule")
  if (taper_solver_spec_set_last_granule(ss, 0_c_size_t, e) /= TAPER_OK) call fail("last_granule 0")
  call taper_solver_spec_set_monitor(ss, c_funloc(stop_at_third), c_null_ptr)
  sim = taper_sim_alloc(chain, ss, e)
  call taper_solver_spec_free(ss)
  status = taper_sim_run(sim, e)
  if (status /= TAPER_EINTERRUPTED .or. calls /= 3 .or. last_granule_seen < 1) &
       call fail("monitor: "//taper_message(e))
  if (abs(taper_sim_statistic(sim, TAPER_STAT_COMPLETE)) > 0) call fail("interrupted but complete")
  call taper_sim_free(sim)

  ! Beyond the paper through the module: a right wall, t_end and a sampler
  ! written in Fortran; the wall statistics, the forces and the time.
  cs = taper_chain_spec_alloc(e)
  if (taper_chain_spec_set_n_granules(cs, 10_c_size_t, e) /= TAPER_OK) call fail("n_granules 10")
  if (taper_chain_spec_set_end(cs, TAPER_RIGHT, TAPER_END_WALL, 0.0_c_double, e) /= TAPER_OK) &
       call fail("set_end: "//taper_message(e))
  if (taper_chain_spec_end(cs, TAPER_RIGHT) /= TAPER_END_WALL) call fail("spec_end")
  status = taper_chain_spec_set_damping(cs, -1.0_c_double, e)
  call refused(status, "damping")
  status = taper_chain_spec_set_end(cs, TAPER_LEFT, TAPER_END_FREE, -1.0_c_double, e)
  call refused(status, "left_compliance")
  ss = taper_solver_spec_alloc(e)
  if (taper_solver_spec_set_t_end(ss, 30.0_c_double, e) /= TAPER_OK) call fail("t_end")
  if (taper_solver_spec_set_sampler(ss, 1.0_c_double, c_funloc(count_samples), c_null_ptr, e) &
       /= TAPER_OK) call fail("sampler: "//taper_message(e))
  if (abs(taper_solver_spec_sample_interval(ss) - 1) > 0) call fail("sample_interval")
  wchain = taper_chain_alloc(cs, e)
  call taper_chain_spec_free(cs)
  if (.not. c_associated(wchain)) call fail("wall chain: "//taper_message(e))
  if (taper_chain_end(wchain, TAPER_RIGHT) /= TAPER_END_WALL) call fail("chain_end")
  x1 = taper_chain_end_contact(wchain, TAPER_RIGHT)
  if (.not. x1 > 0) call fail("chain_end_contact")
  wsim = taper_sim_alloc(wchain, ss, e)
  call taper_solver_spec_free(ss)
  status = taper_sim_run(wsim, e)
  if (status /= TAPER_OK) call fail("wall run: "//taper_message(e))
  ! samples at t = 0, 1, ..., 30
  if (samples /= 31 .or. abs(last_sample_t - 30) > 1d-12) then
     print '(a,i0,a,es12.4)', "FAIL: sampler called ", samples, " times, last at t = ", last_sample_t
     fails = fails + 1
  end if
  if (abs(taper_sim_time(wsim) - 30) > 1d-9) call fail("sim_time after t_end")
  x1 = taper_sim_statistic(wsim, TAPER_STAT_WALL_PEAK_FORCE_RIGHT)
  x2 = taper_sim_statistic(wsim, TAPER_STAT_WALL_PEAK_FORCE_LEFT)
  if (.not. x1 > 0 .or. .not. ieee_is_nan(x2)) call fail("wall statistics")
  if (abs(taper_sim_statistic(wsim, TAPER_STAT_ENERGY_INITIAL) - 0.5_c_double) > 1d-12) &
       call fail("energy_initial")
  allocate (force(11))
  force = -1
  if (taper_sim_forces(wsim, force, e) /= TAPER_OK) call fail("forces: "//taper_message(e))
  if (any(force < 0) .or. abs(force(1)) > 0) call fail("forces: negative, or a free left end pushing")
  deallocate (force)
  call taper_sim_free(wsim)
  call taper_chain_free(wchain)
  ! Real units: one rescaled length is R_1 alpha^(1/n) metres, so at most R_1
  ! for alpha <= 1 (steel, R_1 = 1 cm, 1 m/s); NaN outside the physical range.
  x1 = taper_unit_scale(TAPER_DIM_LENGTH, 193d9, 0.3d0, 8000d0, 0.01d0, 1d0)
  x2 = taper_unit_scale(TAPER_DIM_LENGTH, 193d9, 0.6d0, 8000d0, 0.01d0, 1d0)
  if (.not. x1 > 0 .or. .not. ieee_is_nan(x2)) call fail("unit_scale")
  if (taper_dimension_unit(TAPER_DIM_VELOCITY) /= "m/s") call fail("dimension_unit")
  if (taper_boundary_name(TAPER_END_WALL) /= "wall") call fail("boundary_name")
  if (taper_disorder_name(TAPER_DISORDER_MASS) /= "mass") call fail("disorder_name")

  ! The equations of motion for one's own integrator: the impulse state.
  dyn = taper_dynamics_alloc(chain, e)
  if (.not. c_associated(dyn)) call fail("dynamics: "//taper_message(e))
  allocate (y(60), ydot(60))
  y = 0
  y(1) = 1                   ! v_1 = 1 (Fortran index 2k-1), z_k at 2k
  call taper_dynamics_rhs(dyn, y, ydot)
  call taper_dynamics_energy_momentum(dyn, y, energy, momentum)
  if (abs(ydot(2) - 1) > 0 .or. any(abs(ydot(3:)) > 0) .or. abs(energy - 0.5_c_double) > 0 .or. &
       abs(momentum - 1) > 0) call fail("dynamics at the impulse")
  call taper_dynamics_free(dyn)
  call taper_chain_free(chain)

  ! A fit: y = x^-2.
  fs = taper_fit_spec_alloc(TAPER_FIT_POWER, e)
  status = taper_fit_spec_set_xtol(fs, 0.0_c_double, e)
  call refused(status, "xtol")
  fr = taper_fit(fs, x, yf, 4_c_size_t, e)
  if (.not. c_associated(fr)) then
     call fail("fit: "//taper_message(e))
  else
     if (abs(taper_fit_result_param(fr, 1_c_size_t) + 2) > 1d-12) call fail("fit exponent")
     if (taper_fit_result_n_points(fr) /= 4) call fail("fit points")
  end if
  call taper_fit_result_free(fr)
  call taper_fit_spec_free(fs)
  ! Main-program variables are implicitly SAVE'd: never deallocated for us.
  deallocate (y, ydot)

  if (fails > 0) error stop 1
  print '(a)', "Fortran module: taper_error and taper_progress laid out as in C; setters, "// &
       "fields, names, statistics, monitor, dynamics and fits work"

contains

  integer(c_size_t) function off(field, base)
    type(c_ptr), intent(in) :: field, base
    off = int(transfer(field, 0_c_intptr_t) - transfer(base, 0_c_intptr_t), c_size_t)
  end function off

  ! The length of one of the library's name lists (1 profiles, 2 methods,
  ! 3 fit models, 4 statistics).
  integer function count_names(list) result(n)
    integer, intent(in) :: list
    character(len=:), allocatable :: name
    n = 0
    do i = 0, 100
       select case (list)
       case (1)
          name = taper_profile_name(int(i, c_int))
       case (2)
          name = taper_method_name(int(i, c_int))
       case (3)
          name = taper_fit_model_name(int(i, c_int))
       case default
          name = taper_statistic_name(int(i, c_int))
       end select
       if (len(name) == 0) exit
       n = n + 1
    end do
  end function count_names

  subroutine same(type, name, nbytes, offsets)
    integer, intent(in) :: type
    character(len=*), intent(in) :: name
    integer(c_size_t), intent(in) :: nbytes, offsets(:)
    integer :: j
    if (nbytes /= layout(int(type, c_int), 0_c_int)) then
       print '(a,i0,a,i0)', name//": Fortran size ", nbytes, ", C size ", layout(int(type, c_int), 0_c_int)
       fails = fails + 1
    end if
    do j = 1, size(offsets)
       if (offsets(j) /= layout(int(type, c_int), int(j, c_int))) then
          print '(a,i0,a,i0,a,i0)', name//": field ", j, " at Fortran offset ", offsets(j), &
               ", C offset ", layout(int(type, c_int), int(j, c_int))
          fails = fails + 1
       end if
    end do
  end subroutine same

  ! A refusal: status TAPER_EINVAL, err naming `field`, with a message.
  subroutine refused(got, field)
    integer(c_int), intent(in) :: got
    character(len=*), intent(in) :: field
    character(len=:), allocatable :: named, message
    named = taper_field(e)
    message = taper_message(e)
    if (got /= TAPER_EINVAL .or. e%status /= TAPER_EINVAL .or. named /= field .or. &
         len(message) == 0) &
         call fail(field//": status "//char(48 + got)//", field '"//named//"': "//message)
  end subroutine refused

  subroutine fail(what)
    character(len=*), intent(in) :: what
    print '(a)', "FAIL: "//what
    fails = fails + 1
  end subroutine fail
end program test_fortran_abi
