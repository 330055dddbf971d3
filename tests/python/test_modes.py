# case.modes(): pcsim modes from Python, through the very functions the CLI calls (cpp/modes):
# the same modes.json (and modes.csv, modes_vary.json) as `pcsim modes` on the same case, the
# eigenvalues and shapes as complex arrays equal to the JSON's numbers, the CLI's errors as
# Python exceptions with the same one-line messages, and the GIL released while it computes.
import json
import os
import pathlib
import subprocess
import threading
import time

import numpy as np
import pytest

import pcsim

ROOT = pathlib.Path(__file__).resolve().parents[2]

CASE = ROOT / "cases" / "double_pendulum.toml"
# the double pendulum hanging at rest (its two modes: 2.690 and 5.339 rad/s)
AT_REST = {"initial.x1": 0, "initial.y1": -1, "initial.x2": 0, "initial.y2": -1.7}
AT_REST_CLI = [a for k, v in AT_REST.items() for a in ("--set", f"{k}={v}")]


def cli(pcsim_exe, *args):
    return subprocess.run([pcsim_exe, *map(str, args)], capture_output=True, text=True)


def test_python_and_the_cli_write_and_return_identical_modes_json(tmp_path, pcsim_exe):
    p = cli(pcsim_exe, "modes", CASE, *AT_REST_CLI, "--out", tmp_path / "cli")
    assert p.returncode == 0, p.stderr
    res = pcsim.Case(CASE, set=AT_REST).modes(out=tmp_path / "py")
    for name in ("modes.json", "modes.csv", "model.toml"):
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    assert res.data == json.loads((tmp_path / "cli" / "modes.json").read_text())
    assert res.report.strip() in p.stdout
    # the arrays are the JSON's numbers
    d = res.data
    assert res.eigenvalues.dtype == np.complex128
    assert np.array_equal(res.eigenvalues, np.array([e["re"] + 1j * e["im"] for e in d["eigenvalues"]]))
    assert np.array_equal(res.mode_eigenvalues, np.array([m["re"] + 1j * m["im"] for m in d["modes"]]))
    assert res.coordinates == d["coordinates"] == ["x1", "y1", "x2", "y2"]
    assert res.shapes.shape == (len(d["modes"]), 4)
    for k, m in enumerate(d["modes"]):
        for i, c in enumerate(res.coordinates):
            assert res.shapes[k, i] == complex(m["shape"][c]["re"], m["shape"][c]["im"])
    # an oracle that is not the code: the hanging double pendulum's frequencies, from
    # det(K - w^2 M) = 0 in the two angles (m1 = 1, m2 = 0.5, L1 = 1, L2 = 0.7, g = 9.81)
    m1, m2, l1, l2, g = 1.0, 0.5, 1.0, 0.7, 9.81
    M = np.array([[(m1 + m2) * l1 * l1, m2 * l1 * l2], [m2 * l1 * l2, m2 * l2 * l2]])
    K = np.diag([(m1 + m2) * g * l1, m2 * g * l2])
    w = np.sqrt(np.sort(np.linalg.eigvals(np.linalg.solve(M, K)).real))
    assert np.allclose(np.abs(res.mode_eigenvalues), w, rtol=1e-10)
    assert res["stable"] is True and res.vary is False and res.values is None
    # without out= nothing is written
    before = sorted(os.listdir(tmp_path))
    pcsim.Case(CASE, set=AT_REST).modes()
    assert sorted(os.listdir(tmp_path)) == before


def test_excitation_and_cyclic_are_the_command_line_options(tmp_path, pcsim_exe):
    if not pcsim.with_sieve:
        pytest.skip("built without the sieve")
    case = ROOT / "cases" / "sieve_1995_theta_locked.toml"
    setting = {"initial.from": "equilibrium"}
    p = cli(pcsim_exe, "modes", case, "--set", "initial.from=equilibrium", "--excitation", "0.7",
            "--no-cyclic", "--out", tmp_path / "cli")
    assert p.returncode == 0, p.stderr
    res = pcsim.Case(case, set=setting).modes(excitation=0.7, cyclic=[])
    assert res.data == json.loads((tmp_path / "cli" / "modes.json").read_text())
    assert res["excitation"]["mode"] == "phase" and res["excitation"]["phase"] == 0.7
    off = pcsim.Case(case, set=setting).modes(excitation="off")
    assert off["excitation"]["mode"] == "off"


def test_vary_traces_as_the_cli_does(tmp_path, pcsim_exe):
    p = cli(pcsim_exe, "modes", CASE, *AT_REST_CLI, "--vary", "parameters.L2=0.5:0.9:5", "--out", tmp_path / "cli")
    assert p.returncode == 0, p.stderr
    res = pcsim.Case(CASE, set=AT_REST).modes(vary="parameters.L2=0.5:0.9:5", out=tmp_path / "py")
    for name in ("modes_vary.json", "modes_vary.csv"):
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    d = json.loads((tmp_path / "cli" / "modes_vary.json").read_text())
    assert res.data == d and res.vary
    assert np.array_equal(res.values, np.array(d["values"]))
    assert res.eigenvalues.shape == (5, len(d["tracks"]))
    for t, tr in enumerate(d["tracks"]):
        assert np.array_equal(res.eigenvalues[:, t], np.array(tr["re"]) + 1j * np.array(tr["im"]))
    assert res.shapes is None and res.mode_eigenvalues is None


def cli_error(pcsim_exe, *args):
    p = cli(pcsim_exe, *args)
    line = p.stderr.strip().splitlines()[-1]
    assert line.startswith("pcsim: error: ")
    return p.returncode, line[len("pcsim: error: "):]


def test_errors_are_the_cli_messages(tmp_path, pcsim_exe):
    # not at rest: InputError (exit 2) with the CLI's message, nothing written
    with pytest.raises(pcsim.InputError) as e:
        pcsim.Case(CASE).modes(out=tmp_path / "py")
    rc, message = cli_error(pcsim_exe, "modes", CASE, "--out", tmp_path / "cli")
    assert rc == 2 and str(e.value) == message and "not a rest state" in message
    assert e.value.file == str(CASE)
    assert not (tmp_path / "py").exists() and not (tmp_path / "cli").exists()
    # an unknown cyclic coordinate; a bad --vary
    case = pcsim.Case(CASE, set=AT_REST)
    for kwargs, args in (({"cyclic": ["nope"]}, ["--cyclic", "nope"]),
                         ({"vary": "parameters.L2=1:2"}, ["--vary", "parameters.L2=1:2"]),
                         ({"excitation": "sideways"}, ["--excitation", "sideways"])):
        with pytest.raises(pcsim.InputError) as e:
            case.modes(**kwargs)
        rc, message = cli_error(pcsim_exe, "modes", CASE, *AT_REST_CLI, *args, "--out", tmp_path / "x")
        assert rc == 2 and str(e.value) == message, kwargs
    # a singular mass matrix on the tangent space: NumericalError (exit 3)
    model = tmp_path / "massless.toml"
    model.write_text('[model]\nname = "massless"\ncoordinates = ["x", "z"]\n[model.parameters]\nk = 1.0\n'
                     '[model.energy]\nkinetic = "0.5*x_d^2"\npotential = "0.5*k*x^2 + 0.5*k*z^2"\n')
    with pytest.raises(pcsim.NumericalError) as e:
        pcsim.Case(model).modes()
    rc, message = cli_error(pcsim_exe, "modes", model, "--out", tmp_path / "m")
    assert rc == 3 and str(e.value) == message
    # wrong types name the argument
    for kwargs, name in (({"excitation": True}, "excitation"), ({"excitation": [1.0]}, "excitation"),
                         ({"cyclic": 3}, "cyclic"), ({"vary": 3}, "vary")):
        with pytest.raises(TypeError, match=name):
            case.modes(**kwargs)
    with pytest.raises(pcsim.InputError, match="excitation"):
        case.modes(excitation=float("nan"))
    assert case.modes().data["stable"]  # still usable


def test_the_gil_is_released_while_modes_are_computed():
    sanitized = bool(os.environ.get("PCSIM_SANITIZED"))
    case = pcsim.Case(CASE, set=AT_REST)
    spans, notes = [], []

    def work():
        t0 = time.perf_counter()
        case.modes(vary="parameters.L2=0.5:0.9:" + ("1000" if sanitized else "10000"))
        spans.append((t0, time.perf_counter()))

    worker = threading.Thread(target=work)
    worker.start()
    while worker.is_alive():
        notes.append(time.perf_counter())
    worker.join()
    a, b = spans[0]
    inside = [a] + [t for t in notes if a < t < b] + [b]
    gap = max(y - x for x, y in zip(inside, inside[1:]))
    assert gap < 0.5 * (b - a), f"the main thread stood still {gap:.3f} s of a {b - a:.3f} s call"
