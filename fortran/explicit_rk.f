*> \file explicit_rk.f
*> The explicit embedded Runge-Kutta pair of Dormand and Prince,
*> order 8 with error estimators of orders 5 and 3 and a dense output
*> of order 7 ("DOP853"), for y' = f(t, y), with stiffness detection
*> and event location.  Written for pcsim from the mathematics of
*> Hairer, Norsett & Wanner, Solving ODEs I, sections II.4, II.6 and
*> II.10, and Prince & Dormand (1981); no code copied.
*>
*> Routines in this file:
*>   ERKDP8  the integrator (checks arguments, partitions the work
*>           arrays, calls ERKCOR)
*>   ERKCOR  the step loop
*>   ERKFEV  one evaluation of f, counted and checked for finiteness
*>   ERKGEV  one evaluation of the event functions g on the dense output
*>   ERKROO  locates the earliest sign change of g in a step
*>   ERKDEN  dense output from the continuation coefficients
*>   ERKNFI  true if a number is not finite (NaN or +-Inf)
*>   ERKCOE  the method coefficients as arrays (for tests)
*
*  =====================================================================
      RECURSIVE SUBROUTINE ERKDP8( FCN, GFCN, SOLOUT, CTX, ITOL, IOUT,
     $                   N, NG, T, TEND, Y, H, RTOL, ATOL, WORK, LWORK,
     $                   IWORK, LIWORK, IDID )
      USE, INTRINSIC :: ISO_C_BINDING, ONLY: C_PTR
      IMPLICIT NONE
*
*     .. Scalar Arguments ..
      TYPE(C_PTR)        CTX
      INTEGER            ITOL, IOUT, N, NG, LWORK, LIWORK, IDID
      DOUBLE PRECISION   T, TEND, H
*     .. Array Arguments ..
      INTEGER            IWORK( * )
      DOUBLE PRECISION   Y( * ), RTOL( * ), ATOL( * ), WORK( * )
*     .. External Procedures ..
      EXTERNAL           FCN, GFCN, SOLOUT
*
*  Purpose
*  =======
*
*  ERKDP8 integrates the system of ordinary differential equations
*
*        y'(t) = f(t, y(t)),      y(T) given,
*
*  from T to TEND with the explicit Runge-Kutta pair of Dormand and
*  Prince of order 8 (12 stages, the last one at c = 1), with step-size
*  control, a dense output of order 7, a stiffness test, and the
*  location of the sign changes of NG event functions g(t, y).
*
*  Mathematics
*  ===========
*
*  One step from (x, y0) with step h: k_1 = f(x, y0) (the last stage
*  of the previous step, "first same as last"), and for i = 2..12
*        k_i = f(x + c_i h, Y_i),  Y_i = y0 + h sum_{j<i} a_ij k_j,
*        y1  = y0 + h sum_i b_i k_i                       (order 8).
*  Two embedded differences estimate the error: e5 = h sum_i er_i k_i
*  (order 5) and e3 = h (sum_i b_i k_i - bh1 k_1 - bh9 k_9 - bh12 k_12)
*  (order 3).  With sk_i = atol_i + rtol_i max(|y0_i|, |y1_i|) and the
*  sums of squares S5 = sum (e5_i/(h sk_i))**2, S3 likewise,
*        err = |h| S5 / sqrt(N (S5 + 0.01 S3)),
*  which behaves like an error of order 8 for small h and like the
*  order-5 estimate when it dominates (Hairer, Norsett & Wanner I,
*  II.10).  The step is accepted if err <= 1; the new step is
*        h_new = h min(FACMAX, max(FACMIN, SAFE err**(-1/8)))
*  (FACMAX when err = 0), not larger than |h| right after a rejection,
*  nor larger than HMAX.  A rejected step is retried with h_new.
*
*  After an accepted step, k_13 = f(x + h, y1) is evaluated; it is
*  the first stage of the next step.  If dense output is needed (IOUT
*  = 1 or NG > 0), three more stages k_14..k_16 (c = 0.1, 0.2, 7/9)
*  give the continuation coefficients CONT(:,1:8) of the polynomial
*  of degree 7, u(x + s h) = CONT1 + s (CONT2 + s1 (CONT3 + s (CONT4
*        + s1 (CONT5 + s (CONT6 + s1 (CONT7 + s CONT8)))))), s1 = 1-s,
*  with CONT1 = y0, CONT2 = y1 - y0, CONT3 = h k_1 - CONT2, CONT4 =
*  CONT2 - h k_13 - CONT3 and CONT5..8 = h sum_j d_rj k_j, so u
*  interpolates y0, y1, f(x, y0) and f(x + h, y1).  ERKDEN evaluates it.
*
*  Starting step (H = 0 on entry): with d0 = ||y0||, d1 = ||f(x,y0)||
*  in the Euclidean norm weighted by 1/sk_i (sk_i = atol_i + rtol_i
*  |y0_i|), h0 = 0.01 d0/d1 (1e-6 if either is below 1e-5), one
*  Euler step y0 + h0 f0 and d2 = ||f(x+h0, .) - f0||/h0; then
*  h = min(100 h0, (0.01/max(d1, d2))**(1/8), HMAX) (Hairer, Norsett
*  & Wanner I, II.4; if f fails at the trial point, h = h0).  This
*  costs one evaluation of f.
*
*  Stiffness test.  After each accepted step the stages 12 and 13 have
*  the same abscissa x + h, so
*        h |lambda| ~ |h| ||k_13 - k_12||_2 / ||y1 - Y_12||_2
*  estimates h times the dominant eigenvalue of the Jacobian along
*  that direction.  A step is "stiff" if the estimate exceeds
*  STBND = 6.1, 0.954 times the length 6.39 of the method's stability
*  interval on the negative real axis (in a stiff regime the step-size
*  control holds h |lambda| near that boundary).  Stiffness is
*  reported once NSTPER (15) stiff steps occurred without 6
*  consecutive non-stiff steps in between.
*
*  Events.  g(t, y) has NG components.  After each accepted step the
*  components that change sign between the start and the end of the
*  step (from non-zero to zero or to the other sign) bracket roots;
*  the earliest root of all is located on the dense output u by a
*  regula falsi with the Illinois modification, safeguarded by
*  bisection, to |t_hi - t_lo| <= TOLR (WORK(6)).  The integration
*  returns at t_hi, the end of the final bracket (on the far side of
*  the root, so the same root does not fire again after a restart),
*  with y = u(t_hi).  A component that is exactly zero at the start
*  of the step (a restart at a root) is judged from its value TOLR
*  later, so a root within TOLR of a restart point is not reported.
*  Two sign changes of one component within one step cancel and are
*  not seen.
*
*  Arguments
*  =========
*
*  FCN     (input) EXTERNAL subroutine, the right-hand side
*             SUBROUTINE FCN( N, T, Y, F, CTX, IERR )
*             INTEGER N, IERR;  DOUBLE PRECISION T, Y(N), F(N)
*             TYPE(C_PTR) CTX  (passed through untouched)
*          computes F = f(T, Y).  IERR = 0: success; IERR = 1: f cannot
*          be evaluated at (T, Y) (the step is retried with h/2); any
*          other value: fatal, IDID = ODE_CALLBACK_ERROR.  A non-finite
*          F is treated like IERR = 1 but reported as ODE_NON_FINITE.
*
*  GFCN    (input) EXTERNAL subroutine, the event functions (used if
*          NG > 0)
*             SUBROUTINE GFCN( N, T, Y, NG, G, CTX, IERR )
*          computes G(1:NG) = g(T, Y).  IERR /= 0 or a non-finite G:
*          fatal, IDID = ODE_CALLBACK_ERROR.
*
*  SOLOUT  (input) EXTERNAL subroutine, called after every accepted
*          step if IOUT = 1:
*             SUBROUTINE SOLOUT( N, TOLD, T, HD, Y, CONT, LDC, CTX,
*                                IRTRN )
*          [TOLD, T]: the step just accepted (T is the root if the
*          step ends at an event); HD: the step of the polynomial, so
*          that ERKDEN( N, S, TOLD, HD, CONT, LDC, ... ) evaluates it
*          at S in [TOLD, T]; Y(N): the solution at T, which SOLOUT may
*          modify; CONT(LDC,8): the continuation coefficients.  On
*          return IRTRN = 0: proceed; 1: Y was modified (f and g are
*          evaluated afresh at the new Y); 2: stop (IDID =
*          ODE_STOPPED_BY_CALLBACK); any other value: fatal
*          (ODE_CALLBACK_ERROR).
*
*  CTX     (input) TYPE(C_PTR), opaque context handed to FCN, GFCN and
*          SOLOUT unchanged.
*
*  ITOL    (input) INTEGER.  0: RTOL, ATOL are scalars; 1: vectors.
*
*  IOUT    (input) INTEGER.  0: SOLOUT is never called; 1: it is.
*
*  N       (input) INTEGER.  The number of unknowns, N >= 1.
*
*  NG      (input) INTEGER.  The number of event functions, NG >= 0.
*
*  T       (input/output) DOUBLE PRECISION.  On entry the initial time,
*          on exit the time reached (TEND on success).
*
*  TEND    (input) DOUBLE PRECISION.  Final time (TEND < T integrates
*          backwards; TEND = T returns at once with IDID = 0).
*
*  Y       (input/output) DOUBLE PRECISION array, dimension (N).
*          On entry y(T), on exit y at the T returned.
*
*  H       (input/output) DOUBLE PRECISION.  On entry the initial step
*          (0: the starting-step algorithm above; its sign is ignored);
*          on exit the step size proposed for the next step.
*
*  RTOL    (input) DOUBLE PRECISION array, dimension (1) if ITOL = 0,
*          (N) if ITOL = 1.  Relative tolerances, each >= 10*EPS
*          (EPS the unit roundoff), else IDID = ODE_TOLERANCE_TOO_SMALL.
*
*  ATOL    (input) DOUBLE PRECISION array, dimension like RTOL.
*          Absolute tolerances, each > 0 (else ODE_TOLERANCE_TOO_SMALL).
*          The tolerances are used as given (no transformation).
*
*  WORK    (input/output) DOUBLE PRECISION array, dimension (LWORK).
*          Entries 1..20 are options (0 selects the default) and
*          outputs; the rest is workspace.
*          WORK(1)  HMAX, largest step size (default |TEND - T|)
*          WORK(2)  HFIX > 0: fixed-step mode, every step has size HFIX
*                   (the last one is shortened to hit TEND), no error
*                   control; for order tests.  0: adaptive.
*          WORK(3)  SAFE, safety factor (0.9), 0.0001 < SAFE < 1
*          WORK(4)  FACMIN, smallest step ratio (0.333), 0 < FACMIN
*                   <= 1
*          WORK(5)  FACMAX, largest step ratio (6), FACMAX >= 1
*          WORK(6)  TOLR, absolute time tolerance of event location
*                   (default 100*EPS*(|t| + |h|) in each step)
*          Outputs:
*          WORK(11) the last estimate of h|lambda| (stiffness test)
*          WORK(12) the time at which stiffness was detected (valid if
*                   IWORK(18) = 1)
*
*  LWORK   (input) INTEGER.  LWORK >= 20 + 27*N + 3*NG.
*
*  IWORK   (input/output) INTEGER array, dimension (LIWORK).
*          Options (0 selects the default):
*          IWORK(1)  NMAX, largest number of steps (100000)
*          IWORK(2)  stiffness: 0 test and report in IWORK(17:18);
*                    1 also return IDID = ODE_STIFFNESS_DETECTED when
*                    detected; -1 no test
*          IWORK(3)  NSTPER, stiff steps needed for detection (15)
*          IWORK(4)  NFAILM, consecutive failed evaluations of f
*                    (IERR = 1 or non-finite) before giving up (20)
*          Statistics (output, fixed slots):
*          IWORK(11) f evaluations (all: stages, first-step guess,
*                    dense output, after a modified state)
*          IWORK(12) steps attempted (accepted + rejected + failed)
*          IWORK(13) accepted steps
*          IWORK(14) steps rejected by the error test
*          IWORK(15) steps abandoned because f failed or was not finite
*          IWORK(16) evaluations of g
*          IWORK(17) accepted steps the stiffness test found stiff
*          IWORK(18) 1 if stiffness was detected, else 0
*          Events:
*          IWORK(21:20+NG)     (output) on IDID = ODE_ROOT_FOUND: +1 for
*                    each g_i that crossed zero rising, -1 falling,
*                    0 for the others
*          IWORK(21+NG:20+2NG) (input) direction filter per g_i: 0 any,
*                    +1 only rising, -1 only falling roots are events
*          IWORK(21+2NG:20+3NG) workspace
*
*  LIWORK  (input) INTEGER.  LIWORK >= 20 + 3*NG.
*
*  IDID    (output) INTEGER (codes of fortran/pcsim_ode_status.fi).
*          = ODE_SUCCESS (0): T = TEND.
*          = ODE_STOPPED_BY_CALLBACK (1): SOLOUT returned IRTRN = 2; T
*                is the end of the last accepted step.
*          = ODE_ROOT_FOUND (2): an event; T, Y at the root (see Events)
*                and IWORK(21:20+NG) says which.
*          < 0:  if IDID = -i, the i-th argument had an illegal value
*                (an option in WORK gives -15, in IWORK -17); nothing
*                was computed.
*          = ODE_TOO_MANY_STEPS: more than NMAX steps.
*          = ODE_STEP_TOO_SMALL: 0.1*|h| <= EPS*|t|.
*          = ODE_NON_FINITE: f, the new state or the error estimate was
*                not finite NFAILM times in a row (or h became too
*                small while retrying, or at the initial state or with
*                the fixed step).
*          = ODE_RHS_FAILED: like ODE_NON_FINITE, FCN returned IERR = 1.
*          = ODE_CALLBACK_ERROR: FCN IERR > 1 or < 0, GFCN IERR /= 0 or
*                non-finite G, SOLOUT IRTRN > 2 or < 0.
*          = ODE_TOLERANCE_TOO_SMALL: see RTOL, ATOL.
*          = ODE_STIFFNESS_DETECTED: IWORK(2) = 1 and the stiffness
*                test fired; T, Y are the last accepted step.
*          On IDID >= 3, T and Y are the last accepted state.
*
*  Further Details
*  ===============
*
*  Re-entrant: no COMMON, no SAVE, no I/O; all state lives in the
*  arguments and every routine is RECURSIVE (locals on the stack).
*  A step whose stages fail (FCN IERR = 1, or a non-finite f, y1 or
*  error estimate) is retried with h/2; so is an accepted step whose
*  f(x + h, y1) or dense stages fail, since f must be finite at every
*  accepted state.  The operations are ordered so that the C++ port
*  (cpp/ode/explicit_rk_port.cpp) rounds identically.
*
*  Work layout (1-based offsets from WORK(21)): K (N x 16, the stages),
*  Y1 (N), YT (N, stage arguments and temporaries), YS (N, the stage-
*  12 argument), CONT (N x 8), then GLO, GHI, GMID (NG each).
*
*  =====================================================================
*
      INCLUDE 'pcsim_ode_status.fi'
*     .. External Functions ..
      LOGICAL            ERKNFI
      EXTERNAL           ERKNFI
*     .. Local Scalars ..
      INTEGER            I, NMAX, ISTIF, NSTPER, NFAILM, IK, IY1, IYT,
     $                   IYS, ICO, IGL, IGH, IGM
      DOUBLE PRECISION   HMAXN, HFIX, SAFE, FACMIN, FACMAX, TOLR,
     $                   UROUND
*     .. Intrinsic Functions ..
      INTRINSIC          ABS, EPSILON, MIN
*     ..
*     .. Executable Statements ..
*
      UROUND = EPSILON( 1.0D0 )
*
*     Test the input arguments; the first bad one is reported.
*
      IDID = ODE_SUCCESS
      IF( ITOL.NE.0 .AND. ITOL.NE.1 ) THEN
         IDID = -5
      ELSE IF( IOUT.NE.0 .AND. IOUT.NE.1 ) THEN
         IDID = -6
      ELSE IF( N.LT.1 ) THEN
         IDID = -7
      ELSE IF( NG.LT.0 ) THEN
         IDID = -8
      ELSE IF( ERKNFI( T ) ) THEN
         IDID = -9
      ELSE IF( ERKNFI( TEND ) ) THEN
         IDID = -10
      ELSE IF( ERKNFI( H ) ) THEN
         IDID = -12
      ELSE IF( LWORK.LT.20 + 27*N + 3*NG ) THEN
         IDID = -16
      ELSE IF( LIWORK.LT.20 + 3*NG ) THEN
         IDID = -18
      END IF
      IF( IDID.NE.0 ) RETURN
      DO 10 I = 1, N
         IF( ERKNFI( Y( I ) ) ) THEN
            IDID = -11
            RETURN
         END IF
   10 CONTINUE
*
*     Options in WORK and IWORK.
*
      HMAXN = ABS( TEND - T )
      IF( .NOT.( WORK( 1 ).GE.0.0D0 ) ) IDID = -15
      IF( WORK( 1 ).GT.0.0D0 ) HMAXN = MIN( HMAXN, WORK( 1 ) )
      HFIX = WORK( 2 )
      IF( .NOT.( HFIX.GE.0.0D0 ) ) IDID = -15
      SAFE = 0.9D0
      IF( WORK( 3 ).NE.0.0D0 ) SAFE = WORK( 3 )
      IF( .NOT.( SAFE.GT.1.0D-4 .AND. SAFE.LT.1.0D0 ) ) IDID = -15
      FACMIN = 0.333D0
      IF( WORK( 4 ).NE.0.0D0 ) FACMIN = WORK( 4 )
      IF( .NOT.( FACMIN.GT.0.0D0 .AND. FACMIN.LE.1.0D0 ) ) IDID = -15
      FACMAX = 6.0D0
      IF( WORK( 5 ).NE.0.0D0 ) FACMAX = WORK( 5 )
      IF( .NOT.( FACMAX.GE.1.0D0 ) ) IDID = -15
      TOLR = WORK( 6 )
      IF( .NOT.( TOLR.GE.0.0D0 ) ) IDID = -15
      IF( IDID.NE.0 ) RETURN
      NMAX = 100000
      IF( IWORK( 1 ).NE.0 ) NMAX = IWORK( 1 )
      ISTIF = IWORK( 2 )
      NSTPER = 15
      IF( IWORK( 3 ).NE.0 ) NSTPER = IWORK( 3 )
      NFAILM = 20
      IF( IWORK( 4 ).NE.0 ) NFAILM = IWORK( 4 )
      IF( NMAX.LT.1 .OR. ISTIF.LT.-1 .OR. ISTIF.GT.1 .OR. NSTPER.LT.1
     $    .OR. NFAILM.LT.1 ) THEN
         IDID = -17
         RETURN
      END IF
      DO 20 I = 1, NG
         IF( ABS( IWORK( 20+NG+I ) ).GT.1 ) THEN
            IDID = -17
            RETURN
         END IF
   20 CONTINUE
*
*     Tolerances: rtol >= 10 EPS, atol > 0.
*
      DO 30 I = 1, 1 + ITOL*( N-1 )
         IF( .NOT.( RTOL( I ).GE.10.0D0*UROUND ) .OR.
     $       .NOT.( ATOL( I ).GT.0.0D0 ) .OR.
     $       ERKNFI( RTOL( I ) ) .OR.
     $       ERKNFI( ATOL( I ) ) ) THEN
            IDID = ODE_TOLERANCE_TOO_SMALL
            RETURN
         END IF
   30 CONTINUE
*
*     Partition the work arrays.
*
      IK = 21
      IY1 = IK + 16*N
      IYT = IY1 + N
      IYS = IYT + N
      ICO = IYS + N
      IGL = ICO + 8*N
      IGH = IGL + NG
      IGM = IGH + NG
*
      DO 40 I = 11, 20
         IWORK( I ) = 0
   40 CONTINUE
      DO 50 I = 1, NG
         IWORK( 20+I ) = 0
   50 CONTINUE
      WORK( 11 ) = 0.0D0
      WORK( 12 ) = 0.0D0
      IF( TEND.EQ.T ) RETURN
*
      CALL ERKCOR( FCN, GFCN, SOLOUT, CTX, ITOL, IOUT, N, NG, T, TEND,
     $             Y, H, RTOL, ATOL, NMAX, ISTIF, NSTPER, NFAILM, HMAXN,
     $             HFIX, SAFE, FACMIN, FACMAX, TOLR, WORK( IK ),
     $             WORK( IY1 ), WORK( IYT ), WORK( IYS ), WORK( ICO ),
     $             WORK( IGL ), WORK( IGH ), WORK( IGM ),
     $             IWORK( 21+NG ), IWORK( 21 ), IWORK( 21+2*NG ),
     $             IWORK( 11 ), WORK( 11 ), IDID )
      RETURN
*
*     End of ERKDP8
*
      END
*
*  =====================================================================
      RECURSIVE SUBROUTINE ERKCOR( FCN, GFCN, SOLOUT, CTX, ITOL, IOUT,
     $                   N, NG, X, XEND, Y, H, RTOL, ATOL, NMAX, ISTIF,
     $                   NSTPER, NFAILM, HMAXN, HFIX, SAFE, FACMIN,
     $                   FACMAX, TOLR, K, Y1, YT, YS, CONT, GLO, GHI,
     $                   GMID, IGDIR, JROOT, JT, ISTAT, WOUT, IDID )
      USE, INTRINSIC :: ISO_C_BINDING, ONLY: C_PTR
      IMPLICIT NONE
      TYPE(C_PTR)        CTX
      INTEGER            ITOL, IOUT, N, NG, NMAX, ISTIF, NSTPER, NFAILM,
     $                   IDID
      DOUBLE PRECISION   X, XEND, H, HMAXN, HFIX, SAFE, FACMIN, FACMAX,
     $                   TOLR
      INTEGER            IGDIR( * ), JROOT( * ), JT( * ), ISTAT( 10 )
      DOUBLE PRECISION   Y( N ), RTOL( * ), ATOL( * ), K( N, 16 ),
     $                   Y1( N ), YT( N ), YS( N ), CONT( N, 8 ),
     $                   GLO( * ), GHI( * ), GMID( * ), WOUT( 2 )
      EXTERNAL           FCN, GFCN, SOLOUT
*
*  Purpose
*  =======
*
*  ERKCOR is the step loop of ERKDP8 (see there for the method, the
*  arguments it shares and the meaning of IDID).  X, XEND, H: current
*  time, final time and step.  The scalars after ATOL are the resolved
*  options; K .. GMID the partitioned workspace; IGDIR the direction
*  filter, JROOT the root information of the events and JT integer
*  workspace (NG each); ISTAT(1:8)
*  receives the statistics IWORK(11:18), WOUT(1:2) the outputs
*  WORK(11:12) of ERKDP8.
*
*  =====================================================================
*
      INCLUDE 'pcsim_ode_status.fi'
      INCLUDE 'explicit_rk_coef.inc'
*     .. Parameters ..
      DOUBLE PRECISION   STBND
      PARAMETER          ( STBND = 6.1D0 )
*     .. External Functions ..
      LOGICAL            ERKNFI
      EXTERNAL           ERKNFI
*     .. Local Scalars ..
      INTEGER            I, J, NFCN, NSTEP, NACCPT, NREJCT, NFAIL, NGEV,
     $                   NSTIFP, IASTI, NONSTI, KFAIL, LFAIL, IFAIL,
     $                   IERR, IRTRN, IFOUND
      LOGICAL            REJECT, LAST, FIXED, DENSE, STIFF, MODIF
      DOUBLE PRECISION   UROUND, POSNEG, XOLD, HNEW, ERR, EST3, EST5,
     $                   ERR3, ERR5, DENO, SK, FAC, STNUM, STDEN, HLAMB,
     $                   DNF, DNY, DER2, DER12, H1, TOLX, TROOT, XPH
*     .. External Subroutines ..
      EXTERNAL           ERKFEV, ERKGEV, ERKROO, ERKDEN
*     .. Intrinsic Functions ..
      INTRINSIC          ABS, DBLE, EPSILON, MAX, MIN, SIGN, SQRT
*     ..
      UROUND = EPSILON( 1.0D0 )
      NFCN = 0
      NSTEP = 0
      NACCPT = 0
      NREJCT = 0
      NFAIL = 0
      NGEV = 0
      NSTIFP = 0
      IASTI = 0
      NONSTI = 0
      KFAIL = 0
      LFAIL = 0
      STIFF = .FALSE.
      FIXED = HFIX.GT.0.0D0
      DENSE = IOUT.EQ.1 .OR. NG.GT.0
      POSNEG = SIGN( 1.0D0, XEND - X )
      REJECT = .FALSE.
      HLAMB = 0.0D0
*
*     f and g at the initial state.
*
      CALL ERKFEV( FCN, CTX, N, X, Y, K( 1, 1 ), NFCN, IFAIL )
      IF( IFAIL.NE.0 ) GO TO 800
      IF( NG.GT.0 ) THEN
         CALL ERKGEV( GFCN, CTX, N, NG, X, Y, GLO, NGEV, IERR )
         IF( IERR.NE.0 ) THEN
            IDID = ODE_CALLBACK_ERROR
            GO TO 900
         END IF
      END IF
*
*     Initial step size.
*
      IF( FIXED ) THEN
         H = HFIX
      ELSE IF( H.EQ.0.0D0 ) THEN
         DNF = 0.0D0
         DNY = 0.0D0
         DO 60 I = 1, N
            SK = ATOL( 1 + ITOL*( I-1 ) ) +
     $           RTOL( 1 + ITOL*( I-1 ) )*ABS( Y( I ) )
            DNF = DNF + ( K( I, 1 ) / SK )**2
            DNY = DNY + ( Y( I ) / SK )**2
   60    CONTINUE
         IF( DNF.LE.1.0D-10 .OR. DNY.LE.1.0D-10 ) THEN
            H = 1.0D-6
         ELSE
            H = SQRT( DNY / DNF )*0.01D0
         END IF
         H = MIN( H, HMAXN )*POSNEG
         DO 70 I = 1, N
            YT( I ) = Y( I ) + H*K( I, 1 )
   70    CONTINUE
         CALL ERKFEV( FCN, CTX, N, X + H, YT, K( 1, 2 ), NFCN, IFAIL )
         IF( IFAIL.EQ.3 ) GO TO 800
         IF( IFAIL.EQ.0 ) THEN
            DER2 = 0.0D0
            DO 80 I = 1, N
               SK = ATOL( 1 + ITOL*( I-1 ) ) +
     $              RTOL( 1 + ITOL*( I-1 ) )*ABS( Y( I ) )
               DER2 = DER2 + ( ( K( I, 2 ) - K( I, 1 ) ) / SK )**2
   80       CONTINUE
            DER2 = SQRT( DER2 ) / ABS( H )
            DER12 = MAX( DER2, SQRT( DNF ) )
            IF( DER12.LE.1.0D-15 ) THEN
               H1 = MAX( 1.0D-6, ABS( H )*1.0D-3 )
            ELSE
               H1 = ( 0.01D0 / DER12 )**0.125D0
            END IF
            H = MIN( 100.0D0*ABS( H ), H1, HMAXN )*POSNEG
         END IF
      END IF
      H = MIN( ABS( H ), HMAXN )*POSNEG
      HNEW = H
*
*     ---- Main loop: one step attempt from X with step H.
*
  100 CONTINUE
      IF( NSTEP.GE.NMAX ) THEN
         IDID = ODE_TOO_MANY_STEPS
         GO TO 900
      END IF
      IF( 0.1D0*ABS( H ).LE.ABS( X )*UROUND ) THEN
         IF( LFAIL.EQ.0 ) THEN
            IDID = ODE_STEP_TOO_SMALL
            GO TO 900
         END IF
         GO TO 810
      END IF
      LAST = .FALSE.
      IF( ( X + 1.01D0*H - XEND )*POSNEG.GT.0.0D0 ) THEN
         H = XEND - X
         LAST = .TRUE.
      END IF
      NSTEP = NSTEP + 1
*
*     Stages 2 to 12.
*
      DO 102 I = 1, N
         YT( I ) = Y( I ) + H*( A2_1*K( I, 1 ) )
  102 CONTINUE
      CALL ERKFEV( FCN, CTX, N, X + C2*H, YT, K( 1, 2 ), NFCN, IFAIL )
      IF( IFAIL.NE.0 ) GO TO 700
      DO 103 I = 1, N
         YT( I ) = Y( I ) + H*( A3_1*K( I, 1 ) + A3_2*K( I, 2 ) )
  103 CONTINUE
      CALL ERKFEV( FCN, CTX, N, X + C3*H, YT, K( 1, 3 ), NFCN, IFAIL )
      IF( IFAIL.NE.0 ) GO TO 700
      DO 104 I = 1, N
         YT( I ) = Y( I ) + H*( A4_1*K( I, 1 ) + A4_3*K( I, 3 ) )
  104 CONTINUE
      CALL ERKFEV( FCN, CTX, N, X + C4*H, YT, K( 1, 4 ), NFCN, IFAIL )
      IF( IFAIL.NE.0 ) GO TO 700
      DO 105 I = 1, N
         YT( I ) = Y( I ) + H*( A5_1*K( I, 1 ) + A5_3*K( I, 3 )
     $      + A5_4*K( I, 4 ) )
  105 CONTINUE
      CALL ERKFEV( FCN, CTX, N, X + C5*H, YT, K( 1, 5 ), NFCN, IFAIL )
      IF( IFAIL.NE.0 ) GO TO 700
      DO 106 I = 1, N
         YT( I ) = Y( I ) + H*( A6_1*K( I, 1 ) + A6_4*K( I, 4 )
     $      + A6_5*K( I, 5 ) )
  106 CONTINUE
      CALL ERKFEV( FCN, CTX, N, X + C6*H, YT, K( 1, 6 ), NFCN, IFAIL )
      IF( IFAIL.NE.0 ) GO TO 700
      DO 107 I = 1, N
         YT( I ) = Y( I ) + H*( A7_1*K( I, 1 ) + A7_4*K( I, 4 )
     $      + A7_5*K( I, 5 ) + A7_6*K( I, 6 ) )
  107 CONTINUE
      CALL ERKFEV( FCN, CTX, N, X + C7*H, YT, K( 1, 7 ), NFCN, IFAIL )
      IF( IFAIL.NE.0 ) GO TO 700
      DO 108 I = 1, N
         YT( I ) = Y( I ) + H*( A8_1*K( I, 1 ) + A8_4*K( I, 4 )
     $      + A8_5*K( I, 5 ) + A8_6*K( I, 6 ) + A8_7*K( I, 7 ) )
  108 CONTINUE
      CALL ERKFEV( FCN, CTX, N, X + C8*H, YT, K( 1, 8 ), NFCN, IFAIL )
      IF( IFAIL.NE.0 ) GO TO 700
      DO 109 I = 1, N
         YT( I ) = Y( I ) + H*( A9_1*K( I, 1 ) + A9_4*K( I, 4 )
     $      + A9_5*K( I, 5 ) + A9_6*K( I, 6 ) + A9_7*K( I, 7 )
     $      + A9_8*K( I, 8 ) )
  109 CONTINUE
      CALL ERKFEV( FCN, CTX, N, X + C9*H, YT, K( 1, 9 ), NFCN, IFAIL )
      IF( IFAIL.NE.0 ) GO TO 700
      DO 110 I = 1, N
         YT( I ) = Y( I ) + H*( A10_1*K( I, 1 ) + A10_4*K( I, 4 )
     $      + A10_5*K( I, 5 ) + A10_6*K( I, 6 ) + A10_7*K( I, 7 )
     $      + A10_8*K( I, 8 ) + A10_9*K( I, 9 ) )
  110 CONTINUE
      CALL ERKFEV( FCN, CTX, N, X + C10*H, YT, K( 1, 10 ), NFCN, IFAIL )
      IF( IFAIL.NE.0 ) GO TO 700
      DO 111 I = 1, N
         YT( I ) = Y( I ) + H*( A11_1*K( I, 1 ) + A11_4*K( I, 4 )
     $      + A11_5*K( I, 5 ) + A11_6*K( I, 6 ) + A11_7*K( I, 7 )
     $      + A11_8*K( I, 8 ) + A11_9*K( I, 9 ) + A11_10*K( I, 10 ) )
  111 CONTINUE
      CALL ERKFEV( FCN, CTX, N, X + C11*H, YT, K( 1, 11 ), NFCN, IFAIL )
      IF( IFAIL.NE.0 ) GO TO 700
      DO 112 I = 1, N
         YS( I ) = Y( I ) + H*( A12_1*K( I, 1 ) + A12_4*K( I, 4 )
     $      + A12_5*K( I, 5 ) + A12_6*K( I, 6 ) + A12_7*K( I, 7 )
     $      + A12_8*K( I, 8 ) + A12_9*K( I, 9 ) + A12_10*K( I, 10 )
     $      + A12_11*K( I, 11 ) )
  112 CONTINUE
      XPH = X + H
      CALL ERKFEV( FCN, CTX, N, XPH, YS, K( 1, 12 ), NFCN, IFAIL )
      IF( IFAIL.NE.0 ) GO TO 700
*
*     The new solution (increment in YT) and the error estimate.
*
      DO 120 I = 1, N
         YT( I ) = B1*K( I, 1 ) + B6*K( I, 6 ) + B7*K( I, 7 )
     $      + B8*K( I, 8 ) + B9*K( I, 9 ) + B10*K( I, 10 )
     $      + B11*K( I, 11 ) + B12*K( I, 12 )
         Y1( I ) = Y( I ) + H*YT( I )
  120 CONTINUE
      DO 121 I = 1, N
         IF( ERKNFI( Y1( I ) ) ) THEN
            IFAIL = 2
            GO TO 700
         END IF
  121 CONTINUE
      IF( FIXED ) THEN
         ERR = 0.0D0
         HNEW = H
      ELSE
         ERR3 = 0.0D0
         ERR5 = 0.0D0
         DO 130 I = 1, N
            J = 1 + ITOL*( I-1 )
            SK = ATOL( J ) + RTOL( J )*MAX( ABS( Y( I ) ),
     $           ABS( Y1( I ) ) )
         EST3 = YT( I ) - BH1*K( I, 1 ) - BH9*K( I, 9 )
     $      - BH12*K( I, 12 )
         EST5 = ER1*K( I, 1 ) + ER6*K( I, 6 ) + ER7*K( I, 7 )
     $      + ER8*K( I, 8 ) + ER9*K( I, 9 ) + ER10*K( I, 10 )
     $      + ER11*K( I, 11 ) + ER12*K( I, 12 )
            ERR3 = ERR3 + ( EST3 / SK )**2
            ERR5 = ERR5 + ( EST5 / SK )**2
  130    CONTINUE
         DENO = ERR5 + 0.01D0*ERR3
         IF( DENO.LE.0.0D0 ) DENO = 1.0D0
         ERR = ABS( H )*ERR5*SQRT( 1.0D0 / ( DBLE( N )*DENO ) )
         IF( ERKNFI( ERR ) ) THEN
            IFAIL = 2
            GO TO 700
         END IF
         IF( ERR.EQ.0.0D0 ) THEN
            FAC = FACMAX
         ELSE
            FAC = MIN( FACMAX, MAX( FACMIN, SAFE*ERR**( -0.125D0 ) ) )
         END IF
         HNEW = H*FAC
      END IF
      IF( ERR.GT.1.0D0 ) GO TO 600
*
*     ---- Error test passed: f at the new point (stage 13, the first
*     stage of the next step) and the dense-output stages.  If any of
*     them fails the step is retried smaller.
*
      CALL ERKFEV( FCN, CTX, N, XPH, Y1, K( 1, 13 ), NFCN, IFAIL )
      IF( IFAIL.NE.0 ) GO TO 700
      IF( DENSE ) THEN
         DO 140 I = 1, N
         YT( I ) = Y( I ) + H*( A14_1*K( I, 1 ) + A14_7*K( I, 7 )
     $      + A14_8*K( I, 8 ) + A14_9*K( I, 9 ) + A14_10*K( I, 10 )
     $      + A14_11*K( I, 11 ) + A14_12*K( I, 12 )
     $      + A14_13*K( I, 13 ) )
  140    CONTINUE
         CALL ERKFEV( FCN, CTX, N, X + C14*H, YT, K( 1, 14 ), NFCN,
     $                IFAIL )
         IF( IFAIL.NE.0 ) GO TO 700
         DO 141 I = 1, N
         YT( I ) = Y( I ) + H*( A15_1*K( I, 1 ) + A15_6*K( I, 6 )
     $      + A15_7*K( I, 7 ) + A15_8*K( I, 8 ) + A15_11*K( I, 11 )
     $      + A15_12*K( I, 12 ) + A15_13*K( I, 13 )
     $      + A15_14*K( I, 14 ) )
  141    CONTINUE
         CALL ERKFEV( FCN, CTX, N, X + C15*H, YT, K( 1, 15 ), NFCN,
     $                IFAIL )
         IF( IFAIL.NE.0 ) GO TO 700
         DO 142 I = 1, N
         YT( I ) = Y( I ) + H*( A16_1*K( I, 1 ) + A16_6*K( I, 6 )
     $      + A16_7*K( I, 7 ) + A16_8*K( I, 8 ) + A16_9*K( I, 9 )
     $      + A16_13*K( I, 13 ) + A16_14*K( I, 14 )
     $      + A16_15*K( I, 15 ) )
  142    CONTINUE
         CALL ERKFEV( FCN, CTX, N, X + C16*H, YT, K( 1, 16 ), NFCN,
     $                IFAIL )
         IF( IFAIL.NE.0 ) GO TO 700
         DO 150 I = 1, N
            CONT( I, 1 ) = Y( I )
            CONT( I, 2 ) = Y1( I ) - Y( I )
            CONT( I, 3 ) = H*K( I, 1 ) - CONT( I, 2 )
            CONT( I, 4 ) = CONT( I, 2 ) - H*K( I, 13 ) - CONT( I, 3 )
         CONT( I, 5 ) = H*( D4_1*K( I, 1 ) + D4_6*K( I, 6 )
     $      + D4_7*K( I, 7 ) + D4_8*K( I, 8 ) + D4_9*K( I, 9 )
     $      + D4_10*K( I, 10 ) + D4_11*K( I, 11 ) + D4_12*K( I, 12 )
     $      + D4_13*K( I, 13 ) + D4_14*K( I, 14 ) + D4_15*K( I, 15 )
     $      + D4_16*K( I, 16 ) )
         CONT( I, 6 ) = H*( D5_1*K( I, 1 ) + D5_6*K( I, 6 )
     $      + D5_7*K( I, 7 ) + D5_8*K( I, 8 ) + D5_9*K( I, 9 )
     $      + D5_10*K( I, 10 ) + D5_11*K( I, 11 ) + D5_12*K( I, 12 )
     $      + D5_13*K( I, 13 ) + D5_14*K( I, 14 ) + D5_15*K( I, 15 )
     $      + D5_16*K( I, 16 ) )
         CONT( I, 7 ) = H*( D6_1*K( I, 1 ) + D6_6*K( I, 6 )
     $      + D6_7*K( I, 7 ) + D6_8*K( I, 8 ) + D6_9*K( I, 9 )
     $      + D6_10*K( I, 10 ) + D6_11*K( I, 11 ) + D6_12*K( I, 12 )
     $      + D6_13*K( I, 13 ) + D6_14*K( I, 14 ) + D6_15*K( I, 15 )
     $      + D6_16*K( I, 16 ) )
         CONT( I, 8 ) = H*( D7_1*K( I, 1 ) + D7_6*K( I, 6 )
     $      + D7_7*K( I, 7 ) + D7_8*K( I, 8 ) + D7_9*K( I, 9 )
     $      + D7_10*K( I, 10 ) + D7_11*K( I, 11 ) + D7_12*K( I, 12 )
     $      + D7_13*K( I, 13 ) + D7_14*K( I, 14 ) + D7_15*K( I, 15 )
     $      + D7_16*K( I, 16 ) )
  150    CONTINUE
      END IF
*
*     ---- Step accepted.
*
      NACCPT = NACCPT + 1
      KFAIL = 0
      LFAIL = 0
*
*     Stiffness test on the stages 12 and 13 (both at x + h).
*
      IF( ISTIF.GE.0 ) THEN
         STNUM = 0.0D0
         STDEN = 0.0D0
         DO 160 I = 1, N
            STNUM = STNUM + ( K( I, 13 ) - K( I, 12 ) )**2
            STDEN = STDEN + ( Y1( I ) - YS( I ) )**2
  160    CONTINUE
         IF( STDEN.GT.0.0D0 ) THEN
            HLAMB = ABS( H )*SQRT( STNUM / STDEN )
         ELSE
            HLAMB = 0.0D0
         END IF
         IF( HLAMB.GT.STBND ) THEN
            NSTIFP = NSTIFP + 1
            IASTI = IASTI + 1
            NONSTI = 0
            IF( IASTI.GE.NSTPER .AND. .NOT.STIFF ) THEN
               STIFF = .TRUE.
               WOUT( 2 ) = XPH
               IF( LAST ) WOUT( 2 ) = XEND
            END IF
         ELSE
            NONSTI = NONSTI + 1
            IF( NONSTI.GE.6 ) IASTI = 0
         END IF
      END IF
*
*     Advance: the dense output keeps the old y0 in CONT(:,1).
*
      XOLD = X
      IF( LAST ) THEN
         X = XEND
      ELSE
         X = XPH
      END IF
      DO 170 I = 1, N
         Y( I ) = Y1( I )
         K( I, 1 ) = K( I, 13 )
  170 CONTINUE
      IF( REJECT ) THEN
         HNEW = POSNEG*MIN( ABS( HNEW ), ABS( H ) )
      END IF
      REJECT = .FALSE.
      HNEW = POSNEG*MIN( ABS( HNEW ), HMAXN )
*
*     Events: the earliest sign change of g over [XOLD, X].
*
      IFOUND = 0
      IF( NG.GT.0 ) THEN
         CALL ERKGEV( GFCN, CTX, N, NG, X, Y, GHI, NGEV, IERR )
         IF( IERR.NE.0 ) THEN
            IDID = ODE_CALLBACK_ERROR
            GO TO 900
         END IF
         TOLX = TOLR
         IF( TOLX.EQ.0.0D0 ) TOLX = 100.0D0*UROUND*( ABS( X ) +
     $                              ABS( H ) )
         CALL ERKROO( GFCN, CTX, N, NG, XOLD, H, CONT, XOLD, X, TOLX,
     $                IGDIR, GLO, GHI, GMID, YT, JROOT, JT, TROOT,
     $                NGEV, IFOUND, IERR )
         IF( IERR.NE.0 ) THEN
            IDID = ODE_CALLBACK_ERROR
            GO TO 900
         END IF
         IF( IFOUND.EQ.1 ) THEN
            X = TROOT
            CALL ERKDEN( N, X, XOLD, H, CONT, N, Y, IERR )
         END IF
      END IF
*
*     The step callback.
*
      MODIF = .FALSE.
      IF( IOUT.EQ.1 ) THEN
         CALL SOLOUT( N, XOLD, X, H, Y, CONT, N, CTX, IRTRN )
         IF( IRTRN.EQ.2 ) THEN
            IDID = ODE_STOPPED_BY_CALLBACK
            GO TO 900
         ELSE IF( IRTRN.EQ.1 ) THEN
            MODIF = .TRUE.
         ELSE IF( IRTRN.NE.0 ) THEN
            IDID = ODE_CALLBACK_ERROR
            GO TO 900
         END IF
      END IF
      H = HNEW
      IF( IFOUND.EQ.1 ) THEN
         IDID = ODE_ROOT_FOUND
         GO TO 900
      END IF
      IF( STIFF .AND. ISTIF.EQ.1 ) THEN
         IDID = ODE_STIFFNESS_DETECTED
         GO TO 900
      END IF
      IF( LAST ) THEN
         IDID = ODE_SUCCESS
         GO TO 900
      END IF
*
*     A modified state: f (the first stage) and g afresh.
*
      IF( MODIF ) THEN
         CALL ERKFEV( FCN, CTX, N, X, Y, K( 1, 1 ), NFCN, IFAIL )
         IF( IFAIL.NE.0 ) GO TO 800
         IF( NG.GT.0 ) THEN
            CALL ERKGEV( GFCN, CTX, N, NG, X, Y, GLO, NGEV, IERR )
            IF( IERR.NE.0 ) THEN
               IDID = ODE_CALLBACK_ERROR
               GO TO 900
            END IF
         END IF
      ELSE
         DO 180 I = 1, NG
            GLO( I ) = GHI( I )
  180    CONTINUE
      END IF
      GO TO 100
*
*     ---- Error test failed: retry with the proposed step.
*
  600 CONTINUE
      NREJCT = NREJCT + 1
      REJECT = .TRUE.
      H = HNEW
      GO TO 100
*
*     ---- f failed (IFAIL = 1) or was not finite (IFAIL = 2) during a
*     step, or a callback error (IFAIL = 3): retry with h/2.
*
  700 CONTINUE
      IF( IFAIL.EQ.3 ) THEN
         IDID = ODE_CALLBACK_ERROR
         GO TO 900
      END IF
      NFAIL = NFAIL + 1
      KFAIL = KFAIL + 1
      LFAIL = IFAIL
      IF( FIXED .OR. KFAIL.GE.NFAILM ) GO TO 810
      H = H*0.5D0
      REJECT = .TRUE.
      GO TO 100
*
*     ---- f failed at an accepted state (IFAIL from ERKFEV).
*
  800 CONTINUE
      LFAIL = IFAIL
      IF( IFAIL.EQ.3 ) THEN
         IDID = ODE_CALLBACK_ERROR
         GO TO 900
      END IF
*
*     ---- Persistent failure of f: report its kind.
*
  810 CONTINUE
      IF( LFAIL.EQ.1 ) THEN
         IDID = ODE_RHS_FAILED
      ELSE
         IDID = ODE_NON_FINITE
      END IF
*
*     ---- Return: statistics.
*
  900 CONTINUE
      ISTAT( 1 ) = NFCN
      ISTAT( 2 ) = NSTEP
      ISTAT( 3 ) = NACCPT
      ISTAT( 4 ) = NREJCT
      ISTAT( 5 ) = NFAIL
      ISTAT( 6 ) = NGEV
      ISTAT( 7 ) = NSTIFP
      ISTAT( 8 ) = 0
      IF( STIFF ) ISTAT( 8 ) = 1
      WOUT( 1 ) = HLAMB
      RETURN
*
*     End of ERKCOR
*
      END
*
*  =====================================================================
      RECURSIVE SUBROUTINE ERKFEV( FCN, CTX, N, X, YARG, F, NFCN,
     $                             IFAIL )
      USE, INTRINSIC :: ISO_C_BINDING, ONLY: C_PTR
      IMPLICIT NONE
      TYPE(C_PTR)        CTX
      INTEGER            N, NFCN, IFAIL
      DOUBLE PRECISION   X, YARG( N ), F( N )
      EXTERNAL           FCN
*
*  Purpose
*  =======
*
*  ERKFEV evaluates F = f(X, YARG) through FCN, counts it in NFCN and
*  classifies the outcome: IFAIL = 0 success; 1 FCN returned IERR = 1
*  (cannot evaluate here); 2 some F(i) is not finite; 3 FCN returned
*  any other non-zero IERR (fatal).
*
*  =====================================================================
*
      INTEGER            I, IERR
      DOUBLE PRECISION   XARG
      LOGICAL            ERKNFI
      EXTERNAL           ERKNFI
*
      XARG = X
      IERR = 0
      CALL FCN( N, XARG, YARG, F, CTX, IERR )
      NFCN = NFCN + 1
      IFAIL = 0
      IF( IERR.EQ.1 ) THEN
         IFAIL = 1
      ELSE IF( IERR.NE.0 ) THEN
         IFAIL = 3
      ELSE
         DO 10 I = 1, N
            IF( ERKNFI( F( I ) ) ) THEN
               IFAIL = 2
               RETURN
            END IF
   10    CONTINUE
      END IF
      RETURN
*
*     End of ERKFEV
*
      END
*
*  =====================================================================
      RECURSIVE SUBROUTINE ERKGEV( GFCN, CTX, N, NG, X, YARG, G, NGEV,
     $                             IERR )
      USE, INTRINSIC :: ISO_C_BINDING, ONLY: C_PTR
      IMPLICIT NONE
      TYPE(C_PTR)        CTX
      INTEGER            N, NG, NGEV, IERR
      DOUBLE PRECISION   X, YARG( N ), G( NG )
      EXTERNAL           GFCN
*
*  Purpose
*  =======
*
*  ERKGEV evaluates the event functions G = g(X, YARG) through GFCN
*  and counts it in NGEV.  IERR = 0 success; 1 GFCN reported an error
*  or some G(i) is not finite.
*
*  =====================================================================
*
      INTEGER            I
      DOUBLE PRECISION   XARG
      LOGICAL            ERKNFI
      EXTERNAL           ERKNFI
*
      XARG = X
      IERR = 0
      CALL GFCN( N, XARG, YARG, NG, G, CTX, IERR )
      NGEV = NGEV + 1
      IF( IERR.NE.0 ) THEN
         IERR = 1
         RETURN
      END IF
      DO 10 I = 1, NG
         IF( ERKNFI( G( I ) ) ) THEN
            IERR = 1
            RETURN
         END IF
   10 CONTINUE
      RETURN
*
*     End of ERKGEV
*
      END
*
*  =====================================================================
      RECURSIVE SUBROUTINE ERKROO( GFCN, CTX, N, NG, TOLD, HD, CONT,
     $                   TLO, THI, TOLX, IGDIR, GLO, GHI, GMID, YT,
     $                   JROOT, JT, TROOT, NGEV, IFOUND, IERR )
      USE, INTRINSIC :: ISO_C_BINDING, ONLY: C_PTR
      IMPLICIT NONE
      TYPE(C_PTR)        CTX
      INTEGER            N, NG, NGEV, IFOUND, IERR
      DOUBLE PRECISION   TOLD, HD, TLO, THI, TOLX, TROOT
      INTEGER            IGDIR( NG ), JROOT( NG ), JT( NG )
      DOUBLE PRECISION   CONT( N, 8 ), GLO( NG ), GHI( NG ),
     $                   GMID( NG ), YT( N )
      EXTERNAL           GFCN
*
*  Purpose
*  =======
*
*  ERKROO finds the earliest sign change of the event functions over
*  the step [TLO, THI] (with the direction of TOLD -> TOLD + HD) on
*  the dense output of the step (CONT, TOLD, HD; see ERKDEN).
*
*  Mathematics
*  ===========
*
*  Component i brackets a root in [tl, th] if g_i(tl) /= 0 and g_i(th)
*  is zero or of the other sign, and its direction (rising if g_i(tl)
*  < 0) passes the filter IGDIR(i).  While tl and th are more than
*  TOLX apart, each bracketing component proposes its regula falsi
*  point th - w_h g_i(th) (th - tl) / (w_h g_i(th) - w_l g_i(tl)),
*  the earliest proposal is taken, kept TOLX/2 inside the bracket,
*  and g is evaluated there on the dense output: if some component
*  brackets a root in [tl, tm], th = tm, else tl = tm.  Illinois
*  modification: when the same end is kept twice in a row its weight
*  w is halved (the weights are 1 after the other end moved).  When
*  the bracket shrank by less than half over two iterations the next
*  point is the midpoint.  On exit TROOT = th and JROOT(i) = +1 or
*  -1 for the components bracketing a root in [tl, th] (rising,
*  falling), else 0.
*
*  If some g_i(TLO) = 0 (a restart at a root), tl moves to TLO + TOLX
*  (towards THI, at most to THI) and g is evaluated there first.
*
*  Arguments (beyond those of ERKCOR)
*  ==================================
*
*  TLO, THI  (input) the step: its start (g = GLO there) and end (g =
*            GHI there).  GLO, GHI, GMID are overwritten.
*  JT        (workspace) INTEGER, dimension NG.
*  TOLX      (input) the absolute time tolerance of the location.
*  YT        (workspace) dimension N.
*  TROOT     (output) the root if IFOUND = 1.
*  IFOUND    (output) 1 if a root was found, else 0.
*  IERR      (output) 0, or 1 if GFCN failed.
*
*  =====================================================================
*
*     .. Local Scalars ..
      INTEGER            I, ITER, LASTSD, NSLOW, INFO
      LOGICAL            ANYZ, BRACK
      DOUBLE PRECISION   POSNEG, TL, TH, TM, TI, FR, WL, WH, WIDTH,
     $                   WPREV, DIST
*     .. External Subroutines ..
      EXTERNAL           ERKDEN, ERKGEV, ERKBRK
*     .. Intrinsic Functions ..
      INTRINSIC          ABS, MIN, SIGN
*     ..
      IFOUND = 0
      IERR = 0
      POSNEG = SIGN( 1.0D0, HD )
      TL = TLO
      TH = THI
      DO 10 I = 1, NG
         JROOT( I ) = 0
   10 CONTINUE
*
*     A zero at the left end: judge from TOLX later.
*
      ANYZ = .FALSE.
      DO 20 I = 1, NG
         IF( GLO( I ).EQ.0.0D0 ) ANYZ = .TRUE.
   20 CONTINUE
      IF( ANYZ ) THEN
         TL = TL + POSNEG*MIN( TOLX, ABS( TH - TL ) )
         CALL ERKDEN( N, TL, TOLD, HD, CONT, N, YT, INFO )
         CALL ERKGEV( GFCN, CTX, N, NG, TL, YT, GLO, NGEV, IERR )
         IF( IERR.NE.0 ) RETURN
      END IF
*
*     Is there a root in [TL, TH] at all?
*
      CALL ERKBRK( NG, IGDIR, GLO, GHI, JROOT, BRACK )
      IF( .NOT.BRACK ) RETURN
*
      WL = 1.0D0
      WH = 1.0D0
      LASTSD = 0
      NSLOW = 0
      WPREV = ABS( TH - TL )
      DO 100 ITER = 1, 500
         WIDTH = ABS( TH - TL )
         IF( WIDTH.LE.TOLX ) GO TO 200
*        The earliest regula falsi proposal (a zero at TH proposes TH).
         TM = TH
         DO 30 I = 1, NG
            IF( JROOT( I ).NE.0 .AND. GHI( I ).NE.0.0D0 ) THEN
               FR = WH*GHI( I ) / ( WH*GHI( I ) - WL*GLO( I ) )
               TI = TH - FR*( TH - TL )
               IF( ( TI - TM )*POSNEG.LT.0.0D0 ) TM = TI
            END IF
   30    CONTINUE
         IF( NSLOW.GE.2 ) THEN
            TM = TL + 0.5D0*( TH - TL )
            NSLOW = 0
         END IF
*        Keep TM at least TOLX/2 inside the bracket.
         IF( WIDTH.LE.2.0D0*TOLX ) THEN
            TM = TL + 0.5D0*( TH - TL )
         ELSE
            DIST = ( TM - TL )*POSNEG
            IF( DIST.LT.0.5D0*TOLX ) TM = TL + POSNEG*0.5D0*TOLX
            DIST = ( TH - TM )*POSNEG
            IF( DIST.LT.0.5D0*TOLX ) TM = TH - POSNEG*0.5D0*TOLX
         END IF
         CALL ERKDEN( N, TM, TOLD, HD, CONT, N, YT, INFO )
         CALL ERKGEV( GFCN, CTX, N, NG, TM, YT, GMID, NGEV, IERR )
         IF( IERR.NE.0 ) RETURN
         CALL ERKBRK( NG, IGDIR, GLO, GMID, JT, BRACK )
         IF( BRACK ) THEN
*           A root in [TL, TM]: TL is kept.
            TH = TM
            DO 40 I = 1, NG
               GHI( I ) = GMID( I )
   40       CONTINUE
            IF( LASTSD.EQ.1 ) WL = 0.5D0*WL
            WH = 1.0D0
            LASTSD = 1
         ELSE
*           None in [TL, TM]: TH is kept.
            TL = TM
            DO 50 I = 1, NG
               GLO( I ) = GMID( I )
   50       CONTINUE
            IF( LASTSD.EQ.2 ) WH = 0.5D0*WH
            WL = 1.0D0
            LASTSD = 2
         END IF
         CALL ERKBRK( NG, IGDIR, GLO, GHI, JROOT, BRACK )
         IF( ABS( TH - TL ).GT.0.5D0*WPREV ) THEN
            NSLOW = NSLOW + 1
         ELSE
            NSLOW = 0
            WPREV = ABS( TH - TL )
         END IF
  100 CONTINUE
*
  200 CONTINUE
      TROOT = TH
      IFOUND = 1
      RETURN
*
*     End of ERKROO
*
      END
*
*  =====================================================================
      RECURSIVE SUBROUTINE ERKBRK( NG, IGDIR, GA, GB, JROOT, BRACK )
      IMPLICIT NONE
      INTEGER            NG
      LOGICAL            BRACK
      INTEGER            IGDIR( NG ), JROOT( NG )
      DOUBLE PRECISION   GA( NG ), GB( NG )
*
*  Purpose
*  =======
*
*  ERKBRK marks the components whose sign change between GA (left) and
*  GB (right) is an event: GA(i) /= 0, GB(i) = 0 or of the other sign,
*  and the direction passes IGDIR(i).  JROOT(i) = +1 (rising), -1
*  (falling) or 0; BRACK is true if any is marked.
*
*  =====================================================================
*
      INTEGER            I, IDIR
*
      BRACK = .FALSE.
      DO 10 I = 1, NG
         JROOT( I ) = 0
         IF( GA( I ).NE.0.0D0 ) THEN
            IF( GA( I ).LT.0.0D0 ) THEN
               IDIR = 1
            ELSE
               IDIR = -1
            END IF
            IF( ( GA( I ).LT.0.0D0 .AND. GB( I ).GE.0.0D0 ) .OR.
     $          ( GA( I ).GT.0.0D0 .AND. GB( I ).LE.0.0D0 ) ) THEN
               IF( IGDIR( I ).EQ.0 .OR. IGDIR( I ).EQ.IDIR ) THEN
                  JROOT( I ) = IDIR
                  BRACK = .TRUE.
               END IF
            END IF
         END IF
   10 CONTINUE
      RETURN
*
*     End of ERKBRK
*
      END
*
*  =====================================================================
      RECURSIVE SUBROUTINE ERKDEN( N, T, TOLD, HD, CONT, LDC, YOUT,
     $                             INFO )
      IMPLICIT NONE
      INTEGER            N, LDC, INFO
      DOUBLE PRECISION   T, TOLD, HD
      DOUBLE PRECISION   CONT( LDC, 8 ), YOUT( * )
*
*  Purpose
*  =======
*
*  ERKDEN evaluates the dense output of the step of ERKDP8 that starts
*  at TOLD with step HD, at T (normally in [TOLD, TOLD + HD]):
*        s = (T - TOLD)/HD,  s1 = 1 - s,
*        YOUT = CONT1 + s (CONT2 + s1 (CONT3 + s (CONT4 + s1 (CONT5
*               + s (CONT6 + s1 (CONT7 + s CONT8)))))).
*
*  Arguments
*  =========
*
*  N       (input) INTEGER, N >= 0: the number of components.
*  T       (input) DOUBLE PRECISION, where to evaluate.
*  TOLD    (input) DOUBLE PRECISION, the start of the step.
*  HD      (input) DOUBLE PRECISION, the step, HD /= 0.
*  CONT    (input) DOUBLE PRECISION array, dimension (LDC,8).
*  LDC     (input) INTEGER, LDC >= max(1,N).
*  YOUT    (output) DOUBLE PRECISION array, dimension (N).
*  INFO    (output) INTEGER.  0: success; -i: argument i illegal.
*
*  =====================================================================
*
      INTEGER            I
      DOUBLE PRECISION   S, S1
      INTRINSIC          MAX
*
      INFO = 0
      IF( N.LT.0 ) THEN
         INFO = -1
      ELSE IF( HD.EQ.0.0D0 ) THEN
         INFO = -4
      ELSE IF( LDC.LT.MAX( 1, N ) ) THEN
         INFO = -6
      END IF
      IF( INFO.NE.0 ) RETURN
      S = ( T - TOLD ) / HD
      S1 = 1.0D0 - S
      DO 10 I = 1, N
         YOUT( I ) = CONT( I, 1 ) + S*( CONT( I, 2 ) + S1*( CONT( I, 3 )
     $               + S*( CONT( I, 4 ) + S1*( CONT( I, 5 )
     $               + S*( CONT( I, 6 ) + S1*( CONT( I, 7 )
     $               + S*CONT( I, 8 ) ) ) ) ) ) )
   10 CONTINUE
      RETURN
*
*     End of ERKDEN
*
      END
*
*  =====================================================================
      RECURSIVE LOGICAL FUNCTION ERKNFI( X )
      IMPLICIT NONE
      DOUBLE PRECISION   X
*
*  Purpose
*  =======
*
*  ERKNFI is true if X is NaN or +-Inf.  Written with quiet
*  comparisons only (X.EQ.X is false only for NaN and raises no
*  exception; |X| > HUGE is asked only of a number), so it raises no
*  floating-point exception.  The IEEE_ARITHMETIC module's
*  IEEE_IS_FINITE would do the same, but a procedure that uses that
*  module saves and restores the floating-point environment on every
*  call (gfortran: _gfortran_ieee_procedure_entry/exit), which made
*  the kernel 7 times slower than its C++ port.
*
*  =====================================================================
*
      INTRINSIC          ABS, HUGE
      ERKNFI = .TRUE.
      IF( X.EQ.X ) ERKNFI = ABS( X ).GT.HUGE( X )
      RETURN
*
*     End of ERKNFI
*
      END
*
*  =====================================================================
      RECURSIVE SUBROUTINE ERKCOE( A, B, C, BH, ER, D )
      IMPLICIT NONE
      DOUBLE PRECISION   A( 16, 16 ), B( 16 ), C( 16 ), BH( 16 ),
     $                   ER( 16 ), D( 4, 16 )
*
*  Purpose
*  =======
*
*  ERKCOE returns the coefficients ERKCOR uses, as arrays: the Butcher
*  tableau A (16 x 16, strictly lower triangular; rows 1..12 the
*  method, 13 = f at the new point, 14..16 the dense-output stages),
*  abscissae C, the 8th-order weights B, the 3rd-order weights BH and
*  the 5th-order error weights ER (each 16, zero beyond stage 12), and
*  the dense-output weights D (rows r = 1..4 give CONT(:, r+4)).  For
*  tests: order conditions, stability boundary, agreement of the C++
*  port's constants.
*
*  =====================================================================
*
      INCLUDE 'explicit_rk_coef.inc'
      INTEGER            I, J
*
      DO 20 J = 1, 16
         B( J ) = 0.0D0
         C( J ) = 0.0D0
         BH( J ) = 0.0D0
         ER( J ) = 0.0D0
         DO 10 I = 1, 16
            A( I, J ) = 0.0D0
   10    CONTINUE
         DO 15 I = 1, 4
            D( I, J ) = 0.0D0
   15    CONTINUE
   20 CONTINUE
      C( 2 ) = C2
      C( 3 ) = C3
      C( 4 ) = C4
      C( 5 ) = C5
      C( 6 ) = C6
      C( 7 ) = C7
      C( 8 ) = C8
      C( 9 ) = C9
      C( 10 ) = C10
      C( 11 ) = C11
      C( 14 ) = C14
      C( 15 ) = C15
      C( 16 ) = C16
      C( 12 ) = 1.0D0
      C( 13 ) = 1.0D0
      A( 2, 1 ) = A2_1
      A( 3, 1 ) = A3_1
      A( 3, 2 ) = A3_2
      A( 4, 1 ) = A4_1
      A( 4, 3 ) = A4_3
      A( 5, 1 ) = A5_1
      A( 5, 3 ) = A5_3
      A( 5, 4 ) = A5_4
      A( 6, 1 ) = A6_1
      A( 6, 4 ) = A6_4
      A( 6, 5 ) = A6_5
      A( 7, 1 ) = A7_1
      A( 7, 4 ) = A7_4
      A( 7, 5 ) = A7_5
      A( 7, 6 ) = A7_6
      A( 8, 1 ) = A8_1
      A( 8, 4 ) = A8_4
      A( 8, 5 ) = A8_5
      A( 8, 6 ) = A8_6
      A( 8, 7 ) = A8_7
      A( 9, 1 ) = A9_1
      A( 9, 4 ) = A9_4
      A( 9, 5 ) = A9_5
      A( 9, 6 ) = A9_6
      A( 9, 7 ) = A9_7
      A( 9, 8 ) = A9_8
      A( 10, 1 ) = A10_1
      A( 10, 4 ) = A10_4
      A( 10, 5 ) = A10_5
      A( 10, 6 ) = A10_6
      A( 10, 7 ) = A10_7
      A( 10, 8 ) = A10_8
      A( 10, 9 ) = A10_9
      A( 11, 1 ) = A11_1
      A( 11, 4 ) = A11_4
      A( 11, 5 ) = A11_5
      A( 11, 6 ) = A11_6
      A( 11, 7 ) = A11_7
      A( 11, 8 ) = A11_8
      A( 11, 9 ) = A11_9
      A( 11, 10 ) = A11_10
      A( 12, 1 ) = A12_1
      A( 12, 4 ) = A12_4
      A( 12, 5 ) = A12_5
      A( 12, 6 ) = A12_6
      A( 12, 7 ) = A12_7
      A( 12, 8 ) = A12_8
      A( 12, 9 ) = A12_9
      A( 12, 10 ) = A12_10
      A( 12, 11 ) = A12_11
      A( 14, 1 ) = A14_1
      A( 14, 7 ) = A14_7
      A( 14, 8 ) = A14_8
      A( 14, 9 ) = A14_9
      A( 14, 10 ) = A14_10
      A( 14, 11 ) = A14_11
      A( 14, 12 ) = A14_12
      A( 14, 13 ) = A14_13
      A( 15, 1 ) = A15_1
      A( 15, 6 ) = A15_6
      A( 15, 7 ) = A15_7
      A( 15, 8 ) = A15_8
      A( 15, 11 ) = A15_11
      A( 15, 12 ) = A15_12
      A( 15, 13 ) = A15_13
      A( 15, 14 ) = A15_14
      A( 16, 1 ) = A16_1
      A( 16, 6 ) = A16_6
      A( 16, 7 ) = A16_7
      A( 16, 8 ) = A16_8
      A( 16, 9 ) = A16_9
      A( 16, 13 ) = A16_13
      A( 16, 14 ) = A16_14
      A( 16, 15 ) = A16_15
      B( 1 ) = B1
      B( 6 ) = B6
      B( 7 ) = B7
      B( 8 ) = B8
      B( 9 ) = B9
      B( 10 ) = B10
      B( 11 ) = B11
      B( 12 ) = B12
      BH( 1 ) = BH1
      BH( 9 ) = BH9
      BH( 12 ) = BH12
      ER( 1 ) = ER1
      ER( 6 ) = ER6
      ER( 7 ) = ER7
      ER( 8 ) = ER8
      ER( 9 ) = ER9
      ER( 10 ) = ER10
      ER( 11 ) = ER11
      ER( 12 ) = ER12
      D( 1, 1 ) = D4_1
      D( 1, 6 ) = D4_6
      D( 1, 7 ) = D4_7
      D( 1, 8 ) = D4_8
      D( 1, 9 ) = D4_9
      D( 1, 10 ) = D4_10
      D( 1, 11 ) = D4_11
      D( 1, 12 ) = D4_12
      D( 1, 13 ) = D4_13
      D( 1, 14 ) = D4_14
      D( 1, 15 ) = D4_15
      D( 1, 16 ) = D4_16
      D( 2, 1 ) = D5_1
      D( 2, 6 ) = D5_6
      D( 2, 7 ) = D5_7
      D( 2, 8 ) = D5_8
      D( 2, 9 ) = D5_9
      D( 2, 10 ) = D5_10
      D( 2, 11 ) = D5_11
      D( 2, 12 ) = D5_12
      D( 2, 13 ) = D5_13
      D( 2, 14 ) = D5_14
      D( 2, 15 ) = D5_15
      D( 2, 16 ) = D5_16
      D( 3, 1 ) = D6_1
      D( 3, 6 ) = D6_6
      D( 3, 7 ) = D6_7
      D( 3, 8 ) = D6_8
      D( 3, 9 ) = D6_9
      D( 3, 10 ) = D6_10
      D( 3, 11 ) = D6_11
      D( 3, 12 ) = D6_12
      D( 3, 13 ) = D6_13
      D( 3, 14 ) = D6_14
      D( 3, 15 ) = D6_15
      D( 3, 16 ) = D6_16
      D( 4, 1 ) = D7_1
      D( 4, 6 ) = D7_6
      D( 4, 7 ) = D7_7
      D( 4, 8 ) = D7_8
      D( 4, 9 ) = D7_9
      D( 4, 10 ) = D7_10
      D( 4, 11 ) = D7_11
      D( 4, 12 ) = D7_12
      D( 4, 13 ) = D7_13
      D( 4, 14 ) = D7_14
      D( 4, 15 ) = D7_15
      D( 4, 16 ) = D7_16
      RETURN
*
*     End of ERKCOE
*
      END
