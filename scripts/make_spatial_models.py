#!/usr/bin/env python3
"""Writes the spatial example models (models/tumbling_body.toml, models/top_heavy.toml,
models/rolling_coin.toml) in today's energy form, from the Euler-parameter kinematics of a rigid
body (docs/bodies-spatial.md). Plain Python (no sympy): the expressions are written with named
definitions, and pcsim derives M, h, Q and the constraint rows from them symbolically.

Per body NAME, coordinates NAME_x, NAME_y, NAME_z (the centre of mass in ground) and NAME_e0..e3
(Euler parameters e = (e0, e1, e2, e3), |e| = 1 as the constraint NAME_norm). Definitions:
  NAME_aIJ   the rotation matrix A(e) (body -> ground), the form exact for any e on |e| = 1
  NAME_wI    the body-frame angular velocity  w' = 2 G(e) e_d
  NAME_WI    the ground-frame angular velocity w = 2 E(e) e_d
  NAME_s     e . e_d (zero on the constraint manifold)
T = 1/2 m |r_d|^2 + 1/2 w'^T J w' + 1/2 k (e . e_d)^2, with k = 4 (J1 + J2 + J3)/3: the last term
makes M positive definite (4 G^T J G is singular, e spans its kernel) and changes neither q_dd
nor R on the manifold (proof in docs/bodies-spatial.md, test in
tests/modelfile/test_modelfile_spatial_bodies.cpp).

Run: python3 scripts/make_spatial_models.py   (writes the three models into models/ and a case
for each into cases/)
"""
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# G(e) (body frame) and E(e) (ground frame): rows are 3 components, columns e0..e3.
G = [["-{1}", "{0}", "{3}", "-{2}"],
     ["-{2}", "-{3}", "{0}", "{1}"],
     ["-{3}", "{2}", "-{1}", "{0}"]]
E = [["-{1}", "{0}", "-{3}", "{2}"],
     ["-{2}", "{3}", "{0}", "-{1}"],
     ["-{3}", "-{2}", "{1}", "{0}"]]


def e_names(b):
    return [f"{b}_e{i}" for i in range(4)]


def coordinates(b):
    return [f"{b}_x", f"{b}_y", f"{b}_z"] + e_names(b)


def rotation_defs(b):
    e0, e1, e2, e3 = e_names(b)
    return {
        f"{b}_a11": f"{e0}^2 + {e1}^2 - {e2}^2 - {e3}^2",
        f"{b}_a12": f"2*({e1}*{e2} - {e0}*{e3})",
        f"{b}_a13": f"2*({e1}*{e3} + {e0}*{e2})",
        f"{b}_a21": f"2*({e1}*{e2} + {e0}*{e3})",
        f"{b}_a22": f"{e0}^2 - {e1}^2 + {e2}^2 - {e3}^2",
        f"{b}_a23": f"2*({e2}*{e3} - {e0}*{e1})",
        f"{b}_a31": f"2*({e1}*{e3} - {e0}*{e2})",
        f"{b}_a32": f"2*({e2}*{e3} + {e0}*{e1})",
        f"{b}_a33": f"{e0}^2 - {e1}^2 - {e2}^2 + {e3}^2",
    }


def rate_entry(mat, b, row, col):
    """The entry of 2 G or 2 E (without the 2) as an expression."""
    return mat[row][col].format(*e_names(b))


def rate_defs(b):
    en = e_names(b)
    d = {}
    for name, mat in (("w", G), ("W", E)):
        for r in range(3):
            terms = " + ".join(f"({rate_entry(mat, b, r, c)})*{en[c]}_d" for c in range(4))
            d[f"{b}_{name}{r + 1}"] = f"2*({terms})"
    d[f"{b}_s"] = " + ".join(f"{x}*{x}_d" for x in en)
    return d


def kinetic(b):
    return (f"0.5*{b}_m*({b}_x_d^2 + {b}_y_d^2 + {b}_z_d^2)"
            f" + 0.5*({b}_J1*{b}_w1^2 + {b}_J2*{b}_w2^2 + {b}_J3*{b}_w3^2)"
            f" + 0.5*{b}_k*{b}_s^2")


def norm_constraint(b):
    return {"name": f"{b}_norm", "holonomic": " + ".join(f"{x}^2" for x in e_names(b)) + " - 1"}


def toml_value(v):
    if isinstance(v, str):
        return '"' + v + '"'
    return repr(float(v))


def write_model(path, header, name, coords, params, defines, kinetic_expr, potential, constraints,
                outputs, draw=None):
    out = [f"# {line}" if line else "#" for line in header]
    out.append("# Written by scripts/make_spatial_models.py (Euler-parameter kinematics,")
    out.append("# docs/bodies-spatial.md). Do not edit: change the script and run it again.")
    out += ["[model]", f'name = "{name}"',
            "coordinates = [" + ", ".join(f'"{c}"' for c in coords) + "]", "",
            "[model.parameters]"]
    for k, v in params.items():
        out.append(f"{k} = {toml_value(v)}")
    out.append(f"{coords[0][:-2]}_kscale = 1.0")
    out += ["", "[model.define]"]
    for k, v in defines.items():
        out.append(f'{k} = "{v}"')
    out += ["", "[model.energy]", f'kinetic = "{kinetic_expr}"']
    if potential:
        out.append(f'potential = "{potential}"')
    for c in constraints:
        out += ["", "[[model.constraint]]"]
        for k, v in c.items():
            if isinstance(v, dict):
                out.append(f"{k} = {{ " + ", ".join(f'{kk} = "{vv}"' for kk, vv in v.items()) + " }")
            else:
                out.append(f'{k} = "{v}"')
    out += ["", "[model.outputs]"]
    for k, v in outputs.items():
        out.append(f'{k} = "{v}"')
    if draw:
        out += ["", "[model.draw]", 'view = "3d"']
        for name, (x, y, z) in draw["points"]:
            out += ["[[model.draw.point]]", f'name = "{name}"', f'x = "{x}"', f'y = "{y}"', f'z = "{z}"']
        for line in draw["lines"]:
            out += ["[[model.draw.line]]", "points = [" + ", ".join(f'"{n}"' for n in line) + "]"]
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def axes_draw(b, lengths, extra_points=(), extra_lines=()):
    """A drawing of body b: its centre and the tips of its body axes (lengths per axis)."""
    pts = [("centre", (f"{b}_x", f"{b}_y", f"{b}_z"))]
    for j, L in enumerate(lengths):
        for sgn, tag in ((1, "p"), (-1, "m")):
            pts.append((f"{'xyz'[j]}{tag}", tuple(f"{b}_{c} {'+' if sgn > 0 else '-'} {L}*{b}_a{i + 1}{j + 1}"
                                                  for i, c in enumerate("xyz"))))
    lines = [["xm", "xp"], ["ym", "yp"], ["zm", "zp"], ["xp", "yp", "xm", "ym", "xp"]]
    return {"points": pts + list(extra_points), "lines": lines + list(extra_lines)}


def body_params(b, m, J):
    return {f"{b}_m": m, f"{b}_J1": J[0], f"{b}_J2": J[1], f"{b}_J3": J[2]}


def k_define(b):
    # 4 G^T J G has the eigenvalues 4 J_i on the tangent space (G G^T = I there): k = 4 mean(J)
    # puts the e direction's eigenvalue among them (kscale = 1). Any k > 0 gives the same motion
    # and reactions; kscale lets a test show it.
    return {f"{b}_k": f"{b}_kscale*4*({b}_J1 + {b}_J2 + {b}_J3)/3"}


def energy_output(b, potential):
    return (f"0.5*{b}_m*({b}_x_d^2 + {b}_y_d^2 + {b}_z_d^2)"
            f" + 0.5*({b}_J1*{b}_w1^2 + {b}_J2*{b}_w2^2 + {b}_J3*{b}_w3^2)"
            + (f" + {potential}" if potential else ""))


def tumbling(path):
    b = "b"
    defs = {**k_define(b), **rotation_defs(b), **rate_defs(b)}
    # Angular momentum about the centre of mass in ground: H = A J w'.
    for r in range(3):
        defs[f"b_H{r + 1}"] = " + ".join(f"b_a{r + 1}{c + 1}*b_J{c + 1}*b_w{c + 1}" for c in range(3))
    outputs = {"w1": "b_w1", "w2": "b_w2", "w3": "b_w3",
               "H1": "b_H1", "H2": "b_H2", "H3": "b_H3",
               "H": "sqrt(b_H1^2 + b_H2^2 + b_H3^2)",
               "energy": energy_output(b, "")}
    write_model(path, [
        "A free asymmetric rigid body in space (no gravity): Euler's equations with the",
        "Dzhanibekov flip when it spins near its intermediate axis (J1 < J2 < J3). Outputs: the",
        "body-frame angular velocity w1..w3, the angular momentum H1..H3 in ground and |H|, the",
        "energy; all but w are conserved."],
        "tumbling_body", coordinates(b), body_params(b, 2.0, (0.1, 0.2, 0.3)), defs, kinetic(b),
        "", [norm_constraint(b)], outputs, axes_draw(b, (0.5, 0.35, 0.25)))


def top(path):
    b = "top"
    defs = {**k_define(b), **rotation_defs(b), **rate_defs(b)}
    params = {**body_params(b, 1.0, (0.005, 0.005, 0.008)), "l": 0.1, "g": 9.81,
              "X0": 0.0, "Y0": 0.0, "Z0": 0.0}
    # Spherical joint at the tip: the tip is the body point -l along the body z axis from the
    # centre of mass; it stays at (X0, Y0, Z0). Rows in ground axes (x, y, z).
    cons = [norm_constraint(b)]
    for axis, r, p in (("x", 1, "X0"), ("y", 2, "Y0"), ("z", 3, "Z0")):
        cons.append({"name": f"tip_{axis}", "holonomic": f"{b}_{axis} - l*{b}_a{r}3 - {p}"})
    # The axis k = A (0, 0, 1) moves with k_d = W x k; its azimuth rate is the precession.
    defs["top_kxd"] = "top_W2*top_a33 - top_W3*top_a23"
    defs["top_kyd"] = "top_W3*top_a13 - top_W1*top_a33"
    pot = f"{b}_m*g*{b}_z"
    outputs = {"kx": "top_a13", "ky": "top_a23", "kz": "top_a33",
               "spin": "top_w3",
               "precession": "(top_a13*top_kyd - top_a23*top_kxd)/(top_a13^2 + top_a23^2)",
               "energy": energy_output(b, pot)}
    write_model(path, [
        "The heavy symmetric top: a body (J1 = J2 transverse, J3 axial, about its centre of",
        "mass) whose tip, a distance l below the centre of mass along the symmetry axis (body z),",
        "is held at (X0, Y0, Z0) by a spherical joint (rows tip_x, tip_y, tip_z in ground axes).",
        "Outputs: the symmetry axis k = (kx, ky, kz) in ground, the spin (body-z angular",
        "velocity), the precession rate (the azimuth rate of k) and the energy."],
        "top_heavy", coordinates(b), params, defs, kinetic(b), pot, cons, outputs,
        axes_draw(b, ("0.06", "0.06", "0.02"), [("tip", ("X0", "Y0", "Z0"))], [["tip", "zm"]]))


def coin(path):
    b = "coin"
    defs = {"coin_J1": "coin_m*r^2/4", "coin_J2": "coin_m*r^2/4", "coin_J3": "coin_m*r^2/2",
            **k_define(b), **rotation_defs(b), **rate_defs(b)}
    params = {"coin_m": 0.1, "r": 0.05, "g": 9.81}
    # The disk's axis n = A (0, 0, 1) = (a13, a23, a33); s = |horizontal part of n| =
    # sqrt(1 - n_z^2) on |e| = 1. The contact point from the centre: rho = r (a33 a13/s,
    # a33 a23/s, -s) (the lowest point of the rim).
    defs["coin_sn"] = "sqrt(coin_a13^2 + coin_a23^2)"
    defs["coin_rx"] = "r*coin_a33*coin_a13/coin_sn"
    defs["coin_ry"] = "r*coin_a33*coin_a23/coin_sn"
    defs["coin_rz"] = "-r*coin_sn"
    en = e_names(b)
    # v_P = v_C + w x rho with w = 2 E e_d: the coefficient of e_i_d in (w x rho)_x is
    # 2 (E_2i rho_z - E_3i rho_y), in (w x rho)_y 2 (E_3i rho_x - E_1i rho_z).
    vx = {f"{b}_x": "1"}
    vy = {f"{b}_y": "1"}
    for i in range(4):
        Ey, Ez, Ex = (rate_entry(E, b, 1, i), rate_entry(E, b, 2, i), rate_entry(E, b, 0, i))
        vx[f"{en[i]}"] = f"2*(({Ey})*coin_rz - ({Ez})*coin_ry)"
        vy[f"{en[i]}"] = f"2*(({Ez})*coin_rx - ({Ex})*coin_rz)"
    cons = [norm_constraint(b),
            {"name": "contact", "holonomic": "coin_z - r*coin_sn"},
            {"name": "roll_x", "velocity": vx},
            {"name": "roll_y", "velocity": vy}]
    pot = f"{b}_m*g*{b}_z"
    outputs = {"tilt": "asin(coin_a33)",
               "px": "coin_x + coin_rx", "py": "coin_y + coin_ry",
               "energy": energy_output(b, pot)}
    write_model(path, [
        "A coin (thin disk, radius r, axis = body z) rolling without slip on the plane z = 0:",
        "the contact (holonomic: the centre is r*sqrt(1 - n_z^2) above the plane) and the",
        "no-slip rows roll_x, roll_y (velocity form: the rim point touching the plane has zero",
        "horizontal velocity). Outputs: tilt = the angle of the disk plane from vertical,",
        "the contact point (px, py), the energy (conserved: rolling does no work)."],
        "rolling_coin", coordinates(b), params, defs, kinetic(b), pot, cons, outputs,
        axes_draw(b, ("r", "r", "r/4"), [("contact", ("coin_x + coin_rx", "coin_y + coin_ry", "0"))],
                  [["centre", "contact"]]))


# ---- cases: initial states from the closed forms (plain floats) ----------------------------

def E_num(e):
    e0, e1, e2, e3 = e
    return [[-e1, e0, -e3, e2], [-e2, e3, e0, -e1], [-e3, -e2, e1, e0]]


def G_num(e):
    e0, e1, e2, e3 = e
    return [[-e1, e0, e3, -e2], [-e2, -e3, e0, e1], [-e3, e2, -e1, e0]]


def e_dot(e, w, frame):
    """e_d = 1/2 E^T w (w in ground) or 1/2 G^T w (w in the body frame)."""
    M = E_num(e) if frame == "ground" else G_num(e)
    return [0.5 * sum(M[k][i] * w[k] for k in range(3)) for i in range(4)]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def write_case(path, header, model, body, r, e, v, ed, solver, params=None):
    out = [f"# {line}" for line in header]
    out.append("# Initial state written by scripts/make_spatial_models.py (e_d = 1/2 E(e)^T w).")
    out += [f'model = "../models/{model}"', ""]
    if params:
        out.append("[parameters]")
        out += [f"{k} = {v!r}" for k, v in params.items()]
        out.append("")
    out.append("[initial]")
    for name, val in zip(["x", "y", "z"], r):
        out.append(f"{body}_{name} = {val!r}")
    for i, val in enumerate(e):
        out.append(f"{body}_e{i} = {val!r}")
    for name, val in zip(["x", "y", "z"], v):
        out.append(f"{body}_{name}_d = {val!r}")
    for i, val in enumerate(ed):
        out.append(f"{body}_e{i}_d = {val!r}")
    out += ["", "[solver]"] + solver + ["", "[output]", "dt = 0.01"]
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def cases(d):
    import math
    # Tumbling: w = (0.15, 3, 0.15) rad/s in the body frame, near the intermediate axis.
    e = [0.9, 0.1, 0.3, 0.2]
    n = math.sqrt(sum(x * x for x in e))
    e = [x / n for x in e]
    write_case(os.path.join(d, "tumbling_body.toml"), [
        "A free asymmetric body spinning near its intermediate axis (models/tumbling_body.toml):",
        "w2 flips sign every ~4 s (the Dzhanibekov effect), energy and |H| stay constant.",
        "Checked against Euler's equations by tests/modelfile/test_modelfile_spatial_bodies.cpp.",
        "Run:  pcsim run cases/tumbling_body.toml && pcsim plot out/tumbling_body"],
        "tumbling_body.toml", "b", [1000.0, -800.0, 500.0], e, [0.3, -0.2, 0.1],
        e_dot(e, [0.15, 3.0, 0.15], "body"), ["t_end = 20.0", "rtol = 1.0e-10", "atol = 1.0e-10"])
    # Heavy top: theta = 0.5, spin 40 rad/s, the slow steady precession.
    m, l, g, J1, J3, th, w3 = 1.0, 0.1, 9.81, 0.005, 0.008, 0.5, 40.0
    I1 = J1 + m * l * l
    a, b, c = I1 * math.cos(th), -J3 * w3, m * g * l
    Om = (-b - math.sqrt(b * b - 4 * a * c)) / (2 * a)
    e = [math.cos(th / 2), math.sin(th / 2), 0.0, 0.0]
    k = [0.0, -math.sin(th), math.cos(th)]
    w = [Om * (i == 2) + (w3 - Om * math.cos(th)) * k[i] for i in range(3)]
    write_case(os.path.join(d, "top_heavy.toml"), [
        "The heavy symmetric top (models/top_heavy.toml) started in steady precession:",
        f"nutation 0.5 rad, spin 40 rad/s, precession {Om:.6f} rad/s (the closed form",
        "Omega (J3 w3 - (J1 + m l^2) Omega cos(theta)) = m g l, slow root). The precession output",
        "stays constant. Run:  pcsim run cases/top_heavy.toml && pcsim plot out/top_heavy"],
        "top_heavy.toml", "top", [l * x for x in k], e, cross(w, [l * x for x in k]),
        e_dot(e, w, "ground"), ["t_end = 7.0", "rtol = 1.0e-9", "atol = 1.0e-10"])
    # Rolling coin: leaning in by beta = 0.3 rad on a circle of radius Rc = 0.5 m.
    r, beta, Rc = 0.05, 0.3, 0.5
    Om = math.sqrt(g * math.tan(beta) / (1.5 * Rc + r * math.sin(beta) / 4))
    spin = Om * (Rc / r + math.sin(beta))
    gam = -math.pi / 2 - beta
    e = [math.cos(gam / 2), math.sin(gam / 2), 0.0, 0.0]
    kax = [0.0, math.cos(beta), -math.sin(beta)]
    dv = [0.0, math.sin(beta), math.cos(beta)]
    w = [Om * (i == 2) + spin * kax[i] for i in range(3)]
    write_case(os.path.join(d, "rolling_coin.toml"), [
        "A coin rolling steadily on a circle (models/rolling_coin.toml): radius 0.05 m, leaning",
        f"0.3 rad into the turn, its centre on a circle of 0.5 m at {Om:.6f} rad/s (the closed",
        "form Omega^2 = g tan(beta) / (3 Rc/2 + r sin(beta)/4)): the tilt stays constant.",
        "Run:  pcsim run cases/rolling_coin.toml && pcsim plot out/rolling_coin"],
        "rolling_coin.toml", "coin", [r * x for x in dv], e, cross(w, [r * x for x in dv]),
        e_dot(e, w, "ground"), ["t_end = 10.0", "rtol = 1.0e-9", "atol = 1.0e-10"])


def slider_crank_case(d):
    """Initial state of models/slider_crank_spatial.toml at th = 0.3 rad, th_d = 6 rad/s: the rod
    and slider from the closed-form geometry (as tests/modelfile/test_modelfile_slider_crank_
    spatial.cpp), rates by complex steps."""
    import cmath
    import math
    a, L, b = 0.1, 0.4, 0.15

    def geo(th):
        P = [0.0, a * cmath.cos(th), a * cmath.sin(th)]
        s = a * cmath.cos(th) + cmath.sqrt(L * L - b * b - a * a * cmath.sin(th) ** 2)
        S = [b, s, 0.0]
        c = [(P[i] + S[i]) / 2 for i in range(3)]
        x = [(S[i] - P[i]) / L for i in range(3)]
        y = cross([0.0, 0.0, 1.0], x)
        n = cmath.sqrt(sum(v * v for v in y))
        y = [v / n for v in y]
        z = cross(x, y)
        R = [[x[i], y[i], z[i]] for i in range(3)]
        return s, c, R

    th0, w0, h = 0.3, 6.0, 1e-30
    s, c, R = geo(th0)
    sc, cc, Rc = geo(complex(th0, h))
    Rr = [[R[i][j].real for j in range(3)] for i in range(3)]
    Rd = [[Rc[i][j].imag / h for j in range(3)] for i in range(3)]
    W = [[sum(Rd[i][k] * Rr[j][k] for k in range(3)) for j in range(3)] for i in range(3)]
    w = [0.5 * (W[2][1] - W[1][2]) * w0, 0.5 * (W[0][2] - W[2][0]) * w0, 0.5 * (W[1][0] - W[0][1]) * w0]
    # Euler parameters of Rr (Shepperd)
    tr = Rr[0][0] + Rr[1][1] + Rr[2][2]
    e0 = 0.5 * math.sqrt(1 + tr)
    e = [e0, (Rr[2][1] - Rr[1][2]) / (4 * e0), (Rr[0][2] - Rr[2][0]) / (4 * e0), (Rr[1][0] - Rr[0][1]) / (4 * e0)]
    ed = e_dot(e, w, "ground")
    out = ["# A spatial slider-crank as bodies (models/slider_crank_spatial.toml) released at th = 0.3 rad,",
           "# th_d = 6 rad/s: the crank swings over the top and back under gravity. The rod's and slider's",
           "# initial state from the closed-form geometry (scripts/make_spatial_models.py). Checked against",
           "# a minimal-coordinate solution by tests/modelfile/test_modelfile_slider_crank_spatial.cpp.",
           "# Run:  pcsim run cases/slider_crank_spatial.toml && pcsim plot out/slider_crank_spatial",
           'model = "../models/slider_crank_spatial.toml"', "", "[initial]",
           f"th = {th0!r}", f"th_d = {w0!r}"]
    for i, n in enumerate("xyz"):
        out.append(f"rod_{n} = {c[i].real!r}")
        out.append(f"rod_{n}_d = {cc[i].imag / h * w0!r}")
    for i in range(4):
        out.append(f"rod_e{i} = {e[i]!r}")
        out.append(f"rod_e{i}_d = {ed[i]!r}")
    out += [f"slider_x = {b!r}", f"slider_y = {s.real!r}", f"slider_y_d = {sc.imag / h * w0!r}",
            "slider_e0 = 1.0", "", "[solver]", "t_end = 4.0", "rtol = 1.0e-9", "atol = 1.0e-10",
            "", "[output]", "dt = 0.005"]
    with open(os.path.join(d, "slider_crank_spatial.toml"), "w") as f:
        f.write("\n".join(out) + "\n")


def main():
    models = os.path.join(ROOT, "models")
    tumbling(os.path.join(models, "tumbling_body.toml"))
    top(os.path.join(models, "top_heavy.toml"))
    coin(os.path.join(models, "rolling_coin.toml"))
    cases(os.path.join(ROOT, "cases"))
    slider_crank_case(os.path.join(ROOT, "cases"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
