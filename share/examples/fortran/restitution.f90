! SPDX-License-Identifier: GPL-3.0-or-later
! restitution.f90 -- two steel beads collide with viscoelastic contacts:
! the coefficient of restitution falls as the impact gets faster.
!
! A constant coefficient of restitution is the usual model of a lossy
! collision, but viscoelastic spheres do not obey it.  With the
! Kuwabara-Kono contact force of docs/physics.md,
!
!     F = r (z^(3/2) + A d(z^(3/2))/dt)   while F > 0,
!
! (G. Kuwabara and K. Kono, Jpn. J. Appl. Phys. 26, 1230 (1987);
! Brilliantov, Spahn, Hertzsch and Poeschel, Phys. Rev. E 53, 5382 (1996))
! the damping constant A is a time, and the collision itself lasts a time
! that grows as the impact slows, as v^(-1/5) for Hertz contacts: a slow
! collision has more time to relax, and loses a smaller fraction of its
! energy.  To first order in A the energy the damping takes from the
! elastic collision (relative velocity v, reduced mass mu, contact factor
! r, largest compression z_m = (5 mu v^2 / (4 r))^(2/5)) is
!
!     D = (6/5) B(3/5, 3/2) r A v z_m^(3/2),
!
! so that e = 1 - D / (mu v^2) + O(A^2), i.e.
!
!     1 - e = (6/5) B(3/5, 3/2) (5/4)^(3/5) (r/mu)^(2/5) A v^(1/5) + O(A^2)
!
! (B the Beta function; derived here by integrating the damping force over
! the elastic Hertz collision.  It is Schwager and Poeschel's first-order
! term, Phys. Rev. E 57, 650 (1998): their C1 = Gamma(3/5) sqrt(pi) /
! (2^(1/5) 5^(2/5) Gamma(21/10)) = 1.15344 times (3/2) (r/mu)^(2/5).)
!
! Two beads of 4.76 mm diameter, type 316 stainless steel (E = 193 GPa,
! nu = 0.3, rho = 8000 kg/m^3, handbook values), and A = 0.1 us, an
! illustrative value (not a measured one), so that e is near 0.96 at
! 1 m/s.  Bead 1 hits bead 2, at rest, at 0.01 to 3 m/s.  In the library's
! rescaled units (eq. (5) of arXiv:0905.4512) every impact is the same
! collision at unit velocity; only the rescaled damping A / t_unit changes,
! as V^(1/5) since the unit of time t_unit goes as V^(-1/5).  The program
! prints e against v, the first-order law e_1, and their difference, which
! shrinks as A^2 (the last column, the difference over (1 - e_1)^2, stays
! put).
!
! The checks: momentum is conserved, the energy lost is what the damping
! dissipated (e^2 = 1 - D / E_rel, from the final velocities and the
! dissipated energy the library integrates), and the difference from the
! first-order law is second order.  Every call's status is checked; a
! failure or a check that does not hold stops the program with a non-zero
! exit code.
!
! Build against an installed libtaper (the module's sources are installed
! in PREFIX/share/taper/fortran; compile them with your compiler):
!     gfortran $(pkg-config --variable=prefix taper)/share/taper/fortran/taper_constants.f90 \
!        $(pkg-config --variable=prefix taper)/share/taper/fortran/taper.f90 restitution.f90 \
!        $(pkg-config --libs taper) -Wl,-rpath,$(pkg-config --variable=libdir taper) -o restitution
program restitution
  use, intrinsic :: iso_c_binding
  use, intrinsic :: iso_fortran_env, only: error_unit
  use taper
  implicit none

  real(c_double), parameter :: young = 193d9, poisson = 0.3d0, density = 8000d0   ! SI
  real(c_double), parameter :: radius = 0.5d0 * 4.76d-3                           ! m
  real(c_double), parameter :: damping_si = 0.1d-6                                ! s
  integer, parameter :: n_impacts = 6
  real(c_double), parameter :: velocity(n_impacts) = [0.01d0, 0.03d0, 0.1d0, 0.3d0, 1d0, 3d0]
  ! two equal beads in rescaled units: masses 1, r = 1, mu = 1/2, v = 1
  real(c_double), parameter :: mu = 0.5d0, r = 1d0
  real(c_double), parameter :: max_momentum_error = 1d-10, max_energy_error = 1d-8
  real(c_double), parameter :: t_end = 20d0    ! rescaled: several collision times

  real(c_double) :: first_order, a(n_impacts), e, dissipated, momentum, e_first
  real(c_double) :: second(n_impacts), beta
  logical :: ok
  integer :: i

  ok = .true.
  beta = gamma(0.6d0) * gamma(1.5d0) / gamma(2.1d0)
  ! 1 - e = first_order * A / t_unit at unit velocity, rescaled
  first_order = 1.2d0 * beta * 1.25d0**0.6d0 * (r / mu)**0.4d0
  print '(a,f4.2,a,f4.2,a)', '# two steel beads of ', 2 * radius * 1d3, &
       ' mm, Kuwabara-Kono damping A = ', damping_si * 1d6, ' us'
  print '(a,f8.5,a)', '# first order: 1 - e = ', first_order, ' A / t_unit'
  print '(a,a9,a11,a11,a12,a12,a9)', '# ', 'v [m/s]', 'A/t_unit', 'e', 'first order', &
       'difference', 'second'
  do i = 1, n_impacts
     a(i) = damping_si / taper_unit_scale(TAPER_DIM_TIME, young, poisson, density, radius, &
          velocity(i))
     call collide(a(i), e, dissipated, momentum)
     e_first = 1 - first_order * a(i)
     second(i) = (e - e_first) / (1 - e_first)**2
     print '(2x,f9.2,f11.6,f11.6,f12.6,es12.2,f9.4)', velocity(i), a(i), e, e_first, &
          e - e_first, second(i)
     ! momentum: the two beads of unit mass carry the striking bead's unit
     call expect(abs(momentum - 1) <= max_momentum_error, 'momentum not conserved')
     ! energy: the relative motion's (mu v^2 / 2 = 1/4) less the dissipated
     call expect(abs(e**2 - (1 - dissipated / 0.25d0)) <= max_energy_error, &
          'the energy lost is not the energy dissipated')
  end do
  ! The difference from the first order is of second order: "second" =
  ! (e - e_1) / (1 - e_1)^2 stays put while A changes by a factor 3.
  print '(a,f7.4,a,f7.4)', '# second order: (e - e_1) / (1 - e_1)^2 from ', minval(second), &
       ' to ', maxval(second)
  if (.not. (maxval(second) <= 1.05d0 * minval(second) .and. minval(second) > 0)) then
     write (error_unit, '(a)') 'FAIL: the difference from the first-order law is not of second order'
     ok = .false.
  end if
  print '(a)', '# checks: momentum conserved, energy lost = energy dissipated, the ' // &
       'first-order law exact to second order: ' // merge('all hold', 'FAILED  ', ok)
  if (.not. ok) error stop 1

contains

  subroutine check(status, funcname, err)
    integer(c_int), intent(in) :: status
    character(len=*), intent(in) :: funcname
    type(taper_error), intent(in) :: err
    if (status == TAPER_OK) return
    write (error_unit, '(a)') 'ERROR: '//funcname//'() failed ('//taper_strerror(status)//') '// &
         taper_field(err)//': '//taper_message(err)
    error stop 1
  end subroutine check

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
    write (error_unit, '(a,f5.2,a)') 'FAIL: v = ', velocity(i), ' m/s: '//what
    ok = .false.
  end subroutine expect

  ! One collision with rescaled damping a: the coefficient of restitution
  ! from the final velocities, the energy dissipated, the final momentum.
  subroutine collide(a, e, dissipated, momentum)
    real(c_double), intent(in) :: a
    real(c_double), intent(out) :: e, dissipated, momentum
    type(taper_error) :: err
    type(c_ptr) :: chain_spec, solver_spec, chain, sim
    real(c_double), target :: v(2)

    chain_spec = taper_chain_spec_alloc(err)
    call check_pointer(chain_spec, 'taper_chain_spec_alloc', err)
    call check(taper_chain_spec_set_n_granules(chain_spec, 2_c_size_t, err), &
         'taper_chain_spec_set_n_granules', err)
    call check(taper_chain_spec_set_damping(chain_spec, a, err), 'taper_chain_spec_set_damping', err)
    chain = taper_chain_alloc(chain_spec, err)
    call taper_chain_spec_free(chain_spec)
    call check_pointer(chain, 'taper_chain_alloc', err)

    ! Past the end of the contact, with tight tolerances: e is a difference
    ! of two velocities.
    solver_spec = taper_solver_spec_alloc(err)
    call check_pointer(solver_spec, 'taper_solver_spec_alloc', err)
    call check(taper_solver_spec_set_t_end(solver_spec, t_end, err), 'taper_solver_spec_set_t_end', err)
    call check(taper_solver_spec_set_rtol(solver_spec, 1d-12, err), 'taper_solver_spec_set_rtol', err)
    sim = taper_sim_alloc(chain, solver_spec, err)
    call taper_solver_spec_free(solver_spec)
    call check_pointer(sim, 'taper_sim_alloc', err)
    call check(taper_sim_run(sim, err), 'taper_sim_run', err)

    call check(taper_sim_state(sim, c_null_ptr, c_loc(v), err), 'taper_sim_state', err)
    e = v(2) - v(1)          ! the relative velocity after, over 1 before
    momentum = v(1) + v(2)
    dissipated = taper_sim_statistic(sim, TAPER_STAT_ENERGY_DISSIPATED)
    call taper_sim_free(sim)
    call taper_chain_free(chain)
  end subroutine collide
end program restitution
