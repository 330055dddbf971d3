*> \file radau_lu.f
*> Small dense LU factorizations with partial pivoting, real and
*> complex (real and imaginary parts stored apart), that skip the work
*> zeros make unnecessary.  Written for pcsim's Radau IIA kernel, whose
*> iteration matrices E1 = (gam/h) K - J and E2 = ((alp+i bet)/h) K - J
*> are small and mostly zero (Andrews' squeezer: 85 of 729 entries).
*> For such matrices an unblocked elimination that skips zero
*> multipliers and zero pivot-row entries is several times faster than
*> DGETRF/ZGETRF, whose blocking and BLAS calls only pay off for large
*> dense matrices (see docs/radau.md "Linear algebra").
*>
*> Routines: RADLUD (real factor), RADLUS (real solve),
*>           RADLZD (complex factor), RADLZS (complex solve).
*
*  =====================================================================
      RECURSIVE SUBROUTINE RADLUD( N, A, LDA, IPIV, IWL, INFO )
      IMPLICIT NONE
      INTEGER            N, LDA, INFO
      INTEGER            IPIV( * ), IWL( * )
      DOUBLE PRECISION   A( LDA, * )
*
*  Purpose
*  =======
*
*  RADLUD computes P A = L U by Gaussian elimination with partial
*  (row) pivoting: L unit lower triangular, U upper triangular, both
*  stored in A, except that the diagonal holds 1/u(k,k) (the solves
*  multiply instead of divide); row k was interchanged with row
*  IPIV(k) (LAPACK's convention, interchanges applied to whole rows).
*
*  Mathematics: at step k the pivot is the first entry of largest
*  modulus in A(k:n,k); after the interchange the multipliers are
*  l(i,k) = a(i,k)/a(k,k), and a(i,j) := a(i,j) - l(i,k) a(k,j) for
*  i, j > k.  Rows with l(i,k) = 0 and columns with a(k,j) = 0 are
*  skipped (their update is exactly zero), which is where a sparse
*  matrix saves its work.
*
*  Arguments
*  =========
*
*  N       (input) INTEGER, the order, N >= 0.
*  A       (input/output) DOUBLE PRECISION array (LDA,N): on entry the
*          matrix, on exit its L and U factors.
*  LDA     (input) INTEGER, LDA >= max(1,N).
*  IPIV    (output) INTEGER array (N), the pivot rows.
*  IWL     (workspace) INTEGER array (N): the rows with nonzero
*          multipliers of the current column.
*  INFO    (output) INTEGER.  0: success; k > 0: the pivot of column k
*          is exactly zero (A is singular); the factorization stopped
*          there and must not be used.
*
*  =====================================================================
*
      INTEGER            I, J, K, P, NL, L
      DOUBLE PRECISION   AMAX, PIV, U, T
      INTRINSIC          ABS
*
      INFO = 0
      DO 60 K = 1, N
         P = K
         AMAX = ABS( A( K, K ) )
         DO 10 I = K + 1, N
            IF( ABS( A( I, K ) ).GT.AMAX ) THEN
               AMAX = ABS( A( I, K ) )
               P = I
            END IF
   10    CONTINUE
         IPIV( K ) = P
         IF( AMAX.EQ.0.0D0 ) THEN
            INFO = K
            RETURN
         END IF
         IF( P.NE.K ) THEN
            DO 20 J = 1, N
               T = A( K, J )
               A( K, J ) = A( P, J )
               A( P, J ) = T
   20       CONTINUE
         END IF
         PIV = A( K, K )
         A( K, K ) = 1.0D0 / PIV
         NL = 0
         DO 30 I = K + 1, N
            IF( A( I, K ).NE.0.0D0 ) THEN
               A( I, K ) = A( I, K ) / PIV
               NL = NL + 1
               IWL( NL ) = I
            END IF
   30    CONTINUE
         IF( NL.EQ.0 ) GO TO 60
         DO 50 J = K + 1, N
            U = A( K, J )
            IF( U.NE.0.0D0 ) THEN
               DO 40 L = 1, NL
                  I = IWL( L )
                  A( I, J ) = A( I, J ) - A( I, K )*U
   40          CONTINUE
            END IF
   50    CONTINUE
   60 CONTINUE
      RETURN
*
*     End of RADLUD
*
      END
*
*  =====================================================================
      RECURSIVE SUBROUTINE RADLUS( N, A, LDA, IPIV, B )
      IMPLICIT NONE
      INTEGER            N, LDA
      INTEGER            IPIV( * )
      DOUBLE PRECISION   A( LDA, * ), B( * )
*
*  Purpose
*  =======
*
*  RADLUS solves A x = b with the factors of RADLUD, in place:
*  b := P b, then L y = b (forward), then U x = y (backward), column
*  by column, skipping the columns whose current entry is zero.
*
*  Arguments
*  =========
*
*  N       (input) INTEGER, the order.
*  A       (input) DOUBLE PRECISION array (LDA,N), factors from RADLUD.
*  LDA     (input) INTEGER, LDA >= max(1,N).
*  IPIV    (input) INTEGER array (N), pivots from RADLUD.
*  B       (input/output) DOUBLE PRECISION array (N): b on entry, x on
*          exit.
*
*  =====================================================================
*
      INTEGER            I, K, P
      DOUBLE PRECISION   T
*
      DO 10 K = 1, N
         P = IPIV( K )
         IF( P.NE.K ) THEN
            T = B( K )
            B( K ) = B( P )
            B( P ) = T
         END IF
   10 CONTINUE
      DO 30 K = 1, N
         T = B( K )
         IF( T.NE.0.0D0 ) THEN
            DO 20 I = K + 1, N
               B( I ) = B( I ) - A( I, K )*T
   20       CONTINUE
         END IF
   30 CONTINUE
      DO 50 K = N, 1, -1
         IF( B( K ).NE.0.0D0 ) THEN
            B( K ) = B( K )*A( K, K )
            T = B( K )
            DO 40 I = 1, K - 1
               B( I ) = B( I ) - A( I, K )*T
   40       CONTINUE
         END IF
   50 CONTINUE
      RETURN
*
*     End of RADLUS
*
      END
*
*  =====================================================================
      RECURSIVE SUBROUTINE RADLZD( N, AR, AI, LDA, IPIV, IWL, INFO )
      IMPLICIT NONE
      INTEGER            N, LDA, INFO
      INTEGER            IPIV( * ), IWL( * )
      DOUBLE PRECISION   AR( LDA, * ), AI( LDA, * )
*
*  Purpose
*  =======
*
*  RADLZD is RADLUD for the complex matrix A = AR + i AI, its real and
*  imaginary parts stored in two real arrays (the diagonal holding
*  1/u(k,k), as in RADLUD).  Every complex operation
*  is written out in real arithmetic (so the C++ port rounds exactly
*  alike); the pivot is the first entry of largest |re| + |im| in
*  A(k:n,k); the reciprocal of the pivot is formed by Smith's
*  algorithm (no overflow for large or small pivots) and multiplies
*  the column.  Zero multipliers and zero pivot-row entries are
*  skipped as in RADLUD.
*
*  Arguments
*  =========
*
*  N       (input) INTEGER, the order.
*  AR, AI  (input/output) DOUBLE PRECISION arrays (LDA,N): the real
*          and imaginary parts of A on entry, of its L and U factors on
*          exit.
*  LDA     (input) INTEGER, LDA >= max(1,N).
*  IPIV    (output) INTEGER array (N), the pivot rows.
*  IWL     (workspace) INTEGER array (N).
*  INFO    (output) INTEGER.  0: success; k > 0: zero pivot in column
*          k (A singular), factorization stopped.
*
*  =====================================================================
*
      INTEGER            I, J, K, P, NL, L
      DOUBLE PRECISION   AMAX, S, RR, RI, Q, D, UR, UI, TR, TI, XR, XI
      INTRINSIC          ABS
*
      INFO = 0
      DO 60 K = 1, N
         P = K
         AMAX = ABS( AR( K, K ) ) + ABS( AI( K, K ) )
         DO 10 I = K + 1, N
            S = ABS( AR( I, K ) ) + ABS( AI( I, K ) )
            IF( S.GT.AMAX ) THEN
               AMAX = S
               P = I
            END IF
   10    CONTINUE
         IPIV( K ) = P
         IF( AMAX.EQ.0.0D0 ) THEN
            INFO = K
            RETURN
         END IF
         IF( P.NE.K ) THEN
            DO 20 J = 1, N
               TR = AR( K, J )
               AR( K, J ) = AR( P, J )
               AR( P, J ) = TR
               TI = AI( K, J )
               AI( K, J ) = AI( P, J )
               AI( P, J ) = TI
   20       CONTINUE
         END IF
*        (RR + i RI) = 1 / (AR(K,K) + i AI(K,K)), Smith's algorithm.
         IF( ABS( AR( K, K ) ).GE.ABS( AI( K, K ) ) ) THEN
            Q = AI( K, K ) / AR( K, K )
            D = AR( K, K ) + AI( K, K )*Q
            RR = 1.0D0 / D
            RI = -Q / D
         ELSE
            Q = AR( K, K ) / AI( K, K )
            D = AI( K, K ) + AR( K, K )*Q
            RR = Q / D
            RI = -1.0D0 / D
         END IF
         AR( K, K ) = RR
         AI( K, K ) = RI
         NL = 0
         DO 30 I = K + 1, N
            IF( AR( I, K ).NE.0.0D0 .OR. AI( I, K ).NE.0.0D0 ) THEN
               XR = AR( I, K )
               XI = AI( I, K )
               AR( I, K ) = XR*RR - XI*RI
               AI( I, K ) = XR*RI + XI*RR
               NL = NL + 1
               IWL( NL ) = I
            END IF
   30    CONTINUE
         IF( NL.EQ.0 ) GO TO 60
         DO 50 J = K + 1, N
            UR = AR( K, J )
            UI = AI( K, J )
            IF( UR.NE.0.0D0 .OR. UI.NE.0.0D0 ) THEN
               DO 40 L = 1, NL
                  I = IWL( L )
                  AR( I, J ) = AR( I, J ) - ( AR( I, K )*UR
     $                         - AI( I, K )*UI )
                  AI( I, J ) = AI( I, J ) - ( AR( I, K )*UI
     $                         + AI( I, K )*UR )
   40          CONTINUE
            END IF
   50    CONTINUE
   60 CONTINUE
      RETURN
*
*     End of RADLZD
*
      END
*
*  =====================================================================
      RECURSIVE SUBROUTINE RADLZS( N, AR, AI, LDA, IPIV, BR, BI )
      IMPLICIT NONE
      INTEGER            N, LDA
      INTEGER            IPIV( * )
      DOUBLE PRECISION   AR( LDA, * ), AI( LDA, * ), BR( * ), BI( * )
*
*  Purpose
*  =======
*
*  RADLZS solves A x = b, A = AR + i AI factored by RADLZD and
*  b = BR + i BI, in place (x = BR + i BI on exit), in real arithmetic
*  as RADLUS does; the diagonal of U is applied as its stored
*  reciprocal.
*
*  Arguments
*  =========
*
*  N       (input) INTEGER, the order.
*  AR, AI  (input) DOUBLE PRECISION arrays (LDA,N), factors (RADLZD).
*  LDA     (input) INTEGER, LDA >= max(1,N).
*  IPIV    (input) INTEGER array (N), pivots (RADLZD).
*  BR, BI  (input/output) DOUBLE PRECISION arrays (N): b on entry, x
*          on exit.
*
*  =====================================================================
*
      INTEGER            I, K, P
      DOUBLE PRECISION   TR, TI, XR, XI
*
      DO 10 K = 1, N
         P = IPIV( K )
         IF( P.NE.K ) THEN
            TR = BR( K )
            BR( K ) = BR( P )
            BR( P ) = TR
            TI = BI( K )
            BI( K ) = BI( P )
            BI( P ) = TI
         END IF
   10 CONTINUE
      DO 30 K = 1, N
         TR = BR( K )
         TI = BI( K )
         IF( TR.NE.0.0D0 .OR. TI.NE.0.0D0 ) THEN
            DO 20 I = K + 1, N
               BR( I ) = BR( I ) - ( AR( I, K )*TR - AI( I, K )*TI )
               BI( I ) = BI( I ) - ( AR( I, K )*TI + AI( I, K )*TR )
   20       CONTINUE
         END IF
   30 CONTINUE
      DO 50 K = N, 1, -1
         XR = BR( K )
         XI = BI( K )
         IF( XR.NE.0.0D0 .OR. XI.NE.0.0D0 ) THEN
*           (TR + i TI) = (XR + i XI) * (1/u(k,k)), stored by RADLZD.
            TR = XR*AR( K, K ) - XI*AI( K, K )
            TI = XR*AI( K, K ) + XI*AR( K, K )
            BR( K ) = TR
            BI( K ) = TI
            DO 40 I = 1, K - 1
               BR( I ) = BR( I ) - ( AR( I, K )*TR - AI( I, K )*TI )
               BI( I ) = BI( I ) - ( AR( I, K )*TI + AI( I, K )*TR )
   40       CONTINUE
         END IF
   50 CONTINUE
      RETURN
*
*     End of RADLZS
*
      END
