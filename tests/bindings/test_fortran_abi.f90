! SPDX-License-Identifier: GPL-3.0-or-later
! test_fortran_abi -- the Fortran module drivers/fortran/module/taper.f90
! against the library: the three bind(C) derived types it declares
! (taper_error, taper_progress, taper_setting) have the size and field
! offsets of the C structs (asked of the C compiler in fortran_abi.c); every
! other object is opaque, set and read through the interfaces, which are
! exercised here: the name lists, setters (a refusal names its setting and
! leaves the spec as it was), a run with a monitor written in Fortran,
! statistics by name, the sim's theory, taper_dynamics and a fit; every
! constant the build wrote from the header against the C compiler's values
! (fortran_abi.c); the options beyond the paper: a right wall with t_end and
! a sampler written in Fortran (31 samples at t = 0..30), the wall's
! statistics, taper_sim_forces, taper_unit_scale and the new names; and the
! table of settings: every setting set and read by name with each kind of
! Fortran value, refusals naming the setting with its range, and a walk over
! every row of the table against fresh specs.
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
       TAPER_MAX_ORDER_ADAMS, TAPER_MAX_ORDER_BDF, TAPER_N_LAWS, &
       TAPER_SETTING_REAL, TAPER_SETTING_INTEGER, TAPER_SETTING_BOOLEAN, TAPER_SETTING_CHOICE, &
       TAPER_SETTING_LIST, TAPER_SETTING_CHAIN, TAPER_SETTING_SOLVER]
  type(taper_error), target :: e
  type(taper_progress), target :: pr
  type(taper_setting), target :: row_layout   ! only its layout is read
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
  call same(2, "taper_setting", c_sizeof(row_layout), [off(c_loc(row_layout%name), c_loc(row_layout)), &
       off(c_loc(row_layout%group), c_loc(row_layout)), off(c_loc(row_layout%object), c_loc(row_layout)), &
       off(c_loc(row_layout%type), c_loc(row_layout)), off(c_loc(row_layout%dimension), c_loc(row_layout)), &
       off(c_loc(row_layout%min), c_loc(row_layout)), off(c_loc(row_layout%max), c_loc(row_layout)), &
       off(c_loc(row_layout%min_open), c_loc(row_layout)), &
       off(c_loc(row_layout%max_open), c_loc(row_layout)), &
       off(c_loc(row_layout%default_value), c_loc(row_layout)), &
       off(c_loc(row_layout%choices), c_loc(row_layout)), &
       off(c_loc(row_layout%beyond_paper), c_loc(row_layout)), &
       off(c_loc(row_layout%description), c_loc(row_layout)), &
       off(c_loc(row_layout%bounds_reason), c_loc(row_layout))])

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

  call settings_by_name()
  call table_of_settings()

  if (fails > 0) error stop 1
  print '(a)', "Fortran module: taper_error, taper_progress and taper_setting laid out as "// &
       "in C; setters, settings by name, the table of settings, fields, names, statistics, "// &
       "monitor, dynamics and fits work"

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

  ! Every kind of Fortran value through taper_chain_spec_set_option and
  ! taper_solver_spec_set_option, read back by name and through the typed
  ! getters; refusals name the setting and state its range; the chain built
  ! from the settings by name is the one they describe.
  subroutine settings_by_name()
    type(c_ptr) :: cs, ss, chain
    type(taper_setting), pointer :: row
    real(c_double), pointer :: radii(:), radius(:)
    integer(c_int) :: status
    cs = taper_chain_spec_alloc(e)
    ss = taper_solver_spec_alloc(e)
    ! a choice by its name in any case, integers of both kinds, a list, a real
    if (taper_chain_spec_set_option(cs, "profile", "Custom", e) /= TAPER_OK) &
         call fail("profile by name: "//taper_message(e))
    if (taper_chain_spec_profile(cs) /= TAPER_CUSTOM) call fail("profile by name: not custom")
    if (taper_chain_spec_set_option(cs, "n_granules", 3_c_int, e) /= TAPER_OK) &
         call fail("n_granules by name: "//taper_message(e))
    if (taper_chain_spec_n_granules(cs) /= 3) call fail("n_granules by name: not 3")
    if (taper_chain_spec_set_option(cs, "radii", [1d0, 2d0, 4d0], e) /= TAPER_OK) &
         call fail("radii by name: "//taper_message(e))
    radii => taper_chain_spec_option_list(cs, "radii")
    if (size(radii) /= 3) then
       call fail("radii read by name")
    else if (any(abs(radii - [1d0, 2d0, 4d0]) > 0)) then
       call fail("radii read by name")
    end if
    if (size(taper_chain_spec_option_list(cs, "pattern")) /= 0) call fail("pattern: not empty")
    if (taper_chain_spec_set_option(cs, "seed", 12345678901_c_int64_t, e) /= TAPER_OK) &
         call fail("seed by name: "//taper_message(e))
    if (taper_chain_spec_disorder_seed(cs) /= 12345678901_c_int64_t) call fail("seed by name")
    if (taper_chain_spec_set_option(cs, "load", 0.25_c_double, e) /= TAPER_OK) &
         call fail("load by name: "//taper_message(e))
    if (abs(taper_chain_spec_load(cs) - 0.25_c_double) > 0) call fail("load read back")
    if (abs(taper_chain_spec_option(cs, "load") - 0.25_c_double) > 0) call fail("load by name")
    if (taper_solver_spec_set_option(ss, "window", .false., e) /= TAPER_OK) &
         call fail("window by name: "//taper_message(e))
    if (taper_solver_spec_window(ss) /= 0) call fail("window by name: still on")
    if (taper_solver_spec_set_option(ss, "method", "BDF", e) /= TAPER_OK) &
         call fail("method by name: "//taper_message(e))
    if (taper_solver_spec_method(ss) /= TAPER_BDF) call fail("method read back")
    if (abs(taper_solver_spec_option(ss, "method") - TAPER_BDF) > 0) call fail("method by name")
    if (taper_solver_spec_set_option(ss, "rtol", " 1e-9 ", e) /= TAPER_OK) &
         call fail("rtol as text: "//taper_message(e))
    if (abs(taper_solver_spec_rtol(ss) - 1d-9) > 0) call fail("rtol as text: not 1e-9")
    if (taper_solver_spec_set_option(ss, "max_steps", 5000000000_c_int64_t, e) /= TAPER_OK) &
         call fail("max_steps by name: "//taper_message(e))
    if (taper_solver_spec_max_steps(ss) /= 5000000000_c_long) call fail("max_steps read back")

    ! Refusals name the setting, say why, and change nothing.
    status = taper_chain_spec_set_option(cs, "exponent", 1.2_c_double, e)
    call refused(status, "exponent")
    if (index(taper_message(e), "out of range [1.5, 20]") == 0) &
         call fail("exponent's refusal states no range: "//taper_message(e))
    if (abs(taper_chain_spec_exponent(cs) - 2.5_c_double) > 0) call fail("a refusal changed exponent")
    status = taper_chain_spec_set_option(cs, "radii", [1d0, -2d0], e)
    call refused(status, "radii")
    if (index(taper_message(e), "radii(2) = -2") == 0) call fail("radii(2): "//taper_message(e))
    if (size(taper_chain_spec_option_list(cs, "radii")) /= 3) call fail("a refusal changed radii")
    status = taper_chain_spec_set_option(cs, "seed", 9007199254740993_c_int64_t, e)
    call refused(status, "seed")
    if (index(taper_message(e), "9007199254740993") == 0) call fail("seed 2^53 + 1: "//taper_message(e))
    if (taper_chain_spec_disorder_seed(cs) /= 12345678901_c_int64_t) call fail("a refusal changed seed")
    status = taper_chain_spec_set_option(cs, "rtol", 1d-8, e)     ! the solver's
    call refused(status, "rtol")
    status = taper_solver_spec_set_option(ss, "window", "maybe", e)
    call refused(status, "window")
    status = taper_chain_spec_set_option(cs, "profile", "linear", e)
    call refused(status, "profile")
    status = taper_chain_spec_set_option(cs, "n_granule", 10_c_int, e)
    if (status /= TAPER_EINVAL .or. index(taper_message(e), "did you mean 'n_granules'") == 0) &
         call fail("unknown name: "//taper_message(e))
    row => taper_setting_find("windw", e)
    if (associated(row) .or. index(taper_message(e), "'window'") == 0) &
         call fail("taper_setting_find('windw'): "//taper_message(e))

    ! The chain the names describe: R = 1, 2, 4.
    chain = taper_chain_alloc(cs, e)
    if (.not. c_associated(chain)) then
       call fail("chain by name: "//taper_message(e))
    else
       radius => taper_chain_array(chain, taper_chain_radius(chain))
       if (size(radius) /= 3 .or. abs(radius(3) - 4) > 0) call fail("chain by name: radii")
       call taper_chain_free(chain)
    end if
    call taper_chain_spec_free(cs)
    call taper_solver_spec_free(ss)
  end subroutine settings_by_name

  ! Every row of the table: its strings, found again by its name, its
  ! default a fresh spec's value, its unit its dimension's, a choice's names
  ! the enum's; the rows end at taper_setting_count().
  subroutine table_of_settings()
    type(taper_setting), pointer :: row, found
    type(c_ptr) :: cs, ss
    character(len=:), allocatable :: name, text
    real(c_double), pointer :: values(:)
    real(c_double) :: fresh
    integer :: k, n, n_chain, n_solver
    cs = taper_chain_spec_alloc(e)
    ss = taper_solver_spec_alloc(e)
    n = int(taper_setting_count())
    if (n < 30) call fail("the table has fewer than 30 rows")
    n_chain = 0
    n_solver = 0
    do k = 1, n
       row => taper_setting_row(k)
       if (.not. associated(row)) then
          call fail("taper_setting_row: a row is missing")
          cycle
       end if
       name = taper_setting_name(row)
       found => taper_setting_find(name, e)
       if (.not. associated(found)) then
          call fail(name//": not found by its name")
       else if (.not. c_associated(c_loc(found), c_loc(row))) then
          call fail(name//": found another row")
       end if
       if (len(taper_setting_description(row)) == 0) call fail(name//": no description")
       text = taper_setting_unit(row)
       if (text /= taper_dimension_unit(row%dimension) .or. len(text) == 0) &
            call fail(name//": unit")
       text = taper_setting_group(row)
       select case (text)
       case ("chain", "ends", "striker", "losses", "solver")
       case default
          call fail(name//": group "//text)
       end select
       if (row%object == TAPER_SETTING_CHAIN) then
          n_chain = n_chain + 1
          fresh = taper_chain_spec_option(cs, name)
       else
          n_solver = n_solver + 1
          fresh = taper_solver_spec_option(ss, name)
       end if
       if (row%type == TAPER_SETTING_LIST) then
          values => taper_chain_spec_option_list(cs, name)
          if (.not. ieee_is_nan(fresh) .or. size(values) /= 0) &
               call fail(name//": a list, read as a value or not empty")
       else if (abs(fresh - row%default_value) > 0) then
          call fail(name//": a fresh spec does not hold the default")
       end if
       if (row%type == TAPER_SETTING_CHOICE) then
          text = taper_setting_choice_name(row, nint(row%default_value) + 1)
          if (taper_setting_n_choices(row) < 2 .or. len(text) == 0) call fail(name//": choices")
       else if (taper_setting_n_choices(row) /= 0) then
          call fail(name//": choices of a setting that is not a choice")
       end if
       if (.not. row%min <= row%max) call fail(name//": min > max")
    end do
    if (n_chain + n_solver /= n .or. n_solver < 5) call fail("objects of the rows")
    if (associated(taper_setting_row(n + 1))) call fail("taper_setting_row past the end")
    if (associated(taper_setting_row(0))) call fail("taper_setting_row(0)")
    ! Two known rows: the tolerance's range is taper.h's, t_end is a time.
    row => taper_setting_find("rtol", e)
    if (abs(row%min - TAPER_RTOL_MIN) > 0 .or. abs(row%max - TAPER_RTOL_MAX) > 0 .or. &
         row%type /= TAPER_SETTING_REAL) call fail("the row of rtol")
    if (taper_setting_unit(row) /= "1") call fail("rtol is not a pure number")
    text = taper_setting_bounds_reason(row)
    if (len(text) == 0) call fail("rtol's bounds have no reason")
    row => taper_setting_find("T_END", e)         ! any case
    if (row%dimension /= TAPER_DIM_TIME) call fail("t_end is not a time")
    if (taper_setting_unit(row) /= "s") call fail("t_end's unit")
    if (taper_setting_group(row) /= "solver") call fail("t_end's group")
    row => taper_setting_find("profile", e)
    do k = 1, TAPER_N_PROFILES
       if (taper_setting_choice_name(row, k) /= taper_profile_name(int(k - 1, c_int))) &
            call fail("profile's choices are not taper_profile_name's")
    end do
    if (len(taper_setting_choice_name(row, TAPER_N_PROFILES + 1)) /= 0) &
         call fail("a choice past the last")
    call taper_chain_spec_free(cs)
    call taper_solver_spec_free(ss)
  end subroutine table_of_settings

  subroutine fail(what)
    character(len=*), intent(in) :: what
    print '(a)', "FAIL: "//what
    fails = fails + 1
  end subroutine fail
end program test_fortran_abi
