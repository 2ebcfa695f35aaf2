"""The FMPy host of the peer benchmark (bench/run, BENCHMARKS.md).

GenevaKnifeDrive, its PythonFMU peer and the C floor in FMPy 0.3.32's FMU2Slave, per
communication step: setReal of the shaft angle, doStep, getReal of 19 Real values (the first
19 Real outputs by value reference, shaft.tau ... crank.tau, the same names in the PythonFMU peer;
the floor's three outputs read cyclically to the same count), at the kinematic and the kinetostatic level. Interleaved rounds, one sample of each
subject per round, median over the rounds, as the native host (benches/peers.rs) does.

    .venv-bench/bin/python bench/fmpy_peers.py --dir out/bench --json out/bench/fmpy.json
"""
import argparse
import json
import math
import statistics
import time
from pathlib import Path

from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

H = 1e-3
W = math.pi
N_READ = 19
FMUS = [("ours", "GenevaKnifeDrive"), ("pythonfmu", "GenevaKnifeDrivePy"), ("floor", "Floor")]
LEVELS = [("kinematic", 1), ("kinetostatic", 2)]


class Subject:
    def __init__(self, path, level):
        md = read_model_description(str(path))
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        outs = [v.valueReference for v in md.modelVariables
                if v.causality == "output" and v.type == "Real"]
        self.read = [outs[i % len(outs)] for i in range(N_READ)]
        self.phi_vr = [self.vr.get("shaft.phi", self.vr.get("u1"))]
        self.dir = extract(str(path))
        self.slave = FMU2Slave(guid=md.guid, unzipDirectory=self.dir,
                               modelIdentifier=md.coSimulation.modelIdentifier,
                               instanceName="bench")
        s = self.slave
        s.instantiate()
        if "model.fidelity" in self.vr:
            s.setInteger([self.vr["model.fidelity"]], [level])
        s.setupExperiment(startTime=0.0)
        s.enterInitializationMode()
        s.exitInitializationMode()
        self.t = 0.0

    def steps(self, m):
        s, phi_vr, read, t = self.slave, self.phi_vr, self.read, self.t
        for _ in range(m):
            s.setReal(phi_vr, [W * t])
            s.doStep(t, H)
            s.getReal(read)
            t += H
        self.t = t

    def close(self):
        self.slave.terminate()
        self.slave.freeInstance()


def check_same_physics(subjects):
    """The PythonFMU peer computes what ours computes: the same 19 outputs at 200 shaft angles
    over a turn, at both levels, to round-off. A benchmark of a peer that differs would be void."""
    by = {(label, level): s for label, level, s in subjects}
    for level, _ in LEVELS:
        ours, py = by[("ours", level)], by[("pythonfmu", level)]
        names = [n for n, vr in sorted(ours.vr.items(), key=lambda x: x[1]) if vr in ours.read]
        for k in range(200):
            phi = 2.0 * math.pi * k / 200 + 1e-3
            got = []
            for s in (ours, py):
                s.slave.setReal(s.phi_vr, [phi])
                s.slave.doStep(s.t, H)
                s.t += H
                got.append(dict(zip(s.read, s.slave.getReal(s.read))))
            for n in names:
                x, y = got[0][ours.vr[n]], got[1][py.vr[n]]
                assert abs(x - y) <= 1e-9 * (1.0 + abs(x)), f"{level} {n} at phi = {phi}: {x} vs {y}"
    print("PythonFMU peer agrees with GenevaKnifeDrive (19 outputs, 200 angles, both levels)")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--dir", default="out/bench", help="folder with the three .fmu files")
    ap.add_argument("--fmus", default="out/fmus", help="folder with GenevaKnifeDrive.fmu")
    ap.add_argument("--json")
    ap.add_argument("--rounds", type=int, default=101)
    ap.add_argument("--sample-ms", type=float, default=5.0)
    a = ap.parse_args()
    paths = {"ours": Path(a.fmus) / "GenevaKnifeDrive.fmu",
             "pythonfmu": Path(a.dir) / "GenevaKnifeDrivePy.fmu",
             "floor": Path(a.dir) / "Floor.fmu"}
    subjects = []
    for level, code in LEVELS:
        for label, _ in FMUS:
            if label == "floor" and code == 1:
                continue  # no levels: measured once, reported under both
            subjects.append((label, level, Subject(paths[label], code)))
    check_same_physics(subjects)
    target = a.sample_ms * 1e-3
    per_sample = []
    for _, _, s in subjects:
        s.steps(50)
        m = 1
        while True:
            t0 = time.perf_counter()
            s.steps(m)
            dt = time.perf_counter() - t0
            if dt > target / 4 or m > 1 << 20:
                per_sample.append(max(1, math.ceil(m * target / dt)))
                break
            m *= 2
    samples = [[] for _ in subjects]
    for _ in range(a.rounds):
        for i, (_, _, s) in enumerate(subjects):
            m = per_sample[i]
            t0 = time.perf_counter_ns()
            s.steps(m)
            samples[i].append((time.perf_counter_ns() - t0) / m)
    rows = []
    for i, (label, level, s) in enumerate(subjects):
        v = sorted(samples[i])
        rows.append({"host": "fmpy", "fmu": label, "level": level,
                     "ns_per_step": round(statistics.median(v), 1),
                     "p10": round(v[len(v) // 10], 1), "p90": round(v[len(v) * 9 // 10], 1),
                     "steps_per_sample": per_sample[i], "samples": len(v),
                     "rounds": [round(x, 1) for x in samples[i]]})
        s.close()
    text = "[\n" + ",\n".join(json.dumps(r) for r in rows) + "\n]"
    print(text)
    if a.json:
        Path(a.json).write_text(text + "\n")


if __name__ == "__main__":
    main()
