"""Error against wall time of an elastodynamic FMU (default GenevaKnifeDrive): the FMU's internal
solvers in Co-Simulation and FMPy's CVode on the Model Exchange interface, in the same process and
host loop (FMPy's simulate_fmu), against a tight-tolerance reference (dopri5, rtol 1e-11; radau5's
error estimate filters the stiff ringing of an undamped 1e12 N/m chain, Dormand-Prince resolves it).

usage: .venv/bin/python scripts/work_precision.py [--fmu GenevaKnifeDrive] [--x knife.s]
       [--k-name elastic.k] [--k 5e7] [--zeta 0.05] [--rpm 30] [--stop 2.0]
Prints one JSON object per run: method, tol, error (max |x - ref| in m over the output
grid), seconds (the median of at least --repeat runs, repeated until they took --min-total
seconds together, at most 51: a run of 10 ms alone moves by a third with the machine's load).
The model description is read and validated once, before the timed runs, and handed to each
run, as a sweep over one FMU does: its parsing (about 3 ms for these descriptions) is the same
for both interfaces and no part of either integration; instantiation and the host loop are
timed."""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from pathlib import Path

import numpy as np
from fmpy import extract, read_model_description, simulate_fmu

ROOT = Path(__file__).resolve().parents[1]
METHODS = {"auto": 1, "dopri5": 2, "radau5": 3, "rk4": 4}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--fmu", default="GenevaKnifeDrive", help="modelIdentifier in out/fmus/")
    ap.add_argument("--x", default="knife.s", help="the position output compared")
    ap.add_argument("--k-name", default="elastic.k", help="the stiffness parameter")
    ap.add_argument("--k", type=float, default=5e7)
    ap.add_argument("--rpm", type=float, default=None, help="shaft speed (default: nominal)")
    ap.add_argument("--set", default="", help="other start values, name=value,name=value")
    ap.add_argument("--zeta", type=float, default=None, help="elastic.zeta (default: the FMU's)")
    ap.add_argument("--stop", type=float, default=2.0)
    ap.add_argument("--dt", type=float, default=1e-3)
    ap.add_argument("--repeat", type=int, default=3, help="at least this many runs of each")
    ap.add_argument("--min-total", type=float, default=0.3, help="runs go on until they took this long, s")
    ap.add_argument("--only", default="", help="comma-separated methods (auto, dopri5, radau5, rk4, fmpy-cvode-me)")
    a = ap.parse_args()
    unzip = extract(str(ROOT / "out" / "fmus" / f"{a.fmu}.fmu"))
    md = read_model_description(unzip)
    base = {"model.fidelity": 3, "drive.mode": 2, a.k_name: a.k}
    if a.zeta is not None:
        base["elastic.zeta"] = a.zeta
    for item in filter(None, a.set.split(",")):
        name, value = item.split("=")
        base[name] = float(value)
    if a.rpm is not None:
        base["drive.n"] = a.rpm * np.pi / 30.0

    def run(fmi_type, start, repeat=True, **kw):
        times, res = [], None
        while not times or repeat and (len(times) < a.repeat or sum(times) < a.min_total) and len(times) < 51:
            t0 = time.perf_counter()
            res = simulate_fmu(unzip, fmi_type=fmi_type, start_time=0.0, stop_time=a.stop,
                               output_interval=a.dt, start_values=dict(base, **start),
                               output=[a.x], model_description=md, **kw)
            times.append(time.perf_counter() - t0)
        return res, statistics.median(times)

    ref, _ = run("CoSimulation", {"solver.method": 2, "solver.rtol": 1e-11, "solver.atol": 1e-14}, repeat=False)
    grid = ref["time"]

    def err(r):
        return float(np.max(np.abs(np.interp(grid, r["time"], r[a.x]) - ref[a.x])))

    only = set(filter(None, a.only.split(",")))
    for name, m in METHODS.items():
        if only and name not in only:
            continue
        tols = [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8] if name != "rk4" else [1e-3, 3e-4, 1e-4, 3e-5, 1e-5]
        for tol in tols:
            start = {"solver.method": m}
            if name == "rk4":
                start["solver.max_step"] = tol
            else:
                start.update({"solver.rtol": tol, "solver.atol": tol * 1e-3})
            try:
                r, s = run("CoSimulation", start)
                print(json.dumps({"method": name, "tol": tol, "error": err(r), "seconds": s}), flush=True)
            except Exception as e:  # a Discard ends the run: reported, not plotted
                print(json.dumps({"method": name, "tol": tol, "error": None, "seconds": None,
                                  "failed": str(e)}), flush=True)
    for tol in [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8]:
        if only and "fmpy-cvode-me" not in only:
            break
        try:
            r, s = run("ModelExchange", {}, solver="CVode", relative_tolerance=tol)
            print(json.dumps({"method": "fmpy-cvode-me", "tol": tol, "error": err(r), "seconds": s}), flush=True)
        except Exception as e:  # CVode's mxstep on the stiffest chain at tight tolerances
            print(json.dumps({"method": "fmpy-cvode-me", "tol": tol, "error": None, "seconds": None,
                              "failed": str(e)}), flush=True)


if __name__ == "__main__":
    sys.exit(main())
