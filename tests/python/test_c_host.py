"""A C host written by the project (tests/c_host/host.c) runs every FMU, and its output equals
FMPy's (issue 7).

host.c is compiled with `gcc -Wall -Wextra -Werror -std=c99`, with AddressSanitizer and
UndefinedBehaviorSanitizer (leak detection on), loads binaries/linux64/<id>.so of the extracted
FMU with dlopen, instantiates with the GUID of modelDescription.xml and runs the FMU at constant
speed (`drive.mode` = 2), printing every output as CSV. FMPy runs the same experiment; every
column must agree.
"""

from __future__ import annotations

import io
import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

HOST_C = Path(__file__).resolve().parents[1] / "c_host" / "host.c"
STOP, STEP = 2.0, 0.01


@pytest.fixture(scope="session")
def host(tmp_path_factory) -> Path:
    gcc = shutil.which("gcc")
    assert gcc, "gcc is needed to build the C host"
    exe = tmp_path_factory.mktemp("c_host") / "host"
    flags = ["-Wall", "-Wextra", "-Werror", "-std=c99", "-g", "-fsanitize=address,undefined",
             "-fno-sanitize-recover=all"]
    subprocess.run([gcc, *flags, "-o", str(exe), str(HOST_C), "-ldl"], check=True)
    return exe


def run_host(host: Path, fmu_dir: Path, *assignments: str) -> subprocess.CompletedProcess:
    env = dict(os.environ, ASAN_OPTIONS="detect_leaks=1", UBSAN_OPTIONS="print_stacktrace=1")
    return subprocess.run([str(host), str(fmu_dir), str(STOP), str(STEP), *assignments],
                          capture_output=True, text=True, env=env, timeout=120)


def is_drive(extracted) -> bool:
    """MainShaft: it turns the shaft (shaft.phi is its output) and runs alone from rest."""
    return extracted.vars["shaft.phi"].causality == "output"


def test_c_host_matches_fmpy(extracted, host):
    alone = {} if is_drive(extracted) else {"drive.mode": 2}
    proc = run_host(host, Path(extracted.dir), *(f"{k}={v}" for k, v in alone.items()))
    assert proc.returncode == 0, proc.stderr
    assert "ERROR: AddressSanitizer" not in proc.stderr and "runtime error" not in proc.stderr
    table = np.genfromtxt(io.StringIO(proc.stdout), delimiter=",", names=True, deletechars="")
    names = [n for n in table.dtype.names if n != "time"]
    assert names == extracted.outputs(types=("Real", "Integer", "Boolean", "Enumeration"))
    assert len(table) == round(STOP / STEP) + 1
    result = extracted.simulate(fmi_type="CoSimulation", start_time=0.0, stop_time=STOP,
                                output_interval=STEP, start_values=alone,
                                output=names)
    assert len(result) == len(table)
    np.testing.assert_allclose(table["time"], result["time"], rtol=0, atol=1e-12)
    for n in names:
        np.testing.assert_allclose(table[n], result[n].astype(float), rtol=1e-12, atol=1e-12,
                                   err_msg=n)


def test_c_host_reports_a_refused_parameter(extracted, host):
    """A parameter outside its bounds: the C host sees fmi2Error and the FMU's log line."""
    name, value = ("motor.lambda", "0.5") if is_drive(extracted) else ("drive.n", "1e9")
    proc = run_host(host, Path(extracted.dir), f"{name}={value}")
    assert proc.returncode == 1
    assert name in proc.stderr and "fmi2ExitInitializationMode" in proc.stderr, proc.stderr
