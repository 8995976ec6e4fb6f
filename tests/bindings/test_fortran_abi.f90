! test_fortran_abi -- the bind(C) derived types of share/fortran/taper.f90
! have the size and field offsets of the C structs of taper.h (asked of the
! C compiler in fortran_abi.c), and the module calls the library correctly:
! a short chain runs and its observables come back through the interfaces.
program test_fortran_abi
  use, intrinsic :: iso_c_binding
  use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
  use taper
  implicit none
  interface
     function layout(type, field) bind(C, name="taper_test_layout") result(n)
       import :: c_int, c_size_t
       integer(c_int), value :: type, field
       integer(c_size_t) :: n
     end function layout
  end interface
  type(taper_error), target :: e
  type(taper_chain_spec), target :: cs
  type(taper_solver_spec), target :: ss
  type(taper_stats), target :: st
  type(taper_progress), target :: pr
  type(taper_fit_spec), target :: fs
  type(taper_fit_result), target :: fr
  type(c_ptr) :: chain, sim
  real(c_double), pointer :: t_pass(:), radius(:)
  real(c_double), allocatable, target :: v(:), t(:)
  integer :: fails
  integer(c_int) :: status, p

  fails = 0
  call same(0, "taper_error", c_sizeof(e), [off(c_loc(e%status), c_loc(e)), off(c_loc(e%message), c_loc(e))])
  call same(1, "taper_chain_spec", c_sizeof(cs), [off(c_loc(cs%profile), c_loc(cs)), &
       off(c_loc(cs%n_granules), c_loc(cs)), off(c_loc(cs%s), c_loc(cs)), off(c_loc(cs%q), c_loc(cs)), &
       off(c_loc(cs%exponent), c_loc(cs)), off(c_loc(cs%radii), c_loc(cs))])
  call same(2, "taper_solver_spec", c_sizeof(ss), [off(c_loc(ss%method), c_loc(ss)), &
       off(c_loc(ss%rtol), c_loc(ss)), off(c_loc(ss%atol), c_loc(ss)), &
       off(c_loc(ss%last_granule), c_loc(ss)), off(c_loc(ss%window), c_loc(ss)), &
       off(c_loc(ss%max_order), c_loc(ss)), off(c_loc(ss%t_max), c_loc(ss)), &
       off(c_loc(ss%max_steps), c_loc(ss)), off(c_loc(ss%monitor), c_loc(ss)), &
       off(c_loc(ss%monitor_data), c_loc(ss)), off(c_loc(ss%log), c_loc(ss)), &
       off(c_loc(ss%log_data), c_loc(ss))])
  call same(3, "taper_stats", c_sizeof(st), [off(c_loc(st%steps), c_loc(st)), &
       off(c_loc(st%rhs_evals), c_loc(st)), off(c_loc(st%root_evals), c_loc(st)), &
       off(c_loc(st%jac_evals), c_loc(st)), off(c_loc(st%nonlin_iters), c_loc(st)), &
       off(c_loc(st%err_test_fails), c_loc(st)), off(c_loc(st%window_changes), c_loc(st)), &
       off(c_loc(st%restarts), c_loc(st)), off(c_loc(st%max_window), c_loc(st)), &
       off(c_loc(st%granule_reached), c_loc(st)), off(c_loc(st%t_final), c_loc(st)), &
       off(c_loc(st%energy_error), c_loc(st)), off(c_loc(st%momentum_error), c_loc(st)), &
       off(c_loc(st%complete), c_loc(st))])
  call same(4, "taper_progress", c_sizeof(pr), [off(c_loc(pr%granule), c_loc(pr)), &
       off(c_loc(pr%target), c_loc(pr)), off(c_loc(pr%t), c_loc(pr)), off(c_loc(pr%steps), c_loc(pr)), &
       off(c_loc(pr%window_lo), c_loc(pr)), off(c_loc(pr%window_hi), c_loc(pr))])
  call same(5, "taper_fit_spec", c_sizeof(fs), [off(c_loc(fs%model), c_loc(fs)), &
       off(c_loc(fs%p), c_loc(fs)), off(c_loc(fs%index_begin), c_loc(fs)), &
       off(c_loc(fs%index_end), c_loc(fs)), off(c_loc(fs%x_min), c_loc(fs)), &
       off(c_loc(fs%x_max), c_loc(fs)), off(c_loc(fs%skip_invalid), c_loc(fs)), &
       off(c_loc(fs%max_iter), c_loc(fs)), off(c_loc(fs%xtol), c_loc(fs))])
  call same(6, "taper_fit_result", c_sizeof(fr), [off(c_loc(fr%model), c_loc(fr)), &
       off(c_loc(fr%n_params), c_loc(fr)), off(c_loc(fr%param), c_loc(fr)), &
       off(c_loc(fr%param_err), c_loc(fr)), off(c_loc(fr%n_points), c_loc(fr)), &
       off(c_loc(fr%n_skipped), c_loc(fr)), off(c_loc(fr%chi2), c_loc(fr)), &
       off(c_loc(fr%iterations), c_loc(fr))])

  ! The interfaces: a run through the module.
  if (taper_version() /= TAPER_VERSION_STRING) call fail("version "//taper_version())
  if (taper_profile_from_name("Backward_Linear", p) /= TAPER_OK .or. p /= TAPER_BACKWARD_LINEAR) &
       call fail("taper_profile_from_name")
  if (taper_profile_name(TAPER_FORWARD_EXPONENTIAL) /= "forward_exponential") call fail("profile_name")
  call taper_chain_spec_init(cs)
  if (cs%n_granules /= 100 .or. cs%exponent /= 2.5_c_double) call fail("chain_spec_init defaults")
  cs%profile = TAPER_BACKWARD_LINEAR
  cs%n_granules = 30
  cs%s = 0.1_c_double
  chain = taper_chain_alloc(cs, e)
  if (.not. c_associated(chain)) call fail("chain: "//taper_message(e))
  radius => taper_chain_array(chain, taper_chain_radius(chain))
  if (size(radius) /= 30 .or. abs(radius(30) - 3.9_c_double) > 1d-12) call fail("radius")
  allocate (v(30), t(30))
  if (taper_theory_compute(chain, c_loc(v), c_null_ptr, c_null_ptr, c_loc(t), e) /= TAPER_OK) &
       call fail("theory")
  call taper_solver_spec_init(ss)
  sim = taper_sim_alloc(chain, ss, e)
  status = taper_sim_run(sim, e)
  if (status /= TAPER_OK) call fail("run: "//taper_message(e))
  t_pass => taper_observable(sim, chain, TAPER_T_PASS)
  if (abs(t_pass(10) / t(10) - 1) > 0.02_c_double .or. .not. ieee_is_nan(t_pass(30))) &
       call fail("t_pass vs theory")
  call taper_sim_stats(sim, st)
  if (st%complete /= 1 .or. st%granule_reached /= 29) call fail("stats")
  call taper_sim_free(sim)
  ! An error: the message arrives through the bind(C) taper_error.
  ss%rtol = -1
  sim = taper_sim_alloc(chain, ss, e)
  if (c_associated(sim) .or. e%status /= TAPER_EINVAL .or. index(taper_message(e), "rtol") == 0) &
       call fail("error message: "//taper_message(e))
  call taper_chain_free(chain)
  ! Main-program variables are implicitly SAVE'd: never deallocated for us.
  deallocate (v, t)

  if (fails > 0) error stop 1
  print '(a)', "Fortran module: 7 struct layouts equal to C, calls and messages work"

contains

  integer(c_size_t) function off(field, base)
    type(c_ptr), intent(in) :: field, base
    off = int(transfer(field, 0_c_intptr_t) - transfer(base, 0_c_intptr_t), c_size_t)
  end function off

  subroutine same(type, name, nbytes, offsets)
    integer, intent(in) :: type
    character(len=*), intent(in) :: name
    integer(c_size_t), intent(in) :: nbytes, offsets(:)
    integer :: i
    if (nbytes /= layout(int(type, c_int), 0_c_int)) then
       print '(a,i0,a,i0)', name//": Fortran size ", nbytes, ", C size ", layout(int(type, c_int), 0_c_int)
       fails = fails + 1
    end if
    do i = 1, size(offsets)
       if (offsets(i) /= layout(int(type, c_int), int(i, c_int))) then
          print '(a,i0,a,i0,a,i0)', name//": field ", i, " at Fortran offset ", offsets(i), &
               ", C offset ", layout(int(type, c_int), int(i, c_int))
          fails = fails + 1
       end if
    end do
  end subroutine same

  subroutine fail(what)
    character(len=*), intent(in) :: what
    print '(a)', "FAIL: "//what
    fails = fails + 1
  end subroutine fail
end program test_fortran_abi
