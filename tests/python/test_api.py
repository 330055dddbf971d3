# The API of the pcsim module: loading (case files, model files, overrides as --set), the
# typed results, the model's quantities at a state against the pendulum's closed form, steady,
# response and sweep against the CLI's contracts, docstrings and the type stubs.
import ast
import json
import math
import pathlib

import numpy as np
import pytest

import pcsim

ROOT = pathlib.Path(__file__).resolve().parents[2]
SIN60 = math.sqrt(3) / 2


def test_run_result_shape_and_columns(pendulum):
    res = pendulum.run()
    assert isinstance(res, pcsim.RunResult)
    assert res.columns[:3] == ["t", "x", "y"]
    assert "R_x" in res and "tension" in res and "nope" not in res
    assert res.data.shape == (6, len(res.columns)) and len(res) == 6
    assert res.data.dtype == np.float64 and res.data.flags["C_CONTIGUOUS"]
    np.testing.assert_allclose(res["t"], [0, 0.01, 0.02, 0.03, 0.04, 0.05], rtol=0, atol=1e-15)
    # the table is the run's own buffer (owned by a capsule: NumPy did not allocate it), the
    # same object on every access, and a column is a view of it, not a copy
    assert not res.data.flags["OWNDATA"] and res.data is res.data
    # a column is a view of the table, not a copy
    col = res["tension"]
    assert col.base is not None and np.shares_memory(col, res.data)
    # the summary is summary.json's structure: dicts, lists, numbers
    s = res.summary
    assert s["complete"] is True and res.complete
    assert s["model"] == "pendulum"
    assert set(s["extremes"]) >= {"x", "y", "R_x", "tension"}
    json.dumps(s)  # plain Python data throughout
    assert res.events is None
    assert "pendulum" in res.report
    with pytest.raises(KeyError, match="no column 'R_u'"):
        res["R_u"]


def test_the_pendulum_moves_as_physics_says(pendulum):
    # Released from rest at 60 degrees: the rod tension starts at m g cos(60) = 4.905 N and
    # the length stays L (the constraint): oracles independent of the code.
    res = pendulum.run()
    assert res["tension"][0] == pytest.approx(9.81 * 0.5, rel=1e-9)
    r = np.hypot(res["x"], res["y"])
    np.testing.assert_allclose(r, 1.0, atol=1e-9)


def test_overrides_are_the_cli_set(pendulum, root):
    c = pcsim.Case(root / "models" / "pendulum.toml",
                   set={"initial.x": 0.8660254037844386, "initial.y": -0.5, "solver.t_end": 0.02,
                        "output.dt": 0.01, "parameters.m": 2, "solver.kernel": "cpp"})
    assert c.model.parameters["m"]["value"] == 2.0
    assert c.run().summary["kernel"] == "cpp"
    c2 = c.with_set({"parameters.m": 3.5})
    assert c2.model.parameters["m"]["value"] == 3.5
    assert c.model.parameters["m"]["value"] == 2.0  # the original is unchanged
    assert "m = 3.5" in c2.to_toml()


def test_model_declaration(pendulum):
    m = pendulum.model
    assert m.name == "pendulum"
    assert m.coordinates == ["x", "y"]
    assert m.outputs == ["tension"]
    p = m.parameters
    assert p["m"]["default"] == 1.0 and p["m"]["unit"] == "kg"
    assert p["m"]["min"] == 0.0 and p["m"]["min_exclusive"] is True
    assert p["g"]["default"] == 9.81
    assert [c["name"] for c in m.constraints] == ["length"]
    assert m.constraints[0]["kind"] == "holonomic" and m.constraints[0]["active"]
    assert m.active_constraints == ["length"]
    assert math.isnan(m.period)


def test_evaluate_against_the_closed_form(pendulum):
    # T = m/2 (xd^2 + yd^2), V = m g y, Phi = x^2 + y^2 - L^2 (m = L = 1, g = 9.81): M = m I,
    # h = 0, Q = (0, -m g), g = [2x, 2y], gamma = 2 v^2, tension = m (g cos phi + v^2 / L).
    x, y, v = SIN60, -0.5, 1.5
    qd = [v * 0.5, v * SIN60]  # tangential: perpendicular to (x, y)
    e = pendulum.model.evaluate([x, y], qd, t=0.0)
    np.testing.assert_allclose(e["M"], np.eye(2), atol=1e-14)
    np.testing.assert_allclose(e["h"], [0, 0], atol=1e-14)
    np.testing.assert_allclose(e["Q"], [0, -9.81], atol=1e-14)
    np.testing.assert_allclose(e["g"], [[2 * x, 2 * y]], atol=1e-14)
    np.testing.assert_allclose(e["g0"], [0], atol=1e-14)
    np.testing.assert_allclose(e["gamma"], [2 * v * v], rtol=1e-13)
    tension = 9.81 * 0.5 + v * v
    np.testing.assert_allclose(e["R"], [-tension * x, -tension * y], rtol=1e-12)
    assert e["outputs"]["tension"] == pytest.approx(tension, rel=1e-12)
    # the accelerations keep the constraint: g qdd + gamma = 0
    assert e["g"] @ e["qdd"] + e["gamma"] == pytest.approx([0], abs=1e-12)
    # qd defaults to rest; numpy arrays and tuples are states too
    e0 = pendulum.model.evaluate(np.array([x, y]))
    assert e0["outputs"]["tension"] == pytest.approx(9.81 * 0.5, rel=1e-12)


def test_model_file_and_constraints(root):
    # a model file runs as a case with its defaults (as pcsim run does); constraints adds one
    c = pcsim.Case(root / "models" / "slider_crank.toml", set={"solver.t_end": 0.1})
    assert c.run().complete
    held = pcsim.Case(root / "cases" / "double_pendulum.toml",
                      set={"solver.t_end": 0.05}, constraints={"hold": "x2 - 1.5660254037844386"})
    assert "hold" in held.model.active_constraints
    assert held.run().summary["constraints"][-1] == "hold"


def test_sweep_matches_the_cli(root, tmp_path, pcsim_exe):
    import subprocess

    base = pcsim.Case(root / "cases" / "slider_crank.toml", set={"solver.t_end": 0.2})
    vary = ["parameters.m2=0.5:1.5:3"]
    sw = base.sweep(vary, jobs=2)
    assert isinstance(sw, pcsim.SweepResult) and len(sw) == 3
    assert sw.status == ["ok"] * 3 and sw.errors == [""] * 3
    np.testing.assert_array_equal(sw["parameters.m2"], [0.5, 1.0, 1.5])
    # each point's summary is the point's own run
    one = base.with_set({"parameters.m2": 1.0}).run()
    a, b = dict(sw.summaries[1]), dict(one.summary)
    a["stats"].pop("wall_seconds"), b["stats"].pop("wall_seconds")
    assert a == b
    # the table is sweep.csv's, value for value
    out = tmp_path / "sweep"
    subprocess.run([pcsim_exe, "sweep", str(root / "cases" / "slider_crank.toml"), "--set",
                    "solver.t_end=0.2", "--vary", vary[0], "--out", str(out), "-j", "1"],
                   check=True, capture_output=True)
    lines = (out / "sweep.csv").read_text().splitlines()
    header = lines[0].split(",")
    assert header[:-2] == sw.columns
    for i, line in enumerate(lines[1:]):
        fields = line.split(",")[:-2]
        for j, f in enumerate(fields):
            want = 1.0 if f == "true" else 0.0 if f == "false" else float(f) if f else math.nan
            got = sw.data[i, j]
            assert (math.isnan(want) and math.isnan(got)) or want == got, (header[j], f, got)


@pytest.mark.skipif(not pcsim.with_sieve, reason="the sieve is not built")
def test_steady_and_response(root):
    c = pcsim.Case(root / "cases" / "sieve_1995.toml")
    st = c.steady()
    assert isinstance(st, pcsim.SteadyResult)
    assert st["complete"] is True and st["newton"]
    assert "summary" in st.data and st.report
    r = c.response("parameters.omega=290,310", jobs=2)
    assert isinstance(r, pcsim.ResponseResult) and len(r) == 2
    assert "parameters.omega" in r.columns
    np.testing.assert_array_equal(r["parameters.omega"], [290.0, 310.0])
    assert r.meta and len(r.summaries) == 2


@pytest.mark.skipif(not pcsim.with_sieve, reason="the sieve is not built")
def test_sieve_columns(root):
    res = pcsim.Case(root / "cases" / "sieve_1995.toml", set={"solver.t_end": 0.5}).run()
    assert res["R_u"].shape == (res.data.shape[0],)
    assert "fstar" in res.columns or any(c.startswith("f") for c in res.columns)


# ---- documentation -----------------------------------------------------------------------------

PUBLIC_CLASSES = [pcsim.Case, pcsim.Model, pcsim.RunResult, pcsim.SteadyResult,
                  pcsim.ResponseResult, pcsim.SweepResult, pcsim.CheckResult]


def public_members(cls):
    return [n for n in dir(cls) if not n.startswith("_") or n in ("__getitem__", "__len__", "__contains__")]


def test_docstrings_on_everything_public():
    assert pcsim.__doc__ and len(pcsim.__doc__) > 100
    for name in pcsim.__all__:
        obj = getattr(pcsim, name)
        if isinstance(obj, type):
            assert obj.__doc__, name
    for cls in PUBLIC_CLASSES:
        for n in public_members(cls):
            member = getattr(cls, n)
            doc = getattr(member, "__doc__", None)
            assert doc and doc.strip(), f"{cls.__name__}.{n} has no docstring"


def stub_names():
    stub = pathlib.Path(pcsim.__file__).with_name("__init__.pyi")
    tree = ast.parse(stub.read_text())
    top, members = set(), {}
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            top.add(node.name)
            # methods and properties (instance attributes, e.g. an exception's .file, are
            # AnnAssign and not looked up on the class)
            members[node.name] = {n.name for n in node.body if isinstance(n, ast.FunctionDef)}
            members[node.name + ".attributes"] = {
                n.target.id for n in node.body if isinstance(n, ast.AnnAssign)}
        elif isinstance(node, ast.AnnAssign):
            top.add(node.target.id)
    return top, members


def test_the_stubs_name_every_public_name():
    assert pathlib.Path(pcsim.__file__).with_name("py.typed").exists()
    top, members = stub_names()
    for name in pcsim.__all__:
        assert name in top, f"{name} is missing from __init__.pyi"
    for cls in PUBLIC_CLASSES:
        for n in public_members(cls):
            assert n in members[cls.__name__], f"{cls.__name__}.{n} is missing from __init__.pyi"
    # and the stubs name nothing the module lacks
    for name in top - {"_Path", "_Value"} - {k for k in members if k.endswith(".attributes")}:
        assert hasattr(pcsim, name), name
        for n in members.get(name, ()):
            if n != "__init__":
                assert hasattr(getattr(pcsim, name), n), f"{name}.{n}"
