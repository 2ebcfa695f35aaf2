"""`bindery sweep` where its users are: the results read by pyarrow (what pandas, Dask and
Polars read Parquet with), an interrupted sweep resumed, and the same sweep on a real Dask
cluster on loopback (a scheduler and two worker processes, one killed in the middle), whose
rows must equal the embedded run's bit for bit, each run exactly once.
"""

from __future__ import annotations

import math
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pyarrow.parquet as pq
import pytest

from harness import ROOT

BINDERY = ROOT / "target" / "release" / "bindery"
VENV_BIN = Path(sys.executable).parent

# An elastodynamic sweep: each run integrates the lever's contact for eight shaft turns (about
# 0.3 s of work), so that on one thread the sweep lasts several times the 2 s after which the
# store writes a part, and can be interrupted between parts (at two turns a faster build ran
# the whole sweep inside the first 2 s).
SWEEP = """
model = "Perforators"
fidelity = "elastodynamic"
[swept]
"spring.M0" = { from = 4.0, to = 10.0, points = 8 }
"spring.kt" = { values = [10.0, 20.0, 30.0] }
[experiment]
speed = 130
turns = 8
steps_per_turn = 360
[metrics]
liftoffs = { output = "contact.liftoffs", stat = "increase" }
F_max = { output = "elastic.F", stat = "max" }
F_rms = { output = "elastic.F", stat = "rms" }
lifted = { output = "roller.lost_contact", stat = "any" }
"""
RUNS = 24


def bindery(*args, **kw) -> subprocess.CompletedProcess:
    if not BINDERY.is_file():
        pytest.fail(f"{BINDERY} is missing: run `cargo build --release` (or tests/run) first")
    return subprocess.run([str(BINDERY), *map(str, args)], capture_output=True, text=True, **kw)


def rows(folder: Path) -> list[dict]:
    t = pq.read_table(folder / "runs")
    return sorted(t.to_pylist(), key=lambda r: r["run"])


def same_bits(a: list[dict], b: list[dict]):
    assert len(a) == len(b)
    for x, y in zip(a, b):
        assert x.keys() == y.keys()
        for k in x:
            p, q = x[k], y[k]
            if isinstance(p, float) and isinstance(q, float):
                assert p.hex() == q.hex() or (math.isnan(p) and math.isnan(q)), (x["run"], k, p, q)
            else:
                assert p == q, (x["run"], k, p, q)


@pytest.fixture(scope="module")
def embedded(tmp_path_factory) -> list[dict]:
    d = tmp_path_factory.mktemp("embedded")
    (d / "s.toml").write_text(SWEEP)
    r = bindery("sweep", d / "s.toml", "--out", d / "out", "--threads", 2, "--csv")
    assert r.returncode == 0, r.stderr
    out = rows(d / "out")
    assert [x["run"] for x in out] == list(range(RUNS))
    # the CSV holds the same rows
    lines = (d / "out" / "runs.csv").read_text().splitlines()
    assert lines[0].split(",")[:5] == ["run", "spring.M0", "spring.kt", "liftoffs", "F_max"]
    assert len(lines) == RUNS + 1
    return out


def test_the_results_are_a_parquet_dataset_with_the_design_and_the_metrics(embedded):
    # the grid: the last swept parameter varies fastest
    assert [r["spring.kt"] for r in embedded[:3]] == [10.0, 20.0, 30.0]
    assert [r["spring.M0"] for r in embedded[::3]] == pytest.approx(
        [4.0 + 6.0 * i / 7 for i in range(8)], rel=0, abs=1e-15
    )
    assert all(r["error"] is None for r in embedded)
    # physics the metrics must show: the weakest spring lets the roller bounce, the strongest
    # holds it on the ramp at this speed (the lift-off count is not monotonic in between: the
    # bounces depend on where the roller lands)
    weakest, strongest = embedded[0], embedded[-1]
    assert (weakest["spring.M0"], weakest["spring.kt"]) == (4.0, 10.0)
    assert (strongest["spring.M0"], strongest["spring.kt"]) == (10.0, 30.0)
    assert weakest["liftoffs"] > 0 and strongest["liftoffs"] == 0
    for r in embedded:
        assert (r["lifted"] == 1.0) == (r["liftoffs"] > 0)
        assert r["warnings"] == 0 or r["warning"]
        assert 0 < r["F_rms"] <= r["F_max"]


def test_an_interrupted_sweep_resumes_without_redoing_or_losing_a_run(embedded, tmp_path):
    (tmp_path / "s.toml").write_text(SWEEP)
    out = tmp_path / "out"
    p = subprocess.Popen(
        [str(BINDERY), "sweep", str(tmp_path / "s.toml"), "--out", str(out), "--threads", "1"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    deadline = time.monotonic() + 60
    while not list((out / "runs").glob("part-*.parquet")) and p.poll() is None:
        assert time.monotonic() < deadline, "no part written in 60 s"
        time.sleep(0.05)
    p.kill()  # SIGKILL: no chance to tidy up
    p.wait()
    first = rows(out)
    assert 0 < len(first) < RUNS, "killed before its end"
    r = bindery("sweep", tmp_path / "s.toml", "--out", out)
    assert r.returncode == 0, r.stderr
    assert f"{RUNS - len(first)} to do" in r.stderr
    same_bits(rows(out), embedded)
    # another sweep file into the same folder is refused, naming --fresh
    (tmp_path / "s.toml").write_text(SWEEP.replace("points = 8", "points = 9"))
    r = bindery("sweep", tmp_path / "s.toml", "--out", out)
    assert r.returncode != 0 and "--fresh" in r.stderr


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_the_same_sweep_on_a_dask_cluster_survives_a_killed_worker(embedded, tmp_path):
    from distributed import Client

    port = free_port()
    address = f"tcp://127.0.0.1:{port}"
    logs = []

    def start(*args):
        log = open(tmp_path / f"dask-{len(logs)}.log", "w")
        logs.append(log)
        return subprocess.Popen(
            [str(VENV_BIN / "dask"), *args], stdout=log, stderr=subprocess.STDOUT, cwd=tmp_path
        )

    procs = [start("scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard")]
    try:
        with Client(address, timeout="30s") as client:
            for _ in range(2):
                procs.append(
                    start("worker", address, "--nthreads", "1", "--no-nanny", "--no-dashboard")
                )
            client.wait_for_workers(2, timeout=60)
            (tmp_path / "s.toml").write_text(SWEEP)
            out = tmp_path / "out"
            env = dict(os.environ, BINDERY_PYTHON=sys.executable)
            sweep = subprocess.Popen(
                [str(BINDERY), "sweep", str(tmp_path / "s.toml"), "--out", str(out),
                 "--dask", address, "--chunk", "2", "--no-plot"],
                stdout=subprocess.PIPE,
                stderr=subprocess.PIPE,
                text=True,
                env=env,
            )
            # kill a worker while it has a task (SIGKILL: the worker cannot hand anything back)
            deadline = time.monotonic() + 60
            victim = procs[1]
            while True:
                assert time.monotonic() < deadline, "no task reached the workers"
                busy = [w for w, tasks in client.processing().items() if tasks]
                if len(busy) == 2:
                    break
                time.sleep(0.02)
            time.sleep(0.3)
            victim.send_signal(signal.SIGKILL)
            victim.wait()
            _, err = sweep.communicate(timeout=300)
            assert sweep.returncode == 0, err
            assert len(client.scheduler_info()["workers"]) == 1
        got = rows(out)
        assert [r["run"] for r in got] == list(range(RUNS)), "every run exactly once"
        same_bits(got, embedded)
    finally:
        for p in procs:
            if p.poll() is None:
                p.terminate()
        for p in procs:
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                p.kill()
        for log in logs:
            log.close()


def test_a_bad_sweep_file_is_refused_with_its_key_and_line(tmp_path):
    bad = SWEEP.replace('stat = "rms"', 'stat = "median"')
    (tmp_path / "s.toml").write_text(bad)
    r = bindery("sweep", tmp_path / "s.toml", "--out", tmp_path / "out")
    assert r.returncode != 0
    line = next(i for i, l in enumerate(bad.splitlines(), 1) if "median" in l)
    assert f"line {line}" in r.stderr and "F_rms" in r.stderr and "median" in r.stderr, r.stderr
    assert not (tmp_path / "out").exists()
