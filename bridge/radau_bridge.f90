! ISO_C_BINDING bridge to the Radau IIA kernel of fortran/radau.f: RADIIA (integrate),
! RADDEN (dense output) and RADCOE (method coefficients). The wrappers only marshal: same
! arguments in the same order as the kernels (so IDID = -i names the same argument i on both
! sides), value scalars, column-major arrays; C function pointers become Fortran procedure
! pointers and the opaque context pointer is passed through untouched.
! Everything is RECURSIVE (locals on the stack) so concurrent calls from several threads are
! safe, also under -fcheck=recursion. C prototypes, callback signatures and array shapes:
! bridge/pcsim_radau.h.
module pcsim_radau_bridge
  use, intrinsic :: iso_c_binding, only: c_int, c_double, c_double_complex, c_ptr, c_funptr, &
                                         c_f_procpointer
  implicit none
  private
  public :: pcsim_radau_integrate, pcsim_radau_dense, pcsim_radau_coefficients

  ! The callbacks as the kernel calls them: every argument by reference (implicit interface),
  ! so on the C side each is a pointer; ctx arrives as a pointer to the context pointer.
  abstract interface
    subroutine radau_fcn_iface(n, t, y, f, ctx, ierr) bind(C)
      import :: c_int, c_double, c_ptr
      integer(c_int), intent(in) :: n
      real(c_double), intent(in) :: t, y(*)
      real(c_double), intent(out) :: f(*)
      type(c_ptr), intent(in) :: ctx
      integer(c_int), intent(out) :: ierr
    end subroutine radau_fcn_iface
    subroutine radau_jac_iface(n, t, y, dfdy, ldj, ctx, ierr) bind(C)
      import :: c_int, c_double, c_ptr
      integer(c_int), intent(in) :: n, ldj
      real(c_double), intent(in) :: t, y(*)
      real(c_double), intent(out) :: dfdy(ldj, *)
      type(c_ptr), intent(in) :: ctx
      integer(c_int), intent(out) :: ierr
    end subroutine radau_jac_iface
    subroutine radau_gfcn_iface(n, t, y, ng, g, ctx, ierr) bind(C)
      import :: c_int, c_double, c_ptr
      integer(c_int), intent(in) :: n, ng
      real(c_double), intent(in) :: t, y(*)
      real(c_double), intent(out) :: g(*)
      type(c_ptr), intent(in) :: ctx
      integer(c_int), intent(out) :: ierr
    end subroutine radau_gfcn_iface
    subroutine radau_solout_iface(n, told, t, y, cont, ldc, ctx, irtrn) bind(C)
      import :: c_int, c_double, c_ptr
      integer(c_int), intent(in) :: n, ldc
      real(c_double), intent(in) :: told, t, cont(ldc, *)
      real(c_double), intent(inout) :: y(*)
      type(c_ptr), intent(in) :: ctx
      integer(c_int), intent(out) :: irtrn
    end subroutine radau_solout_iface
  end interface

  interface
    recursive subroutine radden(n, t, told, tnew, cont, ldc, yout, info)
      integer :: n, ldc, info
      double precision :: t, told, tnew
      double precision :: cont(ldc, *), yout(*)
    end subroutine radden
    recursive subroutine radcoe(c, t, ti, dd, gam, alp, bet)
      double precision :: c(3), t(3, 3), ti(3, 3), dd(3), gam, alp, bet
    end subroutine radcoe
  end interface

  external :: radiia

contains

  recursive subroutine pcsim_radau_integrate(fcn, jac, solout, gfcn, ctx, ijac, imas, itol, iout, &
                                   ng, n, t, tend, y, h, rtol, atol, am, ldm, work, lwork, zwork, &
                                   lzwork, iwork, liwork, idid) bind(C, name="pcsim_radau_integrate")
    type(c_funptr), value, intent(in) :: fcn, jac, solout, gfcn
    type(c_ptr), value, intent(in) :: ctx
    integer(c_int), value, intent(in) :: ijac, imas, itol, iout, ng, n, ldm, lwork, lzwork, liwork
    real(c_double), value, intent(in) :: tend
    real(c_double), intent(inout) :: t, h
    real(c_double), intent(inout) :: y(*)
    real(c_double), intent(in) :: rtol(*), atol(*), am(ldm, *)
    real(c_double), intent(inout) :: work(*)
    complex(c_double_complex), intent(inout) :: zwork(*)
    integer(c_int), intent(inout) :: iwork(*)
    integer(c_int), intent(out) :: idid
    procedure(radau_fcn_iface), pointer :: pfcn
    procedure(radau_jac_iface), pointer :: pjac
    procedure(radau_solout_iface), pointer :: psol
    procedure(radau_gfcn_iface), pointer :: pg
    type(c_ptr) :: ctx_ref
    call c_f_procpointer(fcn, pfcn)
    call c_f_procpointer(jac, pjac)
    call c_f_procpointer(solout, psol)
    call c_f_procpointer(gfcn, pg)
    ctx_ref = ctx
    call radiia(pfcn, pjac, psol, pg, ctx_ref, ijac, imas, itol, iout, ng, n, t, tend, y, h, &
                rtol, atol, am, ldm, work, lwork, zwork, lzwork, iwork, liwork, idid)
  end subroutine pcsim_radau_integrate

  recursive subroutine pcsim_radau_dense(n, t, told, tnew, cont, ldc, yout, info) &
      bind(C, name="pcsim_radau_dense")
    integer(c_int), value, intent(in) :: n, ldc
    real(c_double), value, intent(in) :: t, told, tnew
    real(c_double), intent(in) :: cont(ldc, *)
    real(c_double), intent(out) :: yout(*)
    integer(c_int), intent(out) :: info
    call radden(n, t, told, tnew, cont, ldc, yout, info)
  end subroutine pcsim_radau_dense

  recursive subroutine pcsim_radau_coefficients(c, t, ti, dd, gam, alp, bet) &
      bind(C, name="pcsim_radau_coefficients")
    real(c_double), intent(out) :: c(3), t(3, 3), ti(3, 3), dd(3), gam, alp, bet
    call radcoe(c, t, ti, dd, gam, alp, bet)
  end subroutine pcsim_radau_coefficients

end module pcsim_radau_bridge
