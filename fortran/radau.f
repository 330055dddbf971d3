*> \file radau.f
*> 3-stage Radau IIA (order 5) for K y' = f(t, y), K constant and
*> possibly singular.  Written for pcsim from the mathematics of
*> Hairer & Wanner, Solving ODEs II, section IV.8 (no code copied).
*>
*> Routines in this file:
*>   RADIIA  the integrator (checks arguments, partitions the work
*>           arrays, calls RADCOR)
*>   RADCOR  the step loop
*>   RADDEN  dense output from the continuation coefficients
*>   RADCOE  the method coefficients (c, T, T^{-1}, error weights,
*>           eigenvalues of A^{-1})
*>   RADJAC  Jacobian (user routine or finite differences)
*>   RADDEC  the real and the complex LU decompositions
*>   RADSLV  one simplified-Newton linear solve (real + complex)
*>   RADEST  the embedded error estimate with stiff filtering
*
*  =====================================================================
      RECURSIVE SUBROUTINE RADIIA( FCN, JAC, SOLOUT, CTX, IJAC, IMAS,
     $                   ITOL, IOUT, N, T, TEND, Y, H, RTOL, ATOL, AM,
     $                   LDM, WORK, LWORK, ZWORK, LZWORK, IWORK, LIWORK,
     $                   IDID )
      USE, INTRINSIC :: ISO_C_BINDING, ONLY: C_PTR
      IMPLICIT NONE
*
*     .. Scalar Arguments ..
      TYPE(C_PTR)        CTX
      INTEGER            IJAC, IMAS, ITOL, IOUT, N, LDM, LWORK,
     $                   LZWORK, LIWORK, IDID
      DOUBLE PRECISION   T, TEND, H
*     .. Array Arguments ..
      INTEGER            IWORK( * )
      DOUBLE PRECISION   Y( * ), RTOL( * ), ATOL( * ), AM( LDM, * ),
     $                   WORK( * )
      COMPLEX*16         ZWORK( * )
*     .. External Procedures ..
      EXTERNAL           FCN, JAC, SOLOUT
*
*  Purpose
*  =======
*
*  RADIIA integrates the system of differential(-algebraic) equations
*
*        K y'(t) = f(t, y(t)),      y(T) given,
*
*  from T to TEND with the 3-stage Radau IIA method (collocation at
*  c = (4-sqrt(6))/10, (4+sqrt(6))/10, 1; order 5, stage order 3,
*  L-stable, stiffly accurate).  K is a constant n x n matrix, which
*  may be singular (index-1 DAEs; index-2 and index-3 variables are
*  handled by scaling their error weights with h and h**2).
*
*  Mathematics
*  ===========
*
*  The stage increments Z = (z1,z2,z3), z_i = Y_i - y0, solve
*        (A^{-1}/h (x) K) Z = F(Z),   F_i = f(t0 + c_i h, y0 + z_i).
*  With A^{-1} = T L T^{-1}, L = diag(gam, [alp -bet; bet alp]), and
*  W = (T^{-1} (x) I) Z, the simplified Newton iteration is
*        (L/h (x) K - I (x) J) dW = -(L/h (x) K) W + (T^{-1} (x) I) F(Z)
*  which splits into one real system with E1 = (gam/h) K - J and one
*  complex system with E2 = ((alp + i bet)/h) K - J; each is factored
*  once (DGETRF, ZGETRF) per Jacobian or step-size change.  The
*  iteration stops when eta*||dW|| <= FNEWT with eta = theta/(1-theta),
*  theta the observed contraction rate; it is abandoned (step retried
*  with a smaller h) when theta >= 0.99, when the predicted error after
*  the remaining iterations exceeds FNEWT, or after NIT iterations.
*
*  The error estimate is the difference to an embedded order-3 formula
*  with an explicit first stage, filtered for stiffness:
*        err = E1^{-1} ( f(t0,y0) + K (d1 z1 + d2 z2 + d3 z3)/h ),
*  and, on the first step and after a rejected step, if ||err|| >= 1,
*  once more with f(t0, y0 + err) in place of f(t0, y0).  The new step
*  size is h*min(FACL, max(FACR, fac/||err||**(1/4))), with fac
*  = min(SAFE, SAFE*(2*NIT+1)/(NEWT+2*NIT)); with predictive control
*  (Gustafsson) the smaller of this and the predictive proposal
*  (h/hacc) * (erracc/err**2)**(1/4) * SAFE is used after an accepted
*  step.
*
*  Dense output: after each accepted step [TOLD, T] the collocation
*  polynomial u (degree 3, u(TOLD) = y0, u(TOLD + c_i h) = y0 + z_i)
*  is stored as CONT(1:N,1:4) in Newton form around T:
*        u(T + s h) = CONT1 + s (CONT2 + (s-c2+1) (CONT3
*                     + (s-c1+1) CONT4)),    s = (x - T)/h in [-1,0],
*  evaluated by RADDEN.  The same polynomial, extrapolated, gives the
*  starting values of the next Newton iteration.
*
*  Tolerances.  The user's RTOL and ATOL are transformed as in
*  Hairer & Wanner's RADAU5 (the embedded formula is of lower order):
*        rtol' = 0.1 * RTOL**(2/3),   atol' = rtol' * ATOL / RTOL,
*  and the error weights are sc_i = atol'_i + rtol'_i |y_i|, divided by
*  |h| for index-2 and by h**2 for index-3 variables.  Norms are
*  root-mean-square norms of the weighted vectors.
*
*  Arguments
*  =========
*
*  FCN     (input) EXTERNAL subroutine, the right-hand side
*             SUBROUTINE FCN( N, T, Y, F, CTX, IERR )
*             INTEGER N, IERR;  DOUBLE PRECISION T, Y(N), F(N)
*             TYPE(C_PTR) CTX  (passed through untouched)
*          computes F = f(T, Y).  IERR = 0: success; IERR = 1: f cannot
*          be evaluated at (T, Y) (the step is rejected and retried with
*          h/2); any other value: fatal error, RADIIA returns IDID = 10.
*
*  JAC     (input) EXTERNAL subroutine, the Jacobian (used if IJAC = 1)
*             SUBROUTINE JAC( N, T, Y, DFDY, LDJ, CTX, IERR )
*          computes DFDY(LDJ,N) = df/dy at (T, Y), column major.
*          IERR /= 0: fatal, IDID = 10.
*
*  SOLOUT  (input) EXTERNAL subroutine, called after every accepted
*          step if IOUT = 1:
*             SUBROUTINE SOLOUT( N, TOLD, T, Y, CONT, LDC, CTX, IRTRN )
*          TOLD, T: the step just accepted; Y(N): the solution at T,
*          which SOLOUT may modify; CONT(LDC,4): the continuation
*          coefficients for RADDEN.  On return IRTRN = 0: proceed;
*          1: Y was modified (if by more than the tolerance, i.e.
*          weighted RMS norm > 1, the next step starts its Newton
*          iteration from zero stage values instead of the extrapolated
*          polynomial, with a fresh Jacobian);
*          2: stop (IDID = 1); any other value: fatal error (IDID = 10).
*
*  CTX     (input) TYPE(C_PTR), opaque context handed to FCN, JAC and
*          SOLOUT unchanged.
*
*  IJAC    (input) INTEGER.  0: Jacobian by forward differences;
*          1: by JAC.
*
*  IMAS    (input) INTEGER.  0: K = identity (AM not referenced);
*          1: K = AM (full).
*
*  ITOL    (input) INTEGER.  0: RTOL, ATOL are scalars; 1: vectors.
*
*  IOUT    (input) INTEGER.  0: SOLOUT is never called; 1: it is.
*
*  N       (input) INTEGER.  The number of unknowns, N >= 1.
*
*  T       (input/output) DOUBLE PRECISION.  On entry the initial time,
*          on exit the time reached (TEND on success).
*
*  TEND    (input) DOUBLE PRECISION.  Final time (TEND < T integrates
*          backwards; TEND = T returns at once with IDID = 0).
*
*  Y       (input/output) DOUBLE PRECISION array, dimension (N).
*          On entry y(T) (consistent for DAEs), on exit y at the T
*          returned.
*
*  H       (input/output) DOUBLE PRECISION.  On entry the initial step
*          guess (0: 1.0D-6; its sign is ignored); on exit a step size
*          to continue with: min(|step|, |proposal|) of the last
*          accepted step that was not shortened to hit TEND.
*
*  RTOL    (input) DOUBLE PRECISION array, dimension (1) if ITOL = 0,
*          (N) if ITOL = 1.  Relative tolerances, each > 0.
*
*  ATOL    (input) DOUBLE PRECISION array, dimension like RTOL.
*          Absolute tolerances, each > 0.
*
*  AM      (input) DOUBLE PRECISION array, dimension (LDM,N).  The
*          mass matrix K if IMAS = 1.
*
*  LDM     (input) INTEGER.  Leading dimension of AM; LDM >= N if
*          IMAS = 1, LDM >= 1 otherwise.
*
*  WORK    (input/workspace) DOUBLE PRECISION array, dimension (LWORK).
*          Entries 1..20 are options (0 selects the default); the rest
*          is workspace.
*          WORK(1)  HMAX, largest step size (default |TEND - T|)
*          WORK(2)  HFIX > 0: fixed-step mode, every step has size HFIX
*                   (the last one is shortened to hit TEND), no error
*                   control; for order tests.  0: adaptive.
*          WORK(3)  SAFE, safety factor of the step control (0.9),
*                   0.001 < SAFE < 1
*          WORK(4)  THET, the Jacobian is recomputed after a step only
*                   if the last contraction rate exceeded THET (0.001);
*                   THET < 1
*          WORK(5)  FNEWT, Newton stopping tolerance (default
*                   max(10*EPS/rtol', min(0.03, sqrt(rtol'))),
*                   rtol' = first transformed RTOL)
*          WORK(6), WORK(7)  QUOT1 <= 1 <= QUOT2: if the new step
*                   is h*q with QUOT1 <= q <= QUOT2 and the Jacobian
*                   is kept, h is kept and no new LU is made (1, 1.2)
*          WORK(8)  FACL >= 1, largest step growth factor (5)
*          WORK(9)  FACR <= 1, largest step reduction factor (0.125)
*
*  LWORK   (input) INTEGER.  LWORK >= 20 + 19*N + 2*N*N.
*
*  ZWORK   (workspace) COMPLEX*16 array, dimension (LZWORK).
*
*  LZWORK  (input) INTEGER.  LZWORK >= N*N + N.
*
*  IWORK   (input/output) INTEGER array, dimension (LIWORK).
*          Options (0 selects the default):
*          IWORK(1)  NMAX, largest number of steps (100000)
*          IWORK(2)  NIT, largest number of Newton iterations (7)
*          IWORK(3)  NIND2, number of index-2 variables (0)
*          IWORK(4)  NIND3, number of index-3 variables (0); the
*                    variables are ordered index-1, index-2, index-3
*          IWORK(5)  0: predictive (Gustafsson) step control;
*                    1: classical step control
*          IWORK(6)  0: Newton starts from the extrapolated collocation
*                    polynomial; 1: from zero stage values
*          Statistics (output, fixed slots):
*          IWORK(11) f evaluations (including finite differences)
*          IWORK(12) Jacobian evaluations
*          IWORK(13) LU decompositions (the real+complex pair once)
*          IWORK(14) linear solves (Newton: real+complex pair once;
*                    each error-estimate solve once)
*          IWORK(15) steps attempted (= accepted + rejected)
*          IWORK(16) accepted steps
*          IWORK(17) rejected steps (error test, Newton failure, or
*                    f unable to evaluate)
*          IWORK(18) singular iteration matrices met
*          IWORK(21:20+2N) pivots (workspace)
*
*  LIWORK  (input) INTEGER.  LIWORK >= 20 + 2*N.
*
*  IDID    (output) INTEGER, a code of the pcsim ODE status table
*          (bridge/pcsim_ode_status.h; named constants ODE_* in
*          fortran/pcsim_ode_status.fi; docs/radau.md "Statuses"):
*          = 0  (ODE_SUCCESS):  success, T = TEND.
*          = 1  (ODE_STOPPED_BY_CALLBACK):  stopped by SOLOUT
*               (IRTRN = 2); T is the end of the last accepted step.
*          < 0:  if IDID = -i, the i-th argument had an illegal value
*                (an option in WORK or IWORK gives -18 or -22); nothing
*                was computed.
*          = 3  (ODE_TOO_MANY_STEPS):  more than NMAX steps.
*          = 4  (ODE_STEP_TOO_SMALL):  step size too small:
*               0.1*|h| <= EPS*|t|; in fixed-step mode also: Newton
*               did not converge with a fresh Jacobian.
*          = 6  (ODE_SINGULAR_MATRIX):  the iteration matrix was
*               singular more than 5 times.
*          = 10 (ODE_CALLBACK_ERROR):  a callback reported a fatal
*               error (FCN IERR > 1 or < 0, JAC IERR /= 0, SOLOUT
*               IRTRN > 2 or < 0), or FCN could not be evaluated at an
*               accepted state.
*          On IDID >= 3, T and Y are the last accepted state.
*
*  Further Details
*  ===============
*
*  Re-entrant: no COMMON, no SAVE, no I/O; all state lives in the
*  arguments, and every routine is RECURSIVE, so its locals are on
*  the stack (and -fcheck=recursion, which keeps a static flag per
*  routine, does not mistake two threads for recursion).  A step attempt starts with the Jacobian at the last
*  accepted state if it is stale (computed before the last accepted
*  step with a contraction rate > THET), then the LU pair if h changed.
*  A singular LU halves h.  Newton failures: contraction rate >= 0.99,
*  NIT iterations, or FCN IERR = 1 -> h/2 (and a fresh Jacobian if it
*  was stale); predicted slow convergence -> h times
*  0.8*q**(-1/(4+NIT-1-k)), q the predicted error ratio, k the
*  iteration count.  A rejected first step is retried with h/10, other
*  rejected steps with the step size proposal; after a rejection the
*  step size does not grow on the next step.
*
*  Work layout (1-based offsets): Z1,Z2,Z3 (3N), W1,W2,W3 (3N),
*  F1,F2,F3 (3N), Y0 = f(t,y) (N), SCAL (N), transformed RTOL, ATOL
*  (2N), CONT (4N), two temporaries (2N), Jacobian (N*N), E1 (N*N), all
*  from WORK(21); E2 (N*N) and one complex vector (N) in ZWORK.
*
*  =====================================================================
*
*     .. Local Scalars ..
      INTEGER            I, NMAX, NIT, NIND2, NIND3, IPRED, ISTRT
      INTEGER            IZ1, IZ2, IZ3, IW1, IW2, IW3, IF1, IF2, IF3,
     $                   IY0, ISC, IRT, IAT, ICO, IT1, IT2, IFJ, IE1
      DOUBLE PRECISION   HMAXN, HFIX, SAFE, THET, FNEWT, QUOT1, QUOT2,
     $                   FACL, FACR, UROUND, QUOT, TOLST
*     .. Intrinsic Functions ..
      INTRINSIC          ABS, EPSILON, MAX, MIN, SQRT
*     ..
*     .. Executable Statements ..
*
      UROUND = EPSILON( 1.0D0 )
*
*     Test the input arguments; the first bad one is reported.
*
      IDID = 0
      IF( IJAC.NE.0 .AND. IJAC.NE.1 ) THEN
         IDID = -5
      ELSE IF( IMAS.NE.0 .AND. IMAS.NE.1 ) THEN
         IDID = -6
      ELSE IF( ITOL.NE.0 .AND. ITOL.NE.1 ) THEN
         IDID = -7
      ELSE IF( IOUT.NE.0 .AND. IOUT.NE.1 ) THEN
         IDID = -8
      ELSE IF( N.LT.1 ) THEN
         IDID = -9
      ELSE IF( .NOT.( T.EQ.T ) .OR. ABS( T ).GT.HUGE( T ) ) THEN
         IDID = -10
      ELSE IF( .NOT.( TEND.EQ.TEND ) .OR.
     $         ABS( TEND ).GT.HUGE( TEND ) ) THEN
         IDID = -11
      ELSE IF( .NOT.( H.EQ.H ) ) THEN
         IDID = -13
      END IF
      IF( IDID.NE.0 ) RETURN
      DO 10 I = 1, 1 + ITOL*( N-1 )
         IF( .NOT.( RTOL( I ).GT.0.0D0 ) ) THEN
            IDID = -14
            RETURN
         END IF
   10 CONTINUE
      DO 20 I = 1, 1 + ITOL*( N-1 )
         IF( .NOT.( ATOL( I ).GT.0.0D0 ) ) THEN
            IDID = -15
            RETURN
         END IF
   20 CONTINUE
      IF( LDM.LT.MAX( 1, IMAS*N ) ) THEN
         IDID = -17
      ELSE IF( LWORK.LT.20 + 19*N + 2*N*N ) THEN
         IDID = -19
      ELSE IF( LZWORK.LT.N*N + N ) THEN
         IDID = -21
      ELSE IF( LIWORK.LT.20 + 2*N ) THEN
         IDID = -23
      END IF
      IF( IDID.NE.0 ) RETURN
*
*     Options in WORK.
*
      HMAXN = ABS( TEND - T )
      IF( WORK( 1 ).LT.0.0D0 ) IDID = -18
      IF( WORK( 1 ).GT.0.0D0 ) HMAXN = MIN( HMAXN, WORK( 1 ) )
      HFIX = WORK( 2 )
      IF( HFIX.LT.0.0D0 ) IDID = -18
      SAFE = 0.9D0
      IF( WORK( 3 ).NE.0.0D0 ) SAFE = WORK( 3 )
      IF( SAFE.LE.0.001D0 .OR. SAFE.GE.1.0D0 ) IDID = -18
      THET = 0.001D0
      IF( WORK( 4 ).NE.0.0D0 ) THET = WORK( 4 )
      IF( THET.LT.0.0D0 .OR. THET.GE.1.0D0 ) IDID = -18
      QUOT1 = 1.0D0
      IF( WORK( 6 ).NE.0.0D0 ) QUOT1 = WORK( 6 )
      QUOT2 = 1.2D0
      IF( WORK( 7 ).NE.0.0D0 ) QUOT2 = WORK( 7 )
      IF( QUOT1.LE.0.0D0 .OR. QUOT1.GT.1.0D0 .OR. QUOT2.LT.1.0D0 )
     $   IDID = -18
      FACL = 5.0D0
      IF( WORK( 8 ).NE.0.0D0 ) FACL = WORK( 8 )
      FACR = 0.125D0
      IF( WORK( 9 ).NE.0.0D0 ) FACR = WORK( 9 )
      IF( FACL.LT.1.0D0 .OR. FACR.LE.0.0D0 .OR. FACR.GT.1.0D0 )
     $   IDID = -18
      IF( IDID.NE.0 ) RETURN
*
*     Options in IWORK.
*
      NMAX = 100000
      IF( IWORK( 1 ).NE.0 ) NMAX = IWORK( 1 )
      NIT = 7
      IF( IWORK( 2 ).NE.0 ) NIT = IWORK( 2 )
      NIND2 = IWORK( 3 )
      NIND3 = IWORK( 4 )
      IPRED = IWORK( 5 )
      ISTRT = IWORK( 6 )
      IF( NMAX.LT.1 .OR. NIT.LT.1 .OR. NIND2.LT.0 .OR. NIND3.LT.0
     $    .OR. NIND2 + NIND3.GT.N .OR. IPRED.LT.0 .OR. IPRED.GT.1
     $    .OR. ISTRT.LT.0 .OR. ISTRT.GT.1 ) THEN
         IDID = -22
         RETURN
      END IF
*
*     Partition the work arrays.
*
      IZ1 = 21
      IZ2 = IZ1 + N
      IZ3 = IZ2 + N
      IW1 = IZ3 + N
      IW2 = IW1 + N
      IW3 = IW2 + N
      IF1 = IW3 + N
      IF2 = IF1 + N
      IF3 = IF2 + N
      IY0 = IF3 + N
      ISC = IY0 + N
      IRT = ISC + N
      IAT = IRT + N
      ICO = IAT + N
      IT1 = ICO + 4*N
      IT2 = IT1 + N
      IFJ = IT2 + N
      IE1 = IFJ + N*N
*
*     Transformed tolerances (see Mathematics).  Not vectorized: a
*     SIMD pow (glibc libmvec, which gfortran may call at -O3) rounds
*     differently from the scalar pow the C++ port uses, and the two
*     kernels must round identically.
*
!GCC$ NOVECTOR
      DO 30 I = 1, N
         IF( ITOL.EQ.0 ) THEN
            QUOT = ATOL( 1 ) / RTOL( 1 )
            WORK( IRT+I-1 ) = 0.1D0*RTOL( 1 )**( 2.0D0 / 3.0D0 )
         ELSE
            QUOT = ATOL( I ) / RTOL( I )
            WORK( IRT+I-1 ) = 0.1D0*RTOL( I )**( 2.0D0 / 3.0D0 )
         END IF
         WORK( IAT+I-1 ) = WORK( IRT+I-1 )*QUOT
   30 CONTINUE
      TOLST = WORK( IRT )
      FNEWT = MAX( 10.0D0*UROUND / TOLST, MIN( 0.03D0, SQRT( TOLST ) ) )
      IF( WORK( 5 ).LT.0.0D0 ) THEN
         IDID = -18
         RETURN
      END IF
      IF( WORK( 5 ).GT.0.0D0 ) FNEWT = WORK( 5 )
*
      DO 40 I = 11, 20
         IWORK( I ) = 0
   40 CONTINUE
      IF( TEND.EQ.T ) RETURN
*
      CALL RADCOR( FCN, JAC, SOLOUT, CTX, IJAC, IMAS, IOUT, N, T, TEND,
     $             Y, H, AM, LDM, NIND2, NIND3, NMAX, NIT, IPRED,
     $             ISTRT, HMAXN, HFIX, SAFE, THET, FNEWT, QUOT1, QUOT2,
     $             FACL, FACR, WORK( IRT ), WORK( IAT ), WORK( IZ1 ),
     $             WORK( IZ2 ), WORK( IZ3 ), WORK( IW1 ), WORK( IW2 ),
     $             WORK( IW3 ), WORK( IF1 ), WORK( IF2 ), WORK( IF3 ),
     $             WORK( IY0 ), WORK( ISC ), WORK( ICO ), WORK( IT1 ),
     $             WORK( IT2 ), WORK( IFJ ), WORK( IE1 ), ZWORK( 1 ),
     $             ZWORK( N*N+1 ), IWORK( 21 ), IWORK( 21+N ),
     $             IWORK( 11 ), IDID )
      RETURN
*
*     End of RADIIA
*
      END
*
*  =====================================================================
      RECURSIVE SUBROUTINE RADCOR( FCN, JAC, SOLOUT, CTX, IJAC, IMAS,
     $                   IOUT, N, X, XEND, Y, H, AM, LDM, NIND2, NIND3,
     $                   NMAX, NIT, IPRED, ISTRT, HMAXN, HFIX, SAFE,
     $                   THET, FNEWT, QUOT1, QUOT2, FACL, FACR, RTT,
     $                   ATT, Z1, Z2, Z3, W1, W2, W3, F1, F2, F3, Y0,
     $                   SCAL, CONT, T1, T2, FJAC, E1, E2, ZT, IP1, IP2,
     $                   ISTAT, IDID )
      USE, INTRINSIC :: ISO_C_BINDING, ONLY: C_PTR
      IMPLICIT NONE
      TYPE(C_PTR)        CTX
      INTEGER            IJAC, IMAS, IOUT, N, LDM, NIND2, NIND3, NMAX,
     $                   NIT, IPRED, ISTRT, IDID
      DOUBLE PRECISION   X, XEND, H, HMAXN, HFIX, SAFE, THET, FNEWT,
     $                   QUOT1, QUOT2, FACL, FACR
      INTEGER            IP1( N ), IP2( N ), ISTAT( 10 )
      DOUBLE PRECISION   Y( N ), AM( LDM, * ), RTT( N ), ATT( N ),
     $                   Z1( N ), Z2( N ), Z3( N ), W1( N ), W2( N ),
     $                   W3( N ), F1( N ), F2( N ), F3( N ), Y0( N ),
     $                   SCAL( N ), CONT( N, 4 ), T1( N ), T2( N ),
     $                   FJAC( N, N ), E1( N, N )
      COMPLEX*16         E2( N, N ), ZT( N )
      EXTERNAL           FCN, JAC, SOLOUT
      INCLUDE 'pcsim_ode_status.fi'
*
*  Purpose
*  =======
*
*  RADCOR is the step loop of RADIIA (see there for the method, the
*  arguments it shares and the meaning of IDID).  X, XEND, H: current
*  time, final time and step (signed).  The remaining scalars are the
*  resolved options; RTT, ATT the transformed tolerances; the arrays
*  after them are the partitioned workspace; ISTAT(1:8) receives the
*  statistics IWORK(11:18) of RADIIA.
*
*  =====================================================================
*
*     .. Local Scalars ..
      INTEGER            I, NEWT, NFCN, NJAC, NDEC, NSOL, NSTEP,
     $                   NACCPT, NREJCT, NSING, IERR, INFO, NIND1
      LOGICAL            FIRST, REJECT, LAST, CALJAC, NEEDJ, NEEDLU,
     $                   FIXED, STARTZ, NEWTOK
      DOUBLE PRECISION   UROUND, POSNEG, XOLD, HOLD, HNEW, HOPT, HACC,
     $                   ERRACC, ERR, FACCON, THETA, THQ, THQOLD, DYNO,
     $                   DYNOLD, FAC1, ALPHN, BETAN, CFAC, QUOT, FAC,
     $                   FACGUS, QNEWT, DYTH, HHFAC, QT, C1Q, C2Q, C3Q,
     $                   AK1, AK2, AK3, A1, A2, A3, SUM, HABS
      DOUBLE PRECISION   GAM, ALP, BET, C1M1, C2M1, C1MC2
*     .. Local Arrays ..
      DOUBLE PRECISION   C( 3 ), TT( 3, 3 ), TI( 3, 3 ), DD( 3 )
*     .. External Subroutines ..
      EXTERNAL           RADCOE, RADJAC, RADDEC, RADSLV, RADEST, DGEMV
*     .. Intrinsic Functions ..
      INTRINSIC          ABS, EPSILON, MAX, MIN, SIGN, SQRT
*     ..
      UROUND = EPSILON( 1.0D0 )
      CALL RADCOE( C, TT, TI, DD, GAM, ALP, BET )
      C1M1 = C( 1 ) - 1.0D0
      C2M1 = C( 2 ) - 1.0D0
      C1MC2 = C( 1 ) - C( 2 )
      NIND1 = N - NIND2 - NIND3
*
      NFCN = 0
      NJAC = 0
      NDEC = 0
      NSOL = 0
      NSTEP = 0
      NACCPT = 0
      NREJCT = 0
      NSING = 0
      FIXED = HFIX.GT.0.0D0
      POSNEG = SIGN( 1.0D0, XEND - X )
      IF( FIXED ) THEN
         H = HFIX
      ELSE IF( H.EQ.0.0D0 ) THEN
         H = 1.0D-6
      END IF
      H = MIN( ABS( H ), HMAXN )*POSNEG
      LAST = .FALSE.
      IF( ( X + H*1.0001D0 - XEND )*POSNEG.GE.0.0D0 ) THEN
         H = XEND - X
         LAST = .TRUE.
      END IF
      HOPT = H
      HOLD = H
      HACC = H
      ERRACC = 1.0D-2
      FACCON = 1.0D0
      THETA = ABS( THET )
      CFAC = SAFE*DBLE( 1 + 2*NIT )
      FIRST = .TRUE.
      REJECT = .FALSE.
      CALJAC = .FALSE.
      STARTZ = .TRUE.
      NEEDJ = .TRUE.
      NEEDLU = .TRUE.
      XOLD = X
*
      CALL FCN( N, X, Y, Y0, CTX, IERR )
      NFCN = NFCN + 1
      IF( IERR.NE.0 ) THEN
         IDID = ODE_CALLBACK_ERROR
         GO TO 900
      END IF
*
*     ---- Main loop: Jacobian if stale, LU if h changed, one step.
*
  100 CONTINUE
      IF( NEEDJ ) THEN
         CALL RADJAC( FCN, JAC, CTX, IJAC, N, X, Y, Y0, FJAC, T1, NFCN,
     $                IERR )
         NJAC = NJAC + 1
         IF( IERR.NE.0 ) THEN
            IDID = ODE_CALLBACK_ERROR
            GO TO 900
         END IF
         CALJAC = .TRUE.
         NEEDJ = .FALSE.
         NEEDLU = .TRUE.
      END IF
      IF( NEEDLU ) THEN
         FAC1 = GAM / H
         ALPHN = ALP / H
         BETAN = BET / H
         CALL RADDEC( IMAS, N, FAC1, ALPHN, BETAN, FJAC, AM, LDM, E1,
     $                E2, IP1, IP2, INFO )
         NDEC = NDEC + 1
         IF( INFO.NE.0 ) THEN
            NSING = NSING + 1
            IF( NSING.GT.5 ) THEN
               IDID = ODE_SINGULAR_MATRIX
               GO TO 900
            END IF
            IF( FIXED ) THEN
               IDID = ODE_STEP_TOO_SMALL
               GO TO 900
            END IF
            H = H*0.5D0
            REJECT = .TRUE.
            LAST = .FALSE.
            GO TO 100
         END IF
         NEEDLU = .FALSE.
      END IF
*
*     ---- One step attempt from X with step H.
*
      IF( NSTEP.GE.NMAX ) THEN
         IDID = ODE_TOO_MANY_STEPS
         GO TO 900
      END IF
      IF( 0.1D0*ABS( H ).LE.ABS( X )*UROUND ) THEN
         IDID = ODE_STEP_TOO_SMALL
         GO TO 900
      END IF
      NSTEP = NSTEP + 1
      HABS = ABS( H )
      DO 110 I = 1, N
         SCAL( I ) = ATT( I ) + RTT( I )*ABS( Y( I ) )
  110 CONTINUE
      DO 120 I = NIND1 + 1, NIND1 + NIND2
         SCAL( I ) = SCAL( I ) / HABS
  120 CONTINUE
      DO 130 I = NIND1 + NIND2 + 1, N
         SCAL( I ) = SCAL( I ) / ( HABS*HABS )
  130 CONTINUE
*
*     Starting values of the Newton iteration.
*
      IF( STARTZ .OR. ISTRT.EQ.1 ) THEN
         DO 140 I = 1, N
            Z1( I ) = 0.0D0
            Z2( I ) = 0.0D0
            Z3( I ) = 0.0D0
            W1( I ) = 0.0D0
            W2( I ) = 0.0D0
            W3( I ) = 0.0D0
  140    CONTINUE
      ELSE
         C3Q = H / HOLD
         C1Q = C( 1 )*C3Q
         C2Q = C( 2 )*C3Q
         DO 150 I = 1, N
            AK1 = CONT( I, 2 )
            AK2 = CONT( I, 3 )
            AK3 = CONT( I, 4 )
            Z1( I ) = C1Q*( AK1 + ( C1Q - C2M1 )*( AK2 + ( C1Q - C1M1 )
     $                *AK3 ) )
            Z2( I ) = C2Q*( AK1 + ( C2Q - C2M1 )*( AK2 + ( C2Q - C1M1 )
     $                *AK3 ) )
            Z3( I ) = C3Q*( AK1 + ( C3Q - C2M1 )*( AK2 + ( C3Q - C1M1 )
     $                *AK3 ) )
            W1( I ) = TI( 1, 1 )*Z1( I ) + TI( 1, 2 )*Z2( I )
     $                + TI( 1, 3 )*Z3( I )
            W2( I ) = TI( 2, 1 )*Z1( I ) + TI( 2, 2 )*Z2( I )
     $                + TI( 2, 3 )*Z3( I )
            W3( I ) = TI( 3, 1 )*Z1( I ) + TI( 3, 2 )*Z2( I )
     $                + TI( 3, 3 )*Z3( I )
  150    CONTINUE
      END IF
*
*     Simplified Newton iteration.
*
      NEWT = 0
      FACCON = MAX( FACCON, UROUND )**0.8D0
      THETA = ABS( THET )
      DYNOLD = 0.0D0
      THQOLD = 0.0D0
      NEWTOK = .FALSE.
  200 CONTINUE
      IF( NEWT.GE.NIT ) GO TO 400
*        F_i = f(x + c_i h, y + z_i), i = 1, 2, 3.
      DO 210 I = 1, N
         T1( I ) = Y( I ) + Z1( I )
  210 CONTINUE
      CALL FCN( N, X + C( 1 )*H, T1, F1, CTX, IERR )
      NFCN = NFCN + 1
      IF( IERR.NE.0 ) GO TO 390
      DO 220 I = 1, N
         T1( I ) = Y( I ) + Z2( I )
  220 CONTINUE
      CALL FCN( N, X + C( 2 )*H, T1, F2, CTX, IERR )
      NFCN = NFCN + 1
      IF( IERR.NE.0 ) GO TO 390
      DO 230 I = 1, N
         T1( I ) = Y( I ) + Z3( I )
  230 CONTINUE
      CALL FCN( N, X + H, T1, F3, CTX, IERR )
      NFCN = NFCN + 1
      IF( IERR.NE.0 ) GO TO 390
*        Right-hand side: (T^{-1} (x) I) F - (L/h (x) K) W.
      IF( IMAS.EQ.1 ) THEN
         CALL DGEMV( 'N', N, N, 1.0D0, AM, LDM, W1, 1, 0.0D0, Z1, 1 )
         CALL DGEMV( 'N', N, N, 1.0D0, AM, LDM, W2, 1, 0.0D0, Z2, 1 )
         CALL DGEMV( 'N', N, N, 1.0D0, AM, LDM, W3, 1, 0.0D0, Z3, 1 )
      ELSE
         DO 240 I = 1, N
            Z1( I ) = W1( I )
            Z2( I ) = W2( I )
            Z3( I ) = W3( I )
  240    CONTINUE
      END IF
      DO 250 I = 1, N
         A1 = F1( I )
         A2 = F2( I )
         A3 = F3( I )
         F1( I ) = TI( 1, 1 )*A1 + TI( 1, 2 )*A2 + TI( 1, 3 )*A3
     $             - FAC1*Z1( I )
         F2( I ) = TI( 2, 1 )*A1 + TI( 2, 2 )*A2 + TI( 2, 3 )*A3
     $             - ALPHN*Z2( I ) + BETAN*Z3( I )
         F3( I ) = TI( 3, 1 )*A1 + TI( 3, 2 )*A2 + TI( 3, 3 )*A3
     $             - BETAN*Z2( I ) - ALPHN*Z3( I )
  250 CONTINUE
      CALL RADSLV( N, E1, E2, IP1, IP2, F1, F2, F3, ZT )
      NSOL = NSOL + 1
      NEWT = NEWT + 1
      SUM = 0.0D0
      DO 260 I = 1, N
         SUM = SUM + ( F1( I ) / SCAL( I ) )**2 +
     $         ( F2( I ) / SCAL( I ) )**2 + ( F3( I ) / SCAL( I ) )**2
  260 CONTINUE
      DYNO = SQRT( SUM / DBLE( 3*N ) )
*        Contraction rate and convergence prediction.
      IF( NEWT.GE.2 ) THEN
         THQ = DYNO / DYNOLD
         IF( NEWT.EQ.2 ) THEN
            THETA = THQ
         ELSE
            THETA = SQRT( THQ*THQOLD )
         END IF
         THQOLD = THQ
         IF( THETA.LT.0.99D0 ) THEN
            FACCON = THETA / ( 1.0D0 - THETA )
            IF( THETA.GT.0.0D0 ) THEN
               DYTH = FACCON*DYNO*THETA**DBLE( NIT - 1 - NEWT )
     $                / FNEWT
            ELSE
               DYTH = 0.0D0
            END IF
            IF( DYTH.GE.1.0D0 .AND. .NOT.FIXED ) THEN
*              Convergence too slow: retry with a smaller step.
               QNEWT = MAX( 1.0D-4, MIN( 20.0D0, DYTH ) )
               HHFAC = 0.8D0*QNEWT**( -1.0D0 / DBLE( 4 + NIT - 1
     $                 - NEWT ) )
               H = HHFAC*H
               GO TO 395
            END IF
         ELSE
            GO TO 400
         END IF
      END IF
      DYNOLD = MAX( DYNO, UROUND )
      DO 270 I = 1, N
         W1( I ) = W1( I ) + F1( I )
         W2( I ) = W2( I ) + F2( I )
         W3( I ) = W3( I ) + F3( I )
         Z1( I ) = TT( 1, 1 )*W1( I ) + TT( 1, 2 )*W2( I )
     $             + TT( 1, 3 )*W3( I )
         Z2( I ) = TT( 2, 1 )*W1( I ) + TT( 2, 2 )*W2( I )
     $             + TT( 2, 3 )*W3( I )
         Z3( I ) = TT( 3, 1 )*W1( I ) + TT( 3, 2 )*W2( I )
     $             + TT( 3, 3 )*W3( I )
  270 CONTINUE
      IF( FACCON*DYNO.GT.FNEWT ) GO TO 200
      NEWTOK = .TRUE.
      GO TO 500
*
*     f could not be evaluated at a stage: like a Newton failure.
  390 CONTINUE
      IF( IERR.NE.1 ) THEN
         IDID = ODE_CALLBACK_ERROR
         GO TO 900
      END IF
      GO TO 400
*
*     Newton failure: halve h, fresh Jacobian if it was stale.
  400 CONTINUE
      IF( FIXED ) THEN
         IF( CALJAC ) THEN
            IDID = ODE_STEP_TOO_SMALL
            GO TO 900
         END IF
      ELSE
         H = H*0.5D0
      END IF
*
*     Rejection after slow predicted convergence (h already reduced),
*     and the common tail of a Newton failure: retry the step.
  395 CONTINUE
      REJECT = .TRUE.
      LAST = .FALSE.
      NREJCT = NREJCT + 1
      NEEDLU = .TRUE.
      NEEDJ = .NOT.CALJAC
      GO TO 100
*
*     ---- Newton converged: error estimate and step-size proposal.
  500 CONTINUE
      IF( FIXED ) THEN
         ERR = 0.0D0
         HNEW = H
         QUOT = 1.0D0
      ELSE
         CALL RADEST( FCN, CTX, IMAS, N, X, H, Y, Y0, Z1, Z2, Z3, DD,
     $                SCAL, AM, LDM, E1, IP1, FIRST .OR. REJECT, T1,
     $                T2, F1, NFCN, NSOL, ERR, IERR )
         IF( IERR.NE.0 ) GO TO 390
         FAC = MIN( SAFE, CFAC / DBLE( NEWT + 2*NIT ) )
         QUOT = MAX( FACR, MIN( FACL, ERR**0.25D0 / FAC ) )
         HNEW = H / QUOT
      END IF
      IF( ERR.GE.1.0D0 ) GO TO 700
*
*     ---- Step accepted.
      FIRST = .FALSE.
      NACCPT = NACCPT + 1
      IF( IPRED.EQ.0 .AND. NACCPT.GT.1 .AND. .NOT.FIXED ) THEN
*        Predictive step-size control (Gustafsson).
         FACGUS = ( HACC / H )*( ERR**2 / ERRACC )**0.25D0 / SAFE
         FACGUS = MAX( FACR, MIN( FACL, FACGUS ) )
         QUOT = MAX( QUOT, FACGUS )
         HNEW = H / QUOT
      END IF
      HACC = H
      ERRACC = MAX( 1.0D-2, ERR )
      XOLD = X
      HOLD = H
      IF( LAST ) THEN
         X = XEND
      ELSE
         X = XOLD + H
      END IF
*     Continuation coefficients (Newton divided differences of the
*     collocation polynomial at 1, c2, c1, 0) and the new solution.
      DO 510 I = 1, N
         AK1 = ( Z2( I ) - Z3( I ) ) / C2M1
         AK2 = ( Z1( I ) - Z2( I ) ) / C1MC2
         A1 = Z1( I ) / C( 1 )
         A2 = ( AK2 - A1 ) / C( 2 )
         AK2 = ( AK2 - AK1 ) / C1M1
         Y( I ) = Y( I ) + Z3( I )
         CONT( I, 1 ) = Y( I )
         CONT( I, 2 ) = AK1
         CONT( I, 3 ) = AK2
         CONT( I, 4 ) = AK2 - A2
  510 CONTINUE
      STARTZ = .FALSE.
      IF( IOUT.EQ.1 ) THEN
         CALL SOLOUT( N, XOLD, X, Y, CONT, N, CTX, IERR )
         IF( IERR.EQ.2 ) THEN
            IDID = ODE_STOPPED_BY_CALLBACK
            GO TO 900
         ELSE IF( IERR.EQ.1 ) THEN
*           Y was modified.  A change within the tolerance (weighted
*           RMS norm <= 1, e.g. a projection) keeps the extrapolated
*           Newton start; a larger one restarts from zero.
            SUM = 0.0D0
            DO 520 I = 1, N
               SUM = SUM + ( ( Y( I ) - CONT( I, 1 ) ) / SCAL( I ) )**2
  520       CONTINUE
            STARTZ = SQRT( SUM / DBLE( N ) ).GT.1.0D0
         ELSE IF( IERR.NE.0 ) THEN
            IDID = ODE_CALLBACK_ERROR
            GO TO 900
         END IF
      END IF
      CALJAC = .FALSE.
      IF( LAST ) THEN
         H = HOPT
         IDID = ODE_SUCCESS
         GO TO 900
      END IF
      CALL FCN( N, X, Y, Y0, CTX, IERR )
      NFCN = NFCN + 1
      IF( IERR.NE.0 ) THEN
         IDID = ODE_CALLBACK_ERROR
         GO TO 900
      END IF
      HNEW = POSNEG*MIN( ABS( HNEW ), HMAXN )
      HOPT = POSNEG*MIN( ABS( H ), ABS( HNEW ) )
      IF( REJECT ) HNEW = POSNEG*MIN( ABS( HNEW ), ABS( H ) )
      REJECT = .FALSE.
      IF( FIXED ) THEN
*        Fixed steps: absorb rounding so no sliver step is left.
         QT = 1.0001D0
      ELSE
         QT = 1.0D0 / QUOT1
      END IF
      IF( ( X + HNEW*QT - XEND )*POSNEG.GE.0.0D0 ) THEN
         H = XEND - X
         LAST = .TRUE.
         NEEDLU = .TRUE.
      ELSE
         QT = HNEW / H
         IF( .NOT.( THETA.LE.THET .AND. QT.GE.QUOT1 .AND.
     $       QT.LE.QUOT2 ) ) THEN
            H = HNEW
            NEEDLU = .TRUE.
         END IF
      END IF
*     Fresh Jacobian after slow convergence or a large state change.
      NEEDJ = THETA.GT.THET .OR. STARTZ
      IF( NEEDJ ) NEEDLU = .TRUE.
      GO TO 100
*
*     ---- Step rejected by the error test.
  700 CONTINUE
      REJECT = .TRUE.
      LAST = .FALSE.
      IF( FIRST ) THEN
         H = H*0.1D0
      ELSE
         H = HNEW
      END IF
      NREJCT = NREJCT + 1
      NEEDLU = .TRUE.
      NEEDJ = .NOT.CALJAC
      GO TO 100
*
*     ---- Exit: statistics into their slots.
  900 CONTINUE
      ISTAT( 1 ) = NFCN
      ISTAT( 2 ) = NJAC
      ISTAT( 3 ) = NDEC
      ISTAT( 4 ) = NSOL
      ISTAT( 5 ) = NSTEP
      ISTAT( 6 ) = NACCPT
      ISTAT( 7 ) = NREJCT
      ISTAT( 8 ) = NSING
      RETURN
*
*     End of RADCOR
*
      END
*
*  =====================================================================
      RECURSIVE SUBROUTINE RADCOE( C, T, TI, DD, GAM, ALP, BET )
      IMPLICIT NONE
      DOUBLE PRECISION   C( 3 ), T( 3, 3 ), TI( 3, 3 ), DD( 3 ), GAM,
     $                   ALP, BET
*
*  Purpose
*  =======
*
*  RADCOE returns the coefficients of the 3-stage Radau IIA method.
*
*  Arguments
*  =========
*
*  C       (output) DOUBLE PRECISION array, dimension (3): the nodes
*          (4-sqrt(6))/10, (4+sqrt(6))/10, 1.
*  T       (output) DOUBLE PRECISION array, dimension (3,3): a real
*          matrix with T^{-1} A^{-1} T = [gam 0 0; 0 alp -bet; 0 bet alp],
*          A the Radau IIA coefficient matrix (column 1: the real
*          eigenvector; columns 2, 3: real and imaginary part of the
*          eigenvector of alp - i bet; scaled so that T(3,2) = 1 and
*          T(3,3) = 0).
*  TI      (output) DOUBLE PRECISION array, dimension (3,3): T^{-1}.
*  DD      (output) DOUBLE PRECISION array, dimension (3): error
*          weights, d = gam (bhat - b)^T A^{-1}, bhat the weights of
*          the embedded order-3 formula whose extra node is 0 with
*          weight 1/gam: d = (-(13+7 sqrt 6)/3, (-13+7 sqrt 6)/3, -1/3).
*  GAM     (output) DOUBLE PRECISION, the real eigenvalue of A^{-1}.
*  ALP,BET (output) DOUBLE PRECISION, the complex pair alp +- i bet.
*
*  Further Details
*  ===============
*
*  The eigenvalues are the reciprocals of the roots of the stability
*  denominator: with u = (6 + 81**(1/3) - 9**(1/3))/30 and
*  a +- i b = ((12 - 81**(1/3) + 9**(1/3)) +- i sqrt(3) (81**(1/3) +
*  9**(1/3)))/60 the eigenvalues of A, gam = 1/u and alp +- i bet
*  = 1/(a -+ i b).  gam, alp, bet, T and T^{-1} are given to 20
*  digits; the pcsim tests check them against an Eigen eigen-
*  decomposition of A^{-1} built from the exact Butcher tableau.
*
*  =====================================================================
*
      DOUBLE PRECISION   SQ6
      INTRINSIC          SQRT
*
      SQ6 = SQRT( 6.0D0 )
      C( 1 ) = ( 4.0D0 - SQ6 ) / 10.0D0
      C( 2 ) = ( 4.0D0 + SQ6 ) / 10.0D0
      C( 3 ) = 1.0D0
*     The eigenvalues, to 20 digits (see Further Details; literals, so
*     every compiler and the C++ port round them identically).
      GAM = 3.6378342527444957322D0
      ALP = 2.6810828736277521339D0
      BET = 3.0504301992474105694D0
      DD( 1 ) = -( 13.0D0 + 7.0D0*SQ6 ) / 3.0D0
      DD( 2 ) = ( -13.0D0 + 7.0D0*SQ6 ) / 3.0D0
      DD( 3 ) = -1.0D0 / 3.0D0
      T( 1, 1 ) = 9.1232394870892942792D-02
      T( 1, 2 ) = -0.14125529502095420843D0
      T( 1, 3 ) = -3.0029194105147424492D-02
      T( 2, 1 ) = 0.24171793270710701896D0
      T( 2, 2 ) = 0.20412935229379993199D0
      T( 2, 3 ) = 0.38294211275726193779D0
      T( 3, 1 ) = 0.96604818261509293619D0
      T( 3, 2 ) = 1.0D0
      T( 3, 3 ) = 0.0D0
      TI( 1, 1 ) = 4.3255798900631553510D0
      TI( 1, 2 ) = 0.33919925181580986954D0
      TI( 1, 3 ) = 0.54177053993587487119D0
      TI( 2, 1 ) = -4.1787185915519047273D0
      TI( 2, 2 ) = -0.32768282076106238708D0
      TI( 2, 3 ) = 0.47662355450055045196D0
      TI( 3, 1 ) = -0.50287263494578687595D0
      TI( 3, 2 ) = 2.5719269498556054292D0
      TI( 3, 3 ) = -0.59603920482822492497D0
      RETURN
*
*     End of RADCOE
*
      END
*
*  =====================================================================
      RECURSIVE SUBROUTINE RADJAC( FCN, JAC, CTX, IJAC, N, X, Y, Y0,
     $                   FJAC, T1, NFCN, IERR )
      USE, INTRINSIC :: ISO_C_BINDING, ONLY: C_PTR
      IMPLICIT NONE
      TYPE(C_PTR)        CTX
      INTEGER            IJAC, N, NFCN, IERR
      DOUBLE PRECISION   X, Y( N ), Y0( N ), FJAC( N, N ), T1( N )
      EXTERNAL           FCN, JAC
*
*  Purpose
*  =======
*
*  RADJAC computes the Jacobian FJAC = df/dy at (X, Y): by JAC if
*  IJAC = 1, otherwise by forward differences
*     FJAC(:,j) = (f(X, Y + d e_j) - Y0) / d,
*     d = sqrt(EPS * max(1e-5, |Y(j)|)),
*  with Y0 = f(X, Y) given.  If FCN cannot be evaluated (IERR = 1) at
*  Y + d e_j, the backward difference with -d is tried once.
*
*  Arguments
*  =========
*
*  FCN, JAC, CTX, IJAC  as in RADIIA.
*  N       (input) INTEGER, the number of unknowns.
*  X       (input) DOUBLE PRECISION, the time.
*  Y       (input) DOUBLE PRECISION array (N); used as workspace and
*          restored exactly on return.
*  Y0      (input) DOUBLE PRECISION array (N), f(X, Y).
*  FJAC    (output) DOUBLE PRECISION array (N,N), the Jacobian.
*  T1      (workspace) DOUBLE PRECISION array (N).
*  NFCN    (input/output) INTEGER, incremented per FCN call.
*  IERR    (output) INTEGER.  0: success; /= 0: a callback failed.
*
*  =====================================================================
*
      INTEGER            I, J
      DOUBLE PRECISION   YSAFE, DELT
      INTRINSIC          ABS, EPSILON, MAX, SQRT
*
      IERR = 0
      IF( IJAC.EQ.1 ) THEN
         CALL JAC( N, X, Y, FJAC, N, CTX, IERR )
         RETURN
      END IF
      DO 20 J = 1, N
         YSAFE = Y( J )
         DELT = SQRT( EPSILON( 1.0D0 )*MAX( 1.0D-5, ABS( YSAFE ) ) )
         Y( J ) = YSAFE + DELT
         CALL FCN( N, X, Y, T1, CTX, IERR )
         NFCN = NFCN + 1
         IF( IERR.EQ.1 ) THEN
            DELT = -DELT
            Y( J ) = YSAFE + DELT
            CALL FCN( N, X, Y, T1, CTX, IERR )
            NFCN = NFCN + 1
         END IF
         Y( J ) = YSAFE
         IF( IERR.NE.0 ) RETURN
         DO 10 I = 1, N
            FJAC( I, J ) = ( T1( I ) - Y0( I ) ) / DELT
   10    CONTINUE
   20 CONTINUE
      RETURN
*
*     End of RADJAC
*
      END
*
*  =====================================================================
      RECURSIVE SUBROUTINE RADDEC( IMAS, N, FAC1, ALPHN, BETAN, FJAC,
     $                   AM, LDM, E1, E2, IP1, IP2, INFO )
      IMPLICIT NONE
      INTEGER            IMAS, N, LDM, INFO
      INTEGER            IP1( N ), IP2( N )
      DOUBLE PRECISION   FAC1, ALPHN, BETAN
      DOUBLE PRECISION   FJAC( N, N ), AM( LDM, * ), E1( N, N )
      COMPLEX*16         E2( N, N )
*
*  Purpose
*  =======
*
*  RADDEC forms and LU-factors (with partial pivoting) the two
*  iteration matrices
*     E1 = FAC1 K - J            (real, DGETRF)
*     E2 = (ALPHN + i BETAN) K - J   (complex, ZGETRF)
*  K = AM if IMAS = 1, the identity otherwise; J = FJAC.
*
*  Arguments
*  =========
*
*  IMAS    (input) INTEGER, 0 or 1 as in RADIIA.
*  N       (input) INTEGER, the order.
*  FAC1, ALPHN, BETAN (input) DOUBLE PRECISION: gam/h, alp/h, bet/h.
*  FJAC    (input) DOUBLE PRECISION array (N,N), the Jacobian.
*  AM      (input) DOUBLE PRECISION array (LDM,N), the mass matrix.
*  LDM     (input) INTEGER, leading dimension of AM.
*  E1      (output) DOUBLE PRECISION array (N,N), LU factors of E1.
*  E2      (output) COMPLEX*16 array (N,N), LU factors of E2.
*  IP1,IP2 (output) INTEGER arrays (N), the pivots.
*  INFO    (output) INTEGER.  0: both nonsingular; 1: E1 or E2 has an
*          exactly zero pivot (INFO > 0 from DGETRF or ZGETRF).
*
*  =====================================================================
*
      INTEGER            I, J, INFO1, INFO2
      COMPLEX*16         ZFAC
      EXTERNAL           DGETRF, ZGETRF
      INTRINSIC          DCMPLX
*
      ZFAC = DCMPLX( ALPHN, BETAN )
      IF( IMAS.EQ.1 ) THEN
         DO 20 J = 1, N
            DO 10 I = 1, N
               E1( I, J ) = FAC1*AM( I, J ) - FJAC( I, J )
               E2( I, J ) = DCMPLX( ALPHN*AM( I, J ) - FJAC( I, J ),
     $                      BETAN*AM( I, J ) )
   10       CONTINUE
   20    CONTINUE
      ELSE
         DO 40 J = 1, N
            DO 30 I = 1, N
               E1( I, J ) = -FJAC( I, J )
               E2( I, J ) = DCMPLX( -FJAC( I, J ), 0.0D0 )
   30       CONTINUE
            E1( J, J ) = E1( J, J ) + FAC1
            E2( J, J ) = E2( J, J ) + ZFAC
   40    CONTINUE
      END IF
      CALL DGETRF( N, N, E1, N, IP1, INFO1 )
      CALL ZGETRF( N, N, E2, N, IP2, INFO2 )
      INFO = 0
      IF( INFO1.NE.0 .OR. INFO2.NE.0 ) INFO = 1
      RETURN
*
*     End of RADDEC
*
      END
*
*  =====================================================================
      RECURSIVE SUBROUTINE RADSLV( N, E1, E2, IP1, IP2, F1, F2, F3, ZT )
      IMPLICIT NONE
      INTEGER            N
      INTEGER            IP1( N ), IP2( N )
      DOUBLE PRECISION   E1( N, N ), F1( N ), F2( N ), F3( N )
      COMPLEX*16         E2( N, N ), ZT( N )
*
*  Purpose
*  =======
*
*  RADSLV solves, in place, the transformed simplified-Newton system
*     E1 x1 = F1,   E2 (x2 + i x3) = F2 + i F3,
*  with the LU factors from RADDEC (DGETRS, ZGETRS).
*
*  Arguments
*  =========
*
*  N       (input) INTEGER, the order.
*  E1, IP1 (input) LU factors and pivots of E1.
*  E2, IP2 (input) LU factors and pivots of E2.
*  F1, F2, F3 (input/output) DOUBLE PRECISION arrays (N): right-hand
*          sides on entry, solutions on exit.
*  ZT      (workspace) COMPLEX*16 array (N).
*
*  =====================================================================
*
      INTEGER            I, INFO
      EXTERNAL           DGETRS, ZGETRS
      INTRINSIC          DBLE, DCMPLX, DIMAG
*
      CALL DGETRS( 'N', N, 1, E1, N, IP1, F1, N, INFO )
      DO 10 I = 1, N
         ZT( I ) = DCMPLX( F2( I ), F3( I ) )
   10 CONTINUE
      CALL ZGETRS( 'N', N, 1, E2, N, IP2, ZT, N, INFO )
      DO 20 I = 1, N
         F2( I ) = DBLE( ZT( I ) )
         F3( I ) = DIMAG( ZT( I ) )
   20 CONTINUE
      RETURN
*
*     End of RADSLV
*
      END
*
*  =====================================================================
      RECURSIVE SUBROUTINE RADEST( FCN, CTX, IMAS, N, X, H, Y, Y0, Z1,
     $                   Z2, Z3, DD, SCAL, AM, LDM, E1, IP1, REFINE, T1,
     $                   T2, T3, NFCN, NSOL, ERR, IERR )
      USE, INTRINSIC :: ISO_C_BINDING, ONLY: C_PTR
      IMPLICIT NONE
      TYPE(C_PTR)        CTX
      LOGICAL            REFINE
      INTEGER            IMAS, N, LDM, NFCN, NSOL, IERR
      INTEGER            IP1( N )
      DOUBLE PRECISION   X, H, ERR
      DOUBLE PRECISION   Y( N ), Y0( N ), Z1( N ), Z2( N ), Z3( N ),
     $                   DD( 3 ), SCAL( N ), AM( LDM, * ), E1( N, N ),
     $                   T1( N ), T2( N ), T3( N )
      EXTERNAL           FCN
*
*  Purpose
*  =======
*
*  RADEST computes the weighted RMS norm ERR of the filtered error
*  estimate
*     e = E1^{-1} ( Y0 + K v ),  v = (DD1 Z1 + DD2 Z2 + DD3 Z3) / H,
*  and, if REFINE and ERR >= 1, of the re-filtered estimate
*     e' = E1^{-1} ( f(X, Y + e) + K v ),
*  which removes the error estimate's growth for very stiff components
*  (first step, step after a rejection).  ERR >= 1e-10.
*
*  Arguments
*  =========
*
*  FCN, CTX, IMAS, N, AM, LDM as in RADIIA.
*  X, H    (input) DOUBLE PRECISION, step start and step size.
*  Y, Y0   (input) DOUBLE PRECISION arrays (N): y and f(X, Y).
*  Z1..Z3  (input) DOUBLE PRECISION arrays (N): the stage increments.
*  DD      (input) DOUBLE PRECISION array (3): error weights (RADCOE).
*  SCAL    (input) DOUBLE PRECISION array (N): error weights.
*  E1, IP1 (input) LU factors of E1 (RADDEC).
*  REFINE  (input) LOGICAL: allow the re-filtered estimate.
*  T1, T2, T3 (workspace) DOUBLE PRECISION arrays (N).
*  NFCN, NSOL (input/output) INTEGER: counters, incremented.
*  ERR     (output) DOUBLE PRECISION: the error norm.
*  IERR    (output) INTEGER: 0, or FCN's IERR if it failed.
*
*  =====================================================================
*
      INTEGER            I, INFO
      DOUBLE PRECISION   HEE1, HEE2, HEE3, SUM
      EXTERNAL           DGEMV, DGETRS
      INTRINSIC          DBLE, MAX, SQRT
*
      IERR = 0
      HEE1 = DD( 1 ) / H
      HEE2 = DD( 2 ) / H
      HEE3 = DD( 3 ) / H
      DO 10 I = 1, N
         T1( I ) = HEE1*Z1( I ) + HEE2*Z2( I ) + HEE3*Z3( I )
   10 CONTINUE
      IF( IMAS.EQ.1 ) THEN
         CALL DGEMV( 'N', N, N, 1.0D0, AM, LDM, T1, 1, 0.0D0, T2, 1 )
         DO 20 I = 1, N
            T1( I ) = T2( I )
   20    CONTINUE
      END IF
*     T1 = K v from here on.
      DO 30 I = 1, N
         T2( I ) = Y0( I ) + T1( I )
   30 CONTINUE
      CALL DGETRS( 'N', N, 1, E1, N, IP1, T2, N, INFO )
      NSOL = NSOL + 1
      SUM = 0.0D0
      DO 40 I = 1, N
         SUM = SUM + ( T2( I ) / SCAL( I ) )**2
   40 CONTINUE
      ERR = MAX( SQRT( SUM / DBLE( N ) ), 1.0D-10 )
      IF( ERR.LT.1.0D0 .OR. .NOT.REFINE ) RETURN
*
      DO 50 I = 1, N
         T2( I ) = Y( I ) + T2( I )
   50 CONTINUE
      CALL FCN( N, X, T2, T3, CTX, IERR )
      NFCN = NFCN + 1
      IF( IERR.NE.0 ) RETURN
      DO 60 I = 1, N
         T2( I ) = T3( I ) + T1( I )
   60 CONTINUE
      CALL DGETRS( 'N', N, 1, E1, N, IP1, T2, N, INFO )
      NSOL = NSOL + 1
      SUM = 0.0D0
      DO 70 I = 1, N
         SUM = SUM + ( T2( I ) / SCAL( I ) )**2
   70 CONTINUE
      ERR = MAX( SQRT( SUM / DBLE( N ) ), 1.0D-10 )
      RETURN
*
*     End of RADEST
*
      END
*
*  =====================================================================
      RECURSIVE SUBROUTINE RADDEN( N, T, TOLD, TNEW, CONT, LDC, YOUT,
     $                             INFO )
      IMPLICIT NONE
      INTEGER            N, LDC, INFO
      DOUBLE PRECISION   T, TOLD, TNEW
      DOUBLE PRECISION   CONT( LDC, 4 ), YOUT( * )
*
*  Purpose
*  =======
*
*  RADDEN evaluates the dense output of the last accepted Radau IIA
*  step [TOLD, TNEW] at T: the collocation polynomial
*     u(T) = CONT1 + s (CONT2 + (s-c2+1)(CONT3 + (s-c1+1) CONT4)),
*     s = (T - TNEW) / (TNEW - TOLD),
*  exact at TOLD, at the stages TOLD + c_i h and at TNEW (up to
*  rounding); T outside [TOLD, TNEW] extrapolates.
*
*  Arguments
*  =========
*
*  N       (input) INTEGER, N >= 1.
*  T       (input) DOUBLE PRECISION, where to evaluate.
*  TOLD, TNEW (input) DOUBLE PRECISION, the step, TOLD /= TNEW.
*  CONT    (input) DOUBLE PRECISION array (LDC,4), the continuation
*          coefficients handed to SOLOUT.
*  LDC     (input) INTEGER, LDC >= N.
*  YOUT    (output) DOUBLE PRECISION array (N), u(T).
*  INFO    (output) INTEGER.  0: success; -i: argument i illegal.
*
*  =====================================================================
*
      INTEGER            I
      DOUBLE PRECISION   S, SQ6, C1M1, C2M1
      INTRINSIC          MAX, SQRT
*
      INFO = 0
      IF( N.LT.1 ) THEN
         INFO = -1
      ELSE IF( TNEW.EQ.TOLD ) THEN
         INFO = -4
      ELSE IF( LDC.LT.MAX( 1, N ) ) THEN
         INFO = -6
      END IF
      IF( INFO.NE.0 ) RETURN
      SQ6 = SQRT( 6.0D0 )
      C1M1 = ( 4.0D0 - SQ6 ) / 10.0D0 - 1.0D0
      C2M1 = ( 4.0D0 + SQ6 ) / 10.0D0 - 1.0D0
      S = ( T - TNEW ) / ( TNEW - TOLD )
      DO 10 I = 1, N
         YOUT( I ) = CONT( I, 1 ) + S*( CONT( I, 2 ) + ( S - C2M1 )*
     $               ( CONT( I, 3 ) + ( S - C1M1 )*CONT( I, 4 ) ) )
   10 CONTINUE
      RETURN
*
*     End of RADDEN
*
      END
