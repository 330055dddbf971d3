#!/usr/bin/env python3
"""pcsim's switching contacts side by side with Siconos (issue 12).

Simulates two shared problems with Siconos's own Moreau-Jean time stepping (siconos.kernel, the
reference for nonsmooth mechanics) and compares the impact times and velocities with the
events.csv that `pcsim run` wrote for the same cases:

  - the bouncing ball of cases/bouncing_ball.toml (m = 1, g = 9.81, dropped from 1 m, e = 0.5):
    per impact its time, the velocity before and the velocity after;
  - the rocking block of cases/rocking_block.toml (10 kg, half-width 0.1 m, half-height 0.3 m,
    released at 0.1 rad on its left corner, e = 0, mu = 1): per impact its time, the corner
    that lands, its normal velocity before, and the normal velocity after of the corner that
    lifts off (Housner's factor; the landing corner's own velocity after is 0 on both sides).

The parameters are read from the two case files and their model files, so the two programs
simulate the same problem. Usage (from the repository root, after a Release build; not a CTest
test, it needs the Siconos Python bindings, which pcsim itself does not):

    apt-get install python3-siconos     # Debian package, installed for /usr/bin/python3 only
    build/pcsim run cases/bouncing_ball.toml --out out/bouncing_ball
    build/pcsim run cases/rocking_block.toml --out out/rocking_block
    /usr/bin/python3 scripts/siconos_compare.py out/bouncing_ball out/rocking_block

The rocking block's corners are LagrangianScleronomousR relations with C plugins (h and its
Jacobian G0), which this script writes and compiles with `cc` into a temporary directory: in
Siconos 4.4 a relation subclassed in Python crashes the kernel (its SWIG director passes the
BlockVector arguments as numpy copies; with computeh/computeJachq/computeDotJachq overridden,
even as no-ops, MoreauJeanOSI::computeFreeOutput then calls through a freed object).

Which side is accurate, and the criterion
-----------------------------------------
pcsim is event-driven: each impact is located by root finding on the dense output of an
integrator run at rtol = atol = 1e-10, so its impact times and velocities are exact to about
1e-10 (test_switching_bouncing_ball against the geometric series). Siconos's Moreau-Jean scheme
(theta = 1/2) is a time-stepping scheme of first order in the presence of impacts: it does not
locate an impact, it applies the impulse in the step whose predicted gap y + h/2 y' closes, and
reports the velocity at the step's end. With the Siconos values taken as the step's end time
t_{n+1} and the velocity at the end of the step before (the last one of the flight), a single
impact is off by at most about h in time and by the change of the velocity over a step, |a| h,
in velocity (a the acceleration of the gap in flight, g for the ball). These errors are carried
to the following impacts: the velocity after impact k is e times (ball) or Housner's factor
times (block) a velocity that was off by |a| h, and the flight or the rotation that follows
lasts longer or shorter accordingly, so the error of impact k grows with k (the lead measured
1.5e-4 to 2.2e-4 s at impacts 2..8 of the ball with h = 1e-4 s). A tolerance |dt| <= h per
impact is therefore wrong, and a relative velocity tolerance is meaningless as the velocities
shrink geometrically.

The criterion is convergence, with the event-driven values as the limit. Siconos runs at
h0 = 1e-4 s, h0/4 and h0/16. For each compared quantity Q (impact time, velocity before,
velocity after) the error is E_Q(h) = max over the first N impacts of |Q_siconos(h) - Q_pcsim|.
The comparison passes when, for every quantity:

  1. the same contacts land in the same order in the first N impacts, at every h;
  2. every error is within the leading-order bound of the scheme at every h. Let a be the
     largest normal acceleration of the landing contact in flight (g for the ball; for the
     block the corner's, computed from the rotation about the other corner), r the ratio of
     successive approach speeds (e for the ball, Housner's factor for the block, from pcsim's
     values) and e the restitution. Siconos applies an impulse in the step [t_m, t_m + h] when
     the gap predicted at its middle, y + (h/2) y', is closed at t_m, so t_m lies within h/2 of
     the true impact t* and the reported time t_m + h is h/2 to 3h/2 late. The velocity before
     (that at t_m) is then off by a h/2; the bound allows a h, the factor 2 covering the terms
     of second order left out of this count (the gap's curvature over a step, the change of
     the Jacobian). The penetration left by the impact (at most h |v|(1 - e)/2 with
     theta = 1/2) changes the next landing speed by a h (1 - e)/(2 r), and
     the errors of earlier impacts are carried on multiplied by r, so
         |d v| <= dv_max = a h (1 + (1 - e)/(2 r)) / (1 - r)       (both v- and v+).
     Impact k's time collects, from each impact j <= k, the detection lag 3h/2, the penetration's
     shift h (1 - e)/(2 r), and the change of the flight (ball, 2/g per m/s) or rocking
     half-cycle (block, Housner's linearized T(w) = (2/p) atanh(w/(p alpha)), its derivative at
     pcsim's w) caused by a velocity off by dv_max:
         |d t_k| <= sum_{j<=k} [3h/2 + (j > 1) (h (1 - e)/(2 r) + S_{j-1} dv_max)].
     These bounds are worst cases (errors of successive impacts add with one sign); the observed
     errors are 1.3 (the ball's velocities) to 30 times smaller, so condition 3 carries the
     comparison;
  3. the errors shrink like h: E_Q(h)/E_Q(h/4) >= 2 between consecutive step sizes, i.e. an
     observed order log4(ratio) >= 1/2. A first-order method gives 4; the margin covers the
     position of each impact inside its step, which changes irregularly with h (the error of
     one impact is h times a fractional part), while a disagreement of the models (another e,
     another inertia, a wrong contact point) would leave an error that does not shrink.
     Quantities that are already below pcsim's accuracy at h (E < 1e-9: the velocities after
     a plastic landing, 0 on both sides) are exempt from the ratio.

The script prints every pair at every step size, the errors and the ratios, and exits 1 if a
condition fails, 0 otherwise.
"""
import csv
import math
import os
import subprocess
import sys
import tempfile
import tomllib

# Siconos links OpenBLAS, which busy-waits its threads: with the 2 cores shared this made the
# time stepping 200 times slower. One thread, as pcsim's own LCP plugin does.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

try:
    import numpy as np
    import siconos.kernel as sk
    import siconos.numerics as sn
except ImportError as e:  # pragma: no cover
    sys.exit("siconos_compare.py needs the Siconos Python bindings (Debian: python3-siconos, "
             "for /usr/bin/python3) and numpy: " + str(e))

H0 = 1e-4           # s, the coarsest Siconos step
REFINE = (1, 4, 16)  # h = H0 / r
RATIO_MIN = 2.0     # E(h)/E(h/4) at least this: observed order >= 1/2
E_FLOOR = 1e-9      # errors below pcsim's own accuracy are not asked to shrink


def load_case(case_path):
    """The case's parameters (model defaults overridden by the case) and its initial values."""
    with open(case_path, "rb") as f:
        case = tomllib.load(f)
    model_path = os.path.join(os.path.dirname(case_path), case["model"])
    with open(model_path, "rb") as f:
        model = tomllib.load(f)["model"]
    p = {k: v["value"] for k, v in model.get("parameters", {}).items()}
    p.update(case.get("parameters", {}))
    return p, case.get("initial", {}), case["solver"]["t_end"]


def pcsim_impacts(out_dir, with_lift_off=False):
    """[(t, constraint, vn_before, vn_after)] of every impact in a pcsim events.csv; with
    with_lift_off, vn_after is that of the contact lifted off at the same instant."""
    rows = list(csv.DictReader(open(os.path.join(out_dir, "events.csv"))))
    impacts = []
    for r in rows:
        if r["kind"] not in ("impact", "accumulation"):
            continue
        t, vb, va = float(r["t"]), float(r["vn_before"]), float(r["vn_after"])
        if with_lift_off:
            lifts = [s for s in rows if s["kind"] == "lift_off" and float(s["t"]) == t]
            va = float(lifts[0]["vn_after"]) if lifts else float("nan")
        impacts.append((t, r["constraint"], vb, va))
    return impacts


def time_stepping(nsds, h, osnsp, record):
    """Moreau-Jean (theta = 1/2) from 0 to the system's final time; record(t) after each step."""
    simulation = sk.TimeStepping(nsds, sk.TimeDiscretisation(0.0, h), sk.MoreauJeanOSI(0.5), osnsp)
    while simulation.hasNextEvent():
        simulation.computeOneStep()
        record(simulation.nextTime())
        simulation.nextStep()


def ball(p, init, h, t_end):
    m, g, e = p["m"], p["g"], p["e_n"]
    body = sk.LagrangianLinearTIDS([init["y"]], [0.0], [[m]])
    body.setFExtPtr([-m * g])
    inter = sk.Interaction(sk.NewtonImpactNSL(e), sk.LagrangianLinearTIR([[1.0]]))
    nsds = sk.NonSmoothDynamicalSystem(0.0, t_end)
    nsds.insertDynamicalSystem(body)
    nsds.link(inter, body)
    v = body.velocity()
    impacts = []
    state = {"v": 0.0}

    def record(t):
        # an impact: the velocity turned from falling to rising within the step
        if state["v"] < -1e-6 and v[0] >= 0.0:
            impacts.append((t, "floor", state["v"], v[0]))
        state["v"] = v[0]
    time_stepping(nsds, h, sk.LCP(), record)
    return impacts


CORNER_C = r"""
/* The rocking block's bottom corners for Siconos's LagrangianScleronomousR (written by
   scripts/siconos_compare.py): q = (x, y, theta), corner (s b, -hh) of the body frame,
   s = -1 left, +1 right; y[0] its height over the floor, y[1] its horizontal position. */
#include <math.h>
static void h_corner(double s, const double* q, double* y, unsigned ny) {
  double sn = sin(q[2]), cs = cos(q[2]);
  y[0] = q[1] + s * B * sn - HH * cs;
  if (ny > 1) y[1] = q[0] + s * B * cs + HH * sn;
}
static void G0_corner(double s, const double* q, double* J, unsigned ny) {
  double sn = sin(q[2]), cs = cos(q[2]);   /* ny x 3, column-major */
  J[0] = 0.0; J[ny] = 1.0; J[2 * ny] = s * B * cs + HH * sn;
  if (ny > 1) { J[1] = 1.0; J[ny + 1] = 0.0; J[2 * ny + 1] = -s * B * sn + HH * cs; }
}
void h_left(unsigned nq, double* q, unsigned ny, double* y, unsigned nz, double* z)
{ h_corner(-1.0, q, y, ny); }
void G0_left(unsigned nq, double* q, unsigned ny, double* J, unsigned nz, double* z)
{ G0_corner(-1.0, q, J, ny); }
void h_right(unsigned nq, double* q, unsigned ny, double* y, unsigned nz, double* z)
{ h_corner(1.0, q, y, ny); }
void G0_right(unsigned nq, double* q, unsigned ny, double* J, unsigned nz, double* z)
{ G0_corner(1.0, q, J, ny); }
"""


def corner_plugin(b, hh, workdir):
    """Compile the corners' h and G0 into workdir/corner.so; the Siconos plugin prefix."""
    src = os.path.join(workdir, "corner.c")
    with open(src, "w") as f:
        f.write(CORNER_C)
    cc = os.environ.get("CC", "cc")
    subprocess.run([cc, "-shared", "-fPIC", "-O2", f"-DB={b!r}", f"-DHH={hh!r}",
                    "-o", os.path.join(workdir, "corner.so"), src, "-lm"], check=True)
    return os.path.join(workdir, "corner")


def rocking_block(p, init, h, t_end, plugin):
    m, g, b, hh, mu, e = p["m"], p["g"], p["b"], p["h"], p["mu"], p["e_n"]
    J = m * (b * b + hh * hh) / 3.0
    q0 = [init.get("x", 0.0), init["y"], init["theta"]]
    body = sk.LagrangianLinearTIDS(q0, [0.0, 0.0, 0.0], np.diag([m, m, J]))
    body.setFExtPtr([0.0, -m * g, 0.0])
    nsds = sk.NonSmoothDynamicalSystem(0.0, t_end)
    nsds.insertDynamicalSystem(body)
    inters = {}
    for name in ("left", "right"):
        rel = sk.LagrangianScleronomousR(f"{plugin}:h_{name}", f"{plugin}:G0_{name}")
        inters[name] = sk.Interaction(sk.NewtonImpactFrictionNSL(e, 0.0, mu, 2), rel)
        nsds.link(inters[name], body)
    impacts = []
    prev = {name: 0.0 for name in inters}

    def record(t):
        for name, inter in inters.items():
            vn, gap = inter.y(1)[0], inter.y(0)[0]
            # an impact: a corner at the floor that was approaching at a real speed stopped
            if prev[name] < -1e-3 and vn > 0.5 * prev[name] and gap < 1e-4:
                other = inters["right" if name == "left" else "left"].y(1)[0]
                impacts.append((t, name, prev[name], other))
        for name, inter in inters.items():
            prev[name] = inter.y(1)[0]
    time_stepping(nsds, h, sk.FrictionContact(2, sn.SICONOS_FRICTION_2D_LEMKE), record)
    return impacts


def block_max_normal_acceleration(p, init):
    """a of the criterion for the block: the largest normal acceleration of the lifted corner
    while the block rotates about the other one from rest at theta0, |theta| <= theta0:
    J_c phi'' = m g R sin(alpha - phi) (phi = |theta|, J_c = J + m R^2 about the pivot), the
    energy giving phi'^2, and the corner's normal acceleration 2 b (cos phi phi'' + sin phi phi'^2)."""
    m, g, b, hh, th0 = p["m"], p["g"], p["b"], p["h"], abs(init["theta"])
    big_r, alpha = math.hypot(b, hh), math.atan2(b, hh)
    jc = m * (b * b + hh * hh) / 3.0 + m * big_r ** 2
    amax = 0.0
    for phi in np.linspace(0.0, th0, 401):
        phidd = m * g * big_r * math.sin(alpha - phi) / jc
        w2 = 2 * m * g * big_r * (math.cos(alpha - th0) - math.cos(alpha - phi)) / jc
        amax = max(amax, 2 * b * (math.cos(phi) * phidd + math.sin(phi) * w2))
    return amax


def bounds_of(ours, n, a, r, e, sensitivity):
    """The leading-order bounds of condition 2 at step h: (time bound of each impact, velocity
    bound). sensitivity(v) is dT/dv of the interval that follows an impact leaving at v."""
    def at(h):
        dv = a * h * (1.0 + (1.0 - e) / (2.0 * r)) / (1.0 - r)
        tb, acc = [], 0.0
        for k in range(n):
            acc += 1.5 * h  # the detection lag
            if k > 0:
                acc += h * (1.0 - e) / (2.0 * r) + sensitivity(abs(ours[k - 1][3])) * dv
            tb.append(acc)
        return tb, dv
    return at


def compare(label, ours, runs, n, bounds):
    """Print the pairs, the errors, their bounds and ratios; the number of failed conditions."""
    bad = 0
    names = ("t", "vn_before", "vn_after")
    errors = {}
    print(f"{label}: the first {n} impacts, pcsim (event-driven) against Siconos (Moreau-Jean);")
    print("  columns: contact pcsim/Siconos, t, v- and v+ as pcsim / Siconos (|difference|)")
    for h, theirs in runs:
        print(f"  h = {h:.4g} s: Siconos finds {len(theirs)} impacts before t = "
              f"{theirs[-1][0] if theirs else 0:.4f} s, pcsim {len(ours)} in its whole run")
        if len(theirs) < n or len(ours) < n:
            print("    too few impacts to compare: FAILS")
            bad += 1
            continue
        tb, dvb = bounds(h)
        err = [0.0, 0.0, 0.0]
        for k, (a, s) in enumerate(zip(ours[:n], theirs[:n])):
            d = (abs(a[0] - s[0]), abs(a[2] - s[2]), abs(a[3] - s[3]))
            flags = []
            if a[1] != s[1]:
                flags.append("DIFFERENT CONTACT")
            if d[0] > tb[k]:
                flags.append(f"|dt| > {tb[k]:.1e}")
            if max(d[1], d[2]) > dvb:
                flags.append(f"|dv| > {dvb:.1e}")
            bad += len(flags)
            err = [max(x, y) for x, y in zip(err, d)]
            print(f"    {k + 1}: {a[1]:>5s}/{s[1]:<5s} t = {a[0]:.6f} / {s[0]:.6f} ({d[0]:.1e} <= "
                  f"{tb[k]:.1e})  v- = {a[2]:+.6f} / {s[2]:+.6f} ({d[1]:.1e})  "
                  f"v+ = {a[3]:+.6f} / {s[3]:+.6f} ({d[2]:.1e})  "
                  + ("  ".join(flags) if flags else "ok"))
        print(f"    max |dt| = {err[0]:.3e}, max |dv-| = {err[1]:.3e}, max |dv+| = {err[2]:.3e}"
              f" (velocity bound {dvb:.3e})")
        errors[h] = err
    hs = sorted(errors, reverse=True)
    for h1, h2 in zip(hs, hs[1:]):
        for i, name in enumerate(names):
            e1, e2 = errors[h1][i], errors[h2][i]
            if e1 < E_FLOOR:
                print(f"  {name}: error {e1:.1e} at h = {h1:.4g} already below pcsim's accuracy")
                continue
            ratio = e1 / max(e2, 1e-300)
            ok = ratio >= RATIO_MIN
            bad += not ok
            print(f"  max error of {name:>9s}: E({h1:.4g})/E({h2:.4g}) = {ratio:5.2f}, observed "
                  f"order {math.log(ratio) / math.log(h1 / h2):.2f}  "
                  f"{'ok' if ok else 'DOES NOT CONVERGE'}")
    return bad


def main(argv):
    if len(argv) != 3:
        sys.exit(__doc__)
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    bad = 0

    p, init, _ = load_case(os.path.join(root, "cases", "bouncing_ball.toml"))
    ours = pcsim_impacts(argv[1])
    n = 8
    t_end = ours[n - 1][0] + 0.5 * (ours[n][0] - ours[n - 1][0])  # past impact n, before n+1
    runs = [(H0 / r, ball(p, init, H0 / r, t_end)) for r in REFINE]
    g, e = abs(p["g"]), p["e_n"]
    bounds = bounds_of(ours, n, g, e, e, lambda v: 2.0 / g)  # a flight lasts 2 v/g
    bad += compare("bouncing ball", ours, runs, n, bounds)
    print()

    p, init, _ = load_case(os.path.join(root, "cases", "rocking_block.toml"))
    ours = pcsim_impacts(argv[2], with_lift_off=True)
    n = 6
    t_end = ours[n - 1][0] + 0.5 * (ours[n][0] - ours[n - 1][0])
    with tempfile.TemporaryDirectory() as d:
        plugin = corner_plugin(p["b"], p["h"], d)
        runs = [(H0 / r, rocking_block(p, init, H0 / r, t_end, plugin)) for r in REFINE]
    # Housner's linearized half-cycle T(w) = (2/p) atanh(w/(p alpha)), w = v/(2 b) the angular
    # velocity of a corner leaving at v, p^2 = m g R/J_c; r the largest ratio of successive
    # approach speeds in pcsim's run.
    b = p["b"]
    big_r, alpha = math.hypot(b, p["h"]), math.atan2(b, p["h"])
    pp = math.sqrt(p["m"] * abs(p["g"]) * big_r / (p["m"] * (b * b + p["h"] ** 2) / 3.0
                                                  + p["m"] * big_r ** 2))

    def sensitivity(v):
        x = v / (2.0 * b) / (pp * alpha)
        return (2.0 / pp) / (pp * alpha) / (1.0 - x * x) / (2.0 * b)
    r = max(abs(ours[k + 1][2] / ours[k][2]) for k in range(n - 1))
    bounds = bounds_of(ours, n, block_max_normal_acceleration(p, init), r, p["e_n"], sensitivity)
    bad += compare("rocking block", ours, runs, n, bounds)

    print("agree within the stated criterion" if bad == 0 else f"{bad} conditions fail")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
