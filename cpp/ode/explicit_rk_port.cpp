// The C++ port of ERKDP8 (fortran/explicit_rk.f). Every decision, counter and formula follows
// the Fortran kernel line for line (the Fortran labels are named in the comments), in the same
// order of floating-point operations, so both kernels round identically and take the same
// steps. All storage comes from the caller's work arrays (same layout as the Fortran kernel):
// nothing is allocated per step.
#include "ode/explicit_rk_port.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "pcsim_ode_status.h"

namespace pcsim::explicit_rk_port {

namespace {

// The coefficients of fortran/explicit_rk_coef.inc, digit for digit (test_explicit_rk_kernel
// checks that both sides hold the same doubles).
constexpr double C2 = 0.526001519587677318785587544488e-01;
constexpr double C3 = 0.789002279381515978178381316732e-01;
constexpr double C4 = 0.118350341907227396726757197510e+00;
constexpr double C5 = 0.281649658092772603273242802490e+00;
constexpr double C6 = 0.333333333333333333333333333333e+00;
constexpr double C7 = 0.25e+00;
constexpr double C8 = 0.307692307692307692307692307692e+00;
constexpr double C9 = 0.651282051282051282051282051282e+00;
constexpr double C10 = 0.6e+00;
constexpr double C11 = 0.857142857142857142857142857142e+00;
constexpr double C14 = 0.1e+00;
constexpr double C15 = 0.2e+00;
constexpr double C16 = 0.777777777777777777777777777778e+00;
constexpr double A2_1 = 5.26001519587677318785587544488e-2;
constexpr double A3_1 = 1.97250569845378994544595329183e-2;
constexpr double A3_2 = 5.91751709536136983633785987549e-2;
constexpr double A4_1 = 2.95875854768068491816892993775e-2;
constexpr double A4_3 = 8.87627564304205475450678981324e-2;
constexpr double A5_1 = 2.41365134159266685502369798665e-1;
constexpr double A5_3 = -8.84549479328286085344864962717e-1;
constexpr double A5_4 = 9.24834003261792003115737966543e-1;
constexpr double A6_1 = 3.7037037037037037037037037037e-2;
constexpr double A6_4 = 1.70828608729473871279604482173e-1;
constexpr double A6_5 = 1.25467687566822425016691814123e-1;
constexpr double A7_1 = 3.7109375e-2;
constexpr double A7_4 = 1.70252211019544039314978060272e-1;
constexpr double A7_5 = 6.02165389804559606850219397283e-2;
constexpr double A7_6 = -1.7578125e-2;
constexpr double A8_1 = 3.70920001185047927108779319836e-2;
constexpr double A8_4 = 1.70383925712239993810214054705e-1;
constexpr double A8_5 = 1.07262030446373284651809199168e-1;
constexpr double A8_6 = -1.53194377486244017527936158236e-2;
constexpr double A8_7 = 8.27378916381402288758473766002e-3;
constexpr double A9_1 = 6.24110958716075717114429577812e-1;
constexpr double A9_4 = -3.36089262944694129406857109825e0;
constexpr double A9_5 = -8.68219346841726006818189891453e-1;
constexpr double A9_6 = 2.75920996994467083049415600797e1;
constexpr double A9_7 = 2.01540675504778934086186788979e1;
constexpr double A9_8 = -4.34898841810699588477366255144e1;
constexpr double A10_1 = 4.77662536438264365890433908527e-1;
constexpr double A10_4 = -2.48811461997166764192642586468e0;
constexpr double A10_5 = -5.90290826836842996371446475743e-1;
constexpr double A10_6 = 2.12300514481811942347288949897e1;
constexpr double A10_7 = 1.52792336328824235832596922938e1;
constexpr double A10_8 = -3.32882109689848629194453265587e1;
constexpr double A10_9 = -2.03312017085086261358222928593e-2;
constexpr double A11_1 = -9.3714243008598732571704021658e-1;
constexpr double A11_4 = 5.18637242884406370830023853209e0;
constexpr double A11_5 = 1.09143734899672957818500254654e0;
constexpr double A11_6 = -8.14978701074692612513997267357e0;
constexpr double A11_7 = -1.85200656599969598641566180701e1;
constexpr double A11_8 = 2.27394870993505042818970056734e1;
constexpr double A11_9 = 2.49360555267965238987089396762e0;
constexpr double A11_10 = -3.0467644718982195003823669022e0;
constexpr double A12_1 = 2.27331014751653820792359768449e0;
constexpr double A12_4 = -1.05344954667372501984066689879e1;
constexpr double A12_5 = -2.00087205822486249909675718444e0;
constexpr double A12_6 = -1.79589318631187989172765950534e1;
constexpr double A12_7 = 2.79488845294199600508499808837e1;
constexpr double A12_8 = -2.85899827713502369474065508674e0;
constexpr double A12_9 = -8.87285693353062954433549289258e0;
constexpr double A12_10 = 1.23605671757943030647266201528e1;
constexpr double A12_11 = 6.43392746015763530355970484046e-1;
constexpr double A14_1 = 5.61675022830479523392909219681e-2;
constexpr double A14_7 = 2.53500210216624811088794765333e-1;
constexpr double A14_8 = -2.46239037470802489917441475441e-1;
constexpr double A14_9 = -1.24191423263816360469010140626e-1;
constexpr double A14_10 = 1.5329179827876569731206322685e-1;
constexpr double A14_11 = 8.20105229563468988491666602057e-3;
constexpr double A14_12 = 7.56789766054569976138603589584e-3;
constexpr double A14_13 = -8.298e-3;
constexpr double A15_1 = 3.18346481635021405060768473261e-2;
constexpr double A15_6 = 2.83009096723667755288322961402e-2;
constexpr double A15_7 = 5.35419883074385676223797384372e-2;
constexpr double A15_8 = -5.49237485713909884646569340306e-2;
constexpr double A15_11 = -1.08347328697249322858509316994e-4;
constexpr double A15_12 = 3.82571090835658412954920192323e-4;
constexpr double A15_13 = -3.40465008687404560802977114492e-4;
constexpr double A15_14 = 1.41312443674632500278074618366e-1;
constexpr double A16_1 = -4.28896301583791923408573538692e-1;
constexpr double A16_6 = -4.69762141536116384314449447206e0;
constexpr double A16_7 = 7.68342119606259904184240953878e0;
constexpr double A16_8 = 4.06898981839711007970213554331e0;
constexpr double A16_9 = 3.56727187455281109270669543021e-1;
constexpr double A16_13 = -1.39902416515901462129418009734e-3;
constexpr double A16_14 = 2.9475147891527723389556272149e0;
constexpr double A16_15 = -9.15095847217987001081870187138e0;
constexpr double B1 = 5.42937341165687622380535766363e-2;
constexpr double B6 = 4.45031289275240888144113950566e0;
constexpr double B7 = 1.89151789931450038304281599044e0;
constexpr double B8 = -5.8012039600105847814672114227e0;
constexpr double B9 = 3.1116436695781989440891606237e-1;
constexpr double B10 = -1.52160949662516078556178806805e-1;
constexpr double B11 = 2.01365400804030348374776537501e-1;
constexpr double B12 = 4.47106157277725905176885569043e-2;
constexpr double BH1 = 0.244094488188976377952755905512e+00;
constexpr double BH9 = 0.733846688281611857341361741547e+00;
constexpr double BH12 = 0.220588235294117647058823529412e-01;
constexpr double ER1 = 0.1312004499419488073250102996e-01;
constexpr double ER6 = -0.1225156446376204440720569753e+01;
constexpr double ER7 = -0.4957589496572501915214079952e+00;
constexpr double ER8 = 0.1664377182454986536961530415e+01;
constexpr double ER9 = -0.3503288487499736816886487290e+00;
constexpr double ER10 = 0.3341791187130174790297318841e+00;
constexpr double ER11 = 0.8192320648511571246570742613e-01;
constexpr double ER12 = -0.2235530786388629525884427845e-01;
constexpr double D4_1 = -0.84289382761090128651353491142e+01;
constexpr double D4_6 = 0.56671495351937776962531783590e+00;
constexpr double D4_7 = -0.30689499459498916912797304727e+01;
constexpr double D4_8 = 0.23846676565120698287728149680e+01;
constexpr double D4_9 = 0.21170345824450282767155149946e+01;
constexpr double D4_10 = -0.87139158377797299206789907490e+00;
constexpr double D4_11 = 0.22404374302607882758541771650e+01;
constexpr double D4_12 = 0.63157877876946881815570249290e+00;
constexpr double D4_13 = -0.88990336451333310820698117400e-01;
constexpr double D4_14 = 0.18148505520854727256656404962e+02;
constexpr double D4_15 = -0.91946323924783554000451984436e+01;
constexpr double D4_16 = -0.44360363875948939664310572000e+01;
constexpr double D5_1 = 0.10427508642579134603413151009e+02;
constexpr double D5_6 = 0.24228349177525818288430175319e+03;
constexpr double D5_7 = 0.16520045171727028198505394887e+03;
constexpr double D5_8 = -0.37454675472269020279518312152e+03;
constexpr double D5_9 = -0.22113666853125306036270938578e+02;
constexpr double D5_10 = 0.77334326684722638389603898808e+01;
constexpr double D5_11 = -0.30674084731089398182061213626e+02;
constexpr double D5_12 = -0.93321305264302278729567221706e+01;
constexpr double D5_13 = 0.15697238121770843886131091075e+02;
constexpr double D5_14 = -0.31139403219565177677282850411e+02;
constexpr double D5_15 = -0.93529243588444783865713862664e+01;
constexpr double D5_16 = 0.35816841486394083752465898540e+02;
constexpr double D6_1 = 0.19985053242002433820987653617e+02;
constexpr double D6_6 = -0.38703730874935176555105901742e+03;
constexpr double D6_7 = -0.18917813819516756882830838328e+03;
constexpr double D6_8 = 0.52780815920542364900561016686e+03;
constexpr double D6_9 = -0.11573902539959630126141871134e+02;
constexpr double D6_10 = 0.68812326946963000169666922661e+01;
constexpr double D6_11 = -0.10006050966910838403183860980e+01;
constexpr double D6_12 = 0.77771377980534432092869265740e+00;
constexpr double D6_13 = -0.27782057523535084065932004339e+01;
constexpr double D6_14 = -0.60196695231264120758267380846e+02;
constexpr double D6_15 = 0.84320405506677161018159903784e+02;
constexpr double D6_16 = 0.11992291136182789328035130030e+02;
constexpr double D7_1 = -0.25693933462703749003312586129e+02;
constexpr double D7_6 = -0.15418974869023643374053993627e+03;
constexpr double D7_7 = -0.23152937917604549567536039109e+03;
constexpr double D7_8 = 0.35763911791061412378285349910e+03;
constexpr double D7_9 = 0.93405324183624310003907691704e+02;
constexpr double D7_10 = -0.37458323136451633156875139351e+02;
constexpr double D7_11 = 0.10409964950896230045147246184e+03;
constexpr double D7_12 = 0.29840293426660503123344363579e+02;
constexpr double D7_13 = -0.43533456590011143754432175058e+02;
constexpr double D7_14 = 0.96324553959188282948394950600e+02;
constexpr double D7_15 = -0.39177261675615439165231486172e+02;
constexpr double D7_16 = -0.14972683625798562581422125276e+03;

// The resolved options of ERKDP8.
struct Settings {
  int itol, iout, n, ng, nmax, istif, nstper, nfailm;
  double hmaxn, hfix, safe, facmin, facmax, tolr;
};

// Port of ERKFEV: 0 ok, 1 f cannot evaluate, 2 non-finite, 3 fatal.
int feval(pcsim_erk_fcn fcn, void* const* ctx, int n, double x, const double* yarg, double* f,
          int& nfcn) {
  int ierr = 0;
  fcn(&n, &x, yarg, f, ctx, &ierr);
  ++nfcn;
  if (ierr == 1) return 1;
  if (ierr != 0) return 3;
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(f[i])) return 2;
  return 0;
}

// Port of ERKGEV: 0 ok, 1 failure or non-finite g.
int geval(pcsim_erk_gfcn gfcn, void* const* ctx, int n, int ng, double x, const double* yarg,
          double* g, int& ngev) {
  int ierr = 0;
  gfcn(&n, &x, yarg, &ng, g, ctx, &ierr);
  ++ngev;
  if (ierr != 0) return 1;
  for (int i = 0; i < ng; ++i)
    if (!std::isfinite(g[i])) return 1;
  return 0;
}

// Port of ERKBRK.
bool bracket(int ng, const int* igdir, const double* ga, const double* gb, int* jroot) {
  bool brack = false;
  for (int i = 0; i < ng; ++i) {
    jroot[i] = 0;
    if (ga[i] != 0.0) {
      const int idir = ga[i] < 0.0 ? 1 : -1;
      if ((ga[i] < 0.0 && gb[i] >= 0.0) || (ga[i] > 0.0 && gb[i] <= 0.0)) {
        if (igdir[i] == 0 || igdir[i] == idir) {
          jroot[i] = idir;
          brack = true;
        }
      }
    }
  }
  return brack;
}

// Port of ERKROO. Returns 0, or 1 if the event functions failed; found/troot the result.
int locate_root(pcsim_erk_gfcn gfcn, void* const* ctx, int n, int ng, double told, double hd,
                const double* cont, double tlo, double thi, double tolx, const int* igdir,
                double* glo, double* ghi, double* gmid, double* yt, int* jroot, int* jt,
                double& troot, int& ngev, bool& found) {
  found = false;
  const double posneg = std::copysign(1.0, hd);
  double tl = tlo, th = thi;
  for (int i = 0; i < ng; ++i) jroot[i] = 0;
  bool anyz = false;
  for (int i = 0; i < ng; ++i)
    if (glo[i] == 0.0) anyz = true;
  if (anyz) {
    tl = tl + posneg * std::min(tolx, std::abs(th - tl));
    dense(n, tl, told, hd, cont, n, yt);
    if (geval(gfcn, ctx, n, ng, tl, yt, glo, ngev) != 0) return 1;
  }
  if (!bracket(ng, igdir, glo, ghi, jroot)) return 0;
  double wl = 1.0, wh = 1.0;
  int lastsd = 0, nslow = 0;
  double wprev = std::abs(th - tl);
  for (int iter = 1; iter <= 500; ++iter) {
    const double width = std::abs(th - tl);
    if (width <= tolx) break;
    double tm = th;
    for (int i = 0; i < ng; ++i) {
      if (jroot[i] != 0 && ghi[i] != 0.0) {
        const double fr = wh * ghi[i] / (wh * ghi[i] - wl * glo[i]);
        const double ti = th - fr * (th - tl);
        if ((ti - tm) * posneg < 0.0) tm = ti;
      }
    }
    if (nslow >= 2) {
      tm = tl + 0.5 * (th - tl);
      nslow = 0;
    }
    if (width <= 2.0 * tolx) {
      tm = tl + 0.5 * (th - tl);
    } else {
      double dist = (tm - tl) * posneg;
      if (dist < 0.5 * tolx) tm = tl + posneg * 0.5 * tolx;
      dist = (th - tm) * posneg;
      if (dist < 0.5 * tolx) tm = th - posneg * 0.5 * tolx;
    }
    dense(n, tm, told, hd, cont, n, yt);
    if (geval(gfcn, ctx, n, ng, tm, yt, gmid, ngev) != 0) return 1;
    if (bracket(ng, igdir, glo, gmid, jt)) {
      th = tm;
      for (int i = 0; i < ng; ++i) ghi[i] = gmid[i];
      if (lastsd == 1) wl = 0.5 * wl;
      wh = 1.0;
      lastsd = 1;
    } else {
      tl = tm;
      for (int i = 0; i < ng; ++i) glo[i] = gmid[i];
      if (lastsd == 2) wh = 0.5 * wh;
      wl = 1.0;
      lastsd = 2;
    }
    bracket(ng, igdir, glo, ghi, jroot);
    if (std::abs(th - tl) > 0.5 * wprev) {
      ++nslow;
    } else {
      nslow = 0;
      wprev = std::abs(th - tl);
    }
  }
  troot = th;
  found = true;
  return 0;
}

// Port of ERKCOR, the step loop.
int core(const Settings& s, pcsim_erk_fcn fcn, pcsim_erk_gfcn gfcn, pcsim_erk_solout solout,
         void* const* ctx, double& x, double xend, double* y, double& h, const double* rtol,
         const double* atol, double* w, double* gw, const int* igdir, int* jroot, int* jt,
         int* istat, double* wout) {
  const int n = s.n, ng = s.ng, itol = s.itol;
  double* kk[17];
  for (int j = 1; j <= 16; ++j) kk[j] = w + std::size_t(j - 1) * n;
  double* const k1 = kk[1];
  double* const k2 = kk[2];
  double* const k3 = kk[3];
  double* const k4 = kk[4];
  double* const k5 = kk[5];
  double* const k6 = kk[6];
  double* const k7 = kk[7];
  double* const k8 = kk[8];
  double* const k9 = kk[9];
  double* const k10 = kk[10];
  double* const k11 = kk[11];
  double* const k12 = kk[12];
  double* const k13 = kk[13];
  double* const k14 = kk[14];
  double* const k15 = kk[15];
  double* const k16 = kk[16];
  double* const y1 = w + std::size_t(16) * n;
  double* const yt = y1 + n;
  double* const ys = yt + n;
  double* const cont = ys + n;
  double* const cont1 = cont;
  double* const cont2 = cont + n;
  double* const cont3 = cont + 2 * std::size_t(n);
  double* const cont4 = cont + 3 * std::size_t(n);
  double* const cont5 = cont + 4 * std::size_t(n);
  double* const cont6 = cont + 5 * std::size_t(n);
  double* const cont7 = cont + 6 * std::size_t(n);
  double* const cont8 = cont + 7 * std::size_t(n);
  double* const glo = gw;
  double* const ghi = gw + ng;
  double* const gmid = gw + 2 * std::size_t(ng);

  const double uround = std::numeric_limits<double>::epsilon();
  int nfcn = 0, nstep = 0, naccpt = 0, nrejct = 0, nfail = 0, ngev = 0, nstifp = 0;
  int iasti = 0, nonsti = 0, kfail = 0, lfail = 0, ifail = 0, idid = PCSIM_ODE_success;
  bool stiff = false;
  const bool fixed = s.hfix > 0.0;
  const bool dense_needed = s.iout == 1 || ng > 0;
  const double posneg = std::copysign(1.0, xend - x);
  bool reject = false, last = false;
  double hlamb = 0.0, hnew = 0.0, xph = 0.0;
  auto tol_index = [itol](int i) { return itol * i; };

  // f and g at the initial state.
  ifail = feval(fcn, ctx, n, x, y, k1, nfcn);
  if (ifail != 0) goto l800;
  if (ng > 0 && geval(gfcn, ctx, n, ng, x, y, glo, ngev) != 0) {
    idid = PCSIM_ODE_callback_error;
    goto l900;
  }

  // Initial step size.
  if (fixed) {
    h = s.hfix;
  } else if (h == 0.0) {
    double dnf = 0.0, dny = 0.0;
    for (int i = 0; i < n; ++i) {
      const double sk = atol[tol_index(i)] + rtol[tol_index(i)] * std::abs(y[i]);
      const double qf = k1[i] / sk;
      const double qy = y[i] / sk;
      dnf = dnf + qf * qf;
      dny = dny + qy * qy;
    }
    if (dnf <= 1.0e-10 || dny <= 1.0e-10) {
      h = 1.0e-6;
    } else {
      h = std::sqrt(dny / dnf) * 0.01;
    }
    h = std::min(h, s.hmaxn) * posneg;
    for (int i = 0; i < n; ++i) yt[i] = y[i] + h * k1[i];
    ifail = feval(fcn, ctx, n, x + h, yt, k2, nfcn);
    if (ifail == 3) goto l800;
    if (ifail == 0) {
      double der2 = 0.0;
      for (int i = 0; i < n; ++i) {
        const double sk = atol[tol_index(i)] + rtol[tol_index(i)] * std::abs(y[i]);
        const double q = (k2[i] - k1[i]) / sk;
        der2 = der2 + q * q;
      }
      der2 = std::sqrt(der2) / std::abs(h);
      const double der12 = std::max(der2, std::sqrt(dnf));
      double h1;
      if (der12 <= 1.0e-15) {
        h1 = std::max(1.0e-6, std::abs(h) * 1.0e-3);
      } else {
        h1 = std::pow(0.01 / der12, 0.125);
      }
      h = std::min(std::min(100.0 * std::abs(h), h1), s.hmaxn) * posneg;
    }
  }
  h = std::min(std::abs(h), s.hmaxn) * posneg;
  hnew = h;

  // ---- Main loop (label 100): one step attempt from x with step h.
  for (;;) {
    if (nstep >= s.nmax) {
      idid = PCSIM_ODE_too_many_steps;
      goto l900;
    }
    if (0.1 * std::abs(h) <= std::abs(x) * uround) {
      if (lfail == 0) {
        idid = PCSIM_ODE_step_too_small;
        goto l900;
      }
      goto l810;
    }
    last = false;
    if ((x + 1.01 * h - xend) * posneg > 0.0) {
      h = xend - x;
      last = true;
    }
    ++nstep;

    // Stages 2 to 12.
    for (int i = 0; i < n; ++i) yt[i] = y[i] + h * (A2_1 * k1[i]);
    if ((ifail = feval(fcn, ctx, n, x + C2 * h, yt, k2, nfcn)) != 0) goto l700;
    for (int i = 0; i < n; ++i) yt[i] = y[i] + h * (A3_1 * k1[i] + A3_2 * k2[i]);
    if ((ifail = feval(fcn, ctx, n, x + C3 * h, yt, k3, nfcn)) != 0) goto l700;
    for (int i = 0; i < n; ++i) yt[i] = y[i] + h * (A4_1 * k1[i] + A4_3 * k3[i]);
    if ((ifail = feval(fcn, ctx, n, x + C4 * h, yt, k4, nfcn)) != 0) goto l700;
    for (int i = 0; i < n; ++i) yt[i] = y[i] + h * (A5_1 * k1[i] + A5_3 * k3[i] + A5_4 * k4[i]);
    if ((ifail = feval(fcn, ctx, n, x + C5 * h, yt, k5, nfcn)) != 0) goto l700;
    for (int i = 0; i < n; ++i) yt[i] = y[i] + h * (A6_1 * k1[i] + A6_4 * k4[i] + A6_5 * k5[i]);
    if ((ifail = feval(fcn, ctx, n, x + C6 * h, yt, k6, nfcn)) != 0) goto l700;
    for (int i = 0; i < n; ++i) yt[i] = y[i] + h * (A7_1 * k1[i] + A7_4 * k4[i] + A7_5 * k5[i] + A7_6 * k6[i]);
    if ((ifail = feval(fcn, ctx, n, x + C7 * h, yt, k7, nfcn)) != 0) goto l700;
    for (int i = 0; i < n; ++i) yt[i] = y[i] + h * (A8_1 * k1[i] + A8_4 * k4[i] + A8_5 * k5[i] + A8_6 * k6[i] + A8_7 * k7[i]);
    if ((ifail = feval(fcn, ctx, n, x + C8 * h, yt, k8, nfcn)) != 0) goto l700;
    for (int i = 0; i < n; ++i) yt[i] = y[i] + h * (A9_1 * k1[i] + A9_4 * k4[i] + A9_5 * k5[i] + A9_6 * k6[i] + A9_7 * k7[i] + A9_8 * k8[i]);
    if ((ifail = feval(fcn, ctx, n, x + C9 * h, yt, k9, nfcn)) != 0) goto l700;
    for (int i = 0; i < n; ++i) yt[i] = y[i] + h * (A10_1 * k1[i] + A10_4 * k4[i] + A10_5 * k5[i] + A10_6 * k6[i] + A10_7 * k7[i] + A10_8 * k8[i] + A10_9 * k9[i]);
    if ((ifail = feval(fcn, ctx, n, x + C10 * h, yt, k10, nfcn)) != 0) goto l700;
    for (int i = 0; i < n; ++i) yt[i] = y[i] + h * (A11_1 * k1[i] + A11_4 * k4[i] + A11_5 * k5[i] + A11_6 * k6[i] + A11_7 * k7[i] + A11_8 * k8[i] + A11_9 * k9[i] + A11_10 * k10[i]);
    if ((ifail = feval(fcn, ctx, n, x + C11 * h, yt, k11, nfcn)) != 0) goto l700;
    for (int i = 0; i < n; ++i) ys[i] = y[i] + h * (A12_1 * k1[i] + A12_4 * k4[i] + A12_5 * k5[i] + A12_6 * k6[i] + A12_7 * k7[i] + A12_8 * k8[i] + A12_9 * k9[i] + A12_10 * k10[i] + A12_11 * k11[i]);
    xph = x + h;
    if ((ifail = feval(fcn, ctx, n, xph, ys, k12, nfcn)) != 0) goto l700;

    // The new solution (increment in yt) and the error estimate (label 120).
    for (int i = 0; i < n; ++i) {
      yt[i] = B1 * k1[i] + B6 * k6[i] + B7 * k7[i] + B8 * k8[i] + B9 * k9[i] + B10 * k10[i] + B11 * k11[i] + B12 * k12[i];
      y1[i] = y[i] + h * yt[i];
    }
    for (int i = 0; i < n; ++i) {
      if (!std::isfinite(y1[i])) {
        ifail = 2;
        goto l700;
      }
    }
    {
      double err;
      if (fixed) {
        err = 0.0;
        hnew = h;
      } else {
        double err3 = 0.0, err5 = 0.0;
        for (int i = 0; i < n; ++i) {
          const int j = tol_index(i);
          const double sk = atol[j] + rtol[j] * std::max(std::abs(y[i]), std::abs(y1[i]));
          const double est3 = yt[i] - BH1 * k1[i] - BH9 * k9[i] - BH12 * k12[i];
          const double est5 = ER1 * k1[i] + ER6 * k6[i] + ER7 * k7[i] + ER8 * k8[i] + ER9 * k9[i] + ER10 * k10[i] + ER11 * k11[i] + ER12 * k12[i];
          const double q3 = est3 / sk;
          const double q5 = est5 / sk;
          err3 = err3 + q3 * q3;
          err5 = err5 + q5 * q5;
        }
        double deno = err5 + 0.01 * err3;
        if (deno <= 0.0) deno = 1.0;
        err = std::abs(h) * err5 * std::sqrt(1.0 / (double(n) * deno));
        if (!std::isfinite(err)) {
          ifail = 2;
          goto l700;
        }
        double fac;
        if (err == 0.0) {
          fac = s.facmax;
        } else {
          fac = std::min(s.facmax, std::max(s.facmin, s.safe * std::pow(err, -0.125)));
        }
        hnew = h * fac;
      }
      if (err > 1.0) {
        // ---- Error test failed (label 600): retry with the proposed step.
        ++nrejct;
        reject = true;
        h = hnew;
        continue;
      }
    }

    // ---- Error test passed: f at the new point and the dense-output stages.
    if ((ifail = feval(fcn, ctx, n, xph, y1, k13, nfcn)) != 0) goto l700;
    if (dense_needed) {
      for (int i = 0; i < n; ++i) yt[i] = y[i] + h * (A14_1 * k1[i] + A14_7 * k7[i] + A14_8 * k8[i] + A14_9 * k9[i] + A14_10 * k10[i] + A14_11 * k11[i] + A14_12 * k12[i] + A14_13 * k13[i]);
      if ((ifail = feval(fcn, ctx, n, x + C14 * h, yt, k14, nfcn)) != 0) goto l700;
      for (int i = 0; i < n; ++i) yt[i] = y[i] + h * (A15_1 * k1[i] + A15_6 * k6[i] + A15_7 * k7[i] + A15_8 * k8[i] + A15_11 * k11[i] + A15_12 * k12[i] + A15_13 * k13[i] + A15_14 * k14[i]);
      if ((ifail = feval(fcn, ctx, n, x + C15 * h, yt, k15, nfcn)) != 0) goto l700;
      for (int i = 0; i < n; ++i) yt[i] = y[i] + h * (A16_1 * k1[i] + A16_6 * k6[i] + A16_7 * k7[i] + A16_8 * k8[i] + A16_9 * k9[i] + A16_13 * k13[i] + A16_14 * k14[i] + A16_15 * k15[i]);
      if ((ifail = feval(fcn, ctx, n, x + C16 * h, yt, k16, nfcn)) != 0) goto l700;
      for (int i = 0; i < n; ++i) {
        cont1[i] = y[i];
        cont2[i] = y1[i] - y[i];
        cont3[i] = h * k1[i] - cont2[i];
        cont4[i] = cont2[i] - h * k13[i] - cont3[i];
        cont5[i] = h * (D4_1 * k1[i] + D4_6 * k6[i] + D4_7 * k7[i] + D4_8 * k8[i] + D4_9 * k9[i] + D4_10 * k10[i] + D4_11 * k11[i] + D4_12 * k12[i] + D4_13 * k13[i] + D4_14 * k14[i] + D4_15 * k15[i] + D4_16 * k16[i]);
        cont6[i] = h * (D5_1 * k1[i] + D5_6 * k6[i] + D5_7 * k7[i] + D5_8 * k8[i] + D5_9 * k9[i] + D5_10 * k10[i] + D5_11 * k11[i] + D5_12 * k12[i] + D5_13 * k13[i] + D5_14 * k14[i] + D5_15 * k15[i] + D5_16 * k16[i]);
        cont7[i] = h * (D6_1 * k1[i] + D6_6 * k6[i] + D6_7 * k7[i] + D6_8 * k8[i] + D6_9 * k9[i] + D6_10 * k10[i] + D6_11 * k11[i] + D6_12 * k12[i] + D6_13 * k13[i] + D6_14 * k14[i] + D6_15 * k15[i] + D6_16 * k16[i]);
        cont8[i] = h * (D7_1 * k1[i] + D7_6 * k6[i] + D7_7 * k7[i] + D7_8 * k8[i] + D7_9 * k9[i] + D7_10 * k10[i] + D7_11 * k11[i] + D7_12 * k12[i] + D7_13 * k13[i] + D7_14 * k14[i] + D7_15 * k15[i] + D7_16 * k16[i]);
      }
    }

    // ---- Step accepted.
    ++naccpt;
    kfail = 0;
    lfail = 0;
    if (s.istif >= 0) {
      double stnum = 0.0, stden = 0.0;
      for (int i = 0; i < n; ++i) {
        const double a = k13[i] - k12[i];
        const double b = y1[i] - ys[i];
        stnum = stnum + a * a;
        stden = stden + b * b;
      }
      if (stden > 0.0) {
        hlamb = std::abs(h) * std::sqrt(stnum / stden);
      } else {
        hlamb = 0.0;
      }
      if (hlamb > kStiffnessBound) {
        ++nstifp;
        ++iasti;
        nonsti = 0;
        if (iasti >= s.nstper && !stiff) {
          stiff = true;
          wout[1] = last ? xend : xph;
        }
      } else {
        ++nonsti;
        if (nonsti >= 6) iasti = 0;
      }
    }
    {
      const double xold = x;
      x = last ? xend : xph;
      for (int i = 0; i < n; ++i) {
        y[i] = y1[i];
        k1[i] = k13[i];
      }
      if (reject) hnew = posneg * std::min(std::abs(hnew), std::abs(h));
      reject = false;
      hnew = posneg * std::min(std::abs(hnew), s.hmaxn);

      // Events: the earliest sign change of g over [xold, x].
      bool found = false;
      if (ng > 0) {
        if (geval(gfcn, ctx, n, ng, x, y, ghi, ngev) != 0) {
          idid = PCSIM_ODE_callback_error;
          goto l900;
        }
        double tolx = s.tolr;
        if (tolx == 0.0) tolx = 100.0 * uround * (std::abs(x) + std::abs(h));
        double troot = 0.0;
        if (locate_root(gfcn, ctx, n, ng, xold, h, cont, xold, x, tolx, igdir, glo, ghi, gmid,
                        yt, jroot, jt, troot, ngev, found) != 0) {
          idid = PCSIM_ODE_callback_error;
          goto l900;
        }
        if (found) {
          x = troot;
          dense(n, x, xold, h, cont, n, y);
        }
      }

      // The step callback.
      bool modif = false;
      if (s.iout == 1) {
        int irtrn = 0;
        const double hd = h;
        solout(&n, &xold, &x, &hd, y, cont, &n, ctx, &irtrn);
        if (irtrn == 2) {
          idid = PCSIM_ODE_stopped_by_callback;
          goto l900;
        } else if (irtrn == 1) {
          modif = true;
        } else if (irtrn != 0) {
          idid = PCSIM_ODE_callback_error;
          goto l900;
        }
      }
      h = hnew;
      if (found) {
        idid = PCSIM_ODE_root_found;
        goto l900;
      }
      if (stiff && s.istif == 1) {
        idid = PCSIM_ODE_stiffness_detected;
        goto l900;
      }
      if (last) {
        idid = PCSIM_ODE_success;
        goto l900;
      }
      if (modif) {
        ifail = feval(fcn, ctx, n, x, y, k1, nfcn);
        if (ifail != 0) goto l800;
        if (ng > 0 && geval(gfcn, ctx, n, ng, x, y, glo, ngev) != 0) {
          idid = PCSIM_ODE_callback_error;
          goto l900;
        }
      } else {
        for (int i = 0; i < ng; ++i) glo[i] = ghi[i];
      }
    }
    continue;

  l700:
    // ---- f failed or was not finite during a step (label 700): retry with h/2.
    if (ifail == 3) {
      idid = PCSIM_ODE_callback_error;
      goto l900;
    }
    ++nfail;
    ++kfail;
    lfail = ifail;
    if (fixed || kfail >= s.nfailm) goto l810;
    h = h * 0.5;
    reject = true;
  }

l800:
  // ---- f failed at an accepted state.
  lfail = ifail;
  if (ifail == 3) {
    idid = PCSIM_ODE_callback_error;
    goto l900;
  }
l810:
  idid = lfail == 1 ? PCSIM_ODE_rhs_failed : PCSIM_ODE_non_finite;
l900:
  istat[0] = nfcn;
  istat[1] = nstep;
  istat[2] = naccpt;
  istat[3] = nrejct;
  istat[4] = nfail;
  istat[5] = ngev;
  istat[6] = nstifp;
  istat[7] = stiff ? 1 : 0;
  wout[0] = hlamb;
  return idid;
}

}  // namespace

int integrate(pcsim_erk_fcn fcn, pcsim_erk_gfcn gfcn, pcsim_erk_solout solout, void* ctx,
              int itol, int iout, int n, int ng, double* t, double tend, double* y, double* h,
              const double* rtol, const double* atol, double* work, int lwork, int* iwork,
              int liwork) {
  const double uround = std::numeric_limits<double>::epsilon();
  // Argument checks, in the order of ERKDP8.
  if (itol != 0 && itol != 1) return -5;
  if (iout != 0 && iout != 1) return -6;
  if (n < 1) return -7;
  if (ng < 0) return -8;
  if (!std::isfinite(*t)) return -9;
  if (!std::isfinite(tend)) return -10;
  if (!std::isfinite(*h)) return -12;
  if (lwork < 20 + 27 * n + 3 * ng) return -16;
  if (liwork < 20 + 3 * ng) return -18;
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(y[i])) return -11;

  Settings s{};
  s.itol = itol;
  s.iout = iout;
  s.n = n;
  s.ng = ng;
  bool bad = false;
  s.hmaxn = std::abs(tend - *t);
  if (!(work[0] >= 0.0)) bad = true;
  if (work[0] > 0.0) s.hmaxn = std::min(s.hmaxn, work[0]);
  s.hfix = work[1];
  if (!(s.hfix >= 0.0)) bad = true;
  s.safe = work[2] != 0.0 ? work[2] : 0.9;
  if (!(s.safe > 1.0e-4 && s.safe < 1.0)) bad = true;
  s.facmin = work[3] != 0.0 ? work[3] : 0.333;
  if (!(s.facmin > 0.0 && s.facmin <= 1.0)) bad = true;
  s.facmax = work[4] != 0.0 ? work[4] : 6.0;
  if (!(s.facmax >= 1.0)) bad = true;
  s.tolr = work[5];
  if (!(s.tolr >= 0.0)) bad = true;
  if (bad) return -15;
  s.nmax = iwork[0] != 0 ? iwork[0] : 100000;
  s.istif = iwork[1];
  s.nstper = iwork[2] != 0 ? iwork[2] : 15;
  s.nfailm = iwork[3] != 0 ? iwork[3] : 20;
  if (s.nmax < 1 || s.istif < -1 || s.istif > 1 || s.nstper < 1 || s.nfailm < 1) return -17;
  for (int i = 0; i < ng; ++i)
    if (std::abs(iwork[20 + ng + i]) > 1) return -17;
  for (int i = 0; i < 1 + itol * (n - 1); ++i) {
    if (!(rtol[i] >= 10.0 * uround) || !(atol[i] > 0.0) || !std::isfinite(rtol[i]) ||
        !std::isfinite(atol[i]))
      return PCSIM_ODE_tolerance_too_small;
  }
  for (int i = 10; i < 20; ++i) iwork[i] = 0;
  for (int i = 0; i < ng; ++i) iwork[20 + i] = 0;
  work[10] = 0.0;
  work[11] = 0.0;
  if (tend == *t) return PCSIM_ODE_success;
  void* const ctx_ref = ctx;
  return core(s, fcn, gfcn, solout, &ctx_ref, *t, tend, y, *h, rtol, atol, work + 20,
              work + 20 + 27 * std::size_t(n), iwork + 20 + ng, iwork + 20,
              iwork + 20 + 2 * ng, iwork + 10, work + 10);
}

int dense(int n, double t, double told, double hd, const double* cont, int ldc, double* yout) {
  if (n < 0) return -1;
  if (hd == 0.0) return -4;
  if (ldc < std::max(1, n)) return -6;
  const double s = (t - told) / hd;
  const double s1 = 1.0 - s;
  const std::size_t l = std::size_t(ldc);
  for (int i = 0; i < n; ++i) {
    yout[i] = cont[i] + s * (cont[i + l] + s1 * (cont[i + 2 * l] + s * (cont[i + 3 * l] +
              s1 * (cont[i + 4 * l] + s * (cont[i + 5 * l] + s1 * (cont[i + 6 * l] +
              s * cont[i + 7 * l]))))));
  }
  return 0;
}

void coefficients(double* a, double* b, double* c, double* bh, double* er, double* d) {
  for (int j = 0; j < 16; ++j) {
    b[j] = c[j] = bh[j] = er[j] = 0.0;
    for (int i = 0; i < 16; ++i) a[i + 16 * j] = 0.0;
    for (int i = 0; i < 4; ++i) d[i + 4 * j] = 0.0;
  }
  c[1] = C2;
  c[2] = C3;
  c[3] = C4;
  c[4] = C5;
  c[5] = C6;
  c[6] = C7;
  c[7] = C8;
  c[8] = C9;
  c[9] = C10;
  c[10] = C11;
  c[13] = C14;
  c[14] = C15;
  c[15] = C16;
  c[11] = 1.0;
  c[12] = 1.0;
  a[1 + 16 * 0] = A2_1;
  a[2 + 16 * 0] = A3_1;
  a[2 + 16 * 1] = A3_2;
  a[3 + 16 * 0] = A4_1;
  a[3 + 16 * 2] = A4_3;
  a[4 + 16 * 0] = A5_1;
  a[4 + 16 * 2] = A5_3;
  a[4 + 16 * 3] = A5_4;
  a[5 + 16 * 0] = A6_1;
  a[5 + 16 * 3] = A6_4;
  a[5 + 16 * 4] = A6_5;
  a[6 + 16 * 0] = A7_1;
  a[6 + 16 * 3] = A7_4;
  a[6 + 16 * 4] = A7_5;
  a[6 + 16 * 5] = A7_6;
  a[7 + 16 * 0] = A8_1;
  a[7 + 16 * 3] = A8_4;
  a[7 + 16 * 4] = A8_5;
  a[7 + 16 * 5] = A8_6;
  a[7 + 16 * 6] = A8_7;
  a[8 + 16 * 0] = A9_1;
  a[8 + 16 * 3] = A9_4;
  a[8 + 16 * 4] = A9_5;
  a[8 + 16 * 5] = A9_6;
  a[8 + 16 * 6] = A9_7;
  a[8 + 16 * 7] = A9_8;
  a[9 + 16 * 0] = A10_1;
  a[9 + 16 * 3] = A10_4;
  a[9 + 16 * 4] = A10_5;
  a[9 + 16 * 5] = A10_6;
  a[9 + 16 * 6] = A10_7;
  a[9 + 16 * 7] = A10_8;
  a[9 + 16 * 8] = A10_9;
  a[10 + 16 * 0] = A11_1;
  a[10 + 16 * 3] = A11_4;
  a[10 + 16 * 4] = A11_5;
  a[10 + 16 * 5] = A11_6;
  a[10 + 16 * 6] = A11_7;
  a[10 + 16 * 7] = A11_8;
  a[10 + 16 * 8] = A11_9;
  a[10 + 16 * 9] = A11_10;
  a[11 + 16 * 0] = A12_1;
  a[11 + 16 * 3] = A12_4;
  a[11 + 16 * 4] = A12_5;
  a[11 + 16 * 5] = A12_6;
  a[11 + 16 * 6] = A12_7;
  a[11 + 16 * 7] = A12_8;
  a[11 + 16 * 8] = A12_9;
  a[11 + 16 * 9] = A12_10;
  a[11 + 16 * 10] = A12_11;
  a[13 + 16 * 0] = A14_1;
  a[13 + 16 * 6] = A14_7;
  a[13 + 16 * 7] = A14_8;
  a[13 + 16 * 8] = A14_9;
  a[13 + 16 * 9] = A14_10;
  a[13 + 16 * 10] = A14_11;
  a[13 + 16 * 11] = A14_12;
  a[13 + 16 * 12] = A14_13;
  a[14 + 16 * 0] = A15_1;
  a[14 + 16 * 5] = A15_6;
  a[14 + 16 * 6] = A15_7;
  a[14 + 16 * 7] = A15_8;
  a[14 + 16 * 10] = A15_11;
  a[14 + 16 * 11] = A15_12;
  a[14 + 16 * 12] = A15_13;
  a[14 + 16 * 13] = A15_14;
  a[15 + 16 * 0] = A16_1;
  a[15 + 16 * 5] = A16_6;
  a[15 + 16 * 6] = A16_7;
  a[15 + 16 * 7] = A16_8;
  a[15 + 16 * 8] = A16_9;
  a[15 + 16 * 12] = A16_13;
  a[15 + 16 * 13] = A16_14;
  a[15 + 16 * 14] = A16_15;
  b[0] = B1;
  b[5] = B6;
  b[6] = B7;
  b[7] = B8;
  b[8] = B9;
  b[9] = B10;
  b[10] = B11;
  b[11] = B12;
  bh[0] = BH1;
  bh[8] = BH9;
  bh[11] = BH12;
  er[0] = ER1;
  er[5] = ER6;
  er[6] = ER7;
  er[7] = ER8;
  er[8] = ER9;
  er[9] = ER10;
  er[10] = ER11;
  er[11] = ER12;
  d[0 + 4 * 0] = D4_1;
  d[0 + 4 * 5] = D4_6;
  d[0 + 4 * 6] = D4_7;
  d[0 + 4 * 7] = D4_8;
  d[0 + 4 * 8] = D4_9;
  d[0 + 4 * 9] = D4_10;
  d[0 + 4 * 10] = D4_11;
  d[0 + 4 * 11] = D4_12;
  d[0 + 4 * 12] = D4_13;
  d[0 + 4 * 13] = D4_14;
  d[0 + 4 * 14] = D4_15;
  d[0 + 4 * 15] = D4_16;
  d[1 + 4 * 0] = D5_1;
  d[1 + 4 * 5] = D5_6;
  d[1 + 4 * 6] = D5_7;
  d[1 + 4 * 7] = D5_8;
  d[1 + 4 * 8] = D5_9;
  d[1 + 4 * 9] = D5_10;
  d[1 + 4 * 10] = D5_11;
  d[1 + 4 * 11] = D5_12;
  d[1 + 4 * 12] = D5_13;
  d[1 + 4 * 13] = D5_14;
  d[1 + 4 * 14] = D5_15;
  d[1 + 4 * 15] = D5_16;
  d[2 + 4 * 0] = D6_1;
  d[2 + 4 * 5] = D6_6;
  d[2 + 4 * 6] = D6_7;
  d[2 + 4 * 7] = D6_8;
  d[2 + 4 * 8] = D6_9;
  d[2 + 4 * 9] = D6_10;
  d[2 + 4 * 10] = D6_11;
  d[2 + 4 * 11] = D6_12;
  d[2 + 4 * 12] = D6_13;
  d[2 + 4 * 13] = D6_14;
  d[2 + 4 * 14] = D6_15;
  d[2 + 4 * 15] = D6_16;
  d[3 + 4 * 0] = D7_1;
  d[3 + 4 * 5] = D7_6;
  d[3 + 4 * 6] = D7_7;
  d[3 + 4 * 7] = D7_8;
  d[3 + 4 * 8] = D7_9;
  d[3 + 4 * 9] = D7_10;
  d[3 + 4 * 10] = D7_11;
  d[3 + 4 * 11] = D7_12;
  d[3 + 4 * 12] = D7_13;
  d[3 + 4 * 13] = D7_14;
  d[3 + 4 * 14] = D7_15;
  d[3 + 4 * 15] = D7_16;
}

}  // namespace pcsim::explicit_rk_port
