# Shared fixtures of the pcsim Python tests (tests/python): run by CTest from the source tree's
# root with PYTHONPATH=<build>/python and PCSIM_EXE=<build>/pcsim (tests/python/CMakeLists.txt).
import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def root():
    return ROOT


@pytest.fixture(scope="session")
def pcsim_exe():
    exe = os.environ.get("PCSIM_EXE")
    if not exe:
        pytest.skip("PCSIM_EXE is not set (run through ctest)")
    return exe


# A pendulum (models/pendulum.toml) released from 60 degrees: a short, exactly known case.
PENDULUM_SET = {
    "initial.x": 0.8660254037844386,
    "initial.y": -0.5,
    "solver.t_end": 0.05,
    "output.dt": 0.01,
}


@pytest.fixture
def pendulum():
    import pcsim

    return pcsim.Case(ROOT / "models" / "pendulum.toml", set=PENDULUM_SET)
