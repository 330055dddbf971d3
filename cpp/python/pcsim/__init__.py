"""pcsim: constrained multibody dynamics by the principle of compatibility, from Python.

The same case files, keys, results and errors as the ``pcsim`` command line::

    import pcsim
    case = pcsim.Case("cases/sieve_1995.toml", set={"solver.t_end": 2.0})
    res = case.run()                 # a pcsim.RunResult
    res["R_u"]                       # a column of the time series (NumPy, no copy)
    res.summary["extremes"]["R_u"]   # summary.json's content, as dicts
    case.check().rank                # pcsim check's findings, without running (.report: its text)

Long calls (run, steady, response, sweep) release the GIL: runs on several threads use several
cores. Errors are the CLI's one-line messages as Python exceptions: InputError (a ValueError,
with .file and .key), NumericalError (with .time and the .result computed up to the failure),
IoError (an OSError).
"""

import sys as _sys
from typing import Any, Optional

try:
    import numpy as _numpy  # noqa: F401  (the results are NumPy arrays)
except ImportError as _e:  # e.g. a pyenv python3 first on PATH, without NumPy
    raise ImportError(
        f"pcsim needs NumPy, which {_sys.executable} does not have: use the interpreter pcsim was "
        "built for (Debian: /usr/bin/python3 with python3-numpy)") from _e


class Error(Exception):
    """Every error pcsim reports (the CLI's exit status 1 unless a subclass says otherwise)."""


class InputError(Error, ValueError):
    """Bad input (the CLI's exit 2): the message names the file, the key and what was expected.

    Attributes:
        file: the input file the message names, or None.
        key: the dotted case key the message names, or None.
        check_report: from Case.check() on a case that cannot run, the text pcsim check
            printed before its refusal; else None.
    """

    def __init__(self, message: str, file: Optional[str] = None, key: Optional[str] = None):
        super().__init__(message)
        self.file = file
        self.key = key
        self.check_report: Optional[str] = None


class NumericalError(Error, ArithmeticError):
    """The computation failed numerically (the CLI's exit 3): the message says when and why.

    Attributes:
        time: the model time of the failure, s.
        result: what the run computed up to then (a RunResult marked complete=False, or the
            complete but unreliable result), or None where nothing was kept.
    """

    def __init__(self, message: str, time: float = float("nan"), result: Any = None):
        super().__init__(message)
        self.time = time
        self.result = result


class IoError(Error, OSError):
    """An output file or directory could not be written (the CLI's exit 1)."""

    def __init__(self, message: str):
        Error.__init__(self, message)


from ._pcsim import (  # noqa: E402  (the exceptions above must exist first)
    Case,
    CheckResult,
    Model,
    ModesResult,
    ResponseResult,
    RunResult,
    SteadyResult,
    SweepResult,
    __version__,
    with_sieve,
)

__all__ = [
    "Case",
    "CheckResult",
    "Error",
    "InputError",
    "IoError",
    "Model",
    "ModesResult",
    "NumericalError",
    "ResponseResult",
    "RunResult",
    "SteadyResult",
    "SweepResult",
    "__version__",
    "with_sieve",
]
