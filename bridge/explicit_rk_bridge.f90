! ISO_C_BINDING bridge to the explicit Runge-Kutta kernel of fortran/explicit_rk.f: ERKDP8
! (integrate), ERKDEN (dense output) and ERKCOE (method coefficients). The wrappers only
! marshal: same arguments in the same order as the kernels (so IDID = -i names the same
! argument i on both sides), value scalars, column-major arrays; C function pointers become
! Fortran procedure pointers and the opaque context pointer is passed through untouched.
! Everything is RECURSIVE (locals on the stack), so concurrent calls from several threads are
! safe. C prototypes, callback signatures and array shapes: bridge/pcsim_explicit_rk.h.
module pcsim_explicit_rk_bridge
  use, intrinsic :: iso_c_binding, only: c_int, c_double, c_ptr, c_funptr, c_f_procpointer
  implicit none
  private
  public :: pcsim_erk_integrate, pcsim_erk_dense, pcsim_erk_coefficients

  ! The callbacks as the kernel calls them: every argument by reference (implicit interface),
  ! so on the C side each is a pointer; ctx arrives as a pointer to the context pointer.
  abstract interface
    subroutine erk_fcn_iface(n, t, y, f, ctx, ierr) bind(C)
      import :: c_int, c_double, c_ptr
      integer(c_int), intent(in) :: n
      real(c_double), intent(in) :: t, y(*)
      real(c_double), intent(out) :: f(*)
      type(c_ptr), intent(in) :: ctx
      integer(c_int), intent(out) :: ierr
    end subroutine erk_fcn_iface
    subroutine erk_gfcn_iface(n, t, y, ng, g, ctx, ierr) bind(C)
      import :: c_int, c_double, c_ptr
      integer(c_int), intent(in) :: n, ng
      real(c_double), intent(in) :: t, y(*)
      real(c_double), intent(out) :: g(*)
      type(c_ptr), intent(in) :: ctx
      integer(c_int), intent(out) :: ierr
    end subroutine erk_gfcn_iface
    subroutine erk_solout_iface(n, told, t, hd, y, cont, ldc, ctx, irtrn) bind(C)
      import :: c_int, c_double, c_ptr
      integer(c_int), intent(in) :: n, ldc
      real(c_double), intent(in) :: told, t, hd, cont(ldc, *)
      real(c_double), intent(inout) :: y(*)
      type(c_ptr), intent(in) :: ctx
      integer(c_int), intent(out) :: irtrn
    end subroutine erk_solout_iface
  end interface

  interface
    recursive subroutine erkden(n, t, told, hd, cont, ldc, yout, info)
      integer :: n, ldc, info
      double precision :: t, told, hd
      double precision :: cont(ldc, *), yout(*)
    end subroutine erkden
    recursive subroutine erkcoe(a, b, c, bh, er, d)
      double precision :: a(16, 16), b(16), c(16), bh(16), er(16), d(4, 16)
    end subroutine erkcoe
  end interface

  external :: erkdp8

contains

  recursive subroutine pcsim_erk_integrate(fcn, gfcn, solout, ctx, itol, iout, n, ng, t, tend, &
                                           y, h, rtol, atol, work, lwork, iwork, liwork, idid) &
      bind(C, name="pcsim_erk_integrate")
    type(c_funptr), value, intent(in) :: fcn, gfcn, solout
    type(c_ptr), value, intent(in) :: ctx
    integer(c_int), value, intent(in) :: itol, iout, n, ng, lwork, liwork
    real(c_double), value, intent(in) :: tend
    real(c_double), intent(inout) :: t, h
    real(c_double), intent(inout) :: y(*)
    real(c_double), intent(in) :: rtol(*), atol(*)
    real(c_double), intent(inout) :: work(*)
    integer(c_int), intent(inout) :: iwork(*)
    integer(c_int), intent(out) :: idid
    procedure(erk_fcn_iface), pointer :: pfcn
    procedure(erk_gfcn_iface), pointer :: pgfcn
    procedure(erk_solout_iface), pointer :: psol
    type(c_ptr) :: ctx_ref
    call c_f_procpointer(fcn, pfcn)
    call c_f_procpointer(gfcn, pgfcn)
    call c_f_procpointer(solout, psol)
    ctx_ref = ctx
    call erkdp8(pfcn, pgfcn, psol, ctx_ref, itol, iout, n, ng, t, tend, y, h, rtol, atol, &
                work, lwork, iwork, liwork, idid)
  end subroutine pcsim_erk_integrate

  recursive subroutine pcsim_erk_dense(n, t, told, hd, cont, ldc, yout, info) &
      bind(C, name="pcsim_erk_dense")
    integer(c_int), value, intent(in) :: n, ldc
    real(c_double), value, intent(in) :: t, told, hd
    real(c_double), intent(in) :: cont(ldc, *)
    real(c_double), intent(out) :: yout(*)
    integer(c_int), intent(out) :: info
    call erkden(n, t, told, hd, cont, ldc, yout, info)
  end subroutine pcsim_erk_dense

  recursive subroutine pcsim_erk_coefficients(a, b, c, bh, er, d) &
      bind(C, name="pcsim_erk_coefficients")
    real(c_double), intent(out) :: a(16, 16), b(16), c(16), bh(16), er(16), d(4, 16)
    call erkcoe(a, b, c, bh, er, d)
  end subroutine pcsim_erk_coefficients

end module pcsim_explicit_rk_bridge
