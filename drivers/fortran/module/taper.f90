! SPDX-License-Identifier: GPL-3.0-or-later
! taper.f90 -- Fortran interface to libtaper (iso_c_binding, Fortran 2008).
!
! Pulse propagation in tapered granular chains: the C API of include/taper.h
! as bind(C) interfaces, and helpers that take and give Fortran strings,
! values and arrays.
!
! Settings live in objects the library allocates (type(c_ptr)), written
! through setters and read through getters, as CVODE's memory is: nothing
! here mirrors a struct of settings, so a later libtaper that adds settings
! needs no change of this module (docs/api.md, "Why opaque objects").  Every
! setting can also be set and read by its name in the library's table of
! settings, with a real, an integer, a logical, a choice's name or an array
! (taper_chain_spec_set_option, taper_chain_spec_option, ...), and the table
! itself walked row by row (taper_setting_row: name, group, type, unit,
! range, default, description).  Each setter checks its value; a refusal
! returns TAPER_EINVAL and names the setting in the error (taper_field(err):
! "rtol", "n_granules", ...) with its range.  The only structs declared here
! are those the library fills or owns and never reorders: taper_error,
! taper_progress and a row of the table, taper_setting.  Enums are
! integer(c_int) constants written at build time from the header's own
! lists into the module taper_constants (taper_constants.f90, installed
! beside this file: compile it first); names come from the library
! (taper_profile_name, ...).  `use taper` gives both: the module taper at
! the end of this file re-exports the constants and the binding.
!
!   use taper
!   type(taper_error) :: err
!   type(c_ptr) :: cs, ss, chain, sim
!   real(c_double), pointer :: t_pass(:)
!   cs = taper_chain_spec_alloc(err)
!   if (taper_chain_spec_set_profile(cs, TAPER_BACKWARD_LINEAR, err) /= TAPER_OK .or. &
!       taper_chain_spec_set_n_granules(cs, 100_c_size_t, err) /= TAPER_OK .or. &
!       taper_chain_spec_set_s(cs, 0.1_c_double, err) /= TAPER_OK) &
!       error stop taper_field(err)//": "//taper_message(err)
!   chain = taper_chain_alloc(cs, err)
!   call taper_chain_spec_free(cs)
!   if (.not. c_associated(chain)) error stop taper_message(err)
!   ss = taper_solver_spec_alloc(err)            ! the library's defaults
!   if (taper_solver_spec_set_option(ss, "rtol", 1d-8, err) /= TAPER_OK) &   ! by name
!       error stop taper_field(err)//": "//taper_message(err)
!   sim = taper_sim_alloc(chain, ss, err)
!   call taper_solver_spec_free(ss)
!   if (taper_sim_run(sim, err) /= TAPER_OK) print *, taper_message(err)
!   t_pass => taper_observable(sim, chain, TAPER_T_PASS)  ! length N, owned by sim
!   print *, taper_statistic_name(TAPER_STAT_STEPS), taper_sim_statistic(sim, TAPER_STAT_STEPS)
!   call taper_sim_free(sim); call taper_chain_free(chain)
!
! Granule k is element k of every array (C index k-1).  Values that do not
! exist are NaN (ieee_is_nan).  Arrays returned as pointers belong to the
! chain or sim and are valid until it is freed.  Optional C arguments (NULL)
! are passed as c_null_ptr where the interface takes type(c_ptr); the
! taper_error argument is always required here.  integer(c_size_t) is
! signed in Fortran: a negative count reaches the library as a huge one.
module taper_binding
  use, intrinsic :: iso_c_binding
  ! The version, status codes, every enum of taper.h with its count
  ! (TAPER_N_PROFILES, ...), the ranges of the settings: written at build
  ! time from the header's own lists (gen_constants.c).
  use taper_constants
  implicit none
  private

  ! ---- the structs the library fills or owns (fields only ever appended) ------
  type, bind(C), public :: taper_error
     integer(c_int) :: status = 0
     type(c_ptr) :: field = c_null_ptr          ! taper_field(err)
     character(kind=c_char) :: message(TAPER_MESSAGE_SIZE) = c_null_char  ! taper_message(err)
  end type taper_error

  type, bind(C), public :: taper_progress
     integer(c_size_t) :: granule
     integer(c_size_t) :: target
     real(c_double) :: t
     integer(c_long) :: steps
     integer(c_size_t) :: window_lo
     integer(c_size_t) :: window_hi
  end type taper_progress

  ! One row of the table of settings (taper.h, "Settings by name"): static
  ! storage the library owns, read through a pointer and never copied
  ! (taper_setting_row, taper_setting_find).  Its strings are C pointers:
  ! taper_setting_name(row), taper_setting_group(row), ...
  type, bind(C), public :: taper_setting
     type(c_ptr) :: name             ! "n_granules", "striker_radius", ...
     type(c_ptr) :: group            ! "chain", "ends", "striker", "losses", "solver"
     integer(c_int) :: object        ! TAPER_SETTING_CHAIN or TAPER_SETTING_SOLVER
     integer(c_int) :: type          ! TAPER_SETTING_REAL, ..._INTEGER, ..._BOOLEAN, ...
     integer(c_int) :: dimension     ! TAPER_DIM_*: the unit of its value (rescaled)
     real(c_double) :: min, max      ! range (a list: of each entry); may be infinite
     integer(c_int) :: min_open, max_open   ! 1: that bound excluded
     real(c_double) :: default_value ! a choice: its index (0-based, as in C)
     type(c_ptr) :: choices          ! taper_setting_choice_name(row, k)
     integer(c_int) :: beyond_paper  ! 1: not part of the paper's model
     type(c_ptr) :: description      ! taper_setting_description(row)
     type(c_ptr) :: bounds_reason    ! taper_setting_bounds_reason(row)
  end type taper_setting

  ! ---- the C API ---------------------------------------------------------------
  public :: c_taper_version, c_taper_strerror, c_taper_profile_name, c_taper_method_name, &
            c_taper_fit_model_name, c_taper_statistic_name, c_taper_disorder_name, &
            c_taper_boundary_name, c_taper_dimension_name, c_taper_dimension_unit, &
            c_taper_observable_name, c_taper_theory_quantity_name, c_taper_law_name, &
            c_taper_status_name, c_taper_nearest_name, taper_statistic_dimension, &
            taper_observable_dimension, taper_theory_quantity_dimension
  ! The table of settings (taper.h, "Settings by name"): a row is read through
  ! its C pointer (taper_setting_at, taper_setting_find); settings are set and
  ! read by name.  The Fortran helpers below take Fortran strings and values.
  public :: taper_setting_count, taper_setting_at, c_taper_setting_find, &
            c_taper_chain_spec_set_option, c_taper_chain_spec_set_option_text, &
            c_taper_chain_spec_set_option_list, c_taper_solver_spec_set_option, &
            c_taper_solver_spec_set_option_text, c_taper_chain_spec_option, &
            c_taper_chain_spec_option_list, c_taper_solver_spec_option
  public :: taper_chain_spec_alloc, taper_chain_spec_free, taper_chain_spec_set_profile, &
            taper_chain_spec_set_n_granules, taper_chain_spec_set_s, taper_chain_spec_set_q, &
            taper_chain_spec_set_exponent, taper_chain_spec_set_radii, taper_chain_spec_profile, &
            taper_chain_spec_n_granules, taper_chain_spec_s, taper_chain_spec_q, &
            taper_chain_spec_exponent, taper_chain_spec_radii, taper_chain_spec_check
  public :: taper_chain_spec_set_pattern, taper_chain_spec_pattern, &
            taper_chain_spec_set_disorder, taper_chain_spec_disorder, &
            taper_chain_spec_disorder_amplitude, taper_chain_spec_disorder_seed, &
            taper_chain_spec_set_materials, taper_chain_spec_materials, taper_chain_spec_set_end, taper_chain_spec_end, &
            taper_chain_spec_end_compliance, taper_chain_spec_set_striker, &
            taper_chain_spec_striker_radius, taper_chain_spec_striker_density, &
            taper_chain_spec_striker_compliance, taper_chain_spec_set_load, taper_chain_spec_load, &
            taper_chain_spec_set_damping, taper_chain_spec_damping, taper_chain_spec_set_drag, &
            taper_chain_spec_drag, taper_chain_spec_set_piston, &
            taper_chain_spec_piston_duration, taper_chain_spec_piston_compliance
  public :: taper_chain_end, taper_chain_end_contact, taper_chain_striker_radius, &
            taper_chain_striker_mass, taper_chain_striker_contact, taper_chain_load, &
            taper_chain_damping, taper_chain_drag, c_taper_chain_theory_note, &
            taper_chain_piston_duration, taper_chain_piston_contact
  public :: taper_unit_scale
  public :: taper_chain_alloc, taper_chain_free, taper_chain_size, taper_chain_exponent, &
            taper_chain_profile, taper_chain_radius, taper_chain_mass, taper_chain_contact, &
            taper_chain_rest_position
  public :: taper_dynamics_alloc, taper_dynamics_free, taper_dynamics_rhs, &
            taper_dynamics_energy_momentum, taper_dynamics_peak_function
  public :: taper_theory_collision_time, taper_theory_compute, taper_theory_compute_monitored
  public :: taper_solver_spec_alloc, taper_solver_spec_free, taper_solver_spec_set_method, &
            taper_solver_spec_set_rtol, taper_solver_spec_set_atol, &
            taper_solver_spec_set_last_granule, taper_solver_spec_set_window, &
            taper_solver_spec_set_max_order, taper_solver_spec_set_t_max, &
            taper_solver_spec_set_max_steps, taper_solver_spec_set_monitor, &
            taper_solver_spec_set_log, taper_solver_spec_method, taper_solver_spec_rtol, &
            taper_solver_spec_atol, taper_solver_spec_last_granule, taper_solver_spec_window, &
            taper_solver_spec_max_order, taper_solver_spec_t_max, taper_solver_spec_max_steps, &
            taper_solver_spec_set_t_end, taper_solver_spec_t_end, taper_solver_spec_set_sampler, &
            taper_solver_spec_sample_interval
  public :: taper_sim_alloc, taper_sim_free, taper_sim_run, taper_sim_observable, &
            taper_sim_theory, taper_sim_statistic, taper_sim_state, taper_sim_time, &
            taper_sim_striker_state, taper_sim_forces, taper_sim_piston_work
  public :: taper_asymptotic_exponent, taper_asymptotic_A, taper_asymptotic_lnA, &
            taper_asymptotic_eta, taper_asymptotic_f, taper_asymptotic_position_exponent, &
            taper_asymptotic_speed_exponent, taper_asymptotic_timescale, taper_asymptotic_M, &
            taper_asymptotic_C0, taper_asymptotic_C, taper_asymptotic_forward_linear_b
  public :: taper_fit_spec_alloc, taper_fit_spec_free, taper_fit_spec_set_exponent, &
            taper_fit_spec_set_index_window, taper_fit_spec_set_x_window, &
            taper_fit_spec_set_skip_invalid, taper_fit_spec_set_max_iter, &
            taper_fit_spec_set_xtol, taper_fit_spec_model, taper_fit_spec_exponent, taper_fit, &
            taper_fit_result_free, taper_fit_result_model, taper_fit_result_n_params, &
            taper_fit_result_param, taper_fit_result_param_error, taper_fit_result_n_points, &
            taper_fit_result_n_skipped, taper_fit_result_chi2, taper_fit_result_iterations
  ! Fortran helpers
  public :: taper_version, taper_strerror, taper_profile_name, taper_method_name, &
            taper_fit_model_name, taper_statistic_name, taper_profile_from_name, &
            taper_method_from_name, taper_fit_model_from_name, taper_message, taper_field, &
            taper_observable, taper_theory, taper_chain_array, c_string, taper_disorder_name, &
            taper_disorder_from_name, taper_boundary_name, taper_boundary_from_name, &
            taper_dimension_name, taper_dimension_unit, taper_chain_theory_note, &
            taper_observable_name, taper_theory_quantity_name, taper_law_name
  ! Fortran helpers of the table of settings: its rows, and every setting by
  ! name with a real, an integer, a logical, a choice's name or a list.
  public :: taper_setting_row, taper_setting_find, taper_setting_name, taper_setting_group, &
            taper_setting_description, taper_setting_bounds_reason, taper_setting_unit, &
            taper_setting_choice_name, taper_setting_n_choices, taper_chain_spec_set_option, &
            taper_solver_spec_set_option, taper_chain_spec_option, taper_chain_spec_option_list, &
            taper_solver_spec_option

  ! What taper_chain_spec_option_list points to for an empty list (never
  ! written: it has no element).
  real(c_double), target :: no_values(0)

  ! taper_chain_spec_set_option(spec, name, value, err): value a real(c_double),
  ! an integer (c_int or int64: a whole number), a logical (a boolean
  ! setting), a string (a choice's name, any case; or a number as text) or a
  ! real(c_double) array (a list; size 0 removes it).  TAPER_EINVAL naming
  ! the setting for an unknown name, the other spec's setting, the wrong type
  ! or a value out of range (the message states the range and why).
  interface taper_chain_spec_set_option
     module procedure chain_set_real, chain_set_int, chain_set_int64, chain_set_logical, &
          chain_set_text, chain_set_list
  end interface taper_chain_spec_set_option
  ! The same for a solver spec (no setting of it is a list).
  interface taper_solver_spec_set_option
     module procedure solver_set_real, solver_set_int, solver_set_int64, solver_set_logical, &
          solver_set_text
  end interface taper_solver_spec_set_option

  interface
     ! ---- version, errors, names: strings come back as C pointers (helpers below)
     function c_taper_version() bind(C, name="taper_version") result(s)
       import :: c_ptr
       type(c_ptr) :: s
     end function c_taper_version
     function c_taper_strerror(status) bind(C, name="taper_strerror") result(s)
       import :: c_ptr, c_int
       integer(c_int), value :: status
       type(c_ptr) :: s
     end function c_taper_strerror
     function c_taper_profile_name(profile) bind(C, name="taper_profile_name") result(s)
       import :: c_ptr, c_int
       integer(c_int), value :: profile
       type(c_ptr) :: s
     end function c_taper_profile_name
     function c_taper_method_name(method) bind(C, name="taper_method_name") result(s)
       import :: c_ptr, c_int
       integer(c_int), value :: method
       type(c_ptr) :: s
     end function c_taper_method_name
     function c_taper_fit_model_name(model) bind(C, name="taper_fit_model_name") result(s)
       import :: c_ptr, c_int
       integer(c_int), value :: model
       type(c_ptr) :: s
     end function c_taper_fit_model_name
     function c_taper_statistic_name(which) bind(C, name="taper_statistic_name") result(s)
       import :: c_ptr, c_int
       integer(c_int), value :: which
       type(c_ptr) :: s
     end function c_taper_statistic_name
     function c_taper_profile_from_name(name, profile, err) &
          bind(C, name="taper_profile_from_name") result(status)
       import :: c_char, c_int, taper_error
       character(kind=c_char), intent(in) :: name(*)
       integer(c_int), intent(out) :: profile
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function c_taper_profile_from_name
     function c_taper_method_from_name(name, method, err) &
          bind(C, name="taper_method_from_name") result(status)
       import :: c_char, c_int, taper_error
       character(kind=c_char), intent(in) :: name(*)
       integer(c_int), intent(out) :: method
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function c_taper_method_from_name
     function c_taper_fit_model_from_name(name, model, err) &
          bind(C, name="taper_fit_model_from_name") result(status)
       import :: c_char, c_int, taper_error
       character(kind=c_char), intent(in) :: name(*)
       integer(c_int), intent(out) :: model
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function c_taper_fit_model_from_name
     function c_taper_observable_name(which) bind(C, name="taper_observable_name") result(s)
       import :: c_ptr, c_int
       integer(c_int), value :: which
       type(c_ptr) :: s
     end function c_taper_observable_name
     function c_taper_theory_quantity_name(which) bind(C, name="taper_theory_quantity_name") &
          result(s)
       import :: c_ptr, c_int
       integer(c_int), value :: which
       type(c_ptr) :: s
     end function c_taper_theory_quantity_name
     function c_taper_law_name(law) bind(C, name="taper_law_name") result(s)
       import :: c_ptr, c_int
       integer(c_int), value :: law
       type(c_ptr) :: s
     end function c_taper_law_name
     function c_taper_disorder_name(kind) bind(C, name="taper_disorder_name") result(s)
       import :: c_ptr, c_int
       integer(c_int), value :: kind
       type(c_ptr) :: s
     end function c_taper_disorder_name
     function c_taper_boundary_name(boundary) bind(C, name="taper_boundary_name") result(s)
       import :: c_ptr, c_int
       integer(c_int), value :: boundary
       type(c_ptr) :: s
     end function c_taper_boundary_name
     function c_taper_dimension_name(dim) bind(C, name="taper_dimension_name") result(s)
       import :: c_ptr, c_int
       integer(c_int), value :: dim
       type(c_ptr) :: s
     end function c_taper_dimension_name
     function c_taper_dimension_unit(dim) bind(C, name="taper_dimension_unit") result(s)
       import :: c_ptr, c_int
       integer(c_int), value :: dim
       type(c_ptr) :: s
     end function c_taper_dimension_unit
     function c_taper_disorder_from_name(name, kind, err) &
          bind(C, name="taper_disorder_from_name") result(status)
       import :: c_char, c_int, taper_error
       character(kind=c_char), intent(in) :: name(*)
       integer(c_int), intent(out) :: kind
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function c_taper_disorder_from_name
     function c_taper_boundary_from_name(name, boundary, err) &
          bind(C, name="taper_boundary_from_name") result(status)
       import :: c_char, c_int, taper_error
       character(kind=c_char), intent(in) :: name(*)
       integer(c_int), intent(out) :: boundary
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function c_taper_boundary_from_name

     ! ---- chain settings
     function taper_chain_spec_alloc(err) bind(C, name="taper_chain_spec_alloc") result(spec)
       import :: c_ptr, taper_error
       type(taper_error), intent(inout) :: err
       type(c_ptr) :: spec
     end function taper_chain_spec_alloc
     subroutine taper_chain_spec_free(spec) bind(C, name="taper_chain_spec_free")
       import :: c_ptr
       type(c_ptr), value :: spec
     end subroutine taper_chain_spec_free
     function taper_chain_spec_set_profile(spec, profile, err) &
          bind(C, name="taper_chain_spec_set_profile") result(status)
       import :: c_ptr, c_int, taper_error
       type(c_ptr), value :: spec
       integer(c_int), value :: profile
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_chain_spec_set_profile
     function taper_chain_spec_set_n_granules(spec, n, err) &
          bind(C, name="taper_chain_spec_set_n_granules") result(status)
       import :: c_ptr, c_int, c_size_t, taper_error
       type(c_ptr), value :: spec
       integer(c_size_t), value :: n
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_chain_spec_set_n_granules
     function taper_chain_spec_set_s(spec, s, err) bind(C, name="taper_chain_spec_set_s") &
          result(status)
       import :: c_ptr, c_int, c_double, taper_error
       type(c_ptr), value :: spec
       real(c_double), value :: s
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_chain_spec_set_s
     function taper_chain_spec_set_q(spec, q, err) bind(C, name="taper_chain_spec_set_q") &
          result(status)
       import :: c_ptr, c_int, c_double, taper_error
       type(c_ptr), value :: spec
       real(c_double), value :: q
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_chain_spec_set_q
     function taper_chain_spec_set_exponent(spec, exponent, err) &
          bind(C, name="taper_chain_spec_set_exponent") result(status)
       import :: c_ptr, c_int, c_double, taper_error
       type(c_ptr), value :: spec
       real(c_double), value :: exponent
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_chain_spec_set_exponent
     ! Copies n radii; (c_null_ptr, 0) removes them.  radii: c_loc(r(1)).
     function taper_chain_spec_set_radii(spec, radii, n, err) &
          bind(C, name="taper_chain_spec_set_radii") result(status)
       import :: c_ptr, c_int, c_size_t, taper_error
       type(c_ptr), value :: spec, radii
       integer(c_size_t), value :: n
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_chain_spec_set_radii
     function taper_chain_spec_profile(spec) bind(C, name="taper_chain_spec_profile") result(p)
       import :: c_ptr, c_int
       type(c_ptr), value :: spec
       integer(c_int) :: p
     end function taper_chain_spec_profile
     function taper_chain_spec_n_granules(spec) bind(C, name="taper_chain_spec_n_granules") &
          result(n)
       import :: c_ptr, c_size_t
       type(c_ptr), value :: spec
       integer(c_size_t) :: n
     end function taper_chain_spec_n_granules
     function taper_chain_spec_s(spec) bind(C, name="taper_chain_spec_s") result(x)
       import :: c_ptr, c_double
       type(c_ptr), value :: spec
       real(c_double) :: x
     end function taper_chain_spec_s
     function taper_chain_spec_q(spec) bind(C, name="taper_chain_spec_q") result(x)
       import :: c_ptr, c_double
       type(c_ptr), value :: spec
       real(c_double) :: x
     end function taper_chain_spec_q
     function taper_chain_spec_exponent(spec) bind(C, name="taper_chain_spec_exponent") result(x)
       import :: c_ptr, c_double
       type(c_ptr), value :: spec
       real(c_double) :: x
     end function taper_chain_spec_exponent
     function taper_chain_spec_radii(spec, n) bind(C, name="taper_chain_spec_radii") result(a)
       import :: c_ptr, c_size_t
       type(c_ptr), value :: spec
       integer(c_size_t), intent(out) :: n
       type(c_ptr) :: a
     end function taper_chain_spec_radii
     function taper_chain_spec_check(spec, err) bind(C, name="taper_chain_spec_check") &
          result(status)
       import :: c_ptr, c_int, taper_error
       type(c_ptr), value :: spec
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_chain_spec_check

     ! ---- chain settings beyond the paper (ends, striker, load, losses,
     !      materials, decorated profile, disorder); all default to the paper's
     ! Copies p radii of one period (pattern(1) = 1); (c_null_ptr, 0) removes it.
     function taper_chain_spec_set_pattern(spec, pattern, p, err) &
          bind(C, name="taper_chain_spec_set_pattern") result(status)
       import :: c_ptr, c_int, c_size_t, taper_error
       type(c_ptr), value :: spec, pattern
       integer(c_size_t), value :: p
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_chain_spec_set_pattern
     function taper_chain_spec_pattern(spec, p) bind(C, name="taper_chain_spec_pattern") result(a)
       import :: c_ptr, c_size_t
       type(c_ptr), value :: spec
       integer(c_size_t), intent(out) :: p
       type(c_ptr) :: a
     end function taper_chain_spec_pattern
     ! seed: C's uint64_t; Fortran has no unsigned integers, so seeds of
     ! 2^63 and above are passed as their two's-complement negative value.
     function taper_chain_spec_set_disorder(spec, kind, amplitude, seed, err) &
          bind(C, name="taper_chain_spec_set_disorder") result(status)
       import :: c_ptr, c_int, c_double, c_int64_t, taper_error
       type(c_ptr), value :: spec
       integer(c_int), value :: kind
       real(c_double), value :: amplitude
       integer(c_int64_t), value :: seed
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_chain_spec_set_disorder
     function taper_chain_spec_disorder(spec) bind(C, name="taper_chain_spec_disorder") result(k)
       import :: c_ptr, c_int
       type(c_ptr), value :: spec
       integer(c_int) :: k
     end function taper_chain_spec_disorder
     function taper_chain_spec_disorder_amplitude(spec) &
          bind(C, name="taper_chain_spec_disorder_amplitude") result(x)
       import :: c_ptr, c_double
       type(c_ptr), value :: spec
       real(c_double) :: x
     end function taper_chain_spec_disorder_amplitude
     function taper_chain_spec_disorder_seed(spec) bind(C, name="taper_chain_spec_disorder_seed") &
          result(seed)
       import :: c_ptr, c_int64_t
       type(c_ptr), value :: spec
       integer(c_int64_t) :: seed
     end function taper_chain_spec_disorder_seed
     ! density, compliance: c_loc of arrays of n = n_granules values, or
     ! (c_null_ptr, c_null_ptr, 0) for one material.
     function taper_chain_spec_set_materials(spec, density, compliance, n, err) &
          bind(C, name="taper_chain_spec_set_materials") result(status)
       import :: c_ptr, c_int, c_size_t, taper_error
       type(c_ptr), value :: spec, density, compliance
       integer(c_size_t), value :: n
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_chain_spec_set_materials
     ! The materials set (relative to granule 1's), their number n, 0 if none:
     ! call c_f_pointer(density, rho, [n]).
     function taper_chain_spec_materials(spec, density, compliance) &
          bind(C, name="taper_chain_spec_materials") result(n)
       import :: c_ptr, c_size_t
       type(c_ptr), value :: spec
       type(c_ptr), intent(out) :: density, compliance
       integer(c_size_t) :: n
     end function taper_chain_spec_materials
     ! end: TAPER_LEFT or TAPER_RIGHT; boundary: TAPER_END_FREE or TAPER_END_WALL.
     function taper_chain_spec_set_end(spec, end, boundary, compliance, err) &
          bind(C, name="taper_chain_spec_set_end") result(status)
       import :: c_ptr, c_int, c_double, taper_error
       type(c_ptr), value :: spec
       integer(c_int), value :: end, boundary
       real(c_double), value :: compliance
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_chain_spec_set_end
     function taper_chain_spec_end(spec, end) bind(C, name="taper_chain_spec_end") result(b)
       import :: c_ptr, c_int
       type(c_ptr), value :: spec
       integer(c_int), value :: end
       integer(c_int) :: b
     end function taper_chain_spec_end
     function taper_chain_spec_end_compliance(spec, end) &
          bind(C, name="taper_chain_spec_end_compliance") result(x)
       import :: c_ptr, c_int, c_double
       type(c_ptr), value :: spec
       integer(c_int), value :: end
       real(c_double) :: x
     end function taper_chain_spec_end_compliance
     ! A piston pushing granule 1 at unit velocity for 0 <= t <= duration
     ! (ieee_positive_inf: a steady push; 0: none), its face a wall's of the
     ! given compliance.
     function taper_chain_spec_set_piston(spec, duration, compliance, err) &
          bind(C, name="taper_chain_spec_set_piston") result(status)
       import :: c_ptr, c_int, c_double, taper_error
       type(c_ptr), value :: spec
       real(c_double), value :: duration, compliance
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_chain_spec_set_piston
     function taper_chain_spec_piston_duration(spec) bind(C, name="taper_chain_spec_piston_duration") &
          result(x)
       import :: c_ptr, c_double
       type(c_ptr), value :: spec
       real(c_double) :: x
     end function taper_chain_spec_piston_duration
     function taper_chain_spec_piston_compliance(spec) bind(C, name="taper_chain_spec_piston_compliance") &
          result(x)
       import :: c_ptr, c_double
       type(c_ptr), value :: spec
       real(c_double) :: x
     end function taper_chain_spec_piston_compliance
     function taper_chain_spec_set_striker(spec, radius, density, compliance, err) &
          bind(C, name="taper_chain_spec_set_striker") result(status)
       import :: c_ptr, c_int, c_double, taper_error
       type(c_ptr), value :: spec
       real(c_double), value :: radius, density, compliance
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_chain_spec_set_striker
     function taper_chain_spec_striker_radius(spec) &
          bind(C, name="taper_chain_spec_striker_radius") result(x)
       import :: c_ptr, c_double
       type(c_ptr), value :: spec
       real(c_double) :: x
     end function taper_chain_spec_striker_radius
     function taper_chain_spec_striker_density(spec) &
          bind(C, name="taper_chain_spec_striker_density") result(x)
       import :: c_ptr, c_double
       type(c_ptr), value :: spec
       real(c_double) :: x
     end function taper_chain_spec_striker_density
     function taper_chain_spec_striker_compliance(spec) &
          bind(C, name="taper_chain_spec_striker_compliance") result(x)
       import :: c_ptr, c_double
       type(c_ptr), value :: spec
       real(c_double) :: x
     end function taper_chain_spec_striker_compliance
     function taper_chain_spec_set_load(spec, f0, err) bind(C, name="taper_chain_spec_set_load") &
          result(status)
       import :: c_ptr, c_int, c_double, taper_error
       type(c_ptr), value :: spec
       real(c_double), value :: f0
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_chain_spec_set_load
     function taper_chain_spec_load(spec) bind(C, name="taper_chain_spec_load") result(x)
       import :: c_ptr, c_double
       type(c_ptr), value :: spec
       real(c_double) :: x
     end function taper_chain_spec_load
     function taper_chain_spec_set_damping(spec, damping, err) &
          bind(C, name="taper_chain_spec_set_damping") result(status)
       import :: c_ptr, c_int, c_double, taper_error
       type(c_ptr), value :: spec
       real(c_double), value :: damping
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_chain_spec_set_damping
     function taper_chain_spec_damping(spec) bind(C, name="taper_chain_spec_damping") result(x)
       import :: c_ptr, c_double
       type(c_ptr), value :: spec
       real(c_double) :: x
     end function taper_chain_spec_damping
     function taper_chain_spec_set_drag(spec, drag, err) bind(C, name="taper_chain_spec_set_drag") &
          result(status)
       import :: c_ptr, c_int, c_double, taper_error
       type(c_ptr), value :: spec
       real(c_double), value :: drag
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_chain_spec_set_drag
     function taper_chain_spec_drag(spec) bind(C, name="taper_chain_spec_drag") result(x)
       import :: c_ptr, c_double
       type(c_ptr), value :: spec
       real(c_double) :: x
     end function taper_chain_spec_drag

     ! ---- chains
     function taper_chain_alloc(spec, err) bind(C, name="taper_chain_alloc") result(chain)
       import :: c_ptr, taper_error
       type(c_ptr), value :: spec
       type(taper_error), intent(inout) :: err
       type(c_ptr) :: chain
     end function taper_chain_alloc
     subroutine taper_chain_free(chain) bind(C, name="taper_chain_free")
       import :: c_ptr
       type(c_ptr), value :: chain
     end subroutine taper_chain_free
     function taper_chain_size(chain) bind(C, name="taper_chain_size") result(n)
       import :: c_ptr, c_size_t
       type(c_ptr), value :: chain
       integer(c_size_t) :: n
     end function taper_chain_size
     function taper_chain_exponent(chain) bind(C, name="taper_chain_exponent") result(n)
       import :: c_ptr, c_double
       type(c_ptr), value :: chain
       real(c_double) :: n
     end function taper_chain_exponent
     function taper_chain_profile(chain) bind(C, name="taper_chain_profile") result(p)
       import :: c_ptr, c_int
       type(c_ptr), value :: chain
       integer(c_int) :: p
     end function taper_chain_profile
     function taper_chain_radius(chain) bind(C, name="taper_chain_radius") result(a)
       import :: c_ptr
       type(c_ptr), value :: chain
       type(c_ptr) :: a
     end function taper_chain_radius
     function taper_chain_mass(chain) bind(C, name="taper_chain_mass") result(a)
       import :: c_ptr
       type(c_ptr), value :: chain
       type(c_ptr) :: a
     end function taper_chain_mass
     function taper_chain_contact(chain) bind(C, name="taper_chain_contact") result(a)
       import :: c_ptr
       type(c_ptr), value :: chain
       type(c_ptr) :: a
     end function taper_chain_contact
     function taper_chain_rest_position(chain) bind(C, name="taper_chain_rest_position") result(a)
       import :: c_ptr
       type(c_ptr), value :: chain
       type(c_ptr) :: a
     end function taper_chain_rest_position
     ! What the options made of the chain (NaN where absent).
     function taper_chain_end(chain, end) bind(C, name="taper_chain_end") result(b)
       import :: c_ptr, c_int
       type(c_ptr), value :: chain
       integer(c_int), value :: end
       integer(c_int) :: b
     end function taper_chain_end
     function taper_chain_end_contact(chain, end) bind(C, name="taper_chain_end_contact") result(x)
       import :: c_ptr, c_int, c_double
       type(c_ptr), value :: chain
       integer(c_int), value :: end
       real(c_double) :: x
     end function taper_chain_end_contact
     function taper_chain_striker_radius(chain) bind(C, name="taper_chain_striker_radius") result(x)
       import :: c_ptr, c_double
       type(c_ptr), value :: chain
       real(c_double) :: x
     end function taper_chain_striker_radius
     function taper_chain_striker_mass(chain) bind(C, name="taper_chain_striker_mass") result(x)
       import :: c_ptr, c_double
       type(c_ptr), value :: chain
       real(c_double) :: x
     end function taper_chain_striker_mass
     function taper_chain_striker_contact(chain) bind(C, name="taper_chain_striker_contact") &
          result(x)
       import :: c_ptr, c_double
       type(c_ptr), value :: chain
       real(c_double) :: x
     end function taper_chain_striker_contact
     function taper_chain_piston_duration(chain) bind(C, name="taper_chain_piston_duration") &
          result(x)
       import :: c_ptr, c_double
       type(c_ptr), value :: chain
       real(c_double) :: x
     end function taper_chain_piston_duration
     function taper_chain_piston_contact(chain) bind(C, name="taper_chain_piston_contact") &
          result(x)
       import :: c_ptr, c_double
       type(c_ptr), value :: chain
       real(c_double) :: x
     end function taper_chain_piston_contact
     function taper_chain_load(chain) bind(C, name="taper_chain_load") result(x)
       import :: c_ptr, c_double
       type(c_ptr), value :: chain
       real(c_double) :: x
     end function taper_chain_load
     function taper_chain_damping(chain) bind(C, name="taper_chain_damping") result(x)
       import :: c_ptr, c_double
       type(c_ptr), value :: chain
       real(c_double) :: x
     end function taper_chain_damping
     function taper_chain_drag(chain) bind(C, name="taper_chain_drag") result(x)
       import :: c_ptr, c_double
       type(c_ptr), value :: chain
       real(c_double) :: x
     end function taper_chain_drag
     ! NULL (c_string: '') when the binary collision theory describes the
     ! chain, else why not (taper_chain_theory_note below).
     function c_taper_chain_theory_note(chain) bind(C, name="taper_chain_theory_note") result(s)
       import :: c_ptr
       type(c_ptr), value :: chain
       type(c_ptr) :: s
     end function c_taper_chain_theory_note

     ! ---- real units (Hertz, n = 5/2): SI value of one rescaled unit of dim
     function taper_unit_scale(dim, young, poisson, density, radius, velocity) &
          bind(C, name="taper_unit_scale") result(x)
       import :: c_int, c_double
       integer(c_int), value :: dim
       real(c_double), value :: young, poisson, density, radius, velocity
       real(c_double) :: x
     end function taper_unit_scale

     ! ---- the equations of motion for one's own integrator (state of length 2N:
     ! v_k at y(2k-1), z_k at y(2k) in Fortran's numbering)
     function taper_dynamics_alloc(chain, err) bind(C, name="taper_dynamics_alloc") result(dyn)
       import :: c_ptr, taper_error
       type(c_ptr), value :: chain
       type(taper_error), intent(inout) :: err
       type(c_ptr) :: dyn
     end function taper_dynamics_alloc
     subroutine taper_dynamics_free(dyn) bind(C, name="taper_dynamics_free")
       import :: c_ptr
       type(c_ptr), value :: dyn
     end subroutine taper_dynamics_free
     subroutine taper_dynamics_rhs(dyn, y, ydot) bind(C, name="taper_dynamics_rhs")
       import :: c_ptr, c_double
       type(c_ptr), value :: dyn
       real(c_double), intent(in) :: y(*)
       real(c_double), intent(out) :: ydot(*)
     end subroutine taper_dynamics_rhs
     subroutine taper_dynamics_energy_momentum(dyn, y, energy, momentum) &
          bind(C, name="taper_dynamics_energy_momentum")
       import :: c_ptr, c_double
       type(c_ptr), value :: dyn
       real(c_double), intent(in) :: y(*)
       real(c_double), intent(out) :: energy, momentum
     end subroutine taper_dynamics_energy_momentum
     function taper_dynamics_peak_function(dyn, y, k) &
          bind(C, name="taper_dynamics_peak_function") result(g)
       import :: c_ptr, c_double, c_size_t
       type(c_ptr), value :: dyn
       real(c_double), intent(in) :: y(*)
       integer(c_size_t), value :: k
       real(c_double) :: g
     end function taper_dynamics_peak_function

     ! ---- binary collision theory
     function taper_theory_collision_time(mu, r, zdot0, n) &
          bind(C, name="taper_theory_collision_time") result(t)
       import :: c_double
       real(c_double), value :: mu, r, zdot0, n
       real(c_double) :: t
     end function taper_theory_collision_time
     ! v, mu, T (res_time), t (pass_time): c_loc of arrays of length N, or
     ! c_null_ptr to skip.
     function taper_theory_compute(chain, v, mu, res_time, pass_time, err) &
          bind(C, name="taper_theory_compute") result(status)
       import :: c_ptr, c_int, taper_error
       type(c_ptr), value :: chain, v, mu, res_time, pass_time
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_theory_compute
     ! monitor: c_funloc of a bind(C) function, or c_null_funptr
     function taper_theory_compute_monitored(chain, v, mu, res_time, pass_time, monitor, user, &
          err) bind(C, name="taper_theory_compute_monitored") result(status)
       import :: c_ptr, c_funptr, c_int, taper_error
       type(c_ptr), value :: chain, v, mu, res_time, pass_time
       type(c_funptr), value :: monitor
       type(c_ptr), value :: user
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_theory_compute_monitored

     ! ---- solver settings
     function taper_solver_spec_alloc(err) bind(C, name="taper_solver_spec_alloc") result(spec)
       import :: c_ptr, taper_error
       type(taper_error), intent(inout) :: err
       type(c_ptr) :: spec
     end function taper_solver_spec_alloc
     subroutine taper_solver_spec_free(spec) bind(C, name="taper_solver_spec_free")
       import :: c_ptr
       type(c_ptr), value :: spec
     end subroutine taper_solver_spec_free
     function taper_solver_spec_set_method(spec, method, err) &
          bind(C, name="taper_solver_spec_set_method") result(status)
       import :: c_ptr, c_int, taper_error
       type(c_ptr), value :: spec
       integer(c_int), value :: method
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_solver_spec_set_method
     function taper_solver_spec_set_rtol(spec, rtol, err) &
          bind(C, name="taper_solver_spec_set_rtol") result(status)
       import :: c_ptr, c_int, c_double, taper_error
       type(c_ptr), value :: spec
       real(c_double), value :: rtol
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_solver_spec_set_rtol
     function taper_solver_spec_set_atol(spec, atol, err) &
          bind(C, name="taper_solver_spec_set_atol") result(status)
       import :: c_ptr, c_int, c_double, taper_error
       type(c_ptr), value :: spec
       real(c_double), value :: atol
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_solver_spec_set_atol
     function taper_solver_spec_set_last_granule(spec, last_granule, err) &
          bind(C, name="taper_solver_spec_set_last_granule") result(status)
       import :: c_ptr, c_int, c_size_t, taper_error
       type(c_ptr), value :: spec
       integer(c_size_t), value :: last_granule
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_solver_spec_set_last_granule
     function taper_solver_spec_set_window(spec, window, err) &
          bind(C, name="taper_solver_spec_set_window") result(status)
       import :: c_ptr, c_int, taper_error
       type(c_ptr), value :: spec
       integer(c_int), value :: window
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_solver_spec_set_window
     function taper_solver_spec_set_max_order(spec, max_order, err) &
          bind(C, name="taper_solver_spec_set_max_order") result(status)
       import :: c_ptr, c_int, taper_error
       type(c_ptr), value :: spec
       integer(c_int), value :: max_order
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_solver_spec_set_max_order
     function taper_solver_spec_set_t_max(spec, t_max, err) &
          bind(C, name="taper_solver_spec_set_t_max") result(status)
       import :: c_ptr, c_int, c_double, taper_error
       type(c_ptr), value :: spec
       real(c_double), value :: t_max
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_solver_spec_set_t_max
     function taper_solver_spec_set_max_steps(spec, max_steps, err) &
          bind(C, name="taper_solver_spec_set_max_steps") result(status)
       import :: c_ptr, c_int, c_long, taper_error
       type(c_ptr), value :: spec
       integer(c_long), value :: max_steps
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_solver_spec_set_max_steps
     function taper_solver_spec_set_t_end(spec, t_end, err) &
          bind(C, name="taper_solver_spec_set_t_end") result(status)
       import :: c_ptr, c_int, c_double, taper_error
       type(c_ptr), value :: spec
       real(c_double), value :: t_end
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_solver_spec_set_t_end
     function taper_solver_spec_t_end(spec) bind(C, name="taper_solver_spec_t_end") result(x)
       import :: c_ptr, c_double
       type(c_ptr), value :: spec
       real(c_double) :: x
     end function taper_solver_spec_t_end
     ! fn: c_funloc of a bind(C) function (c_null_funptr removes the sampler)
     !   integer(c_int) function f(sim, user) bind(C)
     !     type(c_ptr), value :: sim, user
     ! called at t = 0, interval, 2 interval, ...; inside it taper_sim_time,
     ! taper_sim_state, taper_sim_striker_state and taper_sim_forces read the
     ! state at the sample time; non-zero stops the run.
     function taper_solver_spec_set_sampler(spec, interval, fn, user, err) &
          bind(C, name="taper_solver_spec_set_sampler") result(status)
       import :: c_ptr, c_funptr, c_int, c_double, taper_error
       type(c_ptr), value :: spec
       real(c_double), value :: interval
       type(c_funptr), value :: fn
       type(c_ptr), value :: user
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_solver_spec_set_sampler
     function taper_solver_spec_sample_interval(spec) &
          bind(C, name="taper_solver_spec_sample_interval") result(x)
       import :: c_ptr, c_double
       type(c_ptr), value :: spec
       real(c_double) :: x
     end function taper_solver_spec_sample_interval
     ! monitor: c_funloc of a bind(C) function
     !   integer(c_int) function f(progress, user) bind(C)
     !     type(taper_progress), intent(in) :: progress; type(c_ptr), value :: user
     ! log: c_funloc of a bind(C) subroutine
     !   subroutine g(level, message, user) bind(C)
     !     integer(c_int), value :: level; type(c_ptr), value :: message, user
     ! Either c_null_funptr for none.
     subroutine taper_solver_spec_set_monitor(spec, monitor, user) &
          bind(C, name="taper_solver_spec_set_monitor")
       import :: c_ptr, c_funptr
       type(c_ptr), value :: spec
       type(c_funptr), value :: monitor
       type(c_ptr), value :: user
     end subroutine taper_solver_spec_set_monitor
     subroutine taper_solver_spec_set_log(spec, log, user) bind(C, name="taper_solver_spec_set_log")
       import :: c_ptr, c_funptr
       type(c_ptr), value :: spec
       type(c_funptr), value :: log
       type(c_ptr), value :: user
     end subroutine taper_solver_spec_set_log
     function taper_solver_spec_method(spec) bind(C, name="taper_solver_spec_method") result(m)
       import :: c_ptr, c_int
       type(c_ptr), value :: spec
       integer(c_int) :: m
     end function taper_solver_spec_method
     function taper_solver_spec_rtol(spec) bind(C, name="taper_solver_spec_rtol") result(x)
       import :: c_ptr, c_double
       type(c_ptr), value :: spec
       real(c_double) :: x
     end function taper_solver_spec_rtol
     function taper_solver_spec_atol(spec) bind(C, name="taper_solver_spec_atol") result(x)
       import :: c_ptr, c_double
       type(c_ptr), value :: spec
       real(c_double) :: x
     end function taper_solver_spec_atol
     function taper_solver_spec_last_granule(spec) &
          bind(C, name="taper_solver_spec_last_granule") result(n)
       import :: c_ptr, c_size_t
       type(c_ptr), value :: spec
       integer(c_size_t) :: n
     end function taper_solver_spec_last_granule
     function taper_solver_spec_window(spec) bind(C, name="taper_solver_spec_window") result(w)
       import :: c_ptr, c_int
       type(c_ptr), value :: spec
       integer(c_int) :: w
     end function taper_solver_spec_window
     function taper_solver_spec_max_order(spec) bind(C, name="taper_solver_spec_max_order") &
          result(q)
       import :: c_ptr, c_int
       type(c_ptr), value :: spec
       integer(c_int) :: q
     end function taper_solver_spec_max_order
     function taper_solver_spec_t_max(spec) bind(C, name="taper_solver_spec_t_max") result(x)
       import :: c_ptr, c_double
       type(c_ptr), value :: spec
       real(c_double) :: x
     end function taper_solver_spec_t_max
     function taper_solver_spec_max_steps(spec) bind(C, name="taper_solver_spec_max_steps") &
          result(n)
       import :: c_ptr, c_long
       type(c_ptr), value :: spec
       integer(c_long) :: n
     end function taper_solver_spec_max_steps

     ! ---- simulations
     ! spec: a solver spec, or c_null_ptr for the defaults.
     function taper_sim_alloc(chain, spec, err) bind(C, name="taper_sim_alloc") result(sim)
       import :: c_ptr, taper_error
       type(c_ptr), value :: chain, spec
       type(taper_error), intent(inout) :: err
       type(c_ptr) :: sim
     end function taper_sim_alloc
     subroutine taper_sim_free(sim) bind(C, name="taper_sim_free")
       import :: c_ptr
       type(c_ptr), value :: sim
     end subroutine taper_sim_free
     function taper_sim_run(sim, err) bind(C, name="taper_sim_run") result(status)
       import :: c_ptr, c_int, taper_error
       type(c_ptr), value :: sim
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_sim_run
     function taper_sim_observable(sim, which) bind(C, name="taper_sim_observable") result(a)
       import :: c_ptr, c_int
       type(c_ptr), value :: sim
       integer(c_int), value :: which
       type(c_ptr) :: a
     end function taper_sim_observable
     function taper_sim_theory(sim, which) bind(C, name="taper_sim_theory") result(a)
       import :: c_ptr, c_int
       type(c_ptr), value :: sim
       integer(c_int), value :: which
       type(c_ptr) :: a
     end function taper_sim_theory
     function taper_sim_statistic(sim, which) bind(C, name="taper_sim_statistic") result(x)
       import :: c_ptr, c_int, c_double
       type(c_ptr), value :: sim
       integer(c_int), value :: which
       real(c_double) :: x
     end function taper_sim_statistic
     ! x, v: c_loc of arrays of length N, or c_null_ptr.
     function taper_sim_state(sim, x, v, err) bind(C, name="taper_sim_state") result(status)
       import :: c_ptr, c_int, taper_error
       type(c_ptr), value :: sim, x, v
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_sim_state
     function taper_sim_time(sim) bind(C, name="taper_sim_time") result(t)
       import :: c_ptr, c_double
       type(c_ptr), value :: sim
       real(c_double) :: t
     end function taper_sim_time
     ! The piston's work until t_final (NaN: no piston, or not run).
     function taper_sim_piston_work(sim) bind(C, name="taper_sim_piston_work") &
          result(x)
       import :: c_ptr, c_double
       type(c_ptr), value :: sim
       real(c_double) :: x
     end function taper_sim_piston_work
     ! x, v: the striker's displacement and velocity (TAPER_EINVAL if none).
     function taper_sim_striker_state(sim, x, v, err) bind(C, name="taper_sim_striker_state") &
          result(status)
       import :: c_ptr, c_int, c_double, taper_error
       type(c_ptr), value :: sim
       real(c_double), intent(out) :: x, v
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_sim_striker_state
     ! force: an array of N + 1 values, force(1) on granule 1 from the left,
     ! force(k + 1) of the contact (k, k+1), force(N + 1) on granule N from
     ! the right (C's force[0..N]).
     function taper_sim_forces(sim, force, err) bind(C, name="taper_sim_forces") result(status)
       import :: c_ptr, c_int, c_double, taper_error
       type(c_ptr), value :: sim
       real(c_double), intent(out) :: force(*)
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_sim_forces

     ! ---- asymptotic laws
     function taper_asymptotic_exponent(law, n) bind(C, name="taper_asymptotic_exponent") result(p)
       import :: c_int, c_double
       integer(c_int), value :: law
       real(c_double), value :: n
       real(c_double) :: p
     end function taper_asymptotic_exponent
     function taper_asymptotic_A(q) bind(C, name="taper_asymptotic_A") result(y)
       import :: c_double
       real(c_double), value :: q
       real(c_double) :: y
     end function taper_asymptotic_A
     function taper_asymptotic_lnA(q) bind(C, name="taper_asymptotic_lnA") result(y)
       import :: c_double
       real(c_double), value :: q
       real(c_double) :: y
     end function taper_asymptotic_lnA
     function taper_asymptotic_eta(q, n) bind(C, name="taper_asymptotic_eta") result(y)
       import :: c_double
       real(c_double), value :: q, n
       real(c_double) :: y
     end function taper_asymptotic_eta
     function taper_asymptotic_f(q, n) bind(C, name="taper_asymptotic_f") result(y)
       import :: c_double
       real(c_double), value :: q, n
       real(c_double) :: y
     end function taper_asymptotic_f
     function taper_asymptotic_position_exponent(q, n) &
          bind(C, name="taper_asymptotic_position_exponent") result(y)
       import :: c_double
       real(c_double), value :: q, n
       real(c_double) :: y
     end function taper_asymptotic_position_exponent
     function taper_asymptotic_speed_exponent(q, n) &
          bind(C, name="taper_asymptotic_speed_exponent") result(y)
       import :: c_double
       real(c_double), value :: q, n
       real(c_double) :: y
     end function taper_asymptotic_speed_exponent
     function taper_asymptotic_timescale(q, n) bind(C, name="taper_asymptotic_timescale") result(y)
       import :: c_double
       real(c_double), value :: q, n
       real(c_double) :: y
     end function taper_asymptotic_timescale
     function taper_asymptotic_M(q, n) bind(C, name="taper_asymptotic_M") result(y)
       import :: c_double
       real(c_double), value :: q, n
       real(c_double) :: y
     end function taper_asymptotic_M
     function taper_asymptotic_C0(S, n) bind(C, name="taper_asymptotic_C0") result(y)
       import :: c_double
       real(c_double), value :: S, n
       real(c_double) :: y
     end function taper_asymptotic_C0
     function taper_asymptotic_C(S, n) bind(C, name="taper_asymptotic_C") result(y)
       import :: c_double
       real(c_double), value :: S, n
       real(c_double) :: y
     end function taper_asymptotic_C
     function taper_asymptotic_forward_linear_b(S) &
          bind(C, name="taper_asymptotic_forward_linear_b") result(y)
       import :: c_double
       real(c_double), value :: S
       real(c_double) :: y
     end function taper_asymptotic_forward_linear_b

     ! ---- fits
     function taper_fit_spec_alloc(model, err) bind(C, name="taper_fit_spec_alloc") result(spec)
       import :: c_ptr, c_int, taper_error
       integer(c_int), value :: model
       type(taper_error), intent(inout) :: err
       type(c_ptr) :: spec
     end function taper_fit_spec_alloc
     subroutine taper_fit_spec_free(spec) bind(C, name="taper_fit_spec_free")
       import :: c_ptr
       type(c_ptr), value :: spec
     end subroutine taper_fit_spec_free
     function taper_fit_spec_set_exponent(spec, p, err) &
          bind(C, name="taper_fit_spec_set_exponent") result(status)
       import :: c_ptr, c_int, c_double, taper_error
       type(c_ptr), value :: spec
       real(c_double), value :: p
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_fit_spec_set_exponent
     ! Points begin <= i < end, C (0-based) indices; end 0: to the end.
     function taper_fit_spec_set_index_window(spec, begin, end, err) &
          bind(C, name="taper_fit_spec_set_index_window") result(status)
       import :: c_ptr, c_int, c_size_t, taper_error
       type(c_ptr), value :: spec
       integer(c_size_t), value :: begin, end
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_fit_spec_set_index_window
     function taper_fit_spec_set_x_window(spec, x_min, x_max, err) &
          bind(C, name="taper_fit_spec_set_x_window") result(status)
       import :: c_ptr, c_int, c_double, taper_error
       type(c_ptr), value :: spec
       real(c_double), value :: x_min, x_max
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_fit_spec_set_x_window
     function taper_fit_spec_set_skip_invalid(spec, skip, err) &
          bind(C, name="taper_fit_spec_set_skip_invalid") result(status)
       import :: c_ptr, c_int, taper_error
       type(c_ptr), value :: spec
       integer(c_int), value :: skip
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_fit_spec_set_skip_invalid
     function taper_fit_spec_set_max_iter(spec, max_iter, err) &
          bind(C, name="taper_fit_spec_set_max_iter") result(status)
       import :: c_ptr, c_int, c_size_t, taper_error
       type(c_ptr), value :: spec
       integer(c_size_t), value :: max_iter
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_fit_spec_set_max_iter
     function taper_fit_spec_set_xtol(spec, xtol, err) bind(C, name="taper_fit_spec_set_xtol") &
          result(status)
       import :: c_ptr, c_int, c_double, taper_error
       type(c_ptr), value :: spec
       real(c_double), value :: xtol
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_fit_spec_set_xtol
     function taper_fit_spec_model(spec) bind(C, name="taper_fit_spec_model") result(m)
       import :: c_ptr, c_int
       type(c_ptr), value :: spec
       integer(c_int) :: m
     end function taper_fit_spec_model
     function taper_fit_spec_exponent(spec) bind(C, name="taper_fit_spec_exponent") result(p)
       import :: c_ptr, c_double
       type(c_ptr), value :: spec
       real(c_double) :: p
     end function taper_fit_spec_exponent
     function taper_fit(spec, x, y, n, err) bind(C, name="taper_fit") result(res)
       import :: c_ptr, c_double, c_size_t, taper_error
       type(c_ptr), value :: spec
       real(c_double), intent(in) :: x(*), y(*)
       integer(c_size_t), value :: n
       type(taper_error), intent(inout) :: err
       type(c_ptr) :: res
     end function taper_fit
     subroutine taper_fit_result_free(res) bind(C, name="taper_fit_result_free")
       import :: c_ptr
       type(c_ptr), value :: res
     end subroutine taper_fit_result_free
     function taper_fit_result_model(res) bind(C, name="taper_fit_result_model") result(m)
       import :: c_ptr, c_int
       type(c_ptr), value :: res
       integer(c_int) :: m
     end function taper_fit_result_model
     function taper_fit_result_n_params(res) bind(C, name="taper_fit_result_n_params") result(n)
       import :: c_ptr, c_size_t
       type(c_ptr), value :: res
       integer(c_size_t) :: n
     end function taper_fit_result_n_params
     ! Parameter i, 0-based as in C (0: a; 1: b, C or M; 2: p or f).
     function taper_fit_result_param(res, i) bind(C, name="taper_fit_result_param") result(x)
       import :: c_ptr, c_size_t, c_double
       type(c_ptr), value :: res
       integer(c_size_t), value :: i
       real(c_double) :: x
     end function taper_fit_result_param
     function taper_fit_result_param_error(res, i) bind(C, name="taper_fit_result_param_error") &
          result(x)
       import :: c_ptr, c_size_t, c_double
       type(c_ptr), value :: res
       integer(c_size_t), value :: i
       real(c_double) :: x
     end function taper_fit_result_param_error
     function taper_fit_result_n_points(res) bind(C, name="taper_fit_result_n_points") result(n)
       import :: c_ptr, c_size_t
       type(c_ptr), value :: res
       integer(c_size_t) :: n
     end function taper_fit_result_n_points
     function taper_fit_result_n_skipped(res) bind(C, name="taper_fit_result_n_skipped") result(n)
       import :: c_ptr, c_size_t
       type(c_ptr), value :: res
       integer(c_size_t) :: n
     end function taper_fit_result_n_skipped
     function taper_fit_result_chi2(res) bind(C, name="taper_fit_result_chi2") result(x)
       import :: c_ptr, c_double
       type(c_ptr), value :: res
       real(c_double) :: x
     end function taper_fit_result_chi2
     function taper_fit_result_iterations(res) bind(C, name="taper_fit_result_iterations") &
          result(n)
       import :: c_ptr, c_size_t
       type(c_ptr), value :: res
       integer(c_size_t) :: n
     end function taper_fit_result_iterations
     ! ---- the dimension of each quantity (its SI unit: taper_dimension_unit)
     function taper_statistic_dimension(which) bind(C, name="taper_statistic_dimension") &
          result(dim)
       import :: c_int
       integer(c_int), value :: which
       integer(c_int) :: dim
     end function taper_statistic_dimension
     function taper_observable_dimension(which) bind(C, name="taper_observable_dimension") &
          result(dim)
       import :: c_int
       integer(c_int), value :: which
       integer(c_int) :: dim
     end function taper_observable_dimension
     function taper_theory_quantity_dimension(which) &
          bind(C, name="taper_theory_quantity_dimension") result(dim)
       import :: c_int
       integer(c_int), value :: which
       integer(c_int) :: dim
     end function taper_theory_quantity_dimension
     ! ---- the table of settings and settings by name ---------------------------
     function c_taper_status_name(status) bind(C, name="taper_status_name") result(s)
       import :: c_ptr, c_int
       integer(c_int), value :: status
       type(c_ptr) :: s
     end function c_taper_status_name
     function c_taper_nearest_name(name, names, n) bind(C, name="taper_nearest_name") result(s)
       import :: c_ptr, c_char, c_size_t
       character(kind=c_char), intent(in) :: name(*)
       type(c_ptr), value :: names
       integer(c_size_t), value :: n
       type(c_ptr) :: s
     end function c_taper_nearest_name
     function taper_setting_count() bind(C, name="taper_setting_count") result(n)
       import :: c_size_t
       integer(c_size_t) :: n
     end function taper_setting_count
     function taper_setting_at(i) bind(C, name="taper_setting_at") result(row)
       import :: c_ptr, c_size_t
       integer(c_size_t), value :: i
       type(c_ptr) :: row
     end function taper_setting_at
     function c_taper_setting_find(name, err) bind(C, name="taper_setting_find") result(row)
       import :: c_ptr, c_char, taper_error
       character(kind=c_char), intent(in) :: name(*)
       type(taper_error), intent(inout) :: err
       type(c_ptr) :: row
     end function c_taper_setting_find
     function c_taper_chain_spec_set_option(spec, name, value, err) &
          bind(C, name="taper_chain_spec_set_option") result(status)
       import :: c_ptr, c_char, c_double, c_int, taper_error
       type(c_ptr), value :: spec
       character(kind=c_char), intent(in) :: name(*)
       real(c_double), value :: value
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function c_taper_chain_spec_set_option
     function c_taper_chain_spec_set_option_text(spec, name, value, err) &
          bind(C, name="taper_chain_spec_set_option_text") result(status)
       import :: c_ptr, c_char, c_int, taper_error
       type(c_ptr), value :: spec
       character(kind=c_char), intent(in) :: name(*), value(*)
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function c_taper_chain_spec_set_option_text
     function c_taper_chain_spec_set_option_list(spec, name, values, n, err) &
          bind(C, name="taper_chain_spec_set_option_list") result(status)
       import :: c_ptr, c_char, c_size_t, c_int, taper_error
       type(c_ptr), value :: spec, values
       character(kind=c_char), intent(in) :: name(*)
       integer(c_size_t), value :: n
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function c_taper_chain_spec_set_option_list
     function c_taper_solver_spec_set_option(spec, name, value, err) &
          bind(C, name="taper_solver_spec_set_option") result(status)
       import :: c_ptr, c_char, c_double, c_int, taper_error
       type(c_ptr), value :: spec
       character(kind=c_char), intent(in) :: name(*)
       real(c_double), value :: value
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function c_taper_solver_spec_set_option
     function c_taper_solver_spec_set_option_text(spec, name, value, err) &
          bind(C, name="taper_solver_spec_set_option_text") result(status)
       import :: c_ptr, c_char, c_int, taper_error
       type(c_ptr), value :: spec
       character(kind=c_char), intent(in) :: name(*), value(*)
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function c_taper_solver_spec_set_option_text
     function c_taper_chain_spec_option(spec, name) bind(C, name="taper_chain_spec_option") &
          result(value)
       import :: c_ptr, c_char, c_double
       type(c_ptr), value :: spec
       character(kind=c_char), intent(in) :: name(*)
       real(c_double) :: value
     end function c_taper_chain_spec_option
     function c_taper_chain_spec_option_list(spec, name, n) &
          bind(C, name="taper_chain_spec_option_list") result(values)
       import :: c_ptr, c_char, c_size_t
       type(c_ptr), value :: spec
       character(kind=c_char), intent(in) :: name(*)
       integer(c_size_t), intent(out) :: n
       type(c_ptr) :: values
     end function c_taper_chain_spec_option_list
     function c_taper_solver_spec_option(spec, name) bind(C, name="taper_solver_spec_option") &
          result(value)
       import :: c_ptr, c_char, c_double
       type(c_ptr), value :: spec
       character(kind=c_char), intent(in) :: name(*)
       real(c_double) :: value
     end function c_taper_solver_spec_option
  end interface

contains

  ! A NUL-terminated C string as a Fortran string ('' for NULL).
  function c_string(p) result(s)
    type(c_ptr), intent(in) :: p
    character(len=:), allocatable :: s
    character(kind=c_char), pointer :: chars(:)
    integer :: n
    interface
       function strlen(str) bind(C, name="strlen") result(len)
         import :: c_ptr, c_size_t
         type(c_ptr), value :: str
         integer(c_size_t) :: len
       end function strlen
    end interface
    if (.not. c_associated(p)) then
       s = ""
       return
    end if
    n = int(strlen(p))
    call c_f_pointer(p, chars, [n])
    allocate (character(len=n) :: s)
    s = transfer(chars, s)
  end function c_string

  ! The version of the loaded library (TAPER_VERSION_STRING of the header it was
  ! built from, when the program runs with the library it was built with).
  function taper_version() result(s)
    character(len=:), allocatable :: s
    s = c_string(c_taper_version())
  end function taper_version

  function taper_strerror(status) result(s)
    integer(c_int), intent(in) :: status
    character(len=:), allocatable :: s
    s = c_string(c_taper_strerror(status))
  end function taper_strerror

  ! The library's names ("backward_linear", "bdf", "divergence_c", "steps");
  ! '' outside the enum, so that a loop from 0 until '' walks each list.
  function taper_profile_name(profile) result(s)
    integer(c_int), intent(in) :: profile
    character(len=:), allocatable :: s
    s = c_string(c_taper_profile_name(profile))
  end function taper_profile_name

  function taper_method_name(method) result(s)
    integer(c_int), intent(in) :: method
    character(len=:), allocatable :: s
    s = c_string(c_taper_method_name(method))
  end function taper_method_name

  function taper_fit_model_name(model) result(s)
    integer(c_int), intent(in) :: model
    character(len=:), allocatable :: s
    s = c_string(c_taper_fit_model_name(model))
  end function taper_fit_model_name

  function taper_statistic_name(which) result(s)
    integer(c_int), intent(in) :: which
    character(len=:), allocatable :: s
    s = c_string(c_taper_statistic_name(which))
  end function taper_statistic_name

  ! Case-insensitive inverses (trailing blanks ignored): TAPER_OK, or
  ! TAPER_EINVAL with err naming the field ("profile", "method", "model").
  function taper_profile_from_name(name, profile, err) result(status)
    character(len=*), intent(in) :: name
    integer(c_int), intent(out) :: profile
    type(taper_error), intent(inout) :: err
    integer(c_int) :: status
    status = c_taper_profile_from_name(trim(name)//c_null_char, profile, err)
  end function taper_profile_from_name

  function taper_method_from_name(name, method, err) result(status)
    character(len=*), intent(in) :: name
    integer(c_int), intent(out) :: method
    type(taper_error), intent(inout) :: err
    integer(c_int) :: status
    status = c_taper_method_from_name(trim(name)//c_null_char, method, err)
  end function taper_method_from_name

  function taper_fit_model_from_name(name, model, err) result(status)
    character(len=*), intent(in) :: name
    integer(c_int), intent(out) :: model
    type(taper_error), intent(inout) :: err
    integer(c_int) :: status
    status = c_taper_fit_model_from_name(trim(name)//c_null_char, model, err)
  end function taper_fit_model_from_name

  ! "t_pass", ...; "v", "mu", "T", "t"; "v_of_k", ... ('' outside each enum).
  function taper_observable_name(which) result(s)
    integer(c_int), intent(in) :: which
    character(len=:), allocatable :: s
    s = c_string(c_taper_observable_name(which))
  end function taper_observable_name

  function taper_theory_quantity_name(which) result(s)
    integer(c_int), intent(in) :: which
    character(len=:), allocatable :: s
    s = c_string(c_taper_theory_quantity_name(which))
  end function taper_theory_quantity_name

  function taper_law_name(law) result(s)
    integer(c_int), intent(in) :: law
    character(len=:), allocatable :: s
    s = c_string(c_taper_law_name(law))
  end function taper_law_name

  ! "radius", "mass"; "free", "wall"; "length", ... and its SI unit "m", ...
  ! ('' outside each enum).
  function taper_disorder_name(kind) result(s)
    integer(c_int), intent(in) :: kind
    character(len=:), allocatable :: s
    s = c_string(c_taper_disorder_name(kind))
  end function taper_disorder_name

  function taper_boundary_name(boundary) result(s)
    integer(c_int), intent(in) :: boundary
    character(len=:), allocatable :: s
    s = c_string(c_taper_boundary_name(boundary))
  end function taper_boundary_name

  function taper_dimension_name(dim) result(s)
    integer(c_int), intent(in) :: dim
    character(len=:), allocatable :: s
    s = c_string(c_taper_dimension_name(dim))
  end function taper_dimension_name

  function taper_dimension_unit(dim) result(s)
    integer(c_int), intent(in) :: dim
    character(len=:), allocatable :: s
    s = c_string(c_taper_dimension_unit(dim))
  end function taper_dimension_unit

  function taper_disorder_from_name(name, kind, err) result(status)
    character(len=*), intent(in) :: name
    integer(c_int), intent(out) :: kind
    type(taper_error), intent(inout) :: err
    integer(c_int) :: status
    status = c_taper_disorder_from_name(trim(name)//c_null_char, kind, err)
  end function taper_disorder_from_name

  function taper_boundary_from_name(name, boundary, err) result(status)
    character(len=*), intent(in) :: name
    integer(c_int), intent(out) :: boundary
    type(taper_error), intent(inout) :: err
    integer(c_int) :: status
    status = c_taper_boundary_from_name(trim(name)//c_null_char, boundary, err)
  end function taper_boundary_from_name

  ! '' when the binary collision theory (taper_theory) describes the chain's
  ! first pass; otherwise why not (dissipation, precompression, ...).
  function taper_chain_theory_note(chain) result(s)
    type(c_ptr), intent(in) :: chain
    character(len=:), allocatable :: s
    s = c_string(c_taper_chain_theory_note(chain))
  end function taper_chain_theory_note

  ! The message of a failed call.
  function taper_message(err) result(s)
    type(taper_error), intent(in) :: err
    character(len=:), allocatable :: s
    integer :: n
    n = 0
    do while (n < TAPER_MESSAGE_SIZE)
       if (err%message(n + 1) == c_null_char) exit
       n = n + 1
    end do
    allocate (character(len=n) :: s)
    s = transfer(err%message(1:n), s)
  end function taper_message

  ! The setting at fault in a failed call, spelt as its setter's suffix and
  ! the scene variable ("rtol", "n_granules", ...); '' when no single setting
  ! is (out of memory, a solver failure).
  function taper_field(err) result(s)
    type(taper_error), intent(in) :: err
    character(len=:), allocatable :: s
    s = c_string(err%field)
  end function taper_field

  ! Observable `which` of a run of `chain`: N values owned by the sim (a
  ! null pointer for an unknown observable).  Valid until taper_sim_free.
  function taper_observable(sim, chain, which) result(a)
    type(c_ptr), intent(in) :: sim, chain
    integer(c_int), intent(in) :: which
    real(c_double), pointer :: a(:)
    a => taper_chain_array(chain, taper_sim_observable(sim, which))
  end function taper_observable

  ! Column `which` (TAPER_THEORY_*) of the binary collision theory the sim
  ! computed once: N values owned by the sim.
  function taper_theory(sim, chain, which) result(a)
    type(c_ptr), intent(in) :: sim, chain
    integer(c_int), intent(in) :: which
    real(c_double), pointer :: a(:)
    a => taper_chain_array(chain, taper_sim_theory(sim, which))
  end function taper_theory

  ! An array of length N owned by a chain or its sim (taper_chain_radius(chain), ...).
  function taper_chain_array(chain, p) result(a)
    type(c_ptr), intent(in) :: chain, p
    real(c_double), pointer :: a(:)
    nullify (a)
    if (.not. c_associated(p)) return
    call c_f_pointer(p, a, [taper_chain_size(chain)])
  end function taper_chain_array


  ! ---- the table of settings ------------------------------------------------------
  ! Row i of the table, i = 1 .. taper_setting_count() (taper_setting_at(i - 1)):
  ! the library's row, read through the pointer; null past the end.
  !
  !   type(taper_setting), pointer :: row
  !   do i = 1, int(taper_setting_count())
  !      row => taper_setting_row(i)
  !      print *, taper_setting_group(row), " ", taper_setting_name(row), " [", &
  !           taper_setting_unit(row), "] ", row%min, row%max, row%default_value
  !   end do
  function taper_setting_row(i) result(row)
    integer, intent(in) :: i
    type(taper_setting), pointer :: row
    type(c_ptr) :: p
    nullify (row)
    if (i < 1) return
    p = taper_setting_at(int(i - 1, c_size_t))
    if (c_associated(p)) call c_f_pointer(p, row)
  end function taper_setting_row

  ! The row of `name` (any case, trailing blanks ignored), or a null pointer
  ! and TAPER_EINVAL in err naming the nearest setting ("did you mean ...").
  function taper_setting_find(name, err) result(row)
    character(len=*), intent(in) :: name
    type(taper_error), intent(inout) :: err
    type(taper_setting), pointer :: row
    type(c_ptr) :: p
    nullify (row)
    p = c_taper_setting_find(trim(name)//c_null_char, err)
    if (c_associated(p)) call c_f_pointer(p, row)
  end function taper_setting_find

  ! The strings of a row.
  function taper_setting_name(row) result(s)
    type(taper_setting), intent(in) :: row
    character(len=:), allocatable :: s
    s = c_string(row%name)
  end function taper_setting_name

  function taper_setting_group(row) result(s)
    type(taper_setting), intent(in) :: row
    character(len=:), allocatable :: s
    s = c_string(row%group)
  end function taper_setting_group

  function taper_setting_description(row) result(s)
    type(taper_setting), intent(in) :: row
    character(len=:), allocatable :: s
    s = c_string(row%description)
  end function taper_setting_description

  ! Why the range is what it is ('' when no bound needs a reason).
  function taper_setting_bounds_reason(row) result(s)
    type(taper_setting), intent(in) :: row
    character(len=:), allocatable :: s
    s = c_string(row%bounds_reason)
  end function taper_setting_bounds_reason

  ! The SI unit of the row's dimension ("s", "N", ...; "1" for a pure
  ! number): values themselves are rescaled (taper_unit_scale converts).
  function taper_setting_unit(row) result(s)
    type(taper_setting), intent(in) :: row
    character(len=:), allocatable :: s
    s = taper_dimension_unit(row%dimension)
  end function taper_setting_unit

  ! How many names a choice setting has (0 for any other setting).
  integer function taper_setting_n_choices(row) result(n)
    type(taper_setting), intent(in) :: row
    type(c_ptr), pointer :: names(:)
    n = 0
    if (.not. c_associated(row%choices)) return
    do
       call c_f_pointer(row%choices, names, [n + 1])
       if (.not. c_associated(names(n + 1))) exit
       n = n + 1
    end do
  end function taper_setting_n_choices

  ! Name k of a choice setting, k = 1 .. taper_setting_n_choices(row): the
  ! value k - 1 (as default_value and taper_chain_spec_option give it); ''
  ! for another k or another setting.
  function taper_setting_choice_name(row, k) result(s)
    type(taper_setting), intent(in) :: row
    integer, intent(in) :: k
    character(len=:), allocatable :: s
    type(c_ptr), pointer :: names(:)
    integer :: n
    s = ""
    n = taper_setting_n_choices(row)
    if (k < 1 .or. k > n) return
    call c_f_pointer(row%choices, names, [k])
    s = c_string(names(k))
  end function taper_setting_choice_name

  ! ---- settings by name (the generic taper_chain_spec_set_option and
  ! taper_solver_spec_set_option) ---------------------------------------------------
  function chain_set_real(spec, name, value, err) result(status)
    type(c_ptr), intent(in) :: spec
    character(len=*), intent(in) :: name
    real(c_double), intent(in) :: value
    type(taper_error), intent(inout) :: err
    integer(c_int) :: status
    status = c_taper_chain_spec_set_option(spec, trim(name)//c_null_char, value, err)
  end function chain_set_real

  function chain_set_int(spec, name, value, err) result(status)
    type(c_ptr), intent(in) :: spec
    character(len=*), intent(in) :: name
    integer(c_int), intent(in) :: value
    type(taper_error), intent(inout) :: err
    integer(c_int) :: status
    status = chain_set_real(spec, name, real(value, c_double), err)
  end function chain_set_int

  function chain_set_int64(spec, name, value, err) result(status)
    type(c_ptr), intent(in) :: spec
    character(len=*), intent(in) :: name
    integer(c_int64_t), intent(in) :: value
    type(taper_error), intent(inout) :: err
    integer(c_int) :: status
    if (inexact(value)) then
       status = refuse_inexact(name, value, err)
    else
       status = chain_set_real(spec, name, real(value, c_double), err)
    end if
  end function chain_set_int64

  function chain_set_logical(spec, name, value, err) result(status)
    type(c_ptr), intent(in) :: spec
    character(len=*), intent(in) :: name
    logical, intent(in) :: value
    type(taper_error), intent(inout) :: err
    integer(c_int) :: status
    status = chain_set_real(spec, name, merge(1.0_c_double, 0.0_c_double, value), err)
  end function chain_set_logical

  function chain_set_text(spec, name, value, err) result(status)
    type(c_ptr), intent(in) :: spec
    character(len=*), intent(in) :: name, value
    type(taper_error), intent(inout) :: err
    integer(c_int) :: status
    status = c_taper_chain_spec_set_option_text(spec, trim(name)//c_null_char, &
         trim(adjustl(value))//c_null_char, err)
  end function chain_set_text

  function chain_set_list(spec, name, values, err) result(status)
    type(c_ptr), intent(in) :: spec
    character(len=*), intent(in) :: name
    real(c_double), intent(in) :: values(:)
    type(taper_error), intent(inout) :: err
    integer(c_int) :: status
    real(c_double), allocatable, target :: copy(:)   ! contiguous, whatever values is
    if (size(values) == 0) then
       status = c_taper_chain_spec_set_option_list(spec, trim(name)//c_null_char, c_null_ptr, &
            0_c_size_t, err)
    else
       copy = values
       status = c_taper_chain_spec_set_option_list(spec, trim(name)//c_null_char, c_loc(copy), &
            size(copy, kind=c_size_t), err)
    end if
  end function chain_set_list

  function solver_set_real(spec, name, value, err) result(status)
    type(c_ptr), intent(in) :: spec
    character(len=*), intent(in) :: name
    real(c_double), intent(in) :: value
    type(taper_error), intent(inout) :: err
    integer(c_int) :: status
    status = c_taper_solver_spec_set_option(spec, trim(name)//c_null_char, value, err)
  end function solver_set_real

  function solver_set_int(spec, name, value, err) result(status)
    type(c_ptr), intent(in) :: spec
    character(len=*), intent(in) :: name
    integer(c_int), intent(in) :: value
    type(taper_error), intent(inout) :: err
    integer(c_int) :: status
    status = solver_set_real(spec, name, real(value, c_double), err)
  end function solver_set_int

  function solver_set_int64(spec, name, value, err) result(status)
    type(c_ptr), intent(in) :: spec
    character(len=*), intent(in) :: name
    integer(c_int64_t), intent(in) :: value
    type(taper_error), intent(inout) :: err
    integer(c_int) :: status
    if (inexact(value)) then
       status = refuse_inexact(name, value, err)
    else
       status = solver_set_real(spec, name, real(value, c_double), err)
    end if
  end function solver_set_int64

  function solver_set_logical(spec, name, value, err) result(status)
    type(c_ptr), intent(in) :: spec
    character(len=*), intent(in) :: name
    logical, intent(in) :: value
    type(taper_error), intent(inout) :: err
    integer(c_int) :: status
    status = solver_set_real(spec, name, merge(1.0_c_double, 0.0_c_double, value), err)
  end function solver_set_logical

  function solver_set_text(spec, name, value, err) result(status)
    type(c_ptr), intent(in) :: spec
    character(len=*), intent(in) :: name, value
    type(taper_error), intent(inout) :: err
    integer(c_int) :: status
    status = c_taper_solver_spec_set_option_text(spec, trim(name)//c_null_char, &
         trim(adjustl(value))//c_null_char, err)
  end function solver_set_text

  ! Every value reaches the library as a double, which holds each whole
  ! number up to 2^53 exactly and rounds those beyond.
  logical function inexact(value)
    integer(c_int64_t), intent(in) :: value
    integer(c_int64_t), parameter :: EXACT = 9007199254740992_c_int64_t   ! 2^53
    inexact = value > EXACT .or. value < -EXACT
  end function inexact

  ! A whole number beyond 2^53 would be set rounded: refused here, naming
  ! the setting as the library does (an unknown name: the library's refusal).
  function refuse_inexact(name, value, err) result(status)
    character(len=*), intent(in) :: name
    integer(c_int64_t), intent(in) :: value
    type(taper_error), intent(inout) :: err
    integer(c_int) :: status
    type(taper_setting), pointer :: row
    character(len=TAPER_MESSAGE_SIZE) :: text
    integer :: k, n
    row => taper_setting_find(name, err)
    if (.not. associated(row)) then
       status = err%status
       return
    end if
    write (text, '(a,i0,a)') taper_setting_name(row)//" = ", value, ": a whole number beyond "// &
         "2^53, which the double every setting is passed as cannot hold exactly"
    n = min(len_trim(text), TAPER_MESSAGE_SIZE - 1)
    do k = 1, n
       err%message(k) = text(k:k)
    end do
    err%message(n + 1) = c_null_char
    err%status = TAPER_EINVAL
    err%field = row%name
    status = TAPER_EINVAL
  end function refuse_inexact

  ! The value of a chain setting by name: the real, the integer, the boolean
  ! (0 or 1) or the choice's index (taper_setting_choice_name(row, index + 1) is
  ! its name); NaN for an unknown name or a solver setting, or a list.  A
  ! null spec (c_null_ptr) reads as a fresh one: the default.
  function taper_chain_spec_option(spec, name) result(x)
    type(c_ptr), intent(in) :: spec
    character(len=*), intent(in) :: name
    real(c_double) :: x
    x = c_taper_chain_spec_option(spec, trim(name)//c_null_char)
  end function taper_chain_spec_option

  ! A list setting's values, owned by the spec (valid until it changes or
  ! is freed); size 0 for none, an unknown name, or a setting that is not a
  ! list.
  function taper_chain_spec_option_list(spec, name) result(values)
    type(c_ptr), intent(in) :: spec
    character(len=*), intent(in) :: name
    real(c_double), pointer :: values(:)
    integer(c_size_t) :: n
    type(c_ptr) :: p
    p = c_taper_chain_spec_option_list(spec, trim(name)//c_null_char, n)
    if (.not. c_associated(p) .or. n == 0) then
       values => no_values
    else
       call c_f_pointer(p, values, [n])
    end if
  end function taper_chain_spec_option_list

  ! The same for a solver setting.
  function taper_solver_spec_option(spec, name) result(x)
    type(c_ptr), intent(in) :: spec
    character(len=*), intent(in) :: name
    real(c_double) :: x
    x = c_taper_solver_spec_option(spec, trim(name)//c_null_char)
  end function taper_solver_spec_option
end module taper_binding

! The module programs use: every public name of the binding and every
! constant of taper.h.
module taper
  use taper_constants
  use taper_binding
  implicit none
  public
end module taper
