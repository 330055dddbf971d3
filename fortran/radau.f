*> \file radau.f
*> 3-stage Radau IIA (order 5) for K y' = f(t, y), K constant and
*> possibly singular, with event functions.  Written for pcsim from
*> the mathematics of Hairer & Wanner, Solving ODEs II, section IV.8
*> (no code copied).
*>
*> Routines in this file:
*>   RADIIA  the integrator (checks arguments, partitions the work
*>           arrays, calls RADCOR)
*>   RADCOR  the step loop
*>   RADCOE  the method coefficients (c, T, T^{-1}, error weights,
*>           eigenvalues of A^{-1})
*>   RADJAC  Jacobian (user routine or finite differences)
*>   RADDEC  the real and the complex iteration matrices and their LU
*>   RADSLV  one simplified-Newton linear solve (real + complex)
*>   RADSL1  the real solve alone (error estimate, consistency check)
*>   RADMAS  product with the mass matrix K (identity, diagonal, full)
*>   RADEST  the embedded error estimate with stiff filtering
*>   RADFIN  .TRUE. if every entry of a vector is finite
*>   RADROT  event functions: sign changes, roots on the dense output
*>   RADCEX  continuation coefficients of the collocation polynomial
*>   RADDEN  dense output from the continuation coefficients
*> The small-matrix LU (RADLUD, RADLUS, RADLZD, RADLZS) is in
*> radau_lu.f; the status codes (ODE_*) in pcsim_ode_status.fi.
*
*  =====================================================================
      RECURSIVE SUBROUTINE RADIIA( FCN, JAC, SOLOUT, GFCN, CTX, IJAC,
     $                   IMAS, ITOL, IOUT, NG, N, T, TEND, Y, H, RTOL,
     $                   ATOL, AM, LDM, WORK, LWORK, ZWORK, LZWORK,
     $                   IWORK, LIWORK, IDID )
      USE, INTRINSIC :: ISO_C_BINDING, ONLY: C_PTR
      IMPLICIT NONE
*
*     .. Scalar Arguments ..
      TYPE(C_PTR)        CTX
      INTEGER            IJAC, IMAS, ITOL, IOUT, NG, N, LDM, LWORK,
     $                   LZWORK, LIWORK, IDID
      DOUBLE PRECISION   T, TEND, H
*     .. Array Arguments ..
      INTEGER            IWORK( * )
      DOUBLE PRECISION   Y( * ), RTOL( * ), ATOL( * ), AM( LDM, * ),
     $                   WORK( * )
      COMPLEX*16         ZWORK( * )
*     .. External Procedures ..
      EXTERNAL           FCN, JAC, SOLOUT, GFCN
      INCLUDE 'pcsim_ode_status.fi'
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
*  handled by scaling their error weights with h and h**2).  If NG > 0
*  it also watches NG event functions g(t, y) and returns at the
*  earliest sign change (IDID = ODE_ROOT_FOUND).
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
*  once per Jacobian or step-size change.  The iteration stops when
*  eta*||dW|| <= FNEWT with eta = theta/(1-theta), theta the observed
*  contraction rate; it is abandoned (step retried with a smaller h)
*  when theta >= 0.99, when the predicted error after the remaining
*  iterations exceeds FNEWT, or after NIT iterations.
*
*  Second-order structure (M1 > 0, as in RADAU5): y'_i = y_{i+M2}
*  for i <= M1, i.e. the first M1 rows of K are those of the identity,
*  f_i = y_{i+M2} and K is block diagonal diag(I, K22).  With s = h/gam
*  the first M1 unknowns of a real system E1 dw = r satisfy
*        dw_i = s (r_i + dw_{i+M2}),
*  so, with p_i = s (r_i + p_{i+M2}) (p = 0 beyond M1) and
*  MM = M1/M2, they are eliminated: the reduced system of order
*  N - M1 has the matrix
*        gam/h K22 - J22 - sum_{b=0}^{MM-1} s^(MM-b) J(:, b M2 + j)
*  added to its first M2 columns j, and the right-hand side
*  r_low + J(low, 1:M1) p; afterwards dw_i, i = M1..1, follow from
*  the recursion.  The complex system is the same with s = h/(alp +
*  i bet).  Only the lower N - M1 rows of J are used.
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
*  Events (NG > 0).  After every accepted step [TOLD, T] the kernel
*  evaluates g(T, y(T)) and compares signs with the last accepted
*  point.  Each g_i that changed sign (g_i reaching 0 exactly counts;
*  a g_i that was exactly 0 has no sign yet and is skipped) in an
*  allowed direction is located on the step's collocation polynomial,
*  t -> g_i(t, u(t)), by the Illinois variant of regula falsi to a
*  bracket of width <= TTOL = 100 UROUND (|t| + |h|); the root
*  reported is the bracket's end on the new-sign side (so g_i has
*  changed sign, or is 0, at the returned time).  The earliest root
*  t* wins; every g_i whose root lies within TTOL of t* is reported
*  with it.  T := t*, Y := u(t*), CONT is re-expanded to the step
*  [TOLD, t*], SOLOUT (if IOUT = 1) is called for that shortened step,
*  and RADIIA returns ODE_ROOT_FOUND.  Restart rule: a sign change
*  whose root lies within TTOL of the starting time T of the call is
*  not reported (it is the root just returned, or a caller's switch
*  exactly there); the sign reference simply moves on.  An even
*  number of sign changes inside one step is not seen.
*
*  Arguments
*  =========
*
*  FCN     (input) EXTERNAL subroutine, the right-hand side
*             SUBROUTINE FCN( N, T, Y, F, CTX, IERR )
*             INTEGER N, IERR;  DOUBLE PRECISION T, Y(N), F(N)
*             TYPE(C_PTR) CTX  (passed through untouched)
*          computes F = f(T, Y).  IERR = 0: success; IERR = 1: f cannot
*          be evaluated at (T, Y) (at a stage: the step is rejected and
*          retried with h/2; 20 times in a row, or at an accepted
*          state: IDID = ODE_RHS_FAILED); any other value: fatal,
*          IDID = ODE_CALLBACK_ERROR.  A non-finite F is treated like
*          IERR = 1 but ends in IDID = ODE_NON_FINITE.
*
*  JAC     (input) EXTERNAL subroutine, the Jacobian (used if IJAC = 1)
*             SUBROUTINE JAC( N, T, Y, DFDY, LDJ, CTX, IERR )
*          computes DFDY(LDJ,N) = df/dy at (T, Y), column major (rows
*          1..M1 are not used).  IERR = 1: failure (IDID =
*          ODE_JACOBIAN_FAILED); other nonzero: ODE_CALLBACK_ERROR; a
*          non-finite entry: ODE_NON_FINITE.
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
*          2: stop (IDID = 1); any other value: ODE_CALLBACK_ERROR.
*
*  GFCN    (input) EXTERNAL subroutine, the event functions (NG > 0):
*             SUBROUTINE GFCN( N, T, Y, NG, G, CTX, IERR )
*          computes G(1:NG) = g(T, Y).  IERR /= 0: ODE_CALLBACK_ERROR.
*
*  CTX     (input) TYPE(C_PTR), opaque context handed to FCN, JAC,
*          SOLOUT and GFCN unchanged.
*
*  IJAC    (input) INTEGER.  0: Jacobian by forward differences;
*          1: by JAC.
*
*  IMAS    (input) INTEGER.  0: K = identity (AM not referenced);
*          1: K = AM (full); 2: K diagonal, K(j,j) = AM(1,j).  With
*          M1 > 0, AM holds only the lower block K22 (order N - M1).
*
*  ITOL    (input) INTEGER.  0: RTOL, ATOL are scalars; 1: vectors.
*
*  IOUT    (input) INTEGER.  0: SOLOUT is never called; 1: it is.
*
*  NG      (input) INTEGER.  Number of event functions, NG >= 0
*          (0: GFCN is never called).
*
*  N       (input) INTEGER.  The number of unknowns, N >= 1.
*
*  T       (input/output) DOUBLE PRECISION.  On entry the initial time,
*          on exit the time reached (TEND on success, the root on
*          ODE_ROOT_FOUND).
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
*          (N) if ITOL = 1.  Relative tolerances, each > 0 and
*          >= 10*UROUND (else IDID = ODE_TOLERANCE_TOO_SMALL).
*
*  ATOL    (input) DOUBLE PRECISION array, dimension like RTOL.
*          Absolute tolerances, each > 0 (else ODE_TOLERANCE_TOO_SMALL).
*
*  AM      (input) DOUBLE PRECISION array, dimension (LDM,*).  The
*          mass matrix (see IMAS).
*
*  LDM     (input) INTEGER.  Leading dimension of AM; LDM >= N - M1 if
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
*                   max(10*UROUND/rtol', min(0.03, sqrt(rtol'))),
*                   rtol' = first transformed RTOL)
*          WORK(6), WORK(7)  QUOT1 <= 1 <= QUOT2: if the new step
*                   is h*q with QUOT1 <= q <= QUOT2 and the Jacobian
*                   is kept, h is kept and no new LU is made (1, 1.2)
*          WORK(8)  FACL >= 1, largest step growth factor (5)
*          WORK(9)  FACR <= 1, largest step reduction factor (0.125)
*          WORK(10) UROUND, the unit roundoff (default EPSILON(1D0) =
*                   2.2D-16), 1D-19 < UROUND < 1D-2
*
*  LWORK   (input) INTEGER.  LWORK >= 20 + 23*N + 4*N*N + 4*NG.
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
*          IWORK(7)  M1 (0), IWORK(8) M2 (0: M2 = M1): second-order
*                    structure, see Mathematics; M1 = MM*M2 for an
*                    integer MM >= 1, M1 + M2 <= N.  FCN must return
*                    F(i) = Y(i+M2), i <= M1 (checked at the start).
*          IWORK(9)  linear algebra: 0: the own LU of radau_lu.f if
*                    N - M1 <= 64, LAPACK above; 1: always the own LU;
*                    2: always LAPACK (DGETRF/ZGETRF/DGETRS/ZGETRS and
*                    DGEMV for a full K, the pre-2024 path)
*          IWORK(31:30+NG)  direction filter of each event function:
*                    0 any sign change, +1 only increasing (- to +),
*                    -1 only decreasing
*          Statistics (output, fixed slots):
*          IWORK(11) f evaluations, those for finite-difference
*                    Jacobians not included (RADAU5's NFCN)
*          IWORK(12) Jacobian evaluations
*          IWORK(13) LU decompositions (the real+complex pair once)
*          IWORK(14) linear solves (Newton: real+complex pair once;
*                    each error-estimate solve once)
*          IWORK(15) steps attempted (= accepted + rejected)
*          IWORK(16) accepted steps
*          IWORK(17) rejected steps (all causes: 20 + 21 + 22 + singular
*                    matrices)
*          IWORK(18) singular iteration matrices met
*          IWORK(19) f evaluations for finite-difference Jacobians
*          IWORK(20) rejections by the error test
*          IWORK(21) rejections by the Newton iteration (divergence,
*                    NIT iterations, predicted slow convergence)
*          IWORK(22) rejections because f could not be evaluated or a
*                    value was not finite
*          IWORK(23) event-function evaluations
*          IWORK(24) on ODE_NON_FINITE: what was not finite: 1 f,
*                    2 the Jacobian, 3 the Newton increment or the
*                    error estimate
*          IWORK(31+NG:30+2*NG) on ODE_ROOT_FOUND: +1 (g_i increased
*                    through 0), -1 (decreased), 0 (no root at T)
*          the rest: workspace (pivots)
*
*  LIWORK  (input) INTEGER.  LIWORK >= 30 + 3*N + 2*NG.
*
*  IDID    (output) INTEGER, a code of the pcsim ODE status table
*          (bridge/pcsim_ode_status.h; named constants ODE_* in
*          fortran/pcsim_ode_status.fi; docs/radau.md "Statuses"):
*          = 0  (ODE_SUCCESS):  success, T = TEND.
*          = 1  (ODE_STOPPED_BY_CALLBACK):  stopped by SOLOUT
*               (IRTRN = 2); T is the end of the last accepted step.
*          = 2  (ODE_ROOT_FOUND):  an event function changed sign; T
*               is the root, Y = u(T), IWORK(31+NG:) which ones.
*          < 0:  if IDID = -i, the i-th argument had an illegal value
*                (an option in WORK or IWORK gives -20 or -24, also
*                when FCN violates the M1/M2 structure); nothing was
*                computed.
*          = 3  (ODE_TOO_MANY_STEPS):  more than NMAX steps.
*          = 4  (ODE_STEP_TOO_SMALL):  0.1*|h| <= UROUND*|t| after
*               error-test rejections.
*          = 5  (ODE_NEWTON_FAILURE):  the step size underflowed
*               (as for 4) after Newton failures, or in fixed-step mode
*               Newton did not converge with a fresh Jacobian.
*          = 6  (ODE_SINGULAR_MATRIX):  the iteration matrix was
*               exactly singular more than 5 times.
*          = 7  (ODE_NON_FINITE):  f, the Jacobian, the Newton
*               increment or the error estimate was not finite: at an
*               accepted state (no retry can help), or 20 times in a
*               row as h was halved; IWORK(24) says which.
*          = 8  (ODE_RHS_FAILED):  FCN returned IERR = 1 at an
*               accepted state, or 20 times in a row as h was halved.
*          = 9  (ODE_JACOBIAN_FAILED):  JAC returned IERR = 1.
*          = 10 (ODE_CALLBACK_ERROR):  a callback returned another
*               nonzero code (e.g. a C++ exception).
*          = 11 (ODE_TOLERANCE_TOO_SMALL):  see RTOL, ATOL.
*          = 12 (ODE_INCONSISTENT_START):  K has zero rows (algebraic
*               equations) and the Newton correction that would make
*               them hold at T, E1^{-1} (0; f_alg(T, Y)), exceeds the
*               tolerance (weighted RMS norm > 1).
*          = 13 (ODE_MISSING_INDEX_COUNTS):  K has zero rows, NIND2 =
*               NIND3 = 0, and either the first step failed (4 or 5
*               above) or the correction of 12 grew by more than 3x
*               when h was divided by 10 (an index-1 correction does
*               not depend on h; index-2/3 ones grow like 1/h, 1/h**2):
*               the index-2/3 counts are probably missing.
*          On IDID >= 3, T and Y are the last accepted state.
*
*  Further Details
*  ===============
*
*  Re-entrant: no COMMON, no SAVE, no I/O; all state lives in the
*  arguments, and every routine is RECURSIVE, so its locals are on
*  the stack.  A step attempt starts with the Jacobian at the last
*  accepted state if it is stale (computed before the last accepted
*  step with a contraction rate > THET), then the LU pair if h
*  changed.  A singular LU halves h.  Newton failures: contraction
*  rate >= 0.99 or NIT iterations -> h/2 (and a fresh Jacobian if it
*  was stale); predicted slow convergence -> h times
*  0.8*q**(-1/(4+NIT-1-k)), q the predicted error ratio, k the
*  iteration count; FCN IERR = 1 or a non-finite value -> h/2.  A
*  rejected first step is retried with h/10, other error-test
*  rejections with the step size proposal; after a rejection the step
*  size does not grow on the next step.
*
*  Work layout (1-based offsets from WORK(21)): Z1,Z2,Z3, W1,W2,W3,
*  F1,F2,F3, Y0 = f(t,y), SCAL, RTOL', ATOL' (N each), CONT (4N), T1,
*  T2 (N each), TS (3N), the Jacobian (N*N), E1, E2R, E2I ((N-M1)**2
*  each, allotted N*N), GOLD, GNEW, GA, GB (NG each); E2 for LAPACK
*  ((N-M1)**2) and one complex vector (N) in ZWORK; IWORK from 31:
*  direction filter (NG), root directions (NG), pivots (2N), row list
*  of the LU (N).
*
*  =====================================================================
*
*     .. Local Scalars ..
      INTEGER            I, NMAX, NIT, NIND2, NIND3, IPRED, ISTRT, M1,
     $                   M2, ILAPCK
      INTEGER            IZ1, IZ2, IZ3, IW1, IW2, IW3, IF1, IF2, IF3,
     $                   IY0, ISC, IRT, IAT, ICO, IT1, IT2, ITS, IFJ,
     $                   IE1, IE2R, IE2I, IGO, IGN, IGA, IGB, IDR, IJR,
     $                   IP1, IP2, IWL, NRT
      DOUBLE PRECISION   HMAXN, HFIX, SAFE, THET, FNEWT, QUOT1, QUOT2,
     $                   FACL, FACR, UROUND, QUOT, TOLST
*     .. External Subroutines ..
      EXTERNAL           RADCOR
*     .. Intrinsic Functions ..
      INTRINSIC          ABS, EPSILON, HUGE, MAX, MIN, SQRT
*     ..
*     .. Executable Statements ..
*
*     Test the input arguments; the first bad one is reported.
*
      IDID = 0
      IF( IJAC.NE.0 .AND. IJAC.NE.1 ) THEN
         IDID = -6
      ELSE IF( IMAS.LT.0 .OR. IMAS.GT.2 ) THEN
         IDID = -7
      ELSE IF( ITOL.NE.0 .AND. ITOL.NE.1 ) THEN
         IDID = -8
      ELSE IF( IOUT.NE.0 .AND. IOUT.NE.1 ) THEN
         IDID = -9
      ELSE IF( NG.LT.0 ) THEN
         IDID = -10
      ELSE IF( N.LT.1 ) THEN
         IDID = -11
      ELSE IF( .NOT.( T.EQ.T ) .OR. ABS( T ).GT.HUGE( T ) ) THEN
         IDID = -12
      ELSE IF( .NOT.( TEND.EQ.TEND ) .OR.
     $         ABS( TEND ).GT.HUGE( TEND ) ) THEN
         IDID = -13
      ELSE IF( .NOT.( H.EQ.H ) ) THEN
         IDID = -15
      ELSE IF( LDM.LT.1 ) THEN
         IDID = -19
      ELSE IF( LWORK.LT.20 + 23*N + 4*N*N + 4*NG ) THEN
         IDID = -21
      ELSE IF( LZWORK.LT.N*N + N ) THEN
         IDID = -23
      ELSE IF( LIWORK.LT.30 + 3*N + 2*NG ) THEN
         IDID = -25
      END IF
      IF( IDID.NE.0 ) RETURN
*
*     Options in WORK.
*
      HMAXN = ABS( TEND - T )
      IF( WORK( 1 ).LT.0.0D0 ) IDID = -20
      IF( WORK( 1 ).GT.0.0D0 ) HMAXN = MIN( HMAXN, WORK( 1 ) )
      HFIX = WORK( 2 )
      IF( HFIX.LT.0.0D0 ) IDID = -20
      SAFE = 0.9D0
      IF( WORK( 3 ).NE.0.0D0 ) SAFE = WORK( 3 )
      IF( SAFE.LE.0.001D0 .OR. SAFE.GE.1.0D0 ) IDID = -20
      THET = 0.001D0
      IF( WORK( 4 ).NE.0.0D0 ) THET = WORK( 4 )
      IF( THET.LT.0.0D0 .OR. THET.GE.1.0D0 ) IDID = -20
      QUOT1 = 1.0D0
      IF( WORK( 6 ).NE.0.0D0 ) QUOT1 = WORK( 6 )
      QUOT2 = 1.2D0
      IF( WORK( 7 ).NE.0.0D0 ) QUOT2 = WORK( 7 )
      IF( QUOT1.LE.0.0D0 .OR. QUOT1.GT.1.0D0 .OR. QUOT2.LT.1.0D0 )
     $   IDID = -20
      FACL = 5.0D0
      IF( WORK( 8 ).NE.0.0D0 ) FACL = WORK( 8 )
      FACR = 0.125D0
      IF( WORK( 9 ).NE.0.0D0 ) FACR = WORK( 9 )
      IF( FACL.LT.1.0D0 .OR. FACR.LE.0.0D0 .OR. FACR.GT.1.0D0 )
     $   IDID = -20
      UROUND = EPSILON( 1.0D0 )
      IF( WORK( 10 ).NE.0.0D0 ) UROUND = WORK( 10 )
      IF( .NOT.( UROUND.GT.1.0D-19 .AND. UROUND.LT.1.0D-2 ) )
     $   IDID = -20
      IF( WORK( 5 ).LT.0.0D0 ) IDID = -20
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
      M1 = IWORK( 7 )
      M2 = IWORK( 8 )
      IF( M2.EQ.0 ) M2 = M1
      ILAPCK = IWORK( 9 )
      IF( NMAX.LT.1 .OR. NIT.LT.1 .OR. NIND2.LT.0 .OR. NIND3.LT.0
     $    .OR. NIND2 + NIND3.GT.N .OR. IPRED.LT.0 .OR. IPRED.GT.1
     $    .OR. ISTRT.LT.0 .OR. ISTRT.GT.1 .OR. M1.LT.0 .OR. M2.LT.0
     $    .OR. ILAPCK.LT.0 .OR. ILAPCK.GT.2 ) THEN
         IDID = -24
         RETURN
      END IF
      IF( M1.GT.0 ) THEN
         IF( MOD( M1, M2 ).NE.0 .OR. M1 + M2.GT.N ) THEN
            IDID = -24
            RETURN
         END IF
      END IF
      IF( IMAS.EQ.1 .AND. LDM.LT.N - M1 ) THEN
         IDID = -19
         RETURN
      END IF
      DO 10 I = 1, NG
         IF( ABS( IWORK( 30+I ) ).GT.1 ) THEN
            IDID = -24
            RETURN
         END IF
   10 CONTINUE
      IF( ILAPCK.EQ.0 ) THEN
         IF( N - M1.LE.64 ) THEN
            ILAPCK = 0
         ELSE
            ILAPCK = 1
         END IF
      ELSE
         ILAPCK = ILAPCK - 1
      END IF
*
*     Tolerances.
*
      DO 20 I = 1, 1 + ITOL*( N-1 )
         IF( .NOT.( RTOL( I ).GE.10.0D0*UROUND ) .OR.
     $       .NOT.( ATOL( I ).GT.0.0D0 ) .OR.
     $       RTOL( I ).GT.HUGE( T ) .OR. ATOL( I ).GT.HUGE( T ) ) THEN
            IDID = ODE_TOLERANCE_TOO_SMALL
            RETURN
         END IF
   20 CONTINUE
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
      ITS = IT2 + N
      IFJ = ITS + 3*N
      IE1 = IFJ + N*N
      IE2R = IE1 + N*N
      IE2I = IE2R + N*N
      IGO = IE2I + N*N
      IGN = IGO + NG
      IGA = IGN + NG
      IGB = IGA + NG
      IDR = 31
      IJR = IDR + NG
      IP1 = IJR + NG
      IP2 = IP1 + N
      IWL = IP2 + N
      NRT = MAX( NG, 1 )
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
      IF( WORK( 5 ).GT.0.0D0 ) FNEWT = WORK( 5 )
*
      DO 40 I = 11, 30
         IWORK( I ) = 0
   40 CONTINUE
      DO 50 I = 1, NG
         IWORK( IJR+I-1 ) = 0
   50 CONTINUE
      IF( TEND.EQ.T ) RETURN
*
      CALL RADCOR( FCN, JAC, SOLOUT, GFCN, CTX, IJAC, IMAS, IOUT,
     $             ILAPCK, NG, N, M1, M2, T, TEND, Y, H, AM, LDM,
     $             NIND2, NIND3, NMAX, NIT, IPRED, ISTRT, UROUND,
     $             HMAXN, HFIX, SAFE, THET, FNEWT, QUOT1, QUOT2, FACL,
     $             FACR, WORK( IRT ), WORK( IAT ), WORK( IZ1 ),
     $             WORK( IZ2 ), WORK( IZ3 ), WORK( IW1 ), WORK( IW2 ),
     $             WORK( IW3 ), WORK( IF1 ), WORK( IF2 ), WORK( IF3 ),
     $             WORK( IY0 ), WORK( ISC ), WORK( ICO ), WORK( IT1 ),
     $             WORK( IT2 ), WORK( ITS ), WORK( IFJ ), WORK( IE1 ),
     $             WORK( IE2R ), WORK( IE2I ), ZWORK( 1 ),
     $             ZWORK( N*N+1 ), WORK( IGO ), WORK( IGN ),
     $             WORK( IGA ), WORK( IGB ), IWORK( IDR ),
     $             IWORK( IJR ), NRT, IWORK( IP1 ), IWORK( IP2 ),
     $             IWORK( IWL ), IWORK( 11 ), IDID )
      RETURN
*
*     End of RADIIA
*
      END
*
*  =====================================================================
      RECURSIVE SUBROUTINE RADCOR( FCN, JAC, SOLOUT, GFCN, CTX, IJAC,
     $                   IMAS, IOUT, ILAPCK, NG, N, M1, M2, X, XEND, Y,
     $                   H, AM, LDM, NIND2, NIND3, NMAX, NIT, IPRED,
     $                   ISTRT, UROUND, HMAXN, HFIX, SAFE, THET, FNEWT,
     $                   QUOT1, QUOT2, FACL, FACR, RTT, ATT, Z1, Z2, Z3,
     $                   W1, W2, W3, F1, F2, F3, Y0, SCAL, CONT, T1, T2,
     $                   TS, FJAC, E1, E2R, E2I, E2, ZT, GOLD, GNEW, GA,
     $                   GB, IRDIR, JROOT, NRT, IP1, IP2, IWL, ISTAT,
     $                   IDID )
      USE, INTRINSIC :: ISO_C_BINDING, ONLY: C_PTR
      IMPLICIT NONE
      TYPE(C_PTR)        CTX
      INTEGER            IJAC, IMAS, IOUT, ILAPCK, NG, N, M1, M2, LDM,
     $                   NIND2, NIND3, NMAX, NIT, IPRED, ISTRT, NRT,
     $                   IDID
      DOUBLE PRECISION   X, XEND, H, UROUND, HMAXN, HFIX, SAFE, THET,
     $                   FNEWT, QUOT1, QUOT2, FACL, FACR
      INTEGER            IP1( N ), IP2( N ), IWL( N ), ISTAT( 20 ),
     $                   IRDIR( NRT ), JROOT( NRT )
      DOUBLE PRECISION   Y( N ), AM( LDM, * ), RTT( N ), ATT( N ),
     $                   Z1( N ), Z2( N ), Z3( N ), W1( N ), W2( N ),
     $                   W3( N ), F1( N ), F2( N ), F3( N ), Y0( N ),
     $                   SCAL( N ), CONT( N, 4 ), T1( N ), T2( N ),
     $                   TS( 3*N ), FJAC( N, N ), E1( * ), E2R( * ),
     $                   E2I( * ), GOLD( NRT ), GNEW( NRT ), GA( NRT ),
     $                   GB( NRT )
      COMPLEX*16         E2( * ), ZT( N )
      EXTERNAL           FCN, JAC, SOLOUT, GFCN
      INCLUDE 'pcsim_ode_status.fi'
*
*  Purpose
*  =======
*
*  RADCOR is the step loop of RADIIA (see there for the method, the
*  arguments it shares and the meaning of IDID).  X, XEND, H: current
*  time, final time and step (signed).  The remaining scalars are the
*  resolved options (ILAPCK 0: own LU, 1: LAPACK); RTT, ATT the
*  transformed tolerances; the arrays after them are the partitioned
*  workspace; IRDIR, JROOT the event direction filter and the root
*  directions (NRT = max(NG,1)); ISTAT(1:20) receives the statistics
*  IWORK(11:30) of RADIIA.
*
*  =====================================================================
*
*     Rejections in a row for f failing or a non-finite value before
*     the run ends with that status.
      INTEGER            NBADMX
      PARAMETER          ( NBADMX = 20 )
*     .. Local Scalars ..
      INTEGER            I, J, NEWT, NFCN, NJAC, NDEC, NSOL, NSTEP,
     $                   NACCPT, NREJCT, NSING, NFCNJ, NERREJ, NNEWTR,
     $                   NFAILR, NGEV, IWHAT, IERR, INFO, NIND1, NBAD,
     $                   IBAD, LSTREJ, NM, IROOT
      LOGICAL            FIRST, REJECT, LAST, CALJAC, NEEDJ, NEEDLU,
     $                   FIXED, STARTZ, KSING, CHECKD
      DOUBLE PRECISION   POSNEG, XOLD, HOLD, HNEW, HOPT, HACC, X0,
     $                   ERRACC, ERR, FACCON, THETA, THQ, THQOLD, DYNO,
     $                   DYNOLD, FAC1, ALPHN, BETAN, CFAC, QUOT, FAC,
     $                   FACGUS, QNEWT, DYTH, HHFAC, QT, C1Q, C2Q, C3Q,
     $                   AK1, AK2, AK3, A1, A2, A3, SUM, HABS, XROOT,
     $                   FCHK
      DOUBLE PRECISION   GAM, ALP, BET, C1M1, C2M1, C1MC2
*     .. Local Arrays ..
      DOUBLE PRECISION   C( 3 ), TT( 3, 3 ), TI( 3, 3 ), DD( 3 )
*     .. External Functions ..
      LOGICAL            RADFIN
      EXTERNAL           RADFIN
*     .. External Subroutines ..
      EXTERNAL           RADCOE, RADJAC, RADDEC, RADSLV, RADSL1,
     $                   RADEST, RADMAS, RADROT, RADCEX
*     .. Intrinsic Functions ..
      INTRINSIC          ABS, HUGE, MAX, MIN, SIGN, SQRT
*     ..
      CALL RADCOE( C, TT, TI, DD, GAM, ALP, BET )
      C1M1 = C( 1 ) - 1.0D0
      C2M1 = C( 2 ) - 1.0D0
      C1MC2 = C( 1 ) - C( 2 )
      NIND1 = N - NIND2 - NIND3
      NM = N - M1
*
      NFCN = 0
      NJAC = 0
      NDEC = 0
      NSOL = 0
      NSTEP = 0
      NACCPT = 0
      NREJCT = 0
      NSING = 0
      NFCNJ = 0
      NERREJ = 0
      NNEWTR = 0
      NFAILR = 0
      NGEV = 0
      IWHAT = 0
      NBAD = 0
      IBAD = 0
      LSTREJ = 0
      IROOT = 0
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
      CHECKD = .FALSE.
      XOLD = X
      X0 = X
*
*     K has zero rows (algebraic equations): IMAS = 2 with a zero
*     diagonal entry, or IMAS = 1 with a zero row of K22.
      KSING = .FALSE.
      IF( IMAS.EQ.2 ) THEN
         DO 10 I = 1, NM
            IF( AM( 1, I ).EQ.0.0D0 ) KSING = .TRUE.
   10    CONTINUE
      ELSE IF( IMAS.EQ.1 ) THEN
         DO 30 I = 1, NM
            SUM = 0.0D0
            DO 20 J = 1, NM
               SUM = SUM + ABS( AM( I, J ) )
   20       CONTINUE
            IF( SUM.EQ.0.0D0 ) KSING = .TRUE.
   30    CONTINUE
      END IF
*
      CALL FCN( N, X, Y, Y0, CTX, IERR )
      NFCN = NFCN + 1
      IF( IERR.NE.0 ) THEN
         IDID = ODE_CALLBACK_ERROR
         IF( IERR.EQ.1 ) IDID = ODE_RHS_FAILED
         GO TO 900
      END IF
      IF( .NOT.RADFIN( N, Y0 ) ) THEN
         IDID = ODE_NON_FINITE
         IWHAT = 1
         GO TO 900
      END IF
*     The second-order structure must hold: f_i = y_{i+M2}, i <= M1.
      DO 40 I = 1, M1
         IF( Y0( I ).NE.Y( I+M2 ) ) THEN
            IDID = -24
            GO TO 900
         END IF
   40 CONTINUE
      IF( NG.GT.0 ) THEN
         CALL GFCN( N, X, Y, NG, GOLD, CTX, IERR )
         NGEV = NGEV + 1
         IF( IERR.NE.0 ) THEN
            IDID = ODE_CALLBACK_ERROR
            GO TO 900
         END IF
      END IF
*
*     ---- Main loop: Jacobian if stale, LU if h changed, one step.
*
  100 CONTINUE
      IF( NEEDJ ) THEN
         CALL RADJAC( FCN, JAC, CTX, IJAC, N, M1, X, Y, Y0, FJAC, T1,
     $                UROUND, NFCNJ, IERR )
         NJAC = NJAC + 1
         IF( IERR.NE.0 ) THEN
            IDID = IERR
            IF( IERR.EQ.ODE_NON_FINITE ) IWHAT = 2
            IF( IERR.EQ.ODE_RHS_FAILED ) IWHAT = 1
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
         CALL RADDEC( IMAS, ILAPCK, N, M1, M2, FAC1, ALPHN, BETAN,
     $                FJAC, AM, LDM, E1, E2R, E2I, E2, IP1, IP2, IWL,
     $                INFO )
         NDEC = NDEC + 1
         IF( INFO.NE.0 ) THEN
            NSING = NSING + 1
            IF( NSING.GT.5 .OR. FIXED ) THEN
               IDID = ODE_SINGULAR_MATRIX
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
*        Named by the cause of the rejections that made h this small.
         IF( LSTREJ.EQ.2 ) THEN
            IDID = ODE_NEWTON_FAILURE
         ELSE IF( LSTREJ.EQ.3 ) THEN
            IDID = IBAD
         ELSE
            IDID = ODE_STEP_TOO_SMALL
         END IF
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
*     Consistency of the algebraic equations at the start: the Newton
*     correction E1^{-1} (0; f_alg) must be within the tolerance.
      IF( KSING .AND. .NOT.CHECKD ) THEN
         CHECKD = .TRUE.
         DO 135 I = 1, N
            T1( I ) = 0.0D0
  135    CONTINUE
         DO 136 I = 1, NM
            IF( IMAS.EQ.2 ) THEN
               IF( AM( 1, I ).EQ.0.0D0 ) T1( M1+I ) = Y0( M1+I )
            ELSE
               SUM = 0.0D0
               DO 137 J = 1, NM
                  SUM = SUM + ABS( AM( I, J ) )
  137          CONTINUE
               IF( SUM.EQ.0.0D0 ) T1( M1+I ) = Y0( M1+I )
            END IF
  136    CONTINUE
         DO 134 I = 1, N
            T2( I ) = T1( I )
  134    CONTINUE
         CALL RADSL1( ILAPCK, N, M1, M2, FAC1, FJAC, E1, IP1, T1, TS )
         SUM = 0.0D0
         DO 138 I = 1, N
            SUM = SUM + ( T1( I ) / SCAL( I ) )**2
  138    CONTINUE
         DYNO = SQRT( SUM / DBLE( N ) )
         IF( .NOT.( DYNO.LE.1.0D0 ) ) THEN
            NSTEP = NSTEP - 1
            IDID = ODE_INCONSISTENT_START
            IF( NIND2 + NIND3.EQ.0 ) THEN
*              Index probe: for index-1 equations the correction does
*              not depend on h; for higher-index ones (whose counts
*              are missing) it grows like 1/h or 1/h**2.  Same
*              correction with h/10; the LU is rebuilt before any step.
               CALL RADDEC( IMAS, ILAPCK, N, M1, M2, 10.0D0*FAC1,
     $                      10.0D0*ALPHN, 10.0D0*BETAN, FJAC, AM, LDM,
     $                      E1, E2R, E2I, E2, IP1, IP2, IWL, INFO )
               NDEC = NDEC + 1
               IF( INFO.EQ.0 ) THEN
                  CALL RADSL1( ILAPCK, N, M1, M2, 10.0D0*FAC1, FJAC,
     $                         E1, IP1, T2, TS )
                  SUM = 0.0D0
                  DO 139 I = 1, N
                     SUM = SUM + ( T2( I ) / SCAL( I ) )**2
  139             CONTINUE
                  IF( SQRT( SUM / DBLE( N ) ).GT.3.0D0*DYNO )
     $               IDID = ODE_MISSING_INDEX_COUNTS
               END IF
            END IF
            GO TO 900
         END IF
      END IF
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
*        Right-hand side: (T^{-1} (x) I) F - (L/h (x) K) W.  FCHK
*        stays 0 unless some F is not finite (x - x is NaN for NaN and
*        Inf): the finiteness test costs no extra pass over F.
      CALL RADMAS( IMAS, ILAPCK, N, M1, AM, LDM, W1, Z1 )
      CALL RADMAS( IMAS, ILAPCK, N, M1, AM, LDM, W2, Z2 )
      CALL RADMAS( IMAS, ILAPCK, N, M1, AM, LDM, W3, Z3 )
      FCHK = 0.0D0
      DO 250 I = 1, N
         A1 = F1( I )
         A2 = F2( I )
         A3 = F3( I )
         FCHK = FCHK + ( ( A1 - A1 ) + ( A2 - A2 ) + ( A3 - A3 ) )
         F1( I ) = TI( 1, 1 )*A1 + TI( 1, 2 )*A2 + TI( 1, 3 )*A3
     $             - FAC1*Z1( I )
         F2( I ) = TI( 2, 1 )*A1 + TI( 2, 2 )*A2 + TI( 2, 3 )*A3
     $             - ALPHN*Z2( I ) + BETAN*Z3( I )
         F3( I ) = TI( 3, 1 )*A1 + TI( 3, 2 )*A2 + TI( 3, 3 )*A3
     $             - BETAN*Z2( I ) - ALPHN*Z3( I )
  250 CONTINUE
      IF( FCHK.NE.0.0D0 ) THEN
         IWHAT = 1
         GO TO 380
      END IF
      CALL RADSLV( ILAPCK, N, M1, M2, FAC1, ALPHN, BETAN, FJAC, E1,
     $             E2R, E2I, E2, IP1, IP2, F1, F2, F3, TS, ZT )
      NSOL = NSOL + 1
      NEWT = NEWT + 1
      SUM = 0.0D0
      DO 260 I = 1, N
         SUM = SUM + ( F1( I ) / SCAL( I ) )**2 +
     $         ( F2( I ) / SCAL( I ) )**2 + ( F3( I ) / SCAL( I ) )**2
  260 CONTINUE
      DYNO = SQRT( SUM / DBLE( 3*N ) )
      IF( .NOT.( DYNO.LE.HUGE( DYNO ) ) ) THEN
         IWHAT = 3
         GO TO 380
      END IF
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
               NNEWTR = NNEWTR + 1
               LSTREJ = 2
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
      GO TO 500
*
*     A value was not finite: reject, retry with h/2.
  380 CONTINUE
      IBAD = ODE_NON_FINITE
      GO TO 385
*     f could not be evaluated: reject, retry with h/2.
  390 CONTINUE
      IF( IERR.NE.1 ) THEN
         IDID = ODE_CALLBACK_ERROR
         GO TO 900
      END IF
      IBAD = ODE_RHS_FAILED
      IWHAT = 1
  385 CONTINUE
      NFAILR = NFAILR + 1
      NBAD = NBAD + 1
      LSTREJ = 3
      IF( NBAD.GE.NBADMX .OR. FIXED ) THEN
         IDID = IBAD
         GO TO 900
      END IF
      H = H*0.5D0
      GO TO 395
*
*     Newton failure: halve h, fresh Jacobian if it was stale.
  400 CONTINUE
      NNEWTR = NNEWTR + 1
      LSTREJ = 2
      IF( FIXED ) THEN
         IF( CALJAC ) THEN
            IDID = ODE_NEWTON_FAILURE
            GO TO 900
         END IF
      ELSE
         H = H*0.5D0
      END IF
*
*     Common tail of the non-error-test rejections: retry the step.
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
         CALL RADEST( FCN, CTX, IMAS, ILAPCK, N, M1, M2, X, H, Y, Y0,
     $                Z1, Z2, Z3, DD, SCAL, AM, LDM, FAC1, FJAC, E1,
     $                IP1, FIRST .OR. REJECT, T1, T2, F1, TS, NFCN,
     $                NSOL, ERR, IERR )
         IF( IERR.NE.0 ) GO TO 390
         IF( .NOT.( ERR.LE.HUGE( ERR ) ) ) THEN
            IWHAT = 3
            GO TO 380
         END IF
         ERR = MAX( ERR, 1.0D-10 )
         FAC = MIN( SAFE, CFAC / DBLE( NEWT + 2*NIT ) )
         QUOT = MAX( FACR, MIN( FACL, ERR**0.25D0 / FAC ) )
         HNEW = H / QUOT
      END IF
      IF( ERR.GE.1.0D0 ) GO TO 700
*
*     ---- Step accepted.
      FIRST = .FALSE.
      NACCPT = NACCPT + 1
      NBAD = 0
      LSTREJ = 0
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
*     Continuation coefficients and the new solution.
      CALL RADCEX( N, C, Z1, Z2, Z3, Y, CONT )
      STARTZ = .FALSE.
*     Event functions: the earliest root in (XOLD, X] ends the call.
      IF( NG.GT.0 ) THEN
         CALL RADROT( GFCN, CTX, NG, N, X0, XOLD, X, H, UROUND, CONT,
     $                GOLD, GNEW, GA, GB, IRDIR, JROOT, T2, NGEV,
     $                XROOT, IROOT, IERR )
         IF( IERR.NE.0 ) THEN
            IDID = ODE_CALLBACK_ERROR
            GO TO 900
         END IF
         IF( IROOT.NE.0 ) THEN
*           y at the root, and the step shortened to [XOLD, XROOT]:
*           its collocation polynomial is the same, re-expanded from
*           its values at XOLD + c_i (XROOT - XOLD) and at XOLD.
            CALL RADDEN( N, XOLD, XOLD, X, CONT, N, T1, INFO )
            HABS = XROOT - XOLD
            CALL RADDEN( N, XOLD + C( 1 )*HABS, XOLD, X, CONT, N, Z1,
     $                   INFO )
            CALL RADDEN( N, XOLD + C( 2 )*HABS, XOLD, X, CONT, N, Z2,
     $                   INFO )
            CALL RADDEN( N, XROOT, XOLD, X, CONT, N, Z3, INFO )
            DO 540 I = 1, N
               Z1( I ) = Z1( I ) - T1( I )
               Z2( I ) = Z2( I ) - T1( I )
               Z3( I ) = Z3( I ) - T1( I )
               Y( I ) = T1( I )
  540       CONTINUE
            CALL RADCEX( N, C, Z1, Z2, Z3, Y, CONT )
            X = XROOT
            LAST = .TRUE.
            HOPT = POSNEG*MIN( ABS( H ), ABS( HNEW ) )
         END IF
      END IF
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
      IF( IROOT.NE.0 ) THEN
         H = HOPT
         IDID = ODE_ROOT_FOUND
         GO TO 900
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
         IF( IERR.EQ.1 ) THEN
            IDID = ODE_RHS_FAILED
            IWHAT = 1
         END IF
         GO TO 900
      END IF
      IF( .NOT.RADFIN( N, Y0 ) ) THEN
         IDID = ODE_NON_FINITE
         IWHAT = 1
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
      NERREJ = NERREJ + 1
      LSTREJ = 1
      NEEDLU = .TRUE.
      NEEDJ = .NOT.CALJAC
      GO TO 100
*
*     ---- Exit: honest names for a failed start, statistics.
  900 CONTINUE
      IF( NACCPT.EQ.0 .AND. KSING .AND. NIND2 + NIND3.EQ.0 .AND.
     $    ( IDID.EQ.ODE_NEWTON_FAILURE .OR.
     $      IDID.EQ.ODE_STEP_TOO_SMALL ) )
     $   IDID = ODE_MISSING_INDEX_COUNTS
      ISTAT( 1 ) = NFCN
      ISTAT( 2 ) = NJAC
      ISTAT( 3 ) = NDEC
      ISTAT( 4 ) = NSOL
      ISTAT( 5 ) = NSTEP
      ISTAT( 6 ) = NACCPT
      ISTAT( 7 ) = NREJCT
      ISTAT( 8 ) = NSING
      ISTAT( 9 ) = NFCNJ
      ISTAT( 10 ) = NERREJ
      ISTAT( 11 ) = NNEWTR
      ISTAT( 12 ) = NFAILR
      ISTAT( 13 ) = NGEV
      ISTAT( 14 ) = IWHAT
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
*
*  =====================================================================
      RECURSIVE SUBROUTINE RADJAC( FCN, JAC, CTX, IJAC, N, M1, X, Y,
     $                   Y0, FJAC, T1, UROUND, NFCNJ, IERR )
      USE, INTRINSIC :: ISO_C_BINDING, ONLY: C_PTR
      IMPLICIT NONE
      TYPE(C_PTR)        CTX
      INTEGER            IJAC, N, M1, NFCNJ, IERR
      DOUBLE PRECISION   X, UROUND, Y( N ), Y0( N ), FJAC( N, N ),
     $                   T1( N )
      EXTERNAL           FCN, JAC
      INCLUDE 'pcsim_ode_status.fi'
*
*  Purpose
*  =======
*
*  RADJAC computes the Jacobian FJAC = df/dy at (X, Y): by JAC if
*  IJAC = 1, otherwise by forward differences
*     FJAC(:,j) = (f(X, Y + d e_j) - Y0) / d,
*     d = sqrt(UROUND * max(1e-5, |Y(j)|)),
*  with Y0 = f(X, Y) given.  If FCN cannot be evaluated (IERR = 1) or
*  gives a non-finite value at Y + d e_j, the backward difference with
*  -d is tried once.  Rows 1..M1 of a JAC result are not used (nor
*  checked).
*
*  Arguments
*  =========
*
*  FCN, JAC, CTX, IJAC  as in RADIIA.
*  N, M1   (input) INTEGER, the number of unknowns and M1 of RADIIA.
*  X       (input) DOUBLE PRECISION, the time.
*  Y       (input) DOUBLE PRECISION array (N); used as workspace and
*          restored exactly on return.
*  Y0      (input) DOUBLE PRECISION array (N), f(X, Y).
*  FJAC    (output) DOUBLE PRECISION array (N,N), the Jacobian.
*  T1      (workspace) DOUBLE PRECISION array (N).
*  UROUND  (input) DOUBLE PRECISION, the unit roundoff.
*  NFCNJ   (input/output) INTEGER, incremented per FCN call.
*  IERR    (output) INTEGER, a status code: 0 success,
*          ODE_JACOBIAN_FAILED (JAC IERR = 1), ODE_RHS_FAILED (FCN
*          IERR = 1 both ways), ODE_NON_FINITE, ODE_CALLBACK_ERROR (any
*          other nonzero code of a callback).
*
*  =====================================================================
*
      INTEGER            I, J, IE
      LOGICAL            BAD
      DOUBLE PRECISION   YSAFE, DELT
      LOGICAL            RADFIN
      EXTERNAL           RADFIN
      INTRINSIC          ABS, MAX, SQRT
*
      IERR = 0
      IF( IJAC.EQ.1 ) THEN
         CALL JAC( N, X, Y, FJAC, N, CTX, IE )
         IF( IE.EQ.1 ) THEN
            IERR = ODE_JACOBIAN_FAILED
         ELSE IF( IE.NE.0 ) THEN
            IERR = ODE_CALLBACK_ERROR
         ELSE
            DO 10 J = 1, N
               IF( .NOT.RADFIN( N - M1, FJAC( M1+1, J ) ) ) THEN
                  IERR = ODE_NON_FINITE
                  RETURN
               END IF
   10       CONTINUE
         END IF
         RETURN
      END IF
      DO 30 J = 1, N
         YSAFE = Y( J )
         DELT = SQRT( UROUND*MAX( 1.0D-5, ABS( YSAFE ) ) )
         Y( J ) = YSAFE + DELT
         CALL FCN( N, X, Y, T1, CTX, IE )
         NFCNJ = NFCNJ + 1
         BAD = .FALSE.
         IF( IE.EQ.0 ) BAD = .NOT.RADFIN( N, T1 )
         IF( IE.EQ.1 .OR. BAD ) THEN
            DELT = -DELT
            Y( J ) = YSAFE + DELT
            CALL FCN( N, X, Y, T1, CTX, IE )
            NFCNJ = NFCNJ + 1
            BAD = .FALSE.
            IF( IE.EQ.0 ) BAD = .NOT.RADFIN( N, T1 )
         END IF
         Y( J ) = YSAFE
         IF( IE.EQ.1 ) THEN
            IERR = ODE_RHS_FAILED
         ELSE IF( IE.NE.0 ) THEN
            IERR = ODE_CALLBACK_ERROR
         ELSE IF( BAD ) THEN
            IERR = ODE_NON_FINITE
         END IF
         IF( IERR.NE.0 ) RETURN
         DO 20 I = 1, N
            FJAC( I, J ) = ( T1( I ) - Y0( I ) ) / DELT
   20    CONTINUE
   30 CONTINUE
      RETURN
*
*     End of RADJAC
*
      END
*
*  =====================================================================
      RECURSIVE SUBROUTINE RADDEC( IMAS, ILAPCK, N, M1, M2, FAC1, ALPHN,
     $                   BETAN, FJAC, AM, LDM, E1, E2R, E2I, E2, IP1,
     $                   IP2, IWL, INFO )
      IMPLICIT NONE
      INTEGER            IMAS, ILAPCK, N, M1, M2, LDM, INFO
      INTEGER            IP1( * ), IP2( * ), IWL( * )
      DOUBLE PRECISION   FAC1, ALPHN, BETAN
      DOUBLE PRECISION   FJAC( N, N ), AM( LDM, * ), E1( N-M1, * ),
     $                   E2R( N-M1, * ), E2I( N-M1, * )
      COMPLEX*16         E2( N-M1, * )
*
*  Purpose
*  =======
*
*  RADDEC forms and LU-factors (partial pivoting) the two iteration
*  matrices of order NM = N - M1
*     E1 = FAC1 K - J            (real)
*     E2 = (ALPHN + i BETAN) K - J   (complex, parts in E2R, E2I)
*  K the mass matrix (IMAS 0: identity, 1: AM full, 2: diag AM(1,:)),
*  J = FJAC; with M1 > 0 the reduced matrices of RADIIA's Mathematics
*  (lower rows and columns, the first M2 columns corrected by the
*  eliminated second-order unknowns).
*
*  Arguments
*  =========
*
*  IMAS    (input) INTEGER, 0, 1 or 2 as in RADIIA.
*  ILAPCK  (input) INTEGER.  0: RADLUD/RADLZD; 1: DGETRF/ZGETRF (E2
*          is then copied into the COMPLEX*16 array E2 and factored
*          there).
*  N, M1, M2 (input) INTEGER, as in RADIIA.
*  FAC1, ALPHN, BETAN (input) DOUBLE PRECISION: gam/h, alp/h, bet/h.
*  FJAC    (input) DOUBLE PRECISION array (N,N), the Jacobian.
*  AM, LDM (input) the mass matrix, as in RADIIA.
*  E1      (output) DOUBLE PRECISION array (NM,NM), LU factors of E1.
*  E2R, E2I (output) DOUBLE PRECISION arrays (NM,NM), E2 (ILAPCK = 0:
*          its LU factors).
*  E2      (output) COMPLEX*16 array (NM,NM), LU factors of E2 if
*          ILAPCK = 1.
*  IP1,IP2 (output) INTEGER arrays (NM), the pivots.
*  IWL     (workspace) INTEGER array (NM).
*  INFO    (output) INTEGER.  0: both nonsingular; 1: E1 or E2 has an
*          exactly zero pivot.
*
*  =====================================================================
*
      INTEGER            I, J, K, NM, MM, INFO1, INFO2
      DOUBLE PRECISION   ABNO, SR, SI, SUM, PR, PI, AR, AI, FJ
      EXTERNAL           DGETRF, ZGETRF, RADLUD, RADLZD
      INTRINSIC          DCMPLX
*
      NM = N - M1
      DO 20 J = 1, NM
         DO 10 I = 1, NM
            E1( I, J ) = -FJAC( M1+I, M1+J )
            E2R( I, J ) = -FJAC( M1+I, M1+J )
            E2I( I, J ) = 0.0D0
   10    CONTINUE
   20 CONTINUE
      IF( IMAS.EQ.0 ) THEN
         DO 30 J = 1, NM
            E1( J, J ) = E1( J, J ) + FAC1
            E2R( J, J ) = E2R( J, J ) + ALPHN
            E2I( J, J ) = BETAN
   30    CONTINUE
      ELSE IF( IMAS.EQ.2 ) THEN
         DO 40 J = 1, NM
            E1( J, J ) = E1( J, J ) + FAC1*AM( 1, J )
            E2R( J, J ) = E2R( J, J ) + ALPHN*AM( 1, J )
            E2I( J, J ) = BETAN*AM( 1, J )
   40    CONTINUE
      ELSE
         DO 60 J = 1, NM
            DO 50 I = 1, NM
               E1( I, J ) = E1( I, J ) + FAC1*AM( I, J )
               E2R( I, J ) = E2R( I, J ) + ALPHN*AM( I, J )
               E2I( I, J ) = BETAN*AM( I, J )
   50       CONTINUE
   60    CONTINUE
      END IF
      IF( M1.GT.0 ) THEN
         MM = M1 / M2
         ABNO = ALPHN*ALPHN + BETAN*BETAN
         SR = ALPHN / ABNO
         SI = -BETAN / ABNO
         DO 90 J = 1, M2
            DO 80 I = 1, NM
               SUM = 0.0D0
               PR = 0.0D0
               PI = 0.0D0
               DO 70 K = 0, MM - 1
                  FJ = FJAC( M1+I, J+K*M2 )
                  SUM = ( SUM + FJ ) / FAC1
                  AR = PR + FJ
                  AI = PI
                  PR = AR*SR - AI*SI
                  PI = AR*SI + AI*SR
   70          CONTINUE
               E1( I, J ) = E1( I, J ) - SUM
               E2R( I, J ) = E2R( I, J ) - PR
               E2I( I, J ) = E2I( I, J ) - PI
   80       CONTINUE
   90    CONTINUE
      END IF
      IF( ILAPCK.EQ.0 ) THEN
         CALL RADLUD( NM, E1, NM, IP1, IWL, INFO1 )
         CALL RADLZD( NM, E2R, E2I, NM, IP2, IWL, INFO2 )
      ELSE
         DO 110 J = 1, NM
            DO 100 I = 1, NM
               E2( I, J ) = DCMPLX( E2R( I, J ), E2I( I, J ) )
  100       CONTINUE
  110    CONTINUE
         CALL DGETRF( NM, NM, E1, NM, IP1, INFO1 )
         CALL ZGETRF( NM, NM, E2, NM, IP2, INFO2 )
      END IF
      INFO = 0
      IF( INFO1.NE.0 .OR. INFO2.NE.0 ) INFO = 1
      RETURN
*
*     End of RADDEC
*
      END
*
*  =====================================================================
      RECURSIVE SUBROUTINE RADSL1( ILAPCK, N, M1, M2, FAC1, FJAC, E1,
     $                   IP1, B, TS )
      IMPLICIT NONE
      INTEGER            ILAPCK, N, M1, M2
      INTEGER            IP1( * )
      DOUBLE PRECISION   FAC1, FJAC( N, N ), E1( N-M1, * ), B( N ),
     $                   TS( * )
*
*  Purpose
*  =======
*
*  RADSL1 solves E1 x = b, in place, with the factors of RADDEC: with
*  M1 > 0 the second-order unknowns are eliminated first (p_k, stored
*  in TS(1:M1)), the reduced system of order N - M1 is solved, and
*  x_k = (b_k + x_{k+M2}) / FAC1, k = M1..1, recovers the rest (see
*  RADIIA, Mathematics).
*
*  Arguments
*  =========
*
*  ILAPCK  (input) INTEGER, 0: RADLUS; 1: DGETRS.
*  N, M1, M2, FAC1, FJAC  as in RADDEC.
*  E1, IP1 (input) factors and pivots from RADDEC.
*  B       (input/output) DOUBLE PRECISION array (N): b, then x.
*  TS      (workspace) DOUBLE PRECISION array (M1).
*
*  =====================================================================
*
      INTEGER            I, K, NM, INFO
      DOUBLE PRECISION   P
      EXTERNAL           DGETRS, RADLUS
*
      NM = N - M1
      IF( M1.GT.0 ) THEN
         DO 10 K = M1, 1, -1
            P = B( K )
            IF( K + M2.LE.M1 ) P = P + TS( K+M2 )
            TS( K ) = P / FAC1
   10    CONTINUE
         DO 30 K = 1, M1
            P = TS( K )
            IF( P.NE.0.0D0 ) THEN
               DO 20 I = 1, NM
                  B( M1+I ) = B( M1+I ) + FJAC( M1+I, K )*P
   20          CONTINUE
            END IF
   30    CONTINUE
      END IF
      IF( ILAPCK.EQ.0 ) THEN
         CALL RADLUS( NM, E1, NM, IP1, B( M1+1 ) )
      ELSE
         CALL DGETRS( 'N', NM, 1, E1, NM, IP1, B( M1+1 ), NM, INFO )
      END IF
      DO 40 K = M1, 1, -1
         B( K ) = ( B( K ) + B( K+M2 ) ) / FAC1
   40 CONTINUE
      RETURN
*
*     End of RADSL1
*
      END
*
*  =====================================================================
      RECURSIVE SUBROUTINE RADSLV( ILAPCK, N, M1, M2, FAC1, ALPHN,
     $                   BETAN, FJAC, E1, E2R, E2I, E2, IP1, IP2, F1,
     $                   F2, F3, TS, ZT )
      IMPLICIT NONE
      INTEGER            ILAPCK, N, M1, M2
      INTEGER            IP1( * ), IP2( * )
      DOUBLE PRECISION   FAC1, ALPHN, BETAN, FJAC( N, N ),
     $                   E1( N-M1, * ), E2R( N-M1, * ), E2I( N-M1, * ),
     $                   F1( N ), F2( N ), F3( N ), TS( * )
      COMPLEX*16         E2( N-M1, * ), ZT( * )
*
*  Purpose
*  =======
*
*  RADSLV solves, in place, the transformed simplified-Newton system
*     E1 x1 = F1,   E2 (x2 + i x3) = F2 + i F3,
*  with the factors of RADDEC; the real part by RADSL1, the complex
*  part alike with s = 1/(ALPHN + i BETAN) in complex arithmetic
*  written out in reals.
*
*  Arguments
*  =========
*
*  ILAPCK, N, M1, M2, FAC1, ALPHN, BETAN, FJAC  as in RADDEC.
*  E1, E2R, E2I, E2, IP1, IP2 (input) factors from RADDEC.
*  F1, F2, F3 (input/output) DOUBLE PRECISION arrays (N): right-hand
*          sides on entry, solutions on exit.
*  TS      (workspace) DOUBLE PRECISION array (3N).
*  ZT      (workspace) COMPLEX*16 array (N).
*
*  =====================================================================
*
      INTEGER            I, K, NM, INFO
      DOUBLE PRECISION   ABNO, SR, SI, AR, AI, PR, PI
      EXTERNAL           RADSL1, RADLZS, ZGETRS
      INTRINSIC          DBLE, DCMPLX, DIMAG
*
      CALL RADSL1( ILAPCK, N, M1, M2, FAC1, FJAC, E1, IP1, F1, TS )
      NM = N - M1
      IF( M1.GT.0 ) THEN
         ABNO = ALPHN*ALPHN + BETAN*BETAN
         SR = ALPHN / ABNO
         SI = -BETAN / ABNO
         DO 10 K = M1, 1, -1
            AR = F2( K )
            AI = F3( K )
            IF( K + M2.LE.M1 ) THEN
               AR = AR + TS( N+K+M2 )
               AI = AI + TS( 2*N+K+M2 )
            END IF
            TS( N+K ) = AR*SR - AI*SI
            TS( 2*N+K ) = AR*SI + AI*SR
   10    CONTINUE
         DO 30 K = 1, M1
            PR = TS( N+K )
            PI = TS( 2*N+K )
            IF( PR.NE.0.0D0 .OR. PI.NE.0.0D0 ) THEN
               DO 20 I = 1, NM
                  F2( M1+I ) = F2( M1+I ) + FJAC( M1+I, K )*PR
                  F3( M1+I ) = F3( M1+I ) + FJAC( M1+I, K )*PI
   20          CONTINUE
            END IF
   30    CONTINUE
      END IF
      IF( ILAPCK.EQ.0 ) THEN
         CALL RADLZS( NM, E2R, E2I, NM, IP2, F2( M1+1 ), F3( M1+1 ) )
      ELSE
         DO 40 I = 1, NM
            ZT( I ) = DCMPLX( F2( M1+I ), F3( M1+I ) )
   40    CONTINUE
         CALL ZGETRS( 'N', NM, 1, E2, NM, IP2, ZT, NM, INFO )
         DO 50 I = 1, NM
            F2( M1+I ) = DBLE( ZT( I ) )
            F3( M1+I ) = DIMAG( ZT( I ) )
   50    CONTINUE
      END IF
      IF( M1.GT.0 ) THEN
         DO 60 K = M1, 1, -1
            AR = F2( K ) + F2( K+M2 )
            AI = F3( K ) + F3( K+M2 )
            F2( K ) = AR*SR - AI*SI
            F3( K ) = AR*SI + AI*SR
   60    CONTINUE
      END IF
      RETURN
*
*     End of RADSLV
*
      END
*
*  =====================================================================
      RECURSIVE SUBROUTINE RADMAS( IMAS, ILAPCK, N, M1, AM, LDM, V, W )
      IMPLICIT NONE
      INTEGER            IMAS, ILAPCK, N, M1, LDM
      DOUBLE PRECISION   AM( LDM, * ), V( N ), W( N )
*
*  Purpose
*  =======
*
*  RADMAS computes W = K V for the mass matrix of RADIIA: rows 1..M1
*  of K are those of the identity; the lower block is the identity
*  (IMAS = 0), diag(AM(1,:)) (IMAS = 2) or AM (IMAS = 1: by columns,
*  skipping zero entries of V; DGEMV if ILAPCK = 1).
*
*  =====================================================================
*
      INTEGER            I, J, NM
      DOUBLE PRECISION   VJ
      EXTERNAL           DGEMV
*
      NM = N - M1
      DO 10 I = 1, M1
         W( I ) = V( I )
   10 CONTINUE
      IF( IMAS.EQ.0 ) THEN
         DO 20 I = 1, NM
            W( M1+I ) = V( M1+I )
   20    CONTINUE
      ELSE IF( IMAS.EQ.2 ) THEN
         DO 30 I = 1, NM
            W( M1+I ) = AM( 1, I )*V( M1+I )
   30    CONTINUE
      ELSE IF( ILAPCK.EQ.1 ) THEN
         CALL DGEMV( 'N', NM, NM, 1.0D0, AM, LDM, V( M1+1 ), 1, 0.0D0,
     $               W( M1+1 ), 1 )
      ELSE
         DO 40 I = 1, NM
            W( M1+I ) = 0.0D0
   40    CONTINUE
         DO 60 J = 1, NM
            VJ = V( M1+J )
            IF( VJ.NE.0.0D0 ) THEN
               DO 50 I = 1, NM
                  W( M1+I ) = W( M1+I ) + AM( I, J )*VJ
   50          CONTINUE
            END IF
   60    CONTINUE
      END IF
      RETURN
*
*     End of RADMAS
*
      END
*
*  =====================================================================
      RECURSIVE SUBROUTINE RADEST( FCN, CTX, IMAS, ILAPCK, N, M1, M2, X,
     $                   H, Y, Y0, Z1, Z2, Z3, DD, SCAL, AM, LDM, FAC1,
     $                   FJAC, E1, IP1, REFINE, T1, T2, T3, TS, NFCN,
     $                   NSOL, ERR, IERR )
      USE, INTRINSIC :: ISO_C_BINDING, ONLY: C_PTR
      IMPLICIT NONE
      TYPE(C_PTR)        CTX
      LOGICAL            REFINE
      INTEGER            IMAS, ILAPCK, N, M1, M2, LDM, NFCN, NSOL, IERR
      INTEGER            IP1( * )
      DOUBLE PRECISION   X, H, FAC1, ERR
      DOUBLE PRECISION   Y( N ), Y0( N ), Z1( N ), Z2( N ), Z3( N ),
     $                   DD( 3 ), SCAL( N ), AM( LDM, * ), FJAC( N, N ),
     $                   E1( * ), T1( N ), T2( N ), T3( N ), TS( * )
      EXTERNAL           FCN
*
*  Purpose
*  =======
*
*  RADEST computes the weighted RMS norm ERR of the filtered error
*  estimate
*     e = E1^{-1} ( Y0 + K v ),  v = (DD1 Z1 + DD2 Z2 + DD3 Z3) / H,
*  and, if REFINE and max(ERR, 1e-10) >= 1, of the re-filtered estimate
*     e' = E1^{-1} ( f(X, Y + e) + K v ),
*  which removes the error estimate's growth for very stiff components
*  (first step, step after a rejection).  ERR is returned as computed
*  (the caller tests it for finiteness, then bounds it below by
*  1e-10).
*
*  Arguments
*  =========
*
*  FCN, CTX, IMAS, N, M1, M2, AM, LDM as in RADIIA.
*  ILAPCK, FAC1, FJAC, E1, IP1  as in RADSL1.
*  X, H    (input) DOUBLE PRECISION, step start and step size.
*  Y, Y0   (input) DOUBLE PRECISION arrays (N): y and f(X, Y).
*  Z1..Z3  (input) DOUBLE PRECISION arrays (N): the stage increments.
*  DD      (input) DOUBLE PRECISION array (3): error weights (RADCOE).
*  SCAL    (input) DOUBLE PRECISION array (N): error weights.
*  REFINE  (input) LOGICAL: allow the re-filtered estimate.
*  T1, T2, T3 (workspace) DOUBLE PRECISION arrays (N); TS (3N).
*  NFCN, NSOL (input/output) INTEGER: counters, incremented.
*  ERR     (output) DOUBLE PRECISION: the error norm.
*  IERR    (output) INTEGER: 0, or FCN's IERR if it failed.
*
*  =====================================================================
*
      INTEGER            I
      DOUBLE PRECISION   HEE1, HEE2, HEE3, SUM
      EXTERNAL           RADMAS, RADSL1
      INTRINSIC          DBLE, HUGE, MAX, SQRT
*
      IERR = 0
      HEE1 = DD( 1 ) / H
      HEE2 = DD( 2 ) / H
      HEE3 = DD( 3 ) / H
      DO 10 I = 1, N
         T2( I ) = HEE1*Z1( I ) + HEE2*Z2( I ) + HEE3*Z3( I )
   10 CONTINUE
*     T1 = K v from here on.
      CALL RADMAS( IMAS, ILAPCK, N, M1, AM, LDM, T2, T1 )
      DO 30 I = 1, N
         T2( I ) = Y0( I ) + T1( I )
   30 CONTINUE
      CALL RADSL1( ILAPCK, N, M1, M2, FAC1, FJAC, E1, IP1, T2, TS )
      NSOL = NSOL + 1
      SUM = 0.0D0
      DO 40 I = 1, N
         SUM = SUM + ( T2( I ) / SCAL( I ) )**2
   40 CONTINUE
      ERR = SQRT( SUM / DBLE( N ) )
      IF( .NOT.( ERR.LE.HUGE( ERR ) ) ) RETURN
      IF( MAX( ERR, 1.0D-10 ).LT.1.0D0 .OR. .NOT.REFINE ) RETURN
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
      CALL RADSL1( ILAPCK, N, M1, M2, FAC1, FJAC, E1, IP1, T2, TS )
      NSOL = NSOL + 1
      SUM = 0.0D0
      DO 70 I = 1, N
         SUM = SUM + ( T2( I ) / SCAL( I ) )**2
   70 CONTINUE
      ERR = SQRT( SUM / DBLE( N ) )
      RETURN
*
*     End of RADEST
*
      END
*
*  =====================================================================
      RECURSIVE LOGICAL FUNCTION RADFIN( N, V )
      IMPLICIT NONE
      INTEGER            N
      DOUBLE PRECISION   V( * )
*
*  Purpose
*  =======
*
*  RADFIN is .TRUE. if V(1:N) are all finite (neither NaN nor
*  infinite), tested as |v| <= HUGE, which is false for both.
*
*  =====================================================================
*
      INTEGER            I
      INTRINSIC          ABS, HUGE
*
      RADFIN = .TRUE.
      DO 10 I = 1, N
         IF( .NOT.( ABS( V( I ) ).LE.HUGE( V( I ) ) ) ) THEN
            RADFIN = .FALSE.
            RETURN
         END IF
   10 CONTINUE
      RETURN
*
*     End of RADFIN
*
      END
*
*  =====================================================================
      RECURSIVE SUBROUTINE RADCEX( N, C, Z1, Z2, Z3, Y, CONT )
      IMPLICIT NONE
      INTEGER            N
      DOUBLE PRECISION   C( 3 ), Z1( N ), Z2( N ), Z3( N ), Y( N ),
     $                   CONT( N, 4 )
*
*  Purpose
*  =======
*
*  RADCEX sets Y := Y + Z3 and the continuation coefficients CONT of
*  the collocation polynomial through (0, Y), (c1, Y+Z1), (c2, Y+Z2),
*  (1, Y+Z3) (relative step times): its Newton divided differences at
*  1, c2, c1, 0 (see RADIIA, Dense output).
*
*  =====================================================================
*
      INTEGER            I
      DOUBLE PRECISION   C1M1, C2M1, C1MC2, AK1, AK2, A1, A2
*
      C1M1 = C( 1 ) - 1.0D0
      C2M1 = C( 2 ) - 1.0D0
      C1MC2 = C( 1 ) - C( 2 )
      DO 10 I = 1, N
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
   10 CONTINUE
      RETURN
*
*     End of RADCEX
*
      END
*
*  =====================================================================
      RECURSIVE SUBROUTINE RADROT( GFCN, CTX, NG, N, X0, XOLD, X, H,
     $                   UROUND, CONT, GOLD, GNEW, GC, TR, IRDIR, JROOT,
     $                   YT, NGEV, XROOT, IROOT, IERR )
      USE, INTRINSIC :: ISO_C_BINDING, ONLY: C_PTR
      IMPLICIT NONE
      TYPE(C_PTR)        CTX
      INTEGER            NG, N, NGEV, IROOT, IERR
      INTEGER            IRDIR( NG ), JROOT( NG )
      DOUBLE PRECISION   X0, XOLD, X, H, UROUND, XROOT
      DOUBLE PRECISION   CONT( N, 4 ), GOLD( NG ), GNEW( NG ), GC( NG ),
     $                   TR( NG ), YT( N )
      EXTERNAL           GFCN
*
*  Purpose
*  =======
*
*  RADROT checks the event functions after the accepted step
*  [XOLD, X] and locates their roots on the step's collocation
*  polynomial u (CONT): see RADIIA, Events.  For each g_i with
*  GOLD(i) /= 0 that changed sign (or reached 0) in an allowed
*  direction, the Illinois method brackets the root of
*  t -> g_i(t, u(t)) to |b - a| <= TTOL = 100 UROUND (|X| + |X-XOLD|),
*  b the end where g_i has its new sign or is 0 (bisection replaces a
*  secant point that is not strictly inside, or when g_i(b) = 0).
*  Roots within TTOL of X0 (the start of the call) are ignored.
*  On return IROOT = 1 if a root was found: XROOT the earliest (in
*  the direction of integration), JROOT(i) = +1/-1 for the functions
*  with a root within TTOL of it, 0 for the others; else IROOT = 0,
*  JROOT = 0 and GOLD := g(X, u(X)) for the next step.
*
*  Arguments
*  =========
*
*  GFCN, CTX, NG, N  as in RADIIA.
*  X0      (input) DOUBLE PRECISION, the start time of this call.
*  XOLD, X (input) DOUBLE PRECISION, the step; H its size (unused
*          beyond the tolerance).
*  UROUND  (input) DOUBLE PRECISION, the unit roundoff.
*  CONT    (input) DOUBLE PRECISION array (N,4), continuation
*          coefficients of the step (RADCEX).
*  GOLD    (input/output) DOUBLE PRECISION array (NG), g at XOLD.
*  GNEW, GC, TR (workspace) DOUBLE PRECISION arrays (NG).
*  IRDIR   (input) INTEGER array (NG), the direction filter.
*  JROOT   (output) INTEGER array (NG).
*  YT      (workspace) DOUBLE PRECISION array (N).
*  NGEV    (input/output) INTEGER, event-function evaluations.
*  XROOT   (output) DOUBLE PRECISION.
*  IROOT   (output) INTEGER, 0 or 1.
*  IERR    (output) INTEGER, 0 or GFCN's nonzero IERR.
*
*  =====================================================================
*
      INTEGER            I, IT, INFO, LASTS, IDIR
      DOUBLE PRECISION   TTOL, A, B, GA, GB, T, GT, SGN
      EXTERNAL           RADDEN
      INTRINSIC          ABS, SIGN
*
      IERR = 0
      IROOT = 0
      XROOT = X
      SGN = SIGN( 1.0D0, X - XOLD )
      TTOL = 100.0D0*UROUND*( ABS( X ) + ABS( X - XOLD ) )
      CALL GFCN( N, X, CONT( 1, 1 ), NG, GNEW, CTX, IERR )
      NGEV = NGEV + 1
      IF( IERR.NE.0 ) RETURN
      DO 30 I = 1, NG
         JROOT( I ) = 0
         IF( GOLD( I ).EQ.0.0D0 ) GO TO 30
         IF( .NOT.( GOLD( I )*GNEW( I ).LT.0.0D0 .OR.
     $       GNEW( I ).EQ.0.0D0 ) ) GO TO 30
         IF( GOLD( I ).LT.0.0D0 ) THEN
            IDIR = 1
         ELSE
            IDIR = -1
         END IF
         IF( IRDIR( I ).NE.0 .AND. IRDIR( I ).NE.IDIR ) GO TO 30
*        Illinois on [A, B]: GA has the old sign, GB the new (or 0).
         A = XOLD
         GA = GOLD( I )
         B = X
         GB = GNEW( I )
         LASTS = 0
         DO 20 IT = 1, 200
            IF( ABS( B - A ).LE.TTOL ) GO TO 25
            IF( GB.NE.0.0D0 ) THEN
               T = B - GB*( B - A ) / ( GB - GA )
            ELSE
               T = A
            END IF
            IF( .NOT.( ( T - A )*( B - T ).GT.0.0D0 ) )
     $         T = A + 0.5D0*( B - A )
            CALL RADDEN( N, T, XOLD, X, CONT, N, YT, INFO )
            CALL GFCN( N, T, YT, NG, GC, CTX, IERR )
            NGEV = NGEV + 1
            IF( IERR.NE.0 ) RETURN
            GT = GC( I )
            IF( GT.EQ.0.0D0 .OR. ( GT.LT.0.0D0 .EQV. IDIR.LT.0 ) ) THEN
*              T on the new-sign side (or a zero): it becomes B.
               B = T
               GB = GT
               IF( LASTS.EQ.1 ) GA = 0.5D0*GA
               LASTS = 1
            ELSE
*              T on the old-sign side: it becomes A.
               A = T
               GA = GT
               IF( LASTS.EQ.-1 ) GB = 0.5D0*GB
               LASTS = -1
            END IF
   20    CONTINUE
   25    CONTINUE
         IF( ABS( B - X0 ).LE.TTOL ) GO TO 30
         TR( I ) = B
         JROOT( I ) = IDIR
         IF( IROOT.EQ.0 ) THEN
            XROOT = B
            IROOT = 1
         ELSE IF( ( B - XROOT )*SGN.LT.0.0D0 ) THEN
            XROOT = B
         END IF
   30 CONTINUE
      IF( IROOT.EQ.0 ) THEN
         DO 40 I = 1, NG
            GOLD( I ) = GNEW( I )
   40    CONTINUE
         RETURN
      END IF
      DO 50 I = 1, NG
         IF( JROOT( I ).NE.0 ) THEN
            IF( ABS( TR( I ) - XROOT ).GT.TTOL ) JROOT( I ) = 0
         END IF
   50 CONTINUE
      RETURN
*
*     End of RADROT
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
