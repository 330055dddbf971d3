// The C++ port of RADIIA (fortran/radau.f). Every decision, counter and formula follows the
// Fortran kernel line for line (same labels in the comments), in the same order of floating-point
// operations, and the linear algebra is the port of the same routines (radau_lu.cpp for the own
// LU of fortran/radau_lu.f; the same LAPACK/BLAS calls on the LAPACK path), so both kernels
// round identically and take the same steps. Why it matters: the error estimate is a difference
// of terms ~1/tol times larger than itself, so a last-bit difference in an LU changes the next
// step size by ~eps/tol relative and, through the fast transitions of stiff problems, the trace
// by far more than 1e-9 (measured with Eigen::PartialPivLU: 1e-4 on van der Pol at
// rtol = 1e-10). All storage comes from the caller's work arrays (same layout as the Fortran
// kernel): nothing is allocated per step.
#include "ode/radau_port.hpp"
#include "common/eigen_instances.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdlib>
#include <limits>

#include "ode/radau_lu.hpp"

extern "C" {
// Reference LAPACK/BLAS (Fortran ABI: everything by reference, hidden CHARACTER lengths last).
void dgetrf_(const int* m, const int* n, double* a, const int* lda, int* ipiv, int* info);
void dgetrs_(const char* trans, const int* n, const int* nrhs, const double* a, const int* lda,
             const int* ipiv, double* b, const int* ldb, int* info, std::size_t trans_len);
void zgetrf_(const int* m, const int* n, std::complex<double>* a, const int* lda, int* ipiv,
             int* info);
void zgetrs_(const char* trans, const int* n, const int* nrhs, const std::complex<double>* a,
             const int* lda, const int* ipiv, std::complex<double>* b, const int* ldb, int* info,
             std::size_t trans_len);
void dgemv_(const char* trans, const int* m, const int* n, const double* alpha, const double* a,
            const int* lda, const double* x, const int* incx, const double* beta, double* y,
            const int* incy, std::size_t trans_len);
}

namespace pcsim::radau_port {

namespace {

struct Coefficients {
  double c[3], t[3][3], ti[3][3], dd[3], gam, alp, bet;  // t[i][j] = T(i+1, j+1)
};

Coefficients make_coefficients() {
  Coefficients k{};
  double cc[3], tt[9], tti[9], dd[3];
  coefficients(cc, tt, tti, dd, &k.gam, &k.alp, &k.bet);
  for (int i = 0; i < 3; ++i) {
    k.c[i] = cc[i];
    k.dd[i] = dd[i];
    for (int j = 0; j < 3; ++j) {
      k.t[i][j] = tt[i + 3 * j];
      k.ti[i][j] = tti[i + 3 * j];
    }
  }
  return k;
}

// Port of RADFIN.
bool finite_all(int n, const double* v) {
  const double huge = std::numeric_limits<double>::max();
  for (int i = 0; i < n; ++i)
    if (!(std::abs(v[i]) <= huge)) return false;
  return true;
}

// The resolved options of RADIIA.
struct Settings {
  int ijac, imas, iout, ilapck, ng, n, m1, m2, nind2, nind3, nmax, nit, ipred, istrt;
  double uround, hmaxn, hfix, safe, thet, fnewt, quot1, quot2, facl, facr;
};

constexpr int kNbadMax = 20;  // NBADMX of RADCOR

// Port of RADJAC; returns a status code (0 on success).
int jacobian(pcsim_radau_fcn fcn, pcsim_radau_jac jac, void* const* ctx, const Settings& s,
             double x, double* y, const double* y0, double* fjac, double* t1, int& nfcnj) {
  const int n = s.n;
  int ie = 0;
  if (s.ijac == 1) {
    jac(&n, &x, y, fjac, &n, ctx, &ie);
    if (ie == 1) return PCSIM_ODE_jacobian_failed;
    if (ie != 0) return PCSIM_ODE_callback_error;
    for (int j = 0; j < n; ++j)
      if (!finite_all(n - s.m1, fjac + s.m1 + static_cast<long>(n) * j)) return PCSIM_ODE_non_finite;
    return 0;
  }
  for (int j = 0; j < n; ++j) {
    const double ysafe = y[j];
    double delt = std::sqrt(s.uround * std::max(1.0e-5, std::abs(ysafe)));
    y[j] = ysafe + delt;
    fcn(&n, &x, y, t1, ctx, &ie);
    ++nfcnj;
    bool bad = false;
    if (ie == 0) bad = !finite_all(n, t1);
    if (ie == 1 || bad) {
      delt = -delt;
      y[j] = ysafe + delt;
      fcn(&n, &x, y, t1, ctx, &ie);
      ++nfcnj;
      bad = false;
      if (ie == 0) bad = !finite_all(n, t1);
    }
    y[j] = ysafe;
    if (ie == 1) return PCSIM_ODE_rhs_failed;
    if (ie != 0) return PCSIM_ODE_callback_error;
    if (bad) return PCSIM_ODE_non_finite;
    for (int i = 0; i < n; ++i) fjac[i + static_cast<long>(n) * j] = (t1[i] - y0[i]) / delt;
  }
  return 0;
}

// Port of RADCEX: y += z3 and the continuation coefficients.
void continuation(int n, const double* c, const double* z1, const double* z2, const double* z3,
                  double* y, double* cont) {
  const double c1m1 = c[0] - 1.0, c2m1 = c[1] - 1.0, c1mc2 = c[0] - c[1];
  for (int i = 0; i < n; ++i) {
    const double ak1 = (z2[i] - z3[i]) / c2m1;
    double ak2 = (z1[i] - z2[i]) / c1mc2;
    const double a1 = z1[i] / c[0];
    const double a2 = (ak2 - a1) / c[1];
    ak2 = (ak2 - ak1) / c1m1;
    y[i] = y[i] + z3[i];
    cont[i] = y[i];
    cont[i + n] = ak1;
    cont[i + 2 * n] = ak2;
    cont[i + 3 * n] = ak2 - a2;
  }
}

// The step loop: port of RADCOR.
class Core {
 public:
  Core(const Settings& s, pcsim_radau_fcn fcn, pcsim_radau_jac jac, pcsim_radau_solout solout,
       pcsim_radau_gfcn gfcn, void* ctx, const double* am, int ldm, const double* rtt,
       const double* att, double* w, std::complex<double>* zw, int* iw, int* istat)
      : s_(s), fcn_(fcn), jac_(jac), solout_(solout), gfcn_(gfcn), ctx_(ctx), am_(am),
        ldm_(ldm), rtt_(rtt), att_(att), n_(s.n), k_(make_coefficients()), istat_(istat) {
    const int n = n_;
    const long nn = static_cast<long>(n) * n;
    z1_ = w;        z2_ = z1_ + n;  z3_ = z2_ + n;
    w1_ = z3_ + n;  w2_ = w1_ + n;  w3_ = w2_ + n;
    f1_ = w3_ + n;  f2_ = f1_ + n;  f3_ = f2_ + n;
    y0_ = f3_ + n;  scal_ = y0_ + n;
    cont_ = scal_ + 3 * n;  // after SCAL, RTOL', ATOL' (which the caller placed there)
    t1_ = cont_ + 4 * n;    t2_ = t1_ + n;  ts_ = t2_ + n;
    fjac_ = ts_ + 3 * n;    e1_ = fjac_ + nn;  e2r_ = e1_ + nn;  e2i_ = e2r_ + nn;
    gold_ = e2i_ + nn;      gnew_ = gold_ + s.ng;  gc_ = gnew_ + s.ng;  tr_ = gc_ + s.ng;
    e2_ = zw;               zt_ = zw + nn;
    irdir_ = iw + 30;       jroot_ = irdir_ + s.ng;
    ip1_ = jroot_ + s.ng;   ip2_ = ip1_ + n;  iwl_ = ip2_ + n;
  }

  int run(double& x, double xend, double* y, double& h);

 private:
  bool decompose(double fac1, double alphn, double betan);
  void solve1(double fac1, double* b);
  void solve(double fac1, double alphn, double betan);
  void mass_times(const double* v, double* out) const;
  int estimate(double x, double h, const double* y, double fac1, bool refine, int& nfcn,
               int& nsol, double& err);
  int roots(double x0, double xold, double x, int& ngev, double& xroot, int& iroot);
  void dense(double t, double told, double tnew, double* out) const;
  double fj(int i, int j) const { return fjac_[i + static_cast<long>(n_) * j]; }

  const Settings s_;
  pcsim_radau_fcn fcn_;
  pcsim_radau_jac jac_;
  pcsim_radau_solout solout_;
  pcsim_radau_gfcn gfcn_;
  void* ctx_;
  const double* am_;
  int ldm_;
  const double *rtt_, *att_;
  int n_;
  Coefficients k_;
  int* istat_;
  double *z1_, *z2_, *z3_, *w1_, *w2_, *w3_, *f1_, *f2_, *f3_, *y0_, *scal_, *cont_, *t1_,
      *t2_, *ts_, *fjac_, *e1_, *e2r_, *e2i_, *gold_, *gnew_, *gc_, *tr_;
  std::complex<double>*e2_, *zt_;
  int *irdir_, *jroot_, *ip1_, *ip2_, *iwl_;
};

// Port of RADMAS: out = K v.
void Core::mass_times(const double* v, double* out) const {
  const int m1 = s_.m1, nm = n_ - m1;
  for (int i = 0; i < m1; ++i) out[i] = v[i];
  if (s_.imas == 0) {
    for (int i = 0; i < nm; ++i) out[m1 + i] = v[m1 + i];
  } else if (s_.imas == 2) {
    for (int i = 0; i < nm; ++i) out[m1 + i] = am_[static_cast<long>(ldm_) * i] * v[m1 + i];
  } else if (s_.ilapck == 1) {
    const double one = 1.0, zero = 0.0;
    const int inc = 1;
    dgemv_("N", &nm, &nm, &one, am_, &ldm_, v + m1, &inc, &zero, out + m1, &inc, 1);
  } else {
    for (int i = 0; i < nm; ++i) out[m1 + i] = 0.0;
    for (int j = 0; j < nm; ++j) {
      const double vj = v[m1 + j];
      if (vj != 0.0)
        for (int i = 0; i < nm; ++i)
          out[m1 + i] = out[m1 + i] + am_[i + static_cast<long>(ldm_) * j] * vj;
    }
  }
}

// Port of RADDEC.
bool Core::decompose(double fac1, double alphn, double betan) {
  const int m1 = s_.m1, m2 = s_.m2, nm = n_ - m1;
  auto E1 = [&](int i, int j) -> double& { return e1_[i + static_cast<long>(nm) * j]; };
  auto ER = [&](int i, int j) -> double& { return e2r_[i + static_cast<long>(nm) * j]; };
  auto EI = [&](int i, int j) -> double& { return e2i_[i + static_cast<long>(nm) * j]; };
  for (int j = 0; j < nm; ++j)
    for (int i = 0; i < nm; ++i) {
      E1(i, j) = -fj(m1 + i, m1 + j);
      ER(i, j) = -fj(m1 + i, m1 + j);
      EI(i, j) = 0.0;
    }
  if (s_.imas == 0) {
    for (int j = 0; j < nm; ++j) {
      E1(j, j) = E1(j, j) + fac1;
      ER(j, j) = ER(j, j) + alphn;
      EI(j, j) = betan;
    }
  } else if (s_.imas == 2) {
    for (int j = 0; j < nm; ++j) {
      const double a = am_[static_cast<long>(ldm_) * j];
      E1(j, j) = E1(j, j) + fac1 * a;
      ER(j, j) = ER(j, j) + alphn * a;
      EI(j, j) = betan * a;
    }
  } else {
    for (int j = 0; j < nm; ++j)
      for (int i = 0; i < nm; ++i) {
        const double a = am_[i + static_cast<long>(ldm_) * j];
        E1(i, j) = E1(i, j) + fac1 * a;
        ER(i, j) = ER(i, j) + alphn * a;
        EI(i, j) = betan * a;
      }
  }
  if (m1 > 0) {
    const int mm = m1 / m2;
    const double abno = alphn * alphn + betan * betan;
    const double sr = alphn / abno, si = -betan / abno;
    for (int j = 0; j < m2; ++j)
      for (int i = 0; i < nm; ++i) {
        double sum = 0.0, pr = 0.0, pi = 0.0;
        for (int k = 0; k < mm; ++k) {
          const double f = fj(m1 + i, j + k * m2);
          sum = (sum + f) / fac1;
          const double ar = pr + f, ai = pi;
          pr = ar * sr - ai * si;
          pi = ar * si + ai * sr;
        }
        E1(i, j) = E1(i, j) - sum;
        ER(i, j) = ER(i, j) - pr;
        EI(i, j) = EI(i, j) - pi;
      }
  }
  int info1 = 0, info2 = 0;
  if (s_.ilapck == 0) {
    info1 = radau_lu::factor(nm, e1_, nm, ip1_, iwl_);
    info2 = radau_lu::factor_complex(nm, e2r_, e2i_, nm, ip2_, iwl_);
  } else {
    for (int j = 0; j < nm; ++j)
      for (int i = 0; i < nm; ++i)
        e2_[i + static_cast<long>(nm) * j] = std::complex<double>(ER(i, j), EI(i, j));
    dgetrf_(&nm, &nm, e1_, &nm, ip1_, &info1);
    zgetrf_(&nm, &nm, e2_, &nm, ip2_, &info2);
  }
  return info1 == 0 && info2 == 0;
}

// Port of RADSL1: E1 x = b in place.
void Core::solve1(double fac1, double* b) {
  const int m1 = s_.m1, m2 = s_.m2, nm = n_ - m1;
  if (m1 > 0) {
    for (int k = m1 - 1; k >= 0; --k) {
      double p = b[k];
      if (k + m2 < m1) p = p + ts_[k + m2];
      ts_[k] = p / fac1;
    }
    for (int k = 0; k < m1; ++k) {
      const double p = ts_[k];
      if (p != 0.0)
        for (int i = 0; i < nm; ++i) b[m1 + i] = b[m1 + i] + fj(m1 + i, k) * p;
    }
  }
  if (s_.ilapck == 0) {
    radau_lu::solve(nm, e1_, nm, ip1_, b + m1);
  } else {
    const int one = 1;
    int info = 0;
    dgetrs_("N", &nm, &one, e1_, &nm, ip1_, b + m1, &nm, &info, 1);
  }
  for (int k = m1 - 1; k >= 0; --k) b[k] = (b[k] + b[k + m2]) / fac1;
}

// Port of RADSLV: E1 x1 = F1, E2 (x2 + i x3) = F2 + i F3, in place.
void Core::solve(double fac1, double alphn, double betan) {
  solve1(fac1, f1_);
  const int n = n_, m1 = s_.m1, m2 = s_.m2, nm = n_ - m1;
  double sr = 0.0, si = 0.0;
  if (m1 > 0) {
    const double abno = alphn * alphn + betan * betan;
    sr = alphn / abno;
    si = -betan / abno;
    for (int k = m1 - 1; k >= 0; --k) {
      double ar = f2_[k], ai = f3_[k];
      if (k + m2 < m1) {
        ar = ar + ts_[n + k + m2];
        ai = ai + ts_[2 * n + k + m2];
      }
      ts_[n + k] = ar * sr - ai * si;
      ts_[2 * n + k] = ar * si + ai * sr;
    }
    for (int k = 0; k < m1; ++k) {
      const double pr = ts_[n + k], pi = ts_[2 * n + k];
      if (pr != 0.0 || pi != 0.0)
        for (int i = 0; i < nm; ++i) {
          f2_[m1 + i] = f2_[m1 + i] + fj(m1 + i, k) * pr;
          f3_[m1 + i] = f3_[m1 + i] + fj(m1 + i, k) * pi;
        }
    }
  }
  if (s_.ilapck == 0) {
    radau_lu::solve_complex(nm, e2r_, e2i_, nm, ip2_, f2_ + m1, f3_ + m1);
  } else {
    const int one = 1;
    int info = 0;
    for (int i = 0; i < nm; ++i) zt_[i] = std::complex<double>(f2_[m1 + i], f3_[m1 + i]);
    zgetrs_("N", &nm, &one, e2_, &nm, ip2_, zt_, &nm, &info, 1);
    for (int i = 0; i < nm; ++i) {
      f2_[m1 + i] = zt_[i].real();
      f3_[m1 + i] = zt_[i].imag();
    }
  }
  if (m1 > 0)
    for (int k = m1 - 1; k >= 0; --k) {
      const double ar = f2_[k] + f2_[k + m2], ai = f3_[k] + f3_[k + m2];
      f2_[k] = ar * sr - ai * si;
      f3_[k] = ar * si + ai * sr;
    }
}

// Port of RADEST (T1 = K v, T2 = e, F1 = f(x, y + e)); err as computed (no lower bound).
int Core::estimate(double x, double h, const double* y, double fac1, bool refine, int& nfcn,
                   int& nsol, double& err) {
  const int n = n_;
  const double hee1 = k_.dd[0] / h, hee2 = k_.dd[1] / h, hee3 = k_.dd[2] / h;
  for (int i = 0; i < n; ++i) t2_[i] = hee1 * z1_[i] + hee2 * z2_[i] + hee3 * z3_[i];
  mass_times(t2_, t1_);
  for (int i = 0; i < n; ++i) t2_[i] = y0_[i] + t1_[i];
  solve1(fac1, t2_);
  ++nsol;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) sum += (t2_[i] / scal_[i]) * (t2_[i] / scal_[i]);
  err = std::sqrt(sum / double(n));
  if (!(err <= std::numeric_limits<double>::max())) return 0;
  if (std::max(err, 1.0e-10) < 1.0 || !refine) return 0;

  for (int i = 0; i < n; ++i) t2_[i] = y[i] + t2_[i];
  int ierr = 0;
  fcn_(&n, &x, t2_, f1_, &ctx_, &ierr);
  ++nfcn;
  if (ierr != 0) return ierr;
  for (int i = 0; i < n; ++i) t2_[i] = f1_[i] + t1_[i];
  solve1(fac1, t2_);
  ++nsol;
  sum = 0.0;
  for (int i = 0; i < n; ++i) sum += (t2_[i] / scal_[i]) * (t2_[i] / scal_[i]);
  err = std::sqrt(sum / double(n));
  return 0;
}

void Core::dense(double t, double told, double tnew, double* out) const {
  radau_port::dense(n_, t, told, tnew, cont_, n_, out);
}

// Port of RADROT: sign changes of the event functions after [xold, x], roots by Illinois.
int Core::roots(double x0, double xold, double x, int& ngev, double& xroot, int& iroot) {
  const int n = n_, ng = s_.ng;
  int ierr = 0;
  iroot = 0;
  xroot = x;
  const double sgn = std::copysign(1.0, x - xold);
  const double ttol = 100.0 * s_.uround * (std::abs(x) + std::abs(x - xold));
  gfcn_(&n, &x, cont_, &ng, gnew_, &ctx_, &ierr);
  ++ngev;
  if (ierr != 0) return ierr;
  for (int i = 0; i < ng; ++i) {
    jroot_[i] = 0;
    if (gold_[i] == 0.0) continue;
    if (!(gold_[i] * gnew_[i] < 0.0 || gnew_[i] == 0.0)) continue;
    const int idir = gold_[i] < 0.0 ? 1 : -1;
    if (irdir_[i] != 0 && irdir_[i] != idir) continue;
    double a = xold, ga = gold_[i], b = x, gb = gnew_[i];
    int lasts = 0;
    for (int it = 1; it <= 200; ++it) {
      if (std::abs(b - a) <= ttol) break;
      double t = gb != 0.0 ? b - gb * (b - a) / (gb - ga) : a;
      if (!((t - a) * (b - t) > 0.0)) t = a + 0.5 * (b - a);
      dense(t, xold, x, t2_);
      gfcn_(&n, &t, t2_, &ng, gc_, &ctx_, &ierr);
      ++ngev;
      if (ierr != 0) return ierr;
      const double gt = gc_[i];
      if (gt == 0.0 || ((gt < 0.0) == (idir < 0))) {
        b = t;
        gb = gt;
        if (lasts == 1) ga = 0.5 * ga;
        lasts = 1;
      } else {
        a = t;
        ga = gt;
        if (lasts == -1) gb = 0.5 * gb;
        lasts = -1;
      }
    }
    if (std::abs(b - x0) <= ttol) continue;
    tr_[i] = b;
    jroot_[i] = idir;
    if (iroot == 0) {
      xroot = b;
      iroot = 1;
    } else if ((b - xroot) * sgn < 0.0) {
      xroot = b;
    }
  }
  if (iroot == 0) {
    for (int i = 0; i < ng; ++i) gold_[i] = gnew_[i];
    return 0;
  }
  for (int i = 0; i < ng; ++i)
    if (jroot_[i] != 0 && std::abs(tr_[i] - xroot) > ttol) jroot_[i] = 0;
  return 0;
}

int Core::run(double& x, double xend, double* y, double& h) {
  const int n = n_;
  const int m1 = s_.m1, m2 = s_.m2, nm = n - m1;
  const double uround = s_.uround;
  const double huge = std::numeric_limits<double>::max();
  const double c1m1 = k_.c[0] - 1.0, c2m1 = k_.c[1] - 1.0;
  const auto& ti = k_.ti;
  const auto& tt = k_.t;
  const int nind1 = n - s_.nind2 - s_.nind3;
  const int nit = s_.nit;

  int nfcn = 0, njac = 0, ndec = 0, nsol = 0, nstep = 0, naccpt = 0, nrejct = 0, nsing = 0;
  int nfcnj = 0, nerrej = 0, nnewtr = 0, nfailr = 0, ngev = 0, iwhat = 0;
  int nbad = 0, ibad = 0, lstrej = 0, iroot = 0;
  int idid = 0, ierr = 0, newt = 0;
  const bool fixed = s_.hfix > 0.0;
  const double posneg = std::copysign(1.0, xend - x);
  if (fixed)
    h = s_.hfix;
  else if (h == 0.0)
    h = 1.0e-6;
  h = std::min(std::abs(h), s_.hmaxn) * posneg;
  bool last = false;
  if ((x + h * 1.0001 - xend) * posneg >= 0.0) {
    h = xend - x;
    last = true;
  }
  double hopt = h, hold = h, hacc = h, erracc = 1.0e-2, faccon = 1.0, theta = std::abs(s_.thet);
  const double cfac = s_.safe * double(1 + 2 * nit);
  bool first = true, reject = false, caljac = false, startz = true, needj = true,
       needlu = true, checkd = false;
  double xold = x, fac1 = 0.0, alphn = 0.0, betan = 0.0, hnew = h, err = 0.0, quot = 1.0;
  double dynold = 0.0, thqold = 0.0, xroot = x;
  const double x0 = x;

  // K has zero rows (algebraic equations).
  auto zero_row = [&](int i) {
    if (s_.imas == 2) return am_[static_cast<long>(ldm_) * i] == 0.0;
    double sum = 0.0;
    for (int j = 0; j < nm; ++j) sum = sum + std::abs(am_[i + static_cast<long>(ldm_) * j]);
    return sum == 0.0;
  };
  bool ksing = false;
  if (s_.imas != 0)
    for (int i = 0; i < nm; ++i)
      if (zero_row(i)) ksing = true;

  // The labels of RADCOR, as the states of one loop.
  enum class Next { main, bad_value, f_failed, newton_failure, retry, exit };
  Next next = Next::main;

  fcn_(&n, &x, y, y0_, &ctx_, &ierr);
  ++nfcn;
  if (ierr != 0) {
    idid = ierr == 1 ? PCSIM_ODE_rhs_failed : PCSIM_ODE_callback_error;
    next = Next::exit;
  } else if (!finite_all(n, y0_)) {
    idid = PCSIM_ODE_non_finite;
    iwhat = 1;
    next = Next::exit;
  } else {
    for (int i = 0; i < m1; ++i)
      if (y0_[i] != y[i + m2]) {
        idid = -24;
        next = Next::exit;
        break;
      }
  }
  if (next != Next::exit && s_.ng > 0) {
    gfcn_(&n, &x, y, &s_.ng, gold_, &ctx_, &ierr);
    ++ngev;
    if (ierr != 0) {
      idid = PCSIM_ODE_callback_error;
      next = Next::exit;
    }
  }

  while (next != Next::exit) {
    // Labels 380/390/385 (bad value, f failed), 400 (Newton failure), 395 (retry).
    if (next == Next::bad_value || next == Next::f_failed) {
      if (next == Next::f_failed) {
        if (ierr != 1) {
          idid = PCSIM_ODE_callback_error;
          break;
        }
        ibad = PCSIM_ODE_rhs_failed;
        iwhat = 1;
      } else {
        ibad = PCSIM_ODE_non_finite;
      }
      ++nfailr;
      ++nbad;
      lstrej = 3;
      if (nbad >= kNbadMax || fixed) {
        idid = ibad;
        break;
      }
      h = h * 0.5;
      next = Next::retry;
    } else if (next == Next::newton_failure) {
      ++nnewtr;
      lstrej = 2;
      if (fixed) {
        if (caljac) {
          idid = PCSIM_ODE_newton_failure;
          break;
        }
      } else {
        h = h * 0.5;
      }
      next = Next::retry;
    }
    if (next == Next::retry) {
      reject = true;
      last = false;
      ++nrejct;
      needlu = true;
      needj = !caljac;
      next = Next::main;
    }
    // Label 100: Jacobian if stale, LU if h changed.
    if (needj) {
      ierr = jacobian(fcn_, jac_, &ctx_, s_, x, y, y0_, fjac_, t1_, nfcnj);
      ++njac;
      if (ierr != 0) {
        idid = ierr;
        if (ierr == PCSIM_ODE_non_finite) iwhat = 2;
        if (ierr == PCSIM_ODE_rhs_failed) iwhat = 1;
        break;
      }
      caljac = true;
      needj = false;
      needlu = true;
    }
    if (needlu) {
      fac1 = k_.gam / h;
      alphn = k_.alp / h;
      betan = k_.bet / h;
      const bool ok = decompose(fac1, alphn, betan);
      ++ndec;
      if (!ok) {
        ++nsing;
        if (nsing > 5 || fixed) {
          idid = PCSIM_ODE_singular_matrix;
          break;
        }
        h = h * 0.5;
        reject = true;
        last = false;
        continue;
      }
      needlu = false;
    }
    // One step attempt.
    if (nstep >= s_.nmax) {
      idid = PCSIM_ODE_too_many_steps;
      break;
    }
    if (0.1 * std::abs(h) <= std::abs(x) * uround) {
      idid = lstrej == 2 ? PCSIM_ODE_newton_failure
                         : (lstrej == 3 ? ibad : PCSIM_ODE_step_too_small);
      break;
    }
    ++nstep;
    const double habs = std::abs(h);
    for (int i = 0; i < n; ++i) scal_[i] = att_[i] + rtt_[i] * std::abs(y[i]);
    for (int i = nind1; i < nind1 + s_.nind2; ++i) scal_[i] = scal_[i] / habs;
    for (int i = nind1 + s_.nind2; i < n; ++i) scal_[i] = scal_[i] / (habs * habs);

    if (ksing && !checkd) {  // consistency of the algebraic equations at the start
      checkd = true;
      for (int i = 0; i < n; ++i) t1_[i] = 0.0;
      for (int i = 0; i < nm; ++i)
        if (zero_row(i)) t1_[m1 + i] = y0_[m1 + i];
      for (int i = 0; i < n; ++i) t2_[i] = t1_[i];
      solve1(fac1, t1_);
      double sum = 0.0;
      for (int i = 0; i < n; ++i) sum = sum + (t1_[i] / scal_[i]) * (t1_[i] / scal_[i]);
      const double dyno = std::sqrt(sum / double(n));
      if (!(dyno <= 1.0)) {
        --nstep;
        idid = PCSIM_ODE_inconsistent_start;
        if (s_.nind2 + s_.nind3 == 0) {  // index probe with h/10 (see RADCOR)
          const bool ok = decompose(10.0 * fac1, 10.0 * alphn, 10.0 * betan);
          ++ndec;
          if (ok) {
            solve1(10.0 * fac1, t2_);
            sum = 0.0;
            for (int i = 0; i < n; ++i) sum = sum + (t2_[i] / scal_[i]) * (t2_[i] / scal_[i]);
            if (std::sqrt(sum / double(n)) > 3.0 * dyno) idid = PCSIM_ODE_missing_index_counts;
          }
        }
        break;
      }
    }

    if (startz || s_.istrt == 1) {
      for (int i = 0; i < n; ++i) {
        z1_[i] = z2_[i] = z3_[i] = 0.0;
        w1_[i] = w2_[i] = w3_[i] = 0.0;
      }
    } else {
      const double c3q = h / hold, c1q = k_.c[0] * c3q, c2q = k_.c[1] * c3q;
      const double* ak1 = cont_ + n;
      const double* ak2 = cont_ + 2 * n;
      const double* ak3 = cont_ + 3 * n;
      for (int i = 0; i < n; ++i) {
        z1_[i] = c1q * (ak1[i] + (c1q - c2m1) * (ak2[i] + (c1q - c1m1) * ak3[i]));
        z2_[i] = c2q * (ak1[i] + (c2q - c2m1) * (ak2[i] + (c2q - c1m1) * ak3[i]));
        z3_[i] = c3q * (ak1[i] + (c3q - c2m1) * (ak2[i] + (c3q - c1m1) * ak3[i]));
        w1_[i] = ti[0][0] * z1_[i] + ti[0][1] * z2_[i] + ti[0][2] * z3_[i];
        w2_[i] = ti[1][0] * z1_[i] + ti[1][1] * z2_[i] + ti[1][2] * z3_[i];
        w3_[i] = ti[2][0] * z1_[i] + ti[2][1] * z2_[i] + ti[2][2] * z3_[i];
      }
    }

    // Simplified Newton iteration (label 200).
    newt = 0;
    faccon = std::pow(std::max(faccon, uround), 0.8);
    theta = std::abs(s_.thet);
    dynold = 0.0;
    thqold = 0.0;
    bool converged = false;
    while (true) {
      if (newt >= nit) {
        next = Next::newton_failure;
        break;
      }
      for (int i = 0; i < n; ++i) t1_[i] = y[i] + z1_[i];
      double xs = x + k_.c[0] * h;
      fcn_(&n, &xs, t1_, f1_, &ctx_, &ierr);
      ++nfcn;
      if (ierr != 0) { next = Next::f_failed; break; }
      for (int i = 0; i < n; ++i) t1_[i] = y[i] + z2_[i];
      xs = x + k_.c[1] * h;
      fcn_(&n, &xs, t1_, f2_, &ctx_, &ierr);
      ++nfcn;
      if (ierr != 0) { next = Next::f_failed; break; }
      for (int i = 0; i < n; ++i) t1_[i] = y[i] + z3_[i];
      xs = x + h;
      fcn_(&n, &xs, t1_, f3_, &ctx_, &ierr);
      ++nfcn;
      if (ierr != 0) { next = Next::f_failed; break; }
      mass_times(w1_, z1_);
      mass_times(w2_, z2_);
      mass_times(w3_, z3_);
      double fchk = 0.0;  // stays 0 unless some F is not finite (x - x is NaN for NaN, Inf)
      for (int i = 0; i < n; ++i) {
        const double a1 = f1_[i], a2 = f2_[i], a3 = f3_[i];
        fchk = fchk + ((a1 - a1) + (a2 - a2) + (a3 - a3));
        f1_[i] = ti[0][0] * a1 + ti[0][1] * a2 + ti[0][2] * a3 - fac1 * z1_[i];
        f2_[i] = ti[1][0] * a1 + ti[1][1] * a2 + ti[1][2] * a3 - alphn * z2_[i] + betan * z3_[i];
        f3_[i] = ti[2][0] * a1 + ti[2][1] * a2 + ti[2][2] * a3 - betan * z2_[i] - alphn * z3_[i];
      }
      if (fchk != 0.0) {
        iwhat = 1;
        next = Next::bad_value;
        break;
      }
      solve(fac1, alphn, betan);
      ++nsol;
      ++newt;
      double sum = 0.0;
      for (int i = 0; i < n; ++i) {
        const double a = f1_[i] / scal_[i], b = f2_[i] / scal_[i], c = f3_[i] / scal_[i];
        sum = sum + a * a + b * b + c * c;
      }
      const double dyno = std::sqrt(sum / double(3 * n));
      if (!(dyno <= huge)) {
        iwhat = 3;
        next = Next::bad_value;
        break;
      }
      if (newt >= 2) {
        const double thq = dyno / dynold;
        theta = newt == 2 ? thq : std::sqrt(thq * thqold);
        thqold = thq;
        if (theta < 0.99) {
          faccon = theta / (1.0 - theta);
          const double dyth =
              theta > 0.0 ? faccon * dyno * std::pow(theta, double(nit - 1 - newt)) / s_.fnewt
                          : 0.0;
          if (dyth >= 1.0 && !fixed) {
            const double qnewt = std::max(1.0e-4, std::min(20.0, dyth));
            const double hhfac = 0.8 * std::pow(qnewt, -1.0 / double(4 + nit - 1 - newt));
            h = hhfac * h;
            ++nnewtr;
            lstrej = 2;
            next = Next::retry;
            break;
          }
        } else {
          next = Next::newton_failure;
          break;
        }
      }
      dynold = std::max(dyno, uround);
      for (int i = 0; i < n; ++i) {
        w1_[i] = w1_[i] + f1_[i];
        w2_[i] = w2_[i] + f2_[i];
        w3_[i] = w3_[i] + f3_[i];
        z1_[i] = tt[0][0] * w1_[i] + tt[0][1] * w2_[i] + tt[0][2] * w3_[i];
        z2_[i] = tt[1][0] * w1_[i] + tt[1][1] * w2_[i] + tt[1][2] * w3_[i];
        z3_[i] = tt[2][0] * w1_[i] + tt[2][1] * w2_[i] + tt[2][2] * w3_[i];
      }
      if (faccon * dyno > s_.fnewt) continue;
      converged = true;
      break;
    }
    if (!converged) continue;

    // Label 500: error estimate and step-size proposal.
    if (fixed) {
      err = 0.0;
      hnew = h;
      quot = 1.0;
    } else {
      ierr = estimate(x, h, y, fac1, first || reject, nfcn, nsol, err);
      if (ierr != 0) {
        next = Next::f_failed;
        continue;
      }
      if (!(err <= huge)) {
        iwhat = 3;
        next = Next::bad_value;
        continue;
      }
      err = std::max(err, 1.0e-10);
      const double fac = std::min(s_.safe, cfac / double(newt + 2 * nit));
      quot = std::max(s_.facr, std::min(s_.facl, std::pow(err, 0.25) / fac));
      hnew = h / quot;
    }
    if (err >= 1.0) {  // label 700: rejected by the error test
      reject = true;
      last = false;
      if (first)
        h = h * 0.1;
      else
        h = hnew;
      ++nrejct;
      ++nerrej;
      lstrej = 1;
      needlu = true;
      needj = !caljac;
      continue;
    }

    // Step accepted.
    first = false;
    ++naccpt;
    nbad = 0;
    lstrej = 0;
    if (s_.ipred == 0 && naccpt > 1 && !fixed) {
      double facgus = (hacc / h) * std::pow(err * err / erracc, 0.25) / s_.safe;
      facgus = std::max(s_.facr, std::min(s_.facl, facgus));
      quot = std::max(quot, facgus);
      hnew = h / quot;
    }
    hacc = h;
    erracc = std::max(1.0e-2, err);
    xold = x;
    hold = h;
    x = last ? xend : xold + h;
    continuation(n, k_.c, z1_, z2_, z3_, y, cont_);
    startz = false;
    if (s_.ng > 0) {
      ierr = roots(x0, xold, x, ngev, xroot, iroot);
      if (ierr != 0) {
        idid = PCSIM_ODE_callback_error;
        break;
      }
      if (iroot != 0) {  // the step shortened to [xold, xroot], its polynomial re-expanded
        dense(xold, xold, x, t1_);
        const double hr = xroot - xold;
        dense(xold + k_.c[0] * hr, xold, x, z1_);
        dense(xold + k_.c[1] * hr, xold, x, z2_);
        dense(xroot, xold, x, z3_);
        for (int i = 0; i < n; ++i) {
          z1_[i] = z1_[i] - t1_[i];
          z2_[i] = z2_[i] - t1_[i];
          z3_[i] = z3_[i] - t1_[i];
          y[i] = t1_[i];
        }
        continuation(n, k_.c, z1_, z2_, z3_, y, cont_);
        x = xroot;
        last = true;
        hopt = posneg * std::min(std::abs(h), std::abs(hnew));
      }
    }
    if (s_.iout == 1) {
      int irtrn = 0;
      solout_(&n, &xold, &x, y, cont_, &n, &ctx_, &irtrn);
      if (irtrn == 2) {
        idid = PCSIM_ODE_stopped_by_callback;
        break;
      } else if (irtrn == 1) {  // y modified: zero Newton start only if beyond the tolerance
        double sum = 0.0;
        for (int i = 0; i < n; ++i) {
          const double d = (y[i] - cont_[i]) / scal_[i];
          sum = sum + d * d;
        }
        startz = std::sqrt(sum / double(n)) > 1.0;
      } else if (irtrn != 0) {
        idid = PCSIM_ODE_callback_error;
        break;
      }
    }
    if (iroot != 0) {
      h = hopt;
      idid = PCSIM_ODE_root_found;
      break;
    }
    caljac = false;
    if (last) {
      h = hopt;
      idid = PCSIM_ODE_success;
      break;
    }
    fcn_(&n, &x, y, y0_, &ctx_, &ierr);
    ++nfcn;
    if (ierr != 0) {
      idid = PCSIM_ODE_callback_error;
      if (ierr == 1) {
        idid = PCSIM_ODE_rhs_failed;
        iwhat = 1;
      }
      break;
    }
    if (!finite_all(n, y0_)) {
      idid = PCSIM_ODE_non_finite;
      iwhat = 1;
      break;
    }
    hnew = posneg * std::min(std::abs(hnew), s_.hmaxn);
    hopt = posneg * std::min(std::abs(h), std::abs(hnew));
    if (reject) hnew = posneg * std::min(std::abs(hnew), std::abs(h));
    reject = false;
    const double qend = fixed ? 1.0001 : 1.0 / s_.quot1;
    if ((x + hnew * qend - xend) * posneg >= 0.0) {
      h = xend - x;
      last = true;
      needlu = true;
    } else {
      const double qt = hnew / h;
      if (!(theta <= s_.thet && qt >= s_.quot1 && qt <= s_.quot2)) {
        h = hnew;
        needlu = true;
      }
    }
    needj = theta > s_.thet || startz;  // slow convergence or a large state change
    if (needj) needlu = true;
  }

  // Label 900.
  if (naccpt == 0 && ksing && s_.nind2 + s_.nind3 == 0 &&
      (idid == PCSIM_ODE_newton_failure || idid == PCSIM_ODE_step_too_small))
    idid = PCSIM_ODE_missing_index_counts;
  istat_[0] = nfcn;
  istat_[1] = njac;
  istat_[2] = ndec;
  istat_[3] = nsol;
  istat_[4] = nstep;
  istat_[5] = naccpt;
  istat_[6] = nrejct;
  istat_[7] = nsing;
  istat_[8] = nfcnj;
  istat_[9] = nerrej;
  istat_[10] = nnewtr;
  istat_[11] = nfailr;
  istat_[12] = ngev;
  istat_[13] = iwhat;
  return idid;
}

}  // namespace

int integrate(pcsim_radau_fcn fcn, pcsim_radau_jac jac, pcsim_radau_solout solout,
              pcsim_radau_gfcn gfcn, void* ctx, int ijac, int imas, int itol, int iout, int ng,
              int n, double* t, double tend, double* y, double* h, const double* rtol,
              const double* atol, const double* am, int ldm, double* work, int lwork,
              double* zwork, int lzwork, int* iwork, int liwork) {
  // Argument checks in RADIIA's order: the first bad argument i gives -i.
  if (ijac != 0 && ijac != 1) return -6;
  if (imas < 0 || imas > 2) return -7;
  if (itol != 0 && itol != 1) return -8;
  if (iout != 0 && iout != 1) return -9;
  if (ng < 0) return -10;
  if (n < 1) return -11;
  if (!std::isfinite(*t)) return -12;
  if (!std::isfinite(tend)) return -13;
  if (std::isnan(*h)) return -15;
  if (ldm < 1) return -19;
  if (lwork < 20 + 23 * n + 4 * n * n + 4 * ng) return -21;
  if (lzwork < n * n + n) return -23;
  if (liwork < 30 + 3 * n + 2 * ng) return -25;

  Settings s{};
  s.ijac = ijac;
  s.imas = imas;
  s.iout = iout;
  s.ng = ng;
  s.n = n;
  bool bad = false;
  s.hmaxn = std::abs(tend - *t);
  if (work[0] < 0.0) bad = true;
  if (work[0] > 0.0) s.hmaxn = std::min(s.hmaxn, work[0]);
  s.hfix = work[1];
  if (s.hfix < 0.0) bad = true;
  s.safe = work[2] != 0.0 ? work[2] : 0.9;
  if (s.safe <= 0.001 || s.safe >= 1.0) bad = true;
  s.thet = work[3] != 0.0 ? work[3] : 0.001;
  if (s.thet < 0.0 || s.thet >= 1.0) bad = true;
  s.quot1 = work[5] != 0.0 ? work[5] : 1.0;
  s.quot2 = work[6] != 0.0 ? work[6] : 1.2;
  if (s.quot1 <= 0.0 || s.quot1 > 1.0 || s.quot2 < 1.0) bad = true;
  s.facl = work[7] != 0.0 ? work[7] : 5.0;
  s.facr = work[8] != 0.0 ? work[8] : 0.125;
  if (s.facl < 1.0 || s.facr <= 0.0 || s.facr > 1.0) bad = true;
  s.uround = work[9] != 0.0 ? work[9] : std::numeric_limits<double>::epsilon();
  if (!(s.uround > 1.0e-19 && s.uround < 1.0e-2)) bad = true;
  if (work[4] < 0.0) bad = true;
  if (bad) return -20;

  s.nmax = iwork[0] != 0 ? iwork[0] : 100000;
  s.nit = iwork[1] != 0 ? iwork[1] : 7;
  s.nind2 = iwork[2];
  s.nind3 = iwork[3];
  s.ipred = iwork[4];
  s.istrt = iwork[5];
  s.m1 = iwork[6];
  s.m2 = iwork[7] != 0 ? iwork[7] : s.m1;
  int ilapck = iwork[8];
  if (s.nmax < 1 || s.nit < 1 || s.nind2 < 0 || s.nind3 < 0 || s.nind2 + s.nind3 > n ||
      s.ipred < 0 || s.ipred > 1 || s.istrt < 0 || s.istrt > 1 || s.m1 < 0 || s.m2 < 0 ||
      ilapck < 0 || ilapck > 2)
    return -24;
  if (s.m1 > 0 && (s.m1 % s.m2 != 0 || s.m1 + s.m2 > n)) return -24;
  if (imas == 1 && ldm < n - s.m1) return -19;
  for (int i = 0; i < ng; ++i)
    if (std::abs(iwork[30 + i]) > 1) return -24;
  s.ilapck = ilapck == 0 ? (n - s.m1 <= 64 ? 0 : 1) : ilapck - 1;

  const int ntol = itol == 1 ? n : 1;
  const double huge = std::numeric_limits<double>::max();
  for (int i = 0; i < ntol; ++i)
    if (!(rtol[i] >= 10.0 * s.uround) || !(atol[i] > 0.0) || rtol[i] > huge || atol[i] > huge)
      return PCSIM_ODE_tolerance_too_small;

  // Work layout of RADIIA, from work[20]: Z(3n) W(3n) F(3n) Y0 SCAL RTOL' ATOL' CONT(4n) ...
  double* const w = work + 20;
  double* const rtt = w + 11 * n;
  double* const att = w + 12 * n;
  for (int i = 0; i < n; ++i) {
    const double r = itol == 0 ? rtol[0] : rtol[i];
    const double a = itol == 0 ? atol[0] : atol[i];
    const double quot = a / r;
    rtt[i] = 0.1 * std::pow(r, 2.0 / 3.0);
    att[i] = rtt[i] * quot;
  }
  const double tolst = rtt[0];
  s.fnewt = std::max(10.0 * s.uround / tolst, std::min(0.03, std::sqrt(tolst)));
  if (work[4] > 0.0) s.fnewt = work[4];

  for (int i = 10; i < 30; ++i) iwork[i] = 0;
  for (int i = 0; i < ng; ++i) iwork[30 + ng + i] = 0;
  if (tend == *t) return 0;

  Core core(s, fcn, jac, solout, gfcn, ctx, am, ldm, rtt, att, w,
            reinterpret_cast<std::complex<double>*>(zwork), iwork, iwork + 10);
  return core.run(*t, tend, y, *h);
}

int dense(int n, double t, double told, double tnew, const double* cont, int ldc, double* yout) {
  if (n < 1) return -1;
  if (tnew == told) return -4;
  if (ldc < std::max(1, n)) return -6;
  const double sq6 = std::sqrt(6.0);
  const double c1m1 = (4.0 - sq6) / 10.0 - 1.0;
  const double c2m1 = (4.0 + sq6) / 10.0 - 1.0;
  const double s = (t - tnew) / (tnew - told);
  for (int i = 0; i < n; ++i)
    yout[i] = cont[i] + s * (cont[i + ldc] + (s - c2m1) * (cont[i + 2 * ldc] +
                                                           (s - c1m1) * cont[i + 3 * ldc]));
  return 0;
}

void coefficients(double* c, double* t, double* ti, double* dd, double* gam, double* alp,
                  double* bet) {
  const double sq6 = std::sqrt(6.0);
  c[0] = (4.0 - sq6) / 10.0;
  c[1] = (4.0 + sq6) / 10.0;
  c[2] = 1.0;
  // Eigenvalues of A^-1 (real, complex pair), literals as in RADCOE.
  *gam = 3.6378342527444957322;
  *alp = 2.6810828736277521339;
  *bet = 3.0504301992474105694;
  dd[0] = -(13.0 + 7.0 * sq6) / 3.0;
  dd[1] = (-13.0 + 7.0 * sq6) / 3.0;
  dd[2] = -1.0 / 3.0;
  // Column-major 3 x 3: t[i + 3 j] = T(i+1, j+1).
  const double tv[9] = {9.1232394870892942792e-02, 0.24171793270710701896, 0.96604818261509293619,
                        -0.14125529502095420843, 0.20412935229379993199, 1.0,
                        -3.0029194105147424492e-02, 0.38294211275726193779, 0.0};
  const double tiv[9] = {4.3255798900631553510, -4.1787185915519047273, -0.50287263494578687595,
                         0.33919925181580986954, -0.32768282076106238708, 2.5719269498556054292,
                         0.54177053993587487119, 0.47662355450055045196, -0.59603920482822492497};
  for (int k = 0; k < 9; ++k) {
    t[k] = tv[k];
    ti[k] = tiv[k];
  }
}

}  // namespace pcsim::radau_port
