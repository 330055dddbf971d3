! ISO_C_BINDING bridge to the Huang (ABS) kernels of fortran/huang.f: PCHUAN (solve A x = b,
! projector onto null(A), rank, dependent rows) and PCHNUL (orthonormal basis of null(A)).
! The wrappers only marshal: same arguments in the same order as the kernels (so INFO = -i
! refers to the same argument i on both sides), value scalars, column-major arrays.
! C prototypes and array shapes: bridge/pcsim_huang.h.
module pcsim_huang_bridge
  use, intrinsic :: iso_c_binding, only: c_int, c_double
  implicit none
  private
  public :: pcsim_huang_solve, pcsim_huang_null_basis

  interface
    subroutine pchuan(meth, m, n, a, lda, b, x, tol, h, ldh, rank, idep, work, lwork, info)
      integer :: meth, m, n, lda, ldh, rank, lwork, info
      double precision :: tol
      double precision :: a(lda, *), b(*), x(*), h(ldh, *), work(*)
      integer :: idep(*)
    end subroutine pchuan
    subroutine pchnul(n, rank, h, ldh, d, ldd, work, lwork, info)
      integer :: n, rank, ldh, ldd, lwork, info
      double precision :: h(ldh, *), d(ldd, *), work(*)
    end subroutine pchnul
  end interface

contains

  subroutine pcsim_huang_solve(meth, m, n, a, lda, b, x, tol, h, ldh, rank, idep, work, lwork, &
                               info) bind(C, name="pcsim_huang_solve")
    integer(c_int), value, intent(in) :: meth, m, n, lda, ldh, lwork
    real(c_double), value, intent(in) :: tol
    real(c_double), intent(in) :: a(lda, *), b(*)
    real(c_double), intent(inout) :: x(*)
    real(c_double), intent(out) :: h(ldh, *)
    integer(c_int), intent(out) :: rank, info
    integer(c_int), intent(out) :: idep(*)
    real(c_double), intent(inout) :: work(*)
    call pchuan(meth, m, n, a, lda, b, x, tol, h, ldh, rank, idep, work, lwork, info)
  end subroutine pcsim_huang_solve

  subroutine pcsim_huang_null_basis(n, rank, h, ldh, d, ldd, work, lwork, info) &
      bind(C, name="pcsim_huang_null_basis")
    integer(c_int), value, intent(in) :: n, rank, ldh, ldd, lwork
    real(c_double), intent(in) :: h(ldh, *)
    real(c_double), intent(out) :: d(ldd, *)
    real(c_double), intent(inout) :: work(*)
    integer(c_int), intent(out) :: info
    call pchnul(n, rank, h, ldh, d, ldd, work, lwork, info)
  end subroutine pcsim_huang_null_basis

end module pcsim_huang_bridge
