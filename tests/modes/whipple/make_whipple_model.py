#!/usr/bin/env python3
"""Writes whipple_bicycle.toml: the Whipple bicycle of Meijaard, Papadopoulos, Ruina and Schwab
(2007, Proc. R. Soc. A 463, "Linearized dynamics equations for the balance and steer of a
bicycle: a benchmark and review"), Table 1's benchmark parameters, as a pcsim model file.

Coordinates (x forward, y right, z down, origin on the ground): x, y the rear contact point, psi
yaw, phi roll, th rear-frame pitch, del steer, thR and thF the wheels' rotations relative to their
frames. Rear frame orientation A = Rz(psi) Rx(phi) Ry(th), pitching about the rear axle; the front
frame turns by del about the steer axis (tilted back by lam, through the ground point w + c ahead
of the rear contact in the reference configuration). Knife-edge wheels. Constraints: the front
wheel touches the ground (holonomic), both contact points do not slip (four velocity-form rows).
The kinetic energy is 1/2 m |v|^2 + 1/2 W^T I W per body (W in body axes), V = -g sum m z.

Run with sympy (Debian's python3): python3 make_whipple_model.py > whipple_bicycle.toml
With the argument `moving`: the same bicycle seen from a frame that moves with the steady motion
at the forward speed v (a parameter): x_d, thR_d and thF_d are written for the velocities
x_d + v, thR_d - v/rR, thF_d - v/rF, so running straight ahead at v is a rest state and
`pcsim modes --vary parameters.v=...` traces the eigenvalues against the speed:
python3 make_whipple_model.py moving > whipple_moving.toml
"""
import sys

import sympy as sp

MOVING = len(sys.argv) > 1 and sys.argv[1] == 'moving'

q = sp.symbols('x y psi phi th del thR thF')
qd = sp.symbols('x_d y_d psi_d phi_d th_d del_d thR_d thF_d')
x, y, psi, phi, th, de, thR, thF = q
P = dict(w=1.02, c=0.08, lam=sp.pi / 10, g=9.81, rR=0.3, mR=2.0, IRxx=0.0603, IRyy=0.12,
         xB=0.3, zB=-0.9, mB=85.0, IBxx=9.2, IByy=11.0, IBzz=2.8, IBxz=2.4,
         xH=0.9, zH=-0.7, mH=4.0, IHxx=0.05892, IHyy=0.06, IHzz=0.00708, IHxz=-0.00756,
         rF=0.35, mF=3.0, IFxx=0.1405, IFyy=0.28)
S = {k: sp.Symbol(k) for k in P}
w, c, lam, g, rR, rF = S['w'], S['c'], S['lam'], S['g'], S['rR'], S['rF']


def Rx(a):
    return sp.Matrix([[1, 0, 0], [0, sp.cos(a), -sp.sin(a)], [0, sp.sin(a), sp.cos(a)]])


def Ry(a):
    return sp.Matrix([[sp.cos(a), 0, sp.sin(a)], [0, 1, 0], [-sp.sin(a), 0, sp.cos(a)]])


def Rz(a):
    return sp.Matrix([[sp.cos(a), -sp.sin(a), 0], [sp.sin(a), sp.cos(a), 0], [0, 0, 1]])


def rodrigues(u, a):
    K = sp.Matrix([[0, -u[2], u[1]], [u[2], 0, -u[0]], [-u[1], u[0], 0]])
    return sp.eye(3) + sp.sin(a) * K + (1 - sp.cos(a)) * K * K


def dt(e):
    return sum(sp.diff(e, qi) * qdi for qi, qdi in zip(q, qd))


def body_rate(R):
    # W = skew^-1(R^T dR/dt), body axes
    Rd = R.applyfunc(dt)
    Wm = R.T * Rd
    return sp.Matrix([Wm[2, 1], Wm[0, 2], Wm[1, 0]])


A = Rz(psi) * Rx(phi) * Ry(th)
Aroll = Rz(psi) * Rx(phi)
ez = Aroll * sp.Matrix([0, 0, 1])
Rc = sp.Matrix([x, y, 0]) - rR * ez                      # rear wheel centre
us = sp.Matrix([sp.sin(lam), 0, sp.cos(lam)])             # steer axis, pointing down
Sp = sp.Matrix([w + c, 0, 0])                             # where it meets the ground (reference)
Rs = rodrigues(us, de)
AH = A * Rs


def rear_point(p):
    return Rc + A * (p + sp.Matrix([0, 0, rR]))


def front_point(p):
    return Rc + A * (Sp + sp.Matrix([0, 0, rR]) + Rs * (p - Sp))


WB = body_rate(A)
WH = body_rate(AH)
WR = WB + sp.Matrix([0, qd[6], 0])
WF = WH + sp.Matrix([0, qd[7], 0])
rB = rear_point(sp.Matrix([S['xB'], 0, S['zB']]))
rH = front_point(sp.Matrix([S['xH'], 0, S['zH']]))
rFc = front_point(sp.Matrix([w, 0, -rF]))
IB = sp.Matrix([[S['IBxx'], 0, S['IBxz']], [0, S['IByy'], 0], [S['IBxz'], 0, S['IBzz']]])
IH = sp.Matrix([[S['IHxx'], 0, S['IHxz']], [0, S['IHyy'], 0], [S['IHxz'], 0, S['IHzz']]])
IR = sp.diag(S['IRxx'], S['IRyy'], S['IRxx'])
IF = sp.diag(S['IFxx'], S['IFyy'], S['IFxx'])


def ke(m, r, W, I):
    v = r.applyfunc(dt)
    return sp.Rational(1, 2) * m * (v.T * v)[0] + sp.Rational(1, 2) * (W.T * I * W)[0]


T = ke(S['mR'], Rc, WR, IR) + ke(S['mB'], rB, WB, IB) + ke(S['mH'], rH, WH, IH) + ke(S['mF'], rFc, WF, IF)
V = -g * (S['mR'] * Rc[2] + S['mB'] * rB[2] + S['mH'] * rH[2] + S['mF'] * rFc[2])
# Front contact: the lowest point of the front wheel (axle aF).
aF = AH * sp.Matrix([0, 1, 0])
zhat = sp.Matrix([0, 0, 1])
nz = sp.sqrt(1 - aF[2] ** 2)
dF = (zhat - aF[2] * aF) / nz
Qc = rFc + rF * dF
holo = rFc[2] + rF * nz
# Slip velocities of the contact points (material points of the wheels), x and y.
wR = A * WR                                 # global angular velocities
wF = AH * WF
vP = Rc.applyfunc(dt) + wR.cross(sp.Matrix([x, y, 0]) - Rc)
vQ = rFc.applyfunc(dt) + wF.cross(Qc - rFc)
rows = {'rear_long': vP[0], 'rear_lat': vP[1], 'front_long': vQ[0], 'front_lat': vQ[1]}
coef = {name: [sp.diff(e, v) for v in qd] for name, e in rows.items()}

vv = sp.Symbol('v')
shift = {qd[0]: qd[0] + vv, qd[6]: qd[6] - vv / rR, qd[7]: qd[7] - vv / rF}
g0 = {name: sp.Integer(0) for name in rows}
if MOVING:
    T = T.subs(shift, simultaneous=True)
    g0 = {name: vv * coef[name][0] - vv / rR * coef[name][6] - vv / rF * coef[name][7] for name in rows}
exprs = [T, V, holo] + [cf for name in rows for cf in coef[name]] + [g0[name] for name in rows]
repl, red = sp.cse(exprs, symbols=sp.numbered_symbols('d_'), optimizations='basic')


def s(e):
    t = sp.sstr(e).replace('**', '^')
    return t


out = []
out.append('# The Whipple bicycle, benchmark parameters of Meijaard et al. (2007), Table 1: written by')
out.append('# tests/modes/whipple/make_whipple_model.py (sympy; see its docstring for the geometry). Do not edit.')
out.append('[model]')
out.append('name = "%s"' % ('whipple_moving' if MOVING else 'whipple_bicycle'))
out.append('coordinates = [' + ', '.join('"%s"' % str(v) for v in q) + ']')
out.append('')
out.append('[model.parameters]')
for k, v in P.items():
    out.append('%s = %s' % (k, repr(float(v))))
if MOVING:
    out.append('v = { value = 4.0, unit = "m/s", meaning = "forward speed of the frame (the steady motion)" }')
out.append('')
out.append('[model.define]')
for sym, e in repl:
    out.append('%s = "%s"' % (sym, s(e)))
out.append('')
out.append('[model.energy]')
out.append('kinetic = "%s"' % s(red[0]))
out.append('potential = "%s"' % s(red[1]))
out.append('')
out.append('[[model.constraint]]')
out.append('name = "front_contact"')
out.append('holonomic = "%s"' % s(red[2]))
k = 3
for name in rows:
    out.append('')
    out.append('[[model.constraint]]')
    out.append('name = "%s"' % name)
    parts = []
    for v in qd:
        e = red[k]
        k += 1
        if e != 0:
            parts.append('%s = "%s"' % (str(v)[:-2], s(e)))
    out.append('velocity = { ' + ', '.join(parts) + ' }')
    if MOVING:
        out.append('velocity0 = "%s"' % s(red[3 + 4 * 8 + list(rows).index(name)]))
print('\n'.join(out))
