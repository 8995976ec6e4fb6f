! SPDX-License-Identifier: GPL-3.0-or-later
! paper_table2.f90 -- Table II of the paper, again: how fast the pulse dies
! in a chain whose granules grow exponentially.
!
! Harbola, Rosas, Esposito and Lindenberg (arXiv:0905.4512, Sec. III B)
! study "backward" exponentially tapered chains, R_k = (1-q)^(1-k): each
! granule is a fixed factor larger than the one before.  The binary
! collision approximation says the pulse leaves granule k with
! v_k = A^(1-k), A(q) = [1 + (1-q)^-3] / 2 (eqs. (34)-(35)): it decays
! exponentially in k at the rate ln A(q).  Their Table II compares that
! rate with the rate fitted to the numerical peak velocities.  This program
! integrates the full equations of motion, eq. (6), for N = 200 granules at
! q = 0.01 ... 0.05, fits v_peak(k) = a e^(-rate k) over granules 50-190
! (past the impact's transient, clear of the free end; the paper states no
! window, docs/paper.md), and prints the rates next to the theory and to the
! numbers the paper prints.  What to look at: the numerics decay slightly
! faster than the theory (the real pulse spreads over a few granules, which
! the two-body picture ignores), by 0.2 % at q = 0.01 and 0.7 % at 0.05,
! and agree with the paper's own numerics to every printed digit.
!
! The checks: the fitted theory is ln A(q) (exact: v_k is exponential), ln A
! agrees with the paper's printed theory and our numerics with its printed
! numerics, each to half a unit of the last printed digit, and the energy
! is conserved.  Every call's status is checked; a failure or a check that
! does not hold stops the program with a non-zero exit code.
!
! Build against an installed libtaper (the module's sources are installed
! in PREFIX/share/taper/fortran; compile them with your compiler):
!     gfortran $(pkg-config --variable=prefix taper)/share/taper/fortran/taper_constants.f90 \
!        $(pkg-config --variable=prefix taper)/share/taper/fortran/taper.f90 paper_table2.f90 \
!        $(pkg-config --libs taper) -Wl,-rpath,$(pkg-config --variable=libdir taper) -o paper_table2
program paper_table2
  use, intrinsic :: iso_c_binding
  use, intrinsic :: iso_fortran_env, only: error_unit
  use taper
  implicit none

  integer, parameter :: n_rows = 5
  integer(c_size_t), parameter :: n = 200, k_first = 50, k_last = 190
  real(c_double), parameter :: q(n_rows) = [0.01d0, 0.02d0, 0.03d0, 0.04d0, 0.05d0]
  ! arXiv:0905.4512, Table II, printed with five decimals
  real(c_double), parameter :: paper_theory(n_rows) = &
       [0.01519d0, 0.03076d0, 0.04673d0, 0.06311d0, 0.07990d0]
  real(c_double), parameter :: paper_numerics(n_rows) = &
       [0.01522d0, 0.03088d0, 0.04697d0, 0.06350d0, 0.08047d0]
  real(c_double), parameter :: half_digit = 0.5d-5 * (1 + 1d-9)
  real(c_double), parameter :: max_energy_error = 1d-6

  real(c_double) :: rate, rate_theory, ln_a, steps, energy_error
  logical :: ok
  integer :: i

  ok = .true.
  print '(a,i0,a,i0,a,i0)', '# backward exponential chains, N = ', n, &
       ', v_peak(k) = a exp(-rate k) fitted over k = ', k_first, '..', k_last
  print '(a,a5,4a12,2a10)', '# ', 'q', 'numerics', 'paper', 'ln A(q)', 'paper', 'steps', 'E error'
  do i = 1, n_rows
     call decay_rate(q(i), rate, rate_theory, steps, energy_error)
     ln_a = taper_asymptotic_lnA(q(i))
     print '(2x,f5.2,2(f12.6,f12.5),i10,es10.2)', q(i), rate, paper_numerics(i), ln_a, &
          paper_theory(i), nint(steps), energy_error
     call expect(abs(rate_theory - ln_a) <= 1d-9 * ln_a, 'the fitted theory is not ln A(q)')
     call expect(abs(ln_a - paper_theory(i)) <= half_digit, 'ln A(q) is not the printed theory')
     call expect(abs(rate - paper_numerics(i)) <= half_digit, &
          'the numerics are not the printed numerics')
     call expect(energy_error <= max_energy_error, 'energy not conserved')
  end do
  print '(a)', '# checks: the theory is ln A(q) and the printed theory, the numerics the ' // &
       'printed numerics (to half a unit of the last digit), energy conserved: ' // &
       merge('all hold', 'FAILED  ', ok)
  if (.not. ok) error stop 1

contains

  ! Stop with the library's message when a call fails.
  subroutine check(status, funcname, err)
    integer(c_int), intent(in) :: status
    character(len=*), intent(in) :: funcname
    type(taper_error), intent(in) :: err
    if (status == TAPER_OK) return
    write (error_unit, '(a)') 'ERROR: '//funcname//'() failed ('//taper_strerror(status)//') '// &
         taper_field(err)//': '//taper_message(err)
    error stop 1
  end subroutine check

  ! A NULL object from an allocator is a failure explained in err.
  subroutine check_pointer(p, funcname, err)
    type(c_ptr), intent(in) :: p
    character(len=*), intent(in) :: funcname
    type(taper_error), intent(in) :: err
    if (.not. c_associated(p)) call check(err%status, funcname, err)
  end subroutine check_pointer

  subroutine expect(condition, what)
    logical, intent(in) :: condition
    character(len=*), intent(in) :: what
    if (condition) return
    write (error_unit, '(a,f5.2,a)') 'FAIL: q = ', q(i), ': '//what
    ok = .false.
  end subroutine expect

  ! The fitted decay rates of the numerics and of the theory for one q.
  subroutine decay_rate(q_row, rate, rate_theory, steps, energy_error)
    real(c_double), intent(in) :: q_row
    real(c_double), intent(out) :: rate, rate_theory, steps, energy_error
    type(taper_error) :: err
    type(c_ptr) :: chain_spec, chain, sim
    real(c_double), pointer :: v_peak(:), v_theory(:)
    real(c_double) :: k(n)
    integer :: j

    chain_spec = taper_chain_spec_alloc(err)
    call check_pointer(chain_spec, 'taper_chain_spec_alloc', err)
    call check(taper_chain_spec_set_profile(chain_spec, TAPER_BACKWARD_EXPONENTIAL, err), &
         'taper_chain_spec_set_profile', err)
    call check(taper_chain_spec_set_n_granules(chain_spec, n, err), &
         'taper_chain_spec_set_n_granules', err)
    call check(taper_chain_spec_set_q(chain_spec, q_row, err), 'taper_chain_spec_set_q', err)
    chain = taper_chain_alloc(chain_spec, err)
    call taper_chain_spec_free(chain_spec)
    call check_pointer(chain, 'taper_chain_alloc', err)

    ! The library's default solver (no solver spec): the run ends once the
    ! pulse has passed every granule.
    sim = taper_sim_alloc(chain, c_null_ptr, err)
    call check_pointer(sim, 'taper_sim_alloc', err)
    call check(taper_sim_run(sim, err), 'taper_sim_run', err)

    v_peak => taper_observable(sim, chain, TAPER_V_PEAK)
    v_theory => taper_theory(sim, chain, TAPER_THEORY_V)
    k = [(real(j, c_double), j = 1, int(n))]
    rate = -fitted_exponent(k, v_peak)
    rate_theory = -fitted_exponent(k, v_theory)
    steps = taper_sim_statistic(sim, TAPER_STAT_STEPS)
    energy_error = taper_sim_statistic(sim, TAPER_STAT_ENERGY_ERROR)
    call taper_sim_free(sim)
    call taper_chain_free(chain)
  end subroutine decay_rate

  ! b of y = a e^(b x) fitted by the library over k_first..k_last.
  function fitted_exponent(x, y) result(b)
    real(c_double), intent(in) :: x(:), y(:)
    real(c_double) :: b
    type(taper_error) :: err
    type(c_ptr) :: spec, fit
    spec = taper_fit_spec_alloc(TAPER_FIT_EXPONENTIAL, err)
    call check_pointer(spec, 'taper_fit_spec_alloc', err)
    ! points begin <= i < end, 0-based as in C: granules k_first..k_last
    call check(taper_fit_spec_set_index_window(spec, k_first - 1, k_last, err), &
         'taper_fit_spec_set_index_window', err)
    fit = taper_fit(spec, x, y, size(x, kind=c_size_t), err)
    call taper_fit_spec_free(spec)
    call check_pointer(fit, 'taper_fit', err)
    b = taper_fit_result_param(fit, 1_c_size_t)
    call taper_fit_result_free(fit)
  end function fitted_exponent
end program paper_table2
