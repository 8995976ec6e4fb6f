! taper.f90 -- Fortran interface to libtaper (iso_c_binding, Fortran 2008).
!
! Pulse propagation in tapered granular chains: the C API of include/taper.h
! as bind(C) interfaces, its structs as interoperable derived types (field
! by field, in the same order: size_t -> c_size_t, long -> c_long, function
! pointers -> c_funptr), and a few helpers that turn C strings and the
! library's arrays into Fortran ones.
!
!   use taper
!   type(taper_chain_spec)  :: cs
!   type(taper_solver_spec) :: ss
!   type(taper_error)       :: err
!   type(c_ptr)             :: chain, sim
!   real(c_double), pointer :: t_pass(:)
!   call taper_chain_spec_init(cs)
!   cs%profile = TAPER_BACKWARD_LINEAR; cs%n_granules = 100; cs%s = 0.1d0
!   chain = taper_chain_alloc(cs, err)
!   if (.not. c_associated(chain)) error stop taper_message(err)
!   call taper_solver_spec_init(ss)
!   sim = taper_sim_alloc(chain, ss, err)
!   if (taper_sim_run(sim, err) /= TAPER_OK) print *, taper_message(err)
!   t_pass => taper_observable(sim, chain, TAPER_T_PASS)  ! length N, owned by sim
!   call taper_sim_free(sim); call taper_chain_free(chain)
!
! Granule k is element k of every array (C index k-1).  Values that do not
! exist are NaN (ieee_is_nan).  Arrays returned as pointers belong to the
! chain or sim and are valid until it is freed.  Objects are type(c_ptr).
! Optional C arguments (NULL) are passed as c_null_ptr where the interface
! takes type(c_ptr); the taper_error argument is always required here.
module taper
  use, intrinsic :: iso_c_binding
  implicit none
  private

  ! ---- version ------------------------------------------------------------
  integer, parameter, public :: TAPER_VERSION_MAJOR = 0, TAPER_VERSION_MINOR = 1, &
                                TAPER_VERSION_PATCH = 0
  character(len=*), parameter, public :: TAPER_VERSION_STRING = "0.1.0"

  ! ---- status codes (enum taper_status) -----------------------------------
  integer(c_int), parameter, public :: TAPER_OK = 0, TAPER_EINVAL = 1, TAPER_ENOMEM = 2, &
       TAPER_ERANGE = 3, TAPER_ESOLVER = 4, TAPER_EINTERRUPTED = 5, TAPER_ELIMIT = 6, &
       TAPER_EIO = 7
  integer, parameter, public :: TAPER_MESSAGE_SIZE = 512

  ! ---- enums ------------------------------------------------------------------
  integer(c_int), parameter, public :: TAPER_MONODISPERSE = 0, TAPER_BACKWARD_LINEAR = 1, &
       TAPER_FORWARD_LINEAR = 2, TAPER_BACKWARD_EXPONENTIAL = 3, &
       TAPER_FORWARD_EXPONENTIAL = 4, TAPER_CUSTOM = 5
  integer(c_int), parameter, public :: TAPER_ADAMS = 0, TAPER_BDF = 1
  integer(c_int), parameter, public :: TAPER_T_PASS = 0, TAPER_T_RES = 1, TAPER_V_PEAK = 2, &
       TAPER_T_PEAK = 3, TAPER_X_PASS = 4
  integer, parameter, public :: TAPER_N_OBSERVABLES = 5
  integer(c_int), parameter, public :: TAPER_LAW_V_OF_K = 0, TAPER_LAW_T_RES_OF_K = 1, &
       TAPER_LAW_T_OF_K = 2, TAPER_LAW_K_OF_T = 3, TAPER_LAW_V_OF_T = 4, &
       TAPER_LAW_X_OF_T = 5, TAPER_LAW_C_OF_T = 6, TAPER_LAW_FWD_V_OF_K = 7, &
       TAPER_LAW_FWD_T_OF_K = 8, TAPER_LAW_FWD_V_OF_T = 9
  integer(c_int), parameter, public :: TAPER_FIT_POWER = 0, TAPER_FIT_EXPONENTIAL = 1, &
       TAPER_FIT_DIVERGENCE_B = 2, TAPER_FIT_DIVERGENCE_C = 3, TAPER_FIT_DIVERGENCE_M = 4

  ! ---- structs of taper.h, field by field ------------------------------------
  type, bind(C), public :: taper_error
     integer(c_int) :: status = 0
     character(kind=c_char) :: message(TAPER_MESSAGE_SIZE) = c_null_char
  end type taper_error

  type, bind(C), public :: taper_chain_spec
     integer(c_int) :: profile
     integer(c_size_t) :: n_granules
     real(c_double) :: s
     real(c_double) :: q
     real(c_double) :: exponent
     type(c_ptr) :: radii           ! TAPER_CUSTOM: c_loc(radii(1)), copied
  end type taper_chain_spec

  type, bind(C), public :: taper_progress
     integer(c_size_t) :: granule
     integer(c_size_t) :: target
     real(c_double) :: t
     integer(c_long) :: steps
     integer(c_size_t) :: window_lo
     integer(c_size_t) :: window_hi
  end type taper_progress

  type, bind(C), public :: taper_solver_spec
     integer(c_int) :: method
     real(c_double) :: rtol
     real(c_double) :: atol
     integer(c_size_t) :: last_granule
     integer(c_int) :: window
     integer(c_int) :: max_order
     real(c_double) :: t_max
     integer(c_long) :: max_steps
     type(c_funptr) :: monitor       ! c_funloc of a bind(C) function, see taper.h
     type(c_ptr) :: monitor_data
     type(c_funptr) :: log
     type(c_ptr) :: log_data
  end type taper_solver_spec

  type, bind(C), public :: taper_stats
     integer(c_long) :: steps
     integer(c_long) :: rhs_evals
     integer(c_long) :: root_evals
     integer(c_long) :: jac_evals
     integer(c_long) :: nonlin_iters
     integer(c_long) :: err_test_fails
     integer(c_long) :: window_changes
     integer(c_long) :: restarts
     integer(c_size_t) :: max_window
     integer(c_size_t) :: granule_reached
     real(c_double) :: t_final
     real(c_double) :: energy_error
     real(c_double) :: momentum_error
     integer(c_int) :: complete
  end type taper_stats

  type, bind(C), public :: taper_fit_spec
     integer(c_int) :: model
     real(c_double) :: p
     integer(c_size_t) :: index_begin
     integer(c_size_t) :: index_end
     real(c_double) :: x_min
     real(c_double) :: x_max
     integer(c_int) :: skip_invalid
     integer(c_size_t) :: max_iter
     real(c_double) :: xtol
  end type taper_fit_spec

  type, bind(C), public :: taper_fit_result
     integer(c_int) :: model
     integer(c_size_t) :: n_params
     real(c_double) :: param(3)
     real(c_double) :: param_err(3)
     integer(c_size_t) :: n_points
     integer(c_size_t) :: n_skipped
     real(c_double) :: chi2
     integer(c_size_t) :: iterations
  end type taper_fit_result

  ! ---- the C API ---------------------------------------------------------------
  public :: c_taper_version, c_taper_strerror, c_taper_profile_name, c_taper_profile_from_name
  public :: taper_chain_spec_init, taper_chain_alloc, taper_chain_free, taper_chain_size, &
            taper_chain_exponent, taper_chain_profile, taper_chain_radius, taper_chain_mass, &
            taper_chain_contact, taper_chain_rest_position
  public :: taper_theory_collision_time, taper_theory_compute
  public :: taper_solver_spec_init, taper_sim_alloc, taper_sim_free, taper_sim_run, &
            taper_sim_observable, taper_sim_stats, taper_sim_state
  public :: taper_asymptotic_exponent, taper_asymptotic_A, taper_asymptotic_lnA, &
            taper_asymptotic_eta, taper_asymptotic_f, taper_asymptotic_position_exponent, &
            taper_asymptotic_speed_exponent, taper_asymptotic_timescale, taper_asymptotic_M, &
            taper_asymptotic_C0, taper_asymptotic_C, taper_asymptotic_forward_linear_b
  public :: taper_fit_spec_init, taper_fit
  ! Fortran helpers
  public :: taper_version, taper_strerror, taper_profile_name, taper_profile_from_name, &
            taper_message, taper_observable, taper_chain_array, c_string

  interface
     ! Strings come back as C pointers: use the helpers below.
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
     function c_taper_profile_from_name(name, profile) bind(C, name="taper_profile_from_name") &
          result(status)
       import :: c_char, c_int
       character(kind=c_char), intent(in) :: name(*)
       integer(c_int), intent(out) :: profile
       integer(c_int) :: status
     end function c_taper_profile_from_name

     subroutine taper_chain_spec_init(spec) bind(C, name="taper_chain_spec_init")
       import :: taper_chain_spec
       type(taper_chain_spec), intent(out) :: spec
     end subroutine taper_chain_spec_init
     function taper_chain_alloc(spec, err) bind(C, name="taper_chain_alloc") result(chain)
       import :: c_ptr, taper_chain_spec, taper_error
       type(taper_chain_spec), intent(in) :: spec
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

     function taper_theory_collision_time(mu, r, zdot0, n) &
          bind(C, name="taper_theory_collision_time") result(t)
       import :: c_double
       real(c_double), value :: mu, r, zdot0, n
       real(c_double) :: t
     end function taper_theory_collision_time
     ! v, mu, T (res_time), t (pass_time): c_loc of arrays of length N, or
     ! c_null_ptr to skip.
     function taper_theory_compute(chain, v, mu, res_time, pass_time, err) bind(C, name="taper_theory_compute") &
          result(status)
       import :: c_ptr, c_int, taper_error
       type(c_ptr), value :: chain, v, mu, res_time, pass_time
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_theory_compute

     subroutine taper_solver_spec_init(spec) bind(C, name="taper_solver_spec_init")
       import :: taper_solver_spec
       type(taper_solver_spec), intent(out) :: spec
     end subroutine taper_solver_spec_init
     function taper_sim_alloc(chain, spec, err) bind(C, name="taper_sim_alloc") result(sim)
       import :: c_ptr, taper_solver_spec, taper_error
       type(c_ptr), value :: chain
       type(taper_solver_spec), intent(in) :: spec
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
     subroutine taper_sim_stats(sim, stats) bind(C, name="taper_sim_stats")
       import :: c_ptr, taper_stats
       type(c_ptr), value :: sim
       type(taper_stats), intent(out) :: stats
     end subroutine taper_sim_stats
     ! x, v: c_loc of arrays of length N, or c_null_ptr.
     function taper_sim_state(sim, x, v, err) bind(C, name="taper_sim_state") result(status)
       import :: c_ptr, c_int, taper_error
       type(c_ptr), value :: sim, x, v
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_sim_state

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

     subroutine taper_fit_spec_init(spec, model) bind(C, name="taper_fit_spec_init")
       import :: taper_fit_spec, c_int
       type(taper_fit_spec), intent(out) :: spec
       integer(c_int), value :: model
     end subroutine taper_fit_spec_init
     function taper_fit(spec, x, y, n, result, err) bind(C, name="taper_fit") result(status)
       import :: taper_fit_spec, taper_fit_result, taper_error, c_double, c_size_t, c_int
       type(taper_fit_spec), intent(in) :: spec
       real(c_double), intent(in) :: x(*), y(*)
       integer(c_size_t), value :: n
       type(taper_fit_result), intent(out) :: result
       type(taper_error), intent(inout) :: err
       integer(c_int) :: status
     end function taper_fit
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

  ! The version of the loaded library ("0.1.0").
  function taper_version() result(s)
    character(len=:), allocatable :: s
    s = c_string(c_taper_version())
  end function taper_version

  function taper_strerror(status) result(s)
    integer(c_int), intent(in) :: status
    character(len=:), allocatable :: s
    s = c_string(c_taper_strerror(status))
  end function taper_strerror

  ! "backward_linear", ...; '' for an unknown profile.
  function taper_profile_name(profile) result(s)
    integer(c_int), intent(in) :: profile
    character(len=:), allocatable :: s
    s = c_string(c_taper_profile_name(profile))
  end function taper_profile_name

  ! TAPER_OK and the profile number for a (case-insensitive) name, or TAPER_EINVAL.
  function taper_profile_from_name(name, profile) result(status)
    character(len=*), intent(in) :: name
    integer(c_int), intent(out) :: profile
    integer(c_int) :: status
    status = c_taper_profile_from_name(trim(name)//c_null_char, profile)
  end function taper_profile_from_name

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

  ! Observable `which` of a run of `chain`: N values owned by the sim (a
  ! null pointer for an unknown observable).  Valid until taper_sim_free.
  function taper_observable(sim, chain, which) result(a)
    type(c_ptr), intent(in) :: sim, chain
    integer(c_int), intent(in) :: which
    real(c_double), pointer :: a(:)
    a => taper_chain_array(chain, taper_sim_observable(sim, which))
  end function taper_observable

  ! An array of length N owned by a chain (taper_chain_radius(chain), ...).
  function taper_chain_array(chain, p) result(a)
    type(c_ptr), intent(in) :: chain, p
    real(c_double), pointer :: a(:)
    nullify (a)
    if (.not. c_associated(p)) return
    call c_f_pointer(p, a, [taper_chain_size(chain)])
  end function taper_chain_array

end module taper
