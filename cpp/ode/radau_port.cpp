// The C++ port of RADIIA (fortran/radau.f). Every decision, counter and formula follows the
// Fortran kernel line for line (same labels in the comments), in the same order of floating-point
// operations, and the linear algebra calls the same LAPACK/BLAS routines (DGETRF/ZGETRF,
// DGETRS/ZGETRS, DGEMV), so both kernels round identically and take the same steps. Why not
// Eigen's LU: the error estimate is a difference of terms ~1/tol times larger than itself, so a
// last-bit difference in an LU changes the next step size by ~eps/tol relative and, through the
// fast transitions of stiff problems, the trace by far more than 1e-9 (measured with
// Eigen::PartialPivLU: 1e-4 on van der Pol at rtol = 1e-10). All storage comes from the
// caller's work arrays (same layout as the Fortran kernel): nothing is allocated per step.
#include "ode/radau_port.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>

#include <Eigen/Dense>

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

using Mat = Eigen::Map<Eigen::MatrixXd>;
using CMat = Eigen::Map<Eigen::MatrixXcd>;

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


// The resolved options of RADIIA.
struct Settings {
  int ijac, imas, iout, n, nind2, nind3, nmax, nit, ipred, istrt;
  double hmaxn, hfix, safe, thet, fnewt, quot1, quot2, facl, facr;
};

// Port of RADJAC: Jacobian by the user or by forward differences (backward on IERR = 1).
int jacobian(pcsim_radau_fcn fcn, pcsim_radau_jac jac, void* const* ctx, const Settings& s,
             double x, double* y, const double* y0, double* fjac, double* t1, int& nfcn) {
  const int n = s.n;
  int ierr = 0;
  if (s.ijac == 1) {
    jac(&n, &x, y, fjac, &n, ctx, &ierr);
    return ierr;
  }
  const double eps = std::numeric_limits<double>::epsilon();
  for (int j = 0; j < n; ++j) {
    const double ysafe = y[j];
    double delt = std::sqrt(eps * std::max(1.0e-5, std::abs(ysafe)));
    y[j] = ysafe + delt;
    fcn(&n, &x, y, t1, ctx, &ierr);
    ++nfcn;
    if (ierr == 1) {
      delt = -delt;
      y[j] = ysafe + delt;
      fcn(&n, &x, y, t1, ctx, &ierr);
      ++nfcn;
    }
    y[j] = ysafe;
    if (ierr != 0) return ierr;
    for (int i = 0; i < n; ++i) fjac[i + n * j] = (t1[i] - y0[i]) / delt;
  }
  return 0;
}

// The step loop: port of RADCOR.
class Core {
 public:
  Core(const Settings& s, pcsim_radau_fcn fcn, pcsim_radau_jac jac, pcsim_radau_solout solout,
       void* ctx, const double* am, int ldm, const double* rtt, const double* att, double* w,
       std::complex<double>* zw, int* ip1, int* ip2, int* istat)
      : s_(s), fcn_(fcn), jac_(jac), solout_(solout), ctx_(ctx), am_(am), ldm_(ldm), rtt_(rtt),
        att_(att), n_(s.n), k_(make_coefficients()), ip1_(ip1), ip2_(ip2), istat_(istat) {
    const int n = n_;
    z1_ = w;        z2_ = z1_ + n;  z3_ = z2_ + n;
    w1_ = z3_ + n;  w2_ = w1_ + n;  w3_ = w2_ + n;
    f1_ = w3_ + n;  f2_ = f1_ + n;  f3_ = f2_ + n;
    y0_ = f3_ + n;  scal_ = y0_ + n;
    cont_ = scal_ + 3 * n;  // after SCAL, RTOL', ATOL' (which the caller placed there)
    t1_ = cont_ + 4 * n;    t2_ = t1_ + n;
    fjac_ = t2_ + n;        e1_ = fjac_ + n * n;
    e2_ = zw;               zt_ = zw + n * n;
  }

  int run(double& x, double xend, double* y, double& h);

 private:
  bool decompose(double fac1, double alphn, double betan);
  void solve();
  int estimate(double x, double h, const double* y, bool refine, int& nfcn, int& nsol,
               double& err);
  void mass_times(const double* v, double* out) const;

  const Settings s_;
  pcsim_radau_fcn fcn_;
  pcsim_radau_jac jac_;
  pcsim_radau_solout solout_;
  void* ctx_;
  const double* am_;
  int ldm_;
  const double *rtt_, *att_;
  int n_;
  Coefficients k_;
  int *ip1_, *ip2_;
  int* istat_;
  double *z1_, *z2_, *z3_, *w1_, *w2_, *w3_, *f1_, *f2_, *f3_, *y0_, *scal_, *cont_, *t1_,
      *t2_, *fjac_, *e1_;
  std::complex<double>*e2_, *zt_;
};

void Core::mass_times(const double* v, double* out) const {
  const double one = 1.0, zero = 0.0;
  const int inc = 1;
  dgemv_("N", &n_, &n_, &one, am_, &ldm_, v, &inc, &zero, out, &inc, 1);
}

// Port of RADDEC: E1 = fac1 K - J, E2 = (alphn + i betan) K - J, both LU-factored.
bool Core::decompose(double fac1, double alphn, double betan) {
  const int n = n_;
  Mat e1(e1_, n, n);
  CMat e2(e2_, n, n);
  const std::complex<double> zfac(alphn, betan);
  if (s_.imas == 1) {
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double a = am_[i + ldm_ * j];
        const double jij = fjac_[i + n * j];
        e1(i, j) = fac1 * a - jij;
        e2(i, j) = std::complex<double>(alphn * a - jij, betan * a);
      }
  } else {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        e1(i, j) = -fjac_[i + n * j];
        e2(i, j) = std::complex<double>(-fjac_[i + n * j], 0.0);
      }
      e1(j, j) = e1(j, j) + fac1;
      e2(j, j) = e2(j, j) + zfac;
    }
  }
  int info1 = 0, info2 = 0;
  dgetrf_(&n, &n, e1_, &n, ip1_, &info1);
  zgetrf_(&n, &n, e2_, &n, ip2_, &info2);
  return info1 == 0 && info2 == 0;
}

// Port of RADSLV: E1 x1 = F1, E2 (x2 + i x3) = F2 + i F3, in place.
void Core::solve() {
  const int n = n_, one = 1;
  int info = 0;
  dgetrs_("N", &n, &one, e1_, &n, ip1_, f1_, &n, &info, 1);
  for (int i = 0; i < n; ++i) zt_[i] = std::complex<double>(f2_[i], f3_[i]);
  zgetrs_("N", &n, &one, e2_, &n, ip2_, zt_, &n, &info, 1);
  for (int i = 0; i < n; ++i) {
    f2_[i] = zt_[i].real();
    f3_[i] = zt_[i].imag();
  }
}


// Port of RADEST: the filtered error estimate (T1 = K v, T2 = e, F1 = f(x, y + e)).
int Core::estimate(double x, double h, const double* y, bool refine, int& nfcn, int& nsol,
                   double& err) {
  const int n = n_;
  const double hee1 = k_.dd[0] / h, hee2 = k_.dd[1] / h, hee3 = k_.dd[2] / h;
  for (int i = 0; i < n; ++i) t1_[i] = hee1 * z1_[i] + hee2 * z2_[i] + hee3 * z3_[i];
  if (s_.imas == 1) {
    mass_times(t1_, t2_);
    for (int i = 0; i < n; ++i) t1_[i] = t2_[i];
  }
  const int one = 1;
  int info = 0;
  for (int i = 0; i < n; ++i) t2_[i] = y0_[i] + t1_[i];
  dgetrs_("N", &n, &one, e1_, &n, ip1_, t2_, &n, &info, 1);
  ++nsol;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) sum += (t2_[i] / scal_[i]) * (t2_[i] / scal_[i]);
  err = std::max(std::sqrt(sum / double(n)), 1.0e-10);
  if (err < 1.0 || !refine) return 0;

  for (int i = 0; i < n; ++i) t2_[i] = y[i] + t2_[i];
  int ierr = 0;
  fcn_(&n, &x, t2_, f1_, &ctx_, &ierr);
  ++nfcn;
  if (ierr != 0) return ierr;
  for (int i = 0; i < n; ++i) t2_[i] = f1_[i] + t1_[i];
  dgetrs_("N", &n, &one, e1_, &n, ip1_, t2_, &n, &info, 1);
  ++nsol;
  sum = 0.0;
  for (int i = 0; i < n; ++i) sum += (t2_[i] / scal_[i]) * (t2_[i] / scal_[i]);
  err = std::max(std::sqrt(sum / double(n)), 1.0e-10);
  return 0;
}

int Core::run(double& x, double xend, double* y, double& h) {
  const int n = n_;
  const double uround = std::numeric_limits<double>::epsilon();
  const double c1m1 = k_.c[0] - 1.0, c2m1 = k_.c[1] - 1.0, c1mc2 = k_.c[0] - k_.c[1];
  const auto& ti = k_.ti;
  const auto& tt = k_.t;
  const int nind1 = n - s_.nind2 - s_.nind3;
  const int nit = s_.nit;

  int nfcn = 0, njac = 0, ndec = 0, nsol = 0, nstep = 0, naccpt = 0, nrejct = 0, nsing = 0;
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
       needlu = true;
  double xold = x, fac1 = 0.0, alphn = 0.0, betan = 0.0, hnew = h, err = 0.0, quot = 1.0;
  double dynold = 0.0, thqold = 0.0;

  // The labels of RADCOR, as the states of one loop.
  enum class Next { main, newton_failure, slow_rejection, exit };
  Next next = Next::main;

  fcn_(&n, &x, y, y0_, &ctx_, &ierr);
  ++nfcn;
  if (ierr != 0) {
    idid = PCSIM_ODE_callback_error;
    next = Next::exit;
  }

  while (next != Next::exit) {
    if (next == Next::newton_failure || next == Next::slow_rejection) {  // labels 400, 395
      if (next == Next::newton_failure) {
        if (fixed) {
          if (caljac) {
            idid = PCSIM_ODE_step_too_small;
            break;
          }
        } else {
          h = h * 0.5;
        }
      }
      reject = true;
      last = false;
      ++nrejct;
      needlu = true;
      needj = !caljac;
      next = Next::main;
    }
    // Label 100: Jacobian if stale, LU if h changed.
    if (needj) {
      ierr = jacobian(fcn_, jac_, &ctx_, s_, x, y, y0_, fjac_, t1_, nfcn);
      ++njac;
      if (ierr != 0) {
        idid = PCSIM_ODE_callback_error;
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
        if (nsing > 5) {
          idid = PCSIM_ODE_singular_matrix;
          break;
        }
        if (fixed) {
          idid = PCSIM_ODE_step_too_small;
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
      idid = PCSIM_ODE_step_too_small;
      break;
    }
    ++nstep;
    const double habs = std::abs(h);
    for (int i = 0; i < n; ++i) scal_[i] = att_[i] + rtt_[i] * std::abs(y[i]);
    for (int i = nind1; i < nind1 + s_.nind2; ++i) scal_[i] = scal_[i] / habs;
    for (int i = nind1 + s_.nind2; i < n; ++i) scal_[i] = scal_[i] / (habs * habs);

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
      if (ierr != 0) break;
      for (int i = 0; i < n; ++i) t1_[i] = y[i] + z2_[i];
      xs = x + k_.c[1] * h;
      fcn_(&n, &xs, t1_, f2_, &ctx_, &ierr);
      ++nfcn;
      if (ierr != 0) break;
      for (int i = 0; i < n; ++i) t1_[i] = y[i] + z3_[i];
      xs = x + h;
      fcn_(&n, &xs, t1_, f3_, &ctx_, &ierr);
      ++nfcn;
      if (ierr != 0) break;
      if (s_.imas == 1) {
        mass_times(w1_, z1_);
        mass_times(w2_, z2_);
        mass_times(w3_, z3_);
      } else {
        for (int i = 0; i < n; ++i) {
          z1_[i] = w1_[i];
          z2_[i] = w2_[i];
          z3_[i] = w3_[i];
        }
      }
      for (int i = 0; i < n; ++i) {
        const double a1 = f1_[i], a2 = f2_[i], a3 = f3_[i];
        f1_[i] = ti[0][0] * a1 + ti[0][1] * a2 + ti[0][2] * a3 - fac1 * z1_[i];
        f2_[i] = ti[1][0] * a1 + ti[1][1] * a2 + ti[1][2] * a3 - alphn * z2_[i] + betan * z3_[i];
        f3_[i] = ti[2][0] * a1 + ti[2][1] * a2 + ti[2][2] * a3 - betan * z2_[i] - alphn * z3_[i];
      }
      solve();
      ++nsol;
      ++newt;
      double sum = 0.0;
      for (int i = 0; i < n; ++i) {
        const double a = f1_[i] / scal_[i], b = f2_[i] / scal_[i], c = f3_[i] / scal_[i];
        sum = sum + a * a + b * b + c * c;
      }
      const double dyno = std::sqrt(sum / double(3 * n));
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
            next = Next::slow_rejection;
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
    if (!converged) {
      if (next == Next::main) {  // f failed (label 390)
        if (ierr != 1) {
          idid = PCSIM_ODE_callback_error;
          break;
        }
        next = Next::newton_failure;
      }
      continue;
    }

    // Label 500: error estimate and step-size proposal.
    if (fixed) {
      err = 0.0;
      hnew = h;
      quot = 1.0;
    } else {
      ierr = estimate(x, h, y, first || reject, nfcn, nsol, err);
      if (ierr != 0) {
        if (ierr != 1) {
          idid = PCSIM_ODE_callback_error;
          break;
        }
        next = Next::newton_failure;
        continue;
      }
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
      needlu = true;
      needj = !caljac;
      continue;
    }

    // Step accepted.
    first = false;
    ++naccpt;
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
    {
      double* c0 = cont_;
      double* c1 = cont_ + n;
      double* c2 = cont_ + 2 * n;
      double* c3 = cont_ + 3 * n;
      for (int i = 0; i < n; ++i) {
        const double ak1 = (z2_[i] - z3_[i]) / c2m1;
        double ak2 = (z1_[i] - z2_[i]) / c1mc2;
        const double a1 = z1_[i] / k_.c[0];
        const double a2 = (ak2 - a1) / k_.c[1];
        ak2 = (ak2 - ak1) / c1m1;
        y[i] = y[i] + z3_[i];
        c0[i] = y[i];
        c1[i] = ak1;
        c2[i] = ak2;
        c3[i] = ak2 - a2;
      }
    }
    startz = false;
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

  istat_[0] = nfcn;
  istat_[1] = njac;
  istat_[2] = ndec;
  istat_[3] = nsol;
  istat_[4] = nstep;
  istat_[5] = naccpt;
  istat_[6] = nrejct;
  istat_[7] = nsing;
  return idid;
}

}  // namespace

int integrate(pcsim_radau_fcn fcn, pcsim_radau_jac jac, pcsim_radau_solout solout, void* ctx,
              int ijac, int imas, int itol, int iout, int n, double* t, double tend, double* y,
              double* h, const double* rtol, const double* atol, const double* am, int ldm,
              double* work, int lwork, double* zwork, int lzwork, int* iwork, int liwork) {
  // Argument checks in RADIIA's order: the first bad argument i gives -i.
  if (ijac != 0 && ijac != 1) return -5;
  if (imas != 0 && imas != 1) return -6;
  if (itol != 0 && itol != 1) return -7;
  if (iout != 0 && iout != 1) return -8;
  if (n < 1) return -9;
  if (!std::isfinite(*t)) return -10;
  if (!std::isfinite(tend)) return -11;
  if (std::isnan(*h)) return -13;
  const int ntol = itol == 1 ? n : 1;
  for (int i = 0; i < ntol; ++i)
    if (!(rtol[i] > 0.0)) return -14;
  for (int i = 0; i < ntol; ++i)
    if (!(atol[i] > 0.0)) return -15;
  if (ldm < std::max(1, imas * n)) return -17;
  if (lwork < 20 + 19 * n + 2 * n * n) return -19;
  if (lzwork < n * n + n) return -21;
  if (liwork < 20 + 2 * n) return -23;

  Settings s{};
  s.ijac = ijac;
  s.imas = imas;
  s.iout = iout;
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
  if (bad) return -18;

  s.nmax = iwork[0] != 0 ? iwork[0] : 100000;
  s.nit = iwork[1] != 0 ? iwork[1] : 7;
  s.nind2 = iwork[2];
  s.nind3 = iwork[3];
  s.ipred = iwork[4];
  s.istrt = iwork[5];
  if (s.nmax < 1 || s.nit < 1 || s.nind2 < 0 || s.nind3 < 0 || s.nind2 + s.nind3 > n ||
      s.ipred < 0 || s.ipred > 1 || s.istrt < 0 || s.istrt > 1)
    return -22;

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
  const double uround = std::numeric_limits<double>::epsilon();
  s.fnewt = std::max(10.0 * uround / tolst, std::min(0.03, std::sqrt(tolst)));
  if (work[4] < 0.0) return -18;
  if (work[4] > 0.0) s.fnewt = work[4];

  for (int i = 10; i < 20; ++i) iwork[i] = 0;
  if (tend == *t) return 0;

  Core core(s, fcn, jac, solout, ctx, am, ldm, rtt, att, w,
            reinterpret_cast<std::complex<double>*>(zwork), iwork + 20, iwork + 20 + n, iwork + 10);
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
