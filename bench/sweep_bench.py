"""The sweep benchmark (bench/sweep, BENCHMARKS.md "Sweeps"), in one run.

The same sweeps of the Perforators (kinematic, kinetostatic, elastodynamic) and the Geneva knife
drive (kinematic, kinetostatic) run
  - embedded: `bindery sweep --threads 1` and `--threads 2`;
  - on Dask: a scheduler and 1, then 2 single-threaded workers on loopback, `bindery sweep --dask`;
  - the peer: FMPy's own loop (`simulate_fmu` on the extracted FMU, the metric computed in
    Python from its result) as Dask tasks, one run per task, on the same 1 and 2 workers; FMPy
    gets fewer runs (it is slower), and its per-run cost is compared.
Wall time of each whole command (the Dask ones include the driver's start and connection);
runs per second and simulated communication steps per second. Writes a Markdown table.

    .venv/bin/python bench/sweep_bench.py --out out/bench/sweep.md
"""
import argparse
import math
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BINDERY = ROOT / "target" / "release" / "bindery"
VENV_BIN = Path(sys.executable).parent
STEPS_PER_TURN = 720

# (name, model, fidelity, swept block, runs, turns, FMPy runs): the Perforators, whose own work
# per run is large (the ramp's synthesis and checks, an inverse of the linkage per step), and the
# Geneva knife drive, whose closed form is cheap
CASES = [
    ("Perforators kinematic", "Perforators", "kinematic",
     '"speed" = { from = 60.0, to = 200.0, points = 4000 }', 4000, 1, 60),
    ("Perforators kinetostatic", "Perforators", "kinetostatic",
     '"spring.M0" = { from = 0.0, to = 12.0, points = 50 }\n'
     '"spring.kt" = { from = 0.0, to = 40.0, points = 40 }', 2000, 1, 60),
    ("Perforators elastodynamic", "Perforators", "elastodynamic",
     '"spring.M0" = { from = 4.0, to = 10.0, points = 12 }\n'
     '"spring.kt" = { values = [10.0, 20.0, 30.0, 40.0] }', 48, 2, 12),
    ("GenevaKnifeDrive kinematic", "GenevaKnifeDrive", "kinematic",
     '"speed" = { from = 20.0, to = 60.0, points = 200000 }', 200000, 1, 60),
    ("GenevaKnifeDrive kinetostatic", "GenevaKnifeDrive", "kinetostatic",
     '"speed" = { from = 20.0, to = 60.0, points = 800 }\n'
     '"cut.F_max" = { from = 1000.0, to = 5000.0, points = 250 }', 200000, 1, 60),
]
METRIC = {("Perforators", "kinematic"): ("perforators.s", "max"),
          ("Perforators", "kinetostatic"): ("roller.F", "min"),
          ("Perforators", "elastodynamic"): ("elastic.F", "max"),
          ("GenevaKnifeDrive", "kinematic"): ("knife.s", "max"),
          ("GenevaKnifeDrive", "kinetostatic"): ("rod.F", "max")}


def sweep_text(model, fidelity, swept, turns):
    speed = "" if "speed" in swept else "speed = 130\n"
    out, stat = METRIC[(model, fidelity)]
    return (f'model = "{model}"\nfidelity = "{fidelity}"\n[swept]\n{swept}\n'
            f"[experiment]\n{speed}turns = {turns}\nsteps_per_turn = {STEPS_PER_TURN}\n"
            f'[metrics]\nm = {{ output = "{out}", stat = "{stat}" }}\n')


def timed(cmd, env=None):
    t = time.perf_counter()
    r = subprocess.run(cmd, capture_output=True, text=True, env=env)
    dt = time.perf_counter() - t
    if r.returncode != 0:
        sys.exit(f"{' '.join(map(str, cmd))}: {r.stderr}")
    return dt


def fmpy_run(fmu_dir, model, fidelity, params, turns):
    """One run in FMPy's loop: the FMU at constant speed, the metric from the result."""
    from fmpy import simulate_fmu
    import numpy as np

    rpm = params.pop("speed", 130.0)
    turn = 60.0 / rpm
    start = {"model.fidelity": {"kinematic": 1, "kinetostatic": 2, "elastodynamic": 3}[fidelity],
             "drive.mode": 2, "drive.n": rpm * math.pi / 30.0, **params}
    out, stat = METRIC[(model, fidelity)]
    res = simulate_fmu(fmu_dir, start_values=start, stop_time=turns * turn,
                       output_interval=turn / STEPS_PER_TURN, output=[out])
    x = res[out][res["time"] >= (turns - 1) * turn - 1e-12]
    return float(np.max(x) if stat == "max" else np.min(x))


def fmpy_params(case, k):
    """Run k of the case's design (the grid's last parameter fastest), as FMPy start values."""
    name = case[0]
    if name == "Perforators kinematic":
        return {"speed": 60.0 + 140.0 * k / 3999}
    if name == "Perforators kinetostatic":
        return {"spring.M0": 12.0 * (k // 40) / 49, "spring.kt": 40.0 * (k % 40) / 39}
    if name == "Perforators elastodynamic":
        return {"spring.M0": 4.0 + 6.0 * (k // 4) / 11, "spring.kt": [10.0, 20.0, 30.0, 40.0][k % 4]}
    if name == "GenevaKnifeDrive kinematic":
        return {"speed": 20.0 + 40.0 * k / 199999}
    return {"speed": 20.0 + 40.0 * (k // 250) / 799, "cut.F_max": 1000.0 + 4000.0 * (k % 250) / 249}


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Cluster:
    def __init__(self, workers, tmp):
        self.port = free_port()
        self.address = f"tcp://127.0.0.1:{self.port}"
        dask = str(VENV_BIN / "dask")
        log = open(Path(tmp) / f"dask-{workers}.log", "w")
        self.procs = [subprocess.Popen([dask, "scheduler", "--host", "127.0.0.1", "--port",
                                        str(self.port), "--no-dashboard"], stdout=log,
                                       stderr=subprocess.STDOUT, cwd=tmp)]
        from distributed import Client
        self.client = Client(self.address, timeout="30s")
        for _ in range(workers):
            self.procs.append(subprocess.Popen(
                [dask, "worker", self.address, "--nthreads", "1", "--no-nanny",
                 "--no-dashboard"], stdout=log, stderr=subprocess.STDOUT, cwd=tmp))
        self.client.wait_for_workers(workers, timeout=60)

    def close(self):
        self.client.close()
        for p in reversed(self.procs):  # the workers, then the scheduler
            p.terminate()
            try:
                p.wait(timeout=10)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=str(ROOT / "out" / "bench" / "sweep.md"))
    args = ap.parse_args()
    tmp = tempfile.mkdtemp(prefix="bindery-sweep-bench-")
    from fmpy import extract
    fmu_dirs = {m: extract(str(ROOT / "out" / "fmus" / f"{m}.fmu")) for m in {c[1] for c in CASES}}
    rows = []  # (case, host, runs, seconds, steps)
    files = {}
    for case in CASES:
        name, model, fidelity, swept, runs, turns, _ = case
        f = Path(tmp) / f"{name.replace(' ', '-')}.toml"
        f.write_text(sweep_text(model, fidelity, swept, turns))
        files[name] = f
        for threads in (1, 2):
            dt = timed([BINDERY, "sweep", f, "--out", Path(tmp) / f"{name.replace(' ', '-')}-e{threads}", "--fresh",
                        "--no-plot", "--threads", str(threads)])
            rows.append((name, f"embedded, {threads} thread{'s' if threads > 1 else ''}", runs, dt,
                         runs * turns * STEPS_PER_TURN))
            print(rows[-1], flush=True)
    env = dict(os.environ, BINDERY_PYTHON=sys.executable)
    for workers in (1, 2):
        c = Cluster(workers, tmp)
        try:
            for case in CASES:
                name, model, fidelity, swept, runs, turns, fmpy_runs = case
                dt = timed([BINDERY, "sweep", files[name], "--out", Path(tmp) / f"{name.replace(' ', '-')}-d{workers}",
                            "--fresh", "--no-plot", "--dask", c.address], env=env)
                label = f"{workers} worker{'s' if workers > 1 else ''}"
                rows.append((name, f"Dask, {label}", runs, dt, runs * turns * STEPS_PER_TURN))
                print(rows[-1], flush=True)
                # the peer: FMPy's loop as Dask tasks, one run each
                c.client.run(lambda: __import__("fmpy"))  # imported before the clock starts
                t = time.perf_counter()
                futs = [c.client.submit(fmpy_run, fmu_dirs[model], model, fidelity,
                                        fmpy_params(case, k * (runs // fmpy_runs)),
                                        turns, pure=False) for k in range(fmpy_runs)]
                c.client.gather(futs)
                dt = time.perf_counter() - t
                rows.append((name, f"FMPy on Dask, {label}", fmpy_runs, dt,
                             fmpy_runs * turns * STEPS_PER_TURN))
                print(rows[-1], flush=True)
        finally:
            c.close()
    shutil.rmtree(tmp, ignore_errors=True)

    def per_run(case, host):
        r = next(r for r in rows if r[0] == case and r[1] == host)
        return r[3] / r[2]

    lines = ["| sweep | host | runs | s | runs/s | steps/s | ms per run |", "|---|---|---:|---:|---:|---:|---:|"]
    for case, host, runs, dt, steps in rows:
        lines.append(f"| {case} | {host} | {runs} | {dt:.2f} | {runs / dt:,.0f} | {steps / dt:,.3g} | {1e3 * dt / runs:.3g} |")
    lines += ["", "| sweep | 2 threads / 1 | 2 Dask workers / 1 | FMPy on Dask / ours on Dask, per run (1 worker) | (2 workers) |",
              "|---|---:|---:|---:|---:|"]
    for case in [c[0] for c in CASES]:
        lines.append(
            f"| {case} | {per_run(case, 'embedded, 1 thread') / per_run(case, 'embedded, 2 threads'):.2f} "
            f"| {per_run(case, 'Dask, 1 worker') / per_run(case, 'Dask, 2 workers'):.2f} "
            f"| {per_run(case, 'FMPy on Dask, 1 worker') / per_run(case, 'Dask, 1 worker'):.0f} "
            f"| {per_run(case, 'FMPy on Dask, 2 workers') / per_run(case, 'Dask, 2 workers'):.0f} |")
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
