*> \brief PCHUAN solves A x = b, A m-by-n of any shape and rank, by
*> the (modified) Huang algorithm of the ABS class; it returns the
*> solution nearest to a start vector, the orthogonal projector onto
*> null(A), the rank and the linearly dependent rows.
*
*  Part of pcsim. Written from the mathematics of the ABS class
*  (Abaffy, Broyden, Spedicato; Bodon 1990 for the re-projection).
*
      RECURSIVE SUBROUTINE PCHUAN( METH, M, N, A, LDA, B, X, TOL, H,
     $                   LDH, RANK,
     $                   IDEP, WORK, LWORK, INFO )
*
*     .. Scalar Arguments ..
      INTEGER            INFO, LDA, LDH, LWORK, M, METH, N, RANK
      DOUBLE PRECISION   TOL
*     ..
*     .. Array Arguments ..
      INTEGER            IDEP( * )
      DOUBLE PRECISION   A( LDA, * ), B( * ), H( LDH, * ), WORK( * ),
     $                   X( * )
*     ..
*
*  Purpose
*  =======
*
*  PCHUAN computes the solution of the linear system A x = b that is
*  nearest (Euclidean norm) to a given start vector x1, where A is a
*  general M-by-N matrix of any rank, M < N, M = N and M > N allowed.
*  With x1 = 0 this is the minimum-norm solution.  It also returns the
*  orthogonal projector H onto null(A), the rank of A, and for each
*  row whether it is linearly independent of the rows before it.
*  An inconsistent system is detected and reported, not solved.
*
*  Mathematics
*  ===========
*
*  Huang's method is the ABS algorithm with H_1 = I and z_i = w_i = a_i
*  (a_i is row i of A as a column vector).  For i = 1, ..., M:
*
*     u_i = H_i a_i
*     if ||u_i|| <= TOL * ||a_i||, row i is linearly dependent on rows
*        1..i-1 (it lies, to the tolerance, in their span).  It is then
*        consistent if
*           |a_i' x_i - b_i| <= TOL * (G_i ||a_i|| ||x_i|| + |b_i|)
*        and skipped (H_{i+1} = H_i, x_{i+1} = x_i); otherwise the
*        system is inconsistent and the routine returns INFO = i.
*        G_i = 1 + sum over the independent rows k < i of
*        ||a_k|| / |a_k' q_k| = 1 + sum 1/sin(angle between a_k and the
*        span of the rows before it): a running estimate of how much
*        the rounding errors of the earlier steps are amplified in x_i
*        (each step divides a residual by a_k' q_k).  Without it, a
*        consistent system whose leading rows are ill conditioned (a
*        tall Vandermonde fit) would be declared inconsistent because
*        of rounding alone.
*     else
*        p_i = H_i u_i = H_i (H_i a_i)   (modified Huang, METH = 0, 1)
*        p_i = u_i     = H_i a_i         (plain Huang, METH = 2)
*        q_i = p_i / ||p_i||
*        x_{i+1} = x_i - (a_i' x_i - b_i) / (a_i' q_i) * q_i
*        H_{i+1} = H_i - q_i q_i'
*
*  In exact arithmetic the p_i are mutually orthogonal, H_{i+1} is the
*  orthogonal projector onto the orthogonal complement of span(a_1..
*  a_i), every x_{i+1} solves rows 1..i and x_{i+1} - x1 lies in the
*  span of those rows; so the final x is x1 - pinv(A) (A x1 - b), the
*  solution nearest to x1, and H = I - pinv(A) A.  (With q = u/||u||
*  the plain update is Huang's H - H a a' H / (a' H a) for symmetric
*  H.)  In floating point the computed H_i stays exactly symmetric but
*  drifts away from a projector (H_i**2 /= H_i; the p_i lose
*  orthogonality) when A is ill conditioned; applying H_i a second
*  time (re-projection) restores orthogonality to working precision,
*  which is why METH = 0 (modified Huang) is the default.  Measured:
*  ||H**2 - H|| is 2E+1 for plain and 8E-16 for modified Huang on the
*  leading 11 rows of the 12-by-12 Hilbert matrix (docs/huang.md).
*
*  Arguments
*  =========
*
*  METH    (input) INTEGER
*          = 0 or 1: modified Huang, p_i = H_i (H_i a_i) (default);
*          = 2:      plain Huang, p_i = H_i a_i (kept for comparison).
*
*  M       (input) INTEGER
*          The number of rows of A (equations).  M >= 0.
*
*  N       (input) INTEGER
*          The number of columns of A (unknowns).  N >= 0.
*
*  A       (input) DOUBLE PRECISION array, dimension (LDA,N)
*          The M-by-N coefficient matrix.  Not modified.
*
*  LDA     (input) INTEGER
*          The leading dimension of A.  LDA >= max(1,M).
*
*  B       (input) DOUBLE PRECISION array, dimension (M)
*          The right-hand side b.  Not modified.
*
*  X       (input/output) DOUBLE PRECISION array, dimension (N)
*          On entry, the start vector x1.  On exit with INFO = 0, the
*          solution of A x = b nearest to x1 (the minimum-norm solution
*          if x1 = 0).  On exit with INFO > 0, the solution of rows
*          1..INFO-1 nearest to x1 (it does not solve row INFO).
*
*  TOL     (input) DOUBLE PRECISION
*          Relative linear-dependence tolerance, TOL < 1.  Row i is
*          taken as dependent on the rows before it when
*          ||H_i a_i|| <= TOL*||a_i||, i.e. when the sine of the angle
*          between a_i and the span of the previous rows is <= TOL;
*          the test is invariant under scaling of row i.  The same TOL,
*          relative to G_i ||a_i|| ||x_i|| + |b_i| (see Mathematics),
*          decides the consistency of a dependent row.
*          If TOL <= 0, the default TOL = 100 * max(M,N) * EPS is used,
*          EPS = DLAMCH('P') = 2**(-52): a small multiple of the
*          rounding error of a product H_i a_i of length max(M,N).
*
*  H       (output) DOUBLE PRECISION array, dimension (LDH,N)
*          On exit, the N-by-N orthogonal projector onto null(A) (of
*          rows 1..INFO-1 if INFO > 0).  Stored in full and exactly
*          symmetric (each update subtracts the same product q_j*q_k
*          from H(j,k) and H(k,j)).
*
*  LDH     (input) INTEGER
*          The leading dimension of H.  LDH >= max(1,N).
*
*  RANK    (output) INTEGER
*          The number of independent rows found, the numerical rank
*          of A (of rows 1..INFO-1 if INFO > 0).  H has rank N - RANK.
*          RANK <= min(M,N): when RANK reaches N, H is set to zero.
*
*  IDEP    (output) INTEGER array, dimension (M)
*          IDEP(i) = 0: row i is independent of rows 1..i-1;
*                  = 1: row i depends on rows 1..i-1, consistently;
*                  = 2: row i depends on rows 1..i-1, inconsistently
*                       (only for i = INFO > 0);
*                  = -1: row i was not examined (i > INFO > 0).
*
*  WORK    (workspace/output) DOUBLE PRECISION array, dimension (LWORK)
*          On exit, if LWORK = -1, WORK(1) returns the minimal LWORK.
*
*  LWORK   (input) INTEGER
*          The dimension of WORK.  LWORK >= max(1,2*N).
*          If LWORK = -1, a workspace query is assumed: the routine
*          only returns max(1,2*N) in WORK(1) (after checking the other
*          arguments) and touches nothing else.
*
*  INFO    (output) INTEGER
*          = 0:  successful exit;
*          < 0:  if INFO = -i, the i-th argument had an illegal value
*                (the first one found, in argument order):
*                -1 METH not in {0,1,2}; -2 M < 0; -3 N < 0;
*                -5 LDA < max(1,M); -8 TOL is NaN or TOL >= 1;
*                -10 LDH < max(1,N); -14 LWORK too small and not -1;
*          > 0:  if INFO = i, row i is linearly dependent on rows
*                1..i-1 but inconsistent with them: A x = b has no
*                solution.  X, H, RANK, IDEP describe rows 1..i-1.
*
*  Further Details
*  ===============
*
*  Rows are processed in their natural order 1..M, so "dependent" means
*  dependent on earlier rows: of two proportional rows, the later one
*  is flagged.  Work per row: two (modified) or one (plain) products
*  with the N-by-N H plus a rank-one update, 3*N**2 + O(N) flops per
*  independent row, in all about 3*M*N**2 flops.  Norms are computed
*  as amax * sqrt(sum((v_k/amax)**2)) (see PCHNRM) so badly scaled rows
*  neither overflow nor underflow.  WORK(1:N) holds u_i, WORK(N+1:2N)
*  holds p_i.  No COMMON, no SAVE, no I/O, and RECURSIVE (locals on
*  the stack): the routine is re-entrant and thread-safe.
*
*  =====================================================================
*
*     .. Parameters ..
      DOUBLE PRECISION   ZERO, ONE, HUNDRD
      PARAMETER          ( ZERO = 0.0D+0, ONE = 1.0D+0,
     $                   HUNDRD = 100.0D+0 )
*     ..
*     .. Local Scalars ..
      LOGICAL            MODIF
      INTEGER            I, J, K, MINWRK
      DOUBLE PRECISION   ALPHA, ANRM, C, GROW, PNRM, R, STEP, TOLD,
     $                   UNRM, XNRM
*     ..
*     .. External Functions ..
      DOUBLE PRECISION   DLAMCH, PCHNRM
      EXTERNAL           DLAMCH, PCHNRM
*     ..
*     .. Intrinsic Functions ..
      INTRINSIC          ABS, DBLE, MAX
*     ..
*     .. Executable Statements ..
*
*     Test the input arguments.
*
      INFO = 0
      MINWRK = MAX( 1, 2*N )
      IF( METH.LT.0 .OR. METH.GT.2 ) THEN
         INFO = -1
      ELSE IF( M.LT.0 ) THEN
         INFO = -2
      ELSE IF( N.LT.0 ) THEN
         INFO = -3
      ELSE IF( LDA.LT.MAX( 1, M ) ) THEN
         INFO = -5
      ELSE IF( TOL.NE.TOL .OR. TOL.GE.ONE ) THEN
         INFO = -8
      ELSE IF( LDH.LT.MAX( 1, N ) ) THEN
         INFO = -10
      ELSE IF( LWORK.LT.MINWRK .AND. LWORK.NE.-1 ) THEN
         INFO = -14
      END IF
      IF( INFO.NE.0 )
     $   RETURN
      IF( LWORK.EQ.-1 ) THEN
         WORK( 1 ) = DBLE( MINWRK )
         RETURN
      END IF
*
      MODIF = METH.NE.2
      TOLD = TOL
      IF( TOLD.LE.ZERO )
     $   TOLD = HUNDRD*DBLE( MAX( M, N ) )*DLAMCH( 'P' )
*
*     H_1 = I, x_1 = X (the start vector), no row examined yet.
*
      DO 20 K = 1, N
         DO 10 J = 1, N
            H( J, K ) = ZERO
   10    CONTINUE
         H( K, K ) = ONE
   20 CONTINUE
      DO 30 I = 1, M
         IDEP( I ) = -1
   30 CONTINUE
      RANK = 0
      GROW = ONE
*
      DO 200 I = 1, M
*
*        u = H a_i into WORK(1:N), column by column of H.
*
         DO 40 J = 1, N
            WORK( J ) = ZERO
   40    CONTINUE
         DO 60 K = 1, N
            C = A( I, K )
            DO 50 J = 1, N
               WORK( J ) = WORK( J ) + H( J, K )*C
   50       CONTINUE
   60    CONTINUE
         ANRM = PCHNRM( N, A( I, 1 ), LDA )
         UNRM = PCHNRM( N, WORK, 1 )
*
*        Residual of row i at the current iterate.
*
         R = ZERO
         DO 70 K = 1, N
            R = R + A( I, K )*X( K )
   70    CONTINUE
         R = R - B( I )
*
         IF( UNRM.LE.TOLD*ANRM )
     $      GO TO 160
*
*        Search direction p into WORK(N+1:2N): H u (modified) or u.
*
         IF( MODIF ) THEN
            DO 80 J = 1, N
               WORK( N+J ) = ZERO
   80       CONTINUE
            DO 100 K = 1, N
               C = WORK( K )
               DO 90 J = 1, N
                  WORK( N+J ) = WORK( N+J ) + H( J, K )*C
   90          CONTINUE
  100       CONTINUE
         ELSE
            DO 110 J = 1, N
               WORK( N+J ) = WORK( J )
  110       CONTINUE
         END IF
*
*        q = p / ||p||, alpha = a_i' q.
*
*        (p = 0 or alpha = 0 cannot happen for u /= 0 in exact
*        arithmetic; if rounding produces it, row i is treated as
*        dependent rather than dividing by zero.)
*
         PNRM = PCHNRM( N, WORK( N+1 ), 1 )
         IF( PNRM.EQ.ZERO )
     $      GO TO 160
         ALPHA = ZERO
         DO 120 J = 1, N
            WORK( N+J ) = WORK( N+J ) / PNRM
            ALPHA = ALPHA + A( I, J )*WORK( N+J )
  120    CONTINUE
         IF( ALPHA.EQ.ZERO )
     $      GO TO 160
*
*        x <- x - (r / alpha) q.
*
         STEP = R / ALPHA
         DO 130 J = 1, N
            X( J ) = X( J ) - STEP*WORK( N+J )
  130    CONTINUE
*
*        H <- H - q q' (the same product for H(j,k) and H(k,j)).
*
         DO 150 K = 1, N
            DO 140 J = 1, N
               H( J, K ) = H( J, K ) - WORK( N+J )*WORK( N+K )
  140       CONTINUE
  150    CONTINUE
         GROW = GROW + ANRM / ABS( ALPHA )
         RANK = RANK + 1
         IDEP( I ) = 0
*
*        N independent rows: null(A) = {0}, so H = 0 exactly (rounding
*        would leave a residue of order EPS that could let a later row
*        pass the dependence test and give RANK > N).
*
         IF( RANK.EQ.N ) THEN
            DO 158 K = 1, N
               DO 156 J = 1, N
                  H( J, K ) = ZERO
  156          CONTINUE
  158       CONTINUE
         END IF
         GO TO 200
*
*        Row i depends on rows 1..i-1: consistent or not.
*
  160    CONTINUE
         XNRM = PCHNRM( N, X, 1 )
         IF( ABS( R ).GT.TOLD*( GROW*ANRM*XNRM+ABS( B( I ) ) ) ) THEN
            IDEP( I ) = 2
            INFO = I
            RETURN
         END IF
         IDEP( I ) = 1
  200 CONTINUE
      RETURN
*
*     End of PCHUAN
*
      END
*
*> \brief PCHNUL extracts an orthonormal basis D of null(A) from the
*> projector H = I - pinv(A) A returned by PCHUAN.
*
      RECURSIVE SUBROUTINE PCHNUL( N, RANK, H, LDH, D, LDD, WORK, LWORK,
     $                             INFO )
*
*     .. Scalar Arguments ..
      INTEGER            INFO, LDD, LDH, LWORK, N, RANK
*     ..
*     .. Array Arguments ..
      DOUBLE PRECISION   D( LDD, * ), H( LDH, * ), WORK( * )
*     ..
*
*  Purpose
*  =======
*
*  PCHNUL computes an N-by-(N-RANK) matrix D with orthonormal columns
*  spanning the range of the orthogonal projector H, i.e. null(A) when
*  H and RANK come from PCHUAN.  The choice of D is deterministic: it
*  is a Gram-Schmidt orthonormalization of selected columns of H, in
*  the order fixed by the pivoting rule below.
*
*  Mathematics
*  ===========
*
*  Let W = H.  For k = 1, ..., N-RANK:
*     w_j = ||W(:,j)|| for every column j, wmax = max_j w_j;
*     if wmax < 1/(2 sqrt(N)), fail with INFO = k (see below);
*     j_k = the FIRST (smallest) j with w_j >= wmax/2;
*     d = W(:,j_k) / w_j_k, re-orthogonalized once against D(:,1:k-1)
*         and normalized again; D(:,k) = d;
*     W <- W - d (d' W)  (project d out of every column), W(:,j_k) = 0.
*  This is QR with relaxed column pivoting of H.  Since the columns of
*  H are H e_j, D(:,k) is the normalized component of the unit vector
*  e_j_k in null(A) orthogonal to D(:,1:k-1): the basis prefers the
*  lowest-numbered coordinates that can move freely.  The relaxed rule
*  (first column within a factor 2 of the largest, instead of the
*  largest) makes the choice insensitive to rounding-level differences
*  between columns of equal norm, which are common for structured A,
*  so two implementations of this routine pick the same columns.
*  Why 1/(2 sqrt(N)): after k-1 steps W is (to rounding) a projector of
*  rank N-RANK-k+1 >= 1, whose squared column norms are its diagonal
*  entries and sum to its trace >= 1, so wmax >= 1/sqrt(N).
*
*  Arguments
*  =========
*
*  N       (input) INTEGER
*          The order of H.  N >= 0.
*
*  RANK    (input) INTEGER
*          The rank of A; D gets N-RANK columns.  0 <= RANK <= N.
*
*  H       (input) DOUBLE PRECISION array, dimension (LDH,N)
*          The N-by-N orthogonal projector onto null(A).  Not modified.
*
*  LDH     (input) INTEGER
*          The leading dimension of H.  LDH >= max(1,N).
*
*  D       (output) DOUBLE PRECISION array, dimension (LDD,N-RANK)
*          On exit with INFO = 0, orthonormal columns spanning range(H).
*          Not referenced if RANK = N.
*
*  LDD     (input) INTEGER
*          The leading dimension of D.  LDD >= max(1,N).
*
*  WORK    (workspace/output) DOUBLE PRECISION array, dimension (LWORK)
*          On exit, if LWORK = -1, WORK(1) returns the minimal LWORK.
*
*  LWORK   (input) INTEGER
*          The dimension of WORK.  LWORK >= max(1,N*N+N).
*          If LWORK = -1, a workspace query is assumed: the routine
*          only returns max(1,N*N+N) in WORK(1) (after checking the
*          other arguments).
*
*  INFO    (output) INTEGER
*          = 0:  successful exit;
*          < 0:  if INFO = -i, the i-th argument had an illegal value
*                (the first one found, in argument order):
*                -1 N < 0; -2 RANK < 0 or RANK > N; -4 LDH < max(1,N);
*                -6 LDD < max(1,N); -8 LWORK too small and not -1;
*          > 0:  if INFO = k, column k of D could not be formed: after
*                k-1 columns, no column of the projected H had norm
*                >= 1/(2 sqrt(N)), so H is not an orthogonal projector
*                of rank >= N-RANK (wrong H, or RANK too small).
*                D(:,1:k-1) are valid orthonormal columns.
*
*  Further Details
*  ===============
*
*  WORK(1:N*N) holds W (column-major, leading dimension N) and
*  WORK(N*N+1:N*N+N) the column norms.  About 2*N**2*(N-RANK) flops
*  for the projections plus N**2 per step for the norms.  No COMMON,
*  no SAVE, no I/O: the routine is re-entrant.
*
*  =====================================================================
*
*     .. Parameters ..
      DOUBLE PRECISION   ZERO, ONE, HALF
      PARAMETER          ( ZERO = 0.0D+0, ONE = 1.0D+0, HALF = 0.5D+0 )
*     ..
*     .. Local Scalars ..
      INTEGER            IW, J, JK, K, L, MINWRK, NN
      DOUBLE PRECISION   C, DNRM, WMAX
*     ..
*     .. External Functions ..
      DOUBLE PRECISION   PCHNRM
      EXTERNAL           PCHNRM
*     ..
*     .. Intrinsic Functions ..
      INTRINSIC          DBLE, MAX, SQRT
*     ..
*     .. Executable Statements ..
*
      INFO = 0
      MINWRK = MAX( 1, N*N+N )
      IF( N.LT.0 ) THEN
         INFO = -1
      ELSE IF( RANK.LT.0 .OR. RANK.GT.N ) THEN
         INFO = -2
      ELSE IF( LDH.LT.MAX( 1, N ) ) THEN
         INFO = -4
      ELSE IF( LDD.LT.MAX( 1, N ) ) THEN
         INFO = -6
      ELSE IF( LWORK.LT.MINWRK .AND. LWORK.NE.-1 ) THEN
         INFO = -8
      END IF
      IF( INFO.NE.0 )
     $   RETURN
      IF( LWORK.EQ.-1 ) THEN
         WORK( 1 ) = DBLE( MINWRK )
         RETURN
      END IF
      IF( RANK.EQ.N )
     $   RETURN
*
*     W = H in WORK(1:N*N); column j of W starts at WORK(IW(j)),
*     IW(j) = (j-1)*N + 1.  Norms in WORK(NN+1:NN+N).
*
      NN = N*N
      DO 20 J = 1, N
         IW = ( J-1 )*N
         DO 10 L = 1, N
            WORK( IW+L ) = H( L, J )
   10    CONTINUE
   20 CONTINUE
*
      DO 200 K = 1, N - RANK
*
*        Column norms of W and the relaxed pivot.
*
         WMAX = ZERO
         DO 30 J = 1, N
            WORK( NN+J ) = PCHNRM( N, WORK( ( J-1 )*N+1 ), 1 )
            IF( WORK( NN+J ).GT.WMAX )
     $         WMAX = WORK( NN+J )
   30    CONTINUE
         IF( WMAX.LT.HALF / SQRT( DBLE( N ) ) ) THEN
            INFO = K
            RETURN
         END IF
         JK = 0
         DO 40 J = N, 1, -1
            IF( WORK( NN+J ).GE.HALF*WMAX )
     $         JK = J
   40    CONTINUE
*
*        d = W(:,jk) / ||W(:,jk)||, re-orthogonalized against
*        D(:,1:k-1) (one pass: "twice is enough"), normalized again.
*
         IW = ( JK-1 )*N
         DO 50 L = 1, N
            D( L, K ) = WORK( IW+L ) / WORK( NN+JK )
   50    CONTINUE
         DO 80 J = 1, K - 1
            C = ZERO
            DO 60 L = 1, N
               C = C + D( L, J )*D( L, K )
   60       CONTINUE
            DO 70 L = 1, N
               D( L, K ) = D( L, K ) - C*D( L, J )
   70       CONTINUE
   80    CONTINUE
         DNRM = PCHNRM( N, D( 1, K ), 1 )
         DO 90 L = 1, N
            D( L, K ) = D( L, K ) / DNRM
   90    CONTINUE
*
*        W <- W - d (d' W); the pivot column is set to zero exactly.
*
         DO 120 J = 1, N
            IW = ( J-1 )*N
            IF( J.EQ.JK ) THEN
               DO 100 L = 1, N
                  WORK( IW+L ) = ZERO
  100          CONTINUE
            ELSE
               C = ZERO
               DO 105 L = 1, N
                  C = C + D( L, K )*WORK( IW+L )
  105          CONTINUE
               DO 110 L = 1, N
                  WORK( IW+L ) = WORK( IW+L ) - C*D( L, K )
  110          CONTINUE
            END IF
  120    CONTINUE
  200 CONTINUE
      RETURN
*
*     End of PCHNUL
*
      END
*
*> \brief PCHNRM returns the Euclidean norm of a strided vector without
*> overflow or destructive underflow.
*
      RECURSIVE DOUBLE PRECISION FUNCTION PCHNRM( N, V, INCV )
*
*     .. Scalar Arguments ..
      INTEGER            INCV, N
*     ..
*     .. Array Arguments ..
      DOUBLE PRECISION   V( * )
*     ..
*
*  Purpose
*  =======
*
*  PCHNRM = ||v||_2 for v = (V(1), V(1+INCV), ..., V(1+(N-1)*INCV)),
*  computed as amax * sqrt( sum_k (v_k/amax)**2 ), amax = max_k |v_k|,
*  in this order (two passes), so that the C++ port of pcsim can
*  reproduce it operation for operation.  Returns 0 if N <= 0 or v = 0.
*
*  Arguments
*  =========
*
*  N       (input) INTEGER
*          The number of elements of v.
*
*  V       (input) DOUBLE PRECISION array, dimension (1+(N-1)*INCV)
*          The vector.
*
*  INCV    (input) INTEGER
*          The stride between elements of v.  INCV >= 1.
*
*  =====================================================================
*
*     .. Parameters ..
      DOUBLE PRECISION   ZERO
      PARAMETER          ( ZERO = 0.0D+0 )
*     ..
*     .. Local Scalars ..
      INTEGER            K
      DOUBLE PRECISION   AMAX, S, T
*     ..
*     .. Intrinsic Functions ..
      INTRINSIC          ABS, SQRT
*     ..
*     .. Executable Statements ..
*
      AMAX = ZERO
      DO 10 K = 1, N
         IF( ABS( V( 1+( K-1 )*INCV ) ).GT.AMAX )
     $      AMAX = ABS( V( 1+( K-1 )*INCV ) )
   10 CONTINUE
      IF( AMAX.EQ.ZERO ) THEN
         PCHNRM = ZERO
         RETURN
      END IF
      S = ZERO
      DO 20 K = 1, N
         T = V( 1+( K-1 )*INCV ) / AMAX
         S = S + T*T
   20 CONTINUE
      PCHNRM = AMAX*SQRT( S )
      RETURN
*
*     End of PCHNRM
*
      END
