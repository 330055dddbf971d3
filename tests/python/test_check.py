# Case.check(): pcsim check from Python. The report text is the CLI's standard output byte for
# byte (the executable run on the same case), the fields say what the text says, and a case the
# CLI refuses (exit 2) raises pcsim.InputError with the CLI's message. The rank, degrees of
# freedom and redundant row of the parallelogram with a third crank are known by construction
# (12 coordinates, 12 constraints, one degree of freedom: the third crank repeats the coupler's
# vertical guidance), not taken from pcsim.
import json
import subprocess

import pytest

import pcsim

CONTRADICTION = {"pin_shifted": "xc0 - h*cos(tc0) - 0.1"}  # a second pin of crank 0, off A0_x


def cli_check(exe, case, *args):
    return subprocess.run([exe, "check", str(case), *args], capture_output=True, text=True)


@pytest.mark.parametrize("name", ["parallelogram_third_crank", "fourbar_a02_N1"])
def test_report_is_the_cli_output(root, pcsim_exe, name):
    case_file = root / "cases" / f"{name}.toml"
    cli = cli_check(pcsim_exe, case_file)
    assert cli.returncode == 0, cli.stderr
    res = pcsim.Case(case_file).check()
    assert isinstance(res, pcsim.CheckResult)
    assert res.report == cli.stdout
    assert res.can_run


def test_parallelogram_fields(root):
    res = pcsim.Case(root / "cases" / "parallelogram_third_crank.toml").check()
    assert len(res.coordinates) == 12 and len(res.active_constraints) == 12
    assert res.rank == 11
    assert res.dof == 1
    assert res.gruebler == 0
    assert res.redundant == ["M_coupler_y"]
    assert res.null_space_dimension == 1
    assert res.smallest_singular_value is not None and res.smallest_singular_value < 1e-8
    assert res.mass_positive_definite and 0 < res.mass_eigenvalues[0] <= res.mass_eigenvalues[1]
    assert res.note  # the accepted dependent row is remarked on
    # the JSON form holds the same fields
    d = res.data
    assert d["rank"] == 11 and d["redundant"] == ["M_coupler_y"] and d["can_run"] is True
    assert d["active_constraints"] == res.active_constraints
    json.dumps(d)  # plain JSON values


def test_independent_chain_fields(root):
    res = pcsim.Case(root / "cases" / "fourbar_a02_N1.toml").check()
    m = len(res.active_constraints)
    assert res.rank == m == 8
    assert res.dof == len(res.coordinates) - 8 == res.gruebler
    assert res.redundant == [] and res.null_space_dimension == 0
    assert res.smallest_singular_value > 1e-6
    assert all(c is not None and c >= 0 for c in res.correction)


def test_contradiction_raises_the_cli_message(root, pcsim_exe):
    case_file = root / "cases" / "fourbar_a02_N1.toml"
    cli = cli_check(pcsim_exe, case_file, "--constraint", "pin_shifted=" + CONTRADICTION["pin_shifted"])
    assert cli.returncode == 2
    with pytest.raises(pcsim.InputError) as e:
        pcsim.Case(case_file, constraints=CONTRADICTION).check()
    assert cli.stderr == f"pcsim: error: {e.value}\n"
    assert "'pin_shifted' contradicts 'A0_x'" in str(e.value)
    assert e.value.check_report == cli.stdout


def test_check_without_constraints_and_in_threads(root):
    import concurrent.futures

    case = pcsim.Case(root / "models" / "double_pendulum_minimal.toml")
    res = case.check()
    assert res.active_constraints == [] and res.rank == 0 and res.dof == 2
    assert res.smallest_singular_value is None and res.position_residual is None
    with concurrent.futures.ThreadPoolExecutor(2) as pool:
        reports = list(pool.map(lambda _: case.check().report, range(4)))
    assert reports == [res.report] * 4
