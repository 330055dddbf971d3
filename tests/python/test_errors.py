# Errors: the CLI's one-line messages as Python exceptions (InputError a ValueError with .file
# and .key, NumericalError with .time and what was computed, IoError an OSError); bad input of
# every kind is a clear exception naming the argument, never a crash; an exception in the
# middle of a run leaves the module usable.
import math
import os
import pathlib
import subprocess

import numpy as np
import pytest

import pcsim

ROOT = pathlib.Path(__file__).resolve().parents[2]

# A force that diverges at t = 0.02 s: the integration fails in the middle of the run.
BLOWUP = """name = "blowup"
[model]
name = "blowup"
coordinates = ["x"]
[model.parameters]
m = { value = 1.0 }
[model.energy]
kinetic = "0.5*m*x_d^2"
[model.forces]
x = "1/(0.02 - t)^3"
[solver]
t_end = 0.05
[output]
dt = 0.001
"""


def cli_error(pcsim_exe, *args):
    p = subprocess.run([pcsim_exe, *map(str, args)], capture_output=True, text=True)
    line = p.stderr.strip().splitlines()[-1]
    assert line.startswith("pcsim: error: ")
    return p.returncode, line[len("pcsim: error: "):]


def test_the_exception_classes():
    assert issubclass(pcsim.InputError, ValueError) and issubclass(pcsim.InputError, pcsim.Error)
    assert issubclass(pcsim.NumericalError, pcsim.Error)
    assert issubclass(pcsim.IoError, OSError) and issubclass(pcsim.IoError, pcsim.Error)


def test_input_error_is_the_cli_message(tmp_path, pcsim_exe):
    case = ROOT / "cases" / "slider_crank.toml"
    with pytest.raises(pcsim.InputError) as e:
        pcsim.Case(case, set={"solver.rtol": -1})
    rc, message = cli_error(pcsim_exe, "run", case, "--set", "solver.rtol=-1", "--out", tmp_path / "o")
    assert rc == 2 and str(e.value) == message
    assert e.value.file == str(case) and e.value.key == "solver.rtol"
    assert not (tmp_path / "o").exists()


def test_unknown_key(pcsim_exe, tmp_path):
    case = ROOT / "cases" / "slider_crank.toml"
    with pytest.raises(pcsim.InputError) as e:
        pcsim.Case(case, set={"solver.nope": 1})
    rc, message = cli_error(pcsim_exe, "run", case, "--set", "solver.nope=1", "--out", tmp_path / "o")
    assert rc == 2 and str(e.value) == message and e.value.key == "solver.nope"


def test_missing_file():
    with pytest.raises(pcsim.InputError, match="nope.toml"):
        pcsim.Case("cases/nope.toml")


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf])
def test_non_finite_values_are_refused_by_key(value):
    with pytest.raises(pcsim.InputError, match="parameters.m2") as e:
        pcsim.Case(ROOT / "cases" / "slider_crank.toml", set={"parameters.m2": value})
    assert e.value.key == "parameters.m2"


def test_wrong_types_name_the_argument(pendulum):
    case = ROOT / "cases" / "slider_crank.toml"
    with pytest.raises(TypeError, match="path"):
        pcsim.Case(42)
    with pytest.raises(TypeError, match="set"):
        pcsim.Case(case, set=[("solver.rtol", 1e-6)])
    with pytest.raises(TypeError, match=r"set\['solver.rtol'\]"):
        pcsim.Case(case, set={"solver.rtol": [1e-6]})
    with pytest.raises(TypeError, match="keys must be str"):
        pcsim.Case(case, set={1: 2})
    with pytest.raises(TypeError, match="constraints"):
        pcsim.Case(case, constraints={"a": 1.5})
    # a string where a number belongs: the case validation's message, as --set gives it
    with pytest.raises(pcsim.InputError) as e:
        pcsim.Case(case, set={"solver.rtol": "small"})
    assert e.value.key == "solver.rtol"
    with pytest.raises(TypeError, match="vary"):
        pendulum.sweep(3)
    with pytest.raises(pcsim.InputError, match="vary"):
        pendulum.sweep([])
    with pytest.raises(pcsim.InputError, match="parameters.nope"):
        pendulum.sweep("parameters.nope=1:2:3")
    with pytest.raises(TypeError):
        pendulum.run(out=3.5)
    with pytest.raises(pcsim.InputError, match="method"):
        pendulum.steady(method="euler")
    with pytest.raises(pcsim.InputError, match="periods"):
        pendulum.steady(periods=0)


def test_evaluate_refuses_bad_states(pendulum):
    m = pendulum.model
    with pytest.raises(ValueError, match=r"q: expected 2 values \(x, y\), got 3"):
        m.evaluate([1.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="qd: expected 2 values"):
        m.evaluate([1.0, 0.0], [0.0])
    with pytest.raises(ValueError, match=r"q\[1\] \(y\): expected a finite number, got nan"):
        m.evaluate([1.0, math.nan])
    with pytest.raises(ValueError, match=r"qd\[0\] \(x_d\): expected a finite number"):
        m.evaluate([1.0, 0.0], [math.inf, 0.0])
    with pytest.raises(TypeError, match="q: expected a 1-D sequence"):
        m.evaluate("xy")
    with pytest.raises(TypeError, match="q: expected a 1-D sequence"):
        m.evaluate([[1.0, 0.0]])
    with pytest.raises(TypeError, match="t: expected a number"):
        m.evaluate([1.0, 0.0], t="now")
    with pytest.raises(ValueError, match="t: expected a finite number"):
        m.evaluate([1.0, 0.0], t=math.nan)
    # the pivot itself, at rest: the rod's row of g vanishes and its acceleration-level equation
    # 0 = -gamma = 0 holds, so the rank-revealing reaction solve (issue 21) gives the unique
    # answer: no reaction, free fall
    e = m.evaluate([0.0, 0.0])
    assert np.array_equal(e["R"], [0.0, 0.0])
    assert e["qdd"][0] == 0.0 and e["qdd"][1] == pytest.approx(-9.81, rel=1e-15)


def test_numerical_error_mid_run_keeps_what_was_computed(tmp_path, pcsim_exe):
    f = tmp_path / "blowup.toml"
    f.write_text(BLOWUP)
    with pytest.raises(pcsim.NumericalError) as e:
        pcsim.Case(f).run(out=tmp_path / "py")
    rc, message = cli_error(pcsim_exe, "run", f, "--out", tmp_path / "cli")
    assert rc == 3
    assert str(e.value) == message.replace(str(tmp_path / "cli"), str(tmp_path / "py"))
    assert 0.019 < e.value.time <= 0.02
    res = e.value.result
    assert isinstance(res, pcsim.RunResult) and not res.complete
    assert res.summary["complete"] is False
    assert 0 < len(res) < 51 and res["t"][-1] <= e.value.time
    # the rows kept are the rows written
    text = (tmp_path / "py" / "timeseries.csv").read_text().splitlines()
    assert len(text) - 1 == len(res)


def test_the_module_is_usable_after_an_exception(tmp_path, pendulum):
    f = tmp_path / "blowup.toml"
    f.write_text(BLOWUP)
    before = pendulum.run()
    for _ in range(3 if os.environ.get("PCSIM_SANITIZED") else 20):  # ~1 s a failure under ASan
        with pytest.raises(pcsim.NumericalError):
            pcsim.Case(f).run()
        with pytest.raises(pcsim.InputError):
            pendulum.with_set({"solver.t_end": -1})
    after = pendulum.run()
    assert np.array_equal(before.data, after.data)


def test_io_error_is_an_oserror(tmp_path, pendulum):
    blocker = tmp_path / "file"
    blocker.write_text("not a directory")
    with pytest.raises(OSError) as e:
        pendulum.run(out=blocker / "sub")
    assert isinstance(e.value, pcsim.IoError)
    assert str(e.value) == f"cannot create the output directory {blocker}: Not a directory"


def test_a_directory_of_another_command_is_refused(tmp_path, pendulum):
    out = tmp_path / "o"
    pendulum.run(out=out)
    (out / "mine.txt").write_text("a user's file")
    with pytest.raises(pcsim.InputError):
        pendulum.run(out=out)
    assert (out / "mine.txt").read_text() == "a user's file"


def test_an_unreliable_result_is_a_numerical_error_with_the_result(tmp_path, pcsim_exe):
    # A pendulum moving 1e-4 m under atol = 1e-3: the run completes, the tolerance does not
    # control it, and the CLI fails with exit 3 after writing it marked unreliable.
    s = {"initial.x": 0.0001, "initial.y": -0.99999999500000003, "solver.atol": 1e-3,
         "solver.t_end": 0.2}
    model = ROOT / "models" / "pendulum.toml"
    with pytest.raises(pcsim.NumericalError) as e:
        pcsim.Case(model, set=s).run()
    rc, message = cli_error(pcsim_exe, "run", model, *[a for k, v in s.items()
                                                        for a in ("--set", f"{k}={v!r}")],
                            "--out", tmp_path / "cli")
    assert rc == 3
    assert message.startswith(str(e.value)) and "wrote it to" in message
    res = e.value.result
    assert res.complete and res.summary["accuracy"]["reliable"] is False
    assert res["t"][-1] == pytest.approx(0.2)
