"""Writes the FMI cross-check files of an FMU, checked against the independent closed form.

Usage, from anywhere, after the FMUs are built (`cargo run --release -- build`) and the test venv
exists (tests/run makes it):

    .venv/bin/python tests/python/make_reference.py                    # every model known below
    .venv/bin/python tests/python/make_reference.py GenevaKnifeDrive   # just that one
    .venv/bin/python tests/python/make_reference.py --check            # compare, write nothing

For each model it writes, in fmus/<id>/ (the layout of the FMI cross-check rules):

    <id>_in.csv   time, shaft.phi, shaft.w, shaft.a: the shaft turning at the machine's nominal
                  speed, phi = w*t (linear in t, so FMPy's linear interpolation of it is exact)
    <id>_ref.opt  StartTime, StopTime, StepSize, RelTol
    <id>_ref.csv  time and the model's reference outputs

`_ref.csv` is what FMPy (fmpy.simulate_fmu, co-simulation, inputs from `_in.csv`, times from
`_ref.opt`) computes with the FMU; the script refuses to write anything unless every row agrees
with the NumPy closed form of the spec (tests/python/closed_form.py) to rtol 1e-9, and every recorded
shaft.phi is the input at its row's time (harness.py: after fmi2DoStep(t_k, h) the FMU is at
t_k + h, as a Model Exchange run is; tests/python/test_cross_check_me.py runs the files through both
interfaces).
tests/python/test_all_fmus.py::test_cross_check_reproduces_reference then checks that the FMU
still reproduces the files.
"""

from __future__ import annotations

import argparse
import math
import shutil
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import closed_form  # noqa: E402
import main_shaft_reference  # noqa: E402
import closed_form_sewing  # noqa: E402
import disc_knife_closed_form  # noqa: E402
import legacy_closed_form  # noqa: E402
from harness import (FMU_DIR, SHAFT_INPUTS, Extracted, check_no_input_lag,  # noqa: E402
                     cross_check_paths, shaft_input, simulate_cross_check, write_csv, write_ref_opt)


@dataclass
class Reference:
    outputs: list[str]
    start: float
    stop: float
    step: float
    rel_tol: float
    speed: float  # rad/s, phi = speed*t
    check: Callable[[np.ndarray], list[str]]  # problems found in a result (with the shaft inputs)
    # constant inputs of a model that drives the shaft instead (MainShaft): {name: value}
    inputs: dict[str, float] | None = None


MODELS = {
    "GenevaKnifeDrive": Reference(
        outputs=["knife.s", "knife.v", "knife.a", "cross.gamma", "shaft.tau", "rod.F"],
        start=0.0, stop=4.0, step=0.01, rel_tol=1e-6,
        speed=math.pi,  # 30 rpm, drive.n's default: two driver turns in 4 s
        check=lambda result: closed_form.mismatches(result, closed_form.Params(), rtol=1e-9),
    ),
    "DiscKnifeDrive": Reference(
        outputs=["slider.x", "holder.beta", "knife.x", "knife.y", "knife.vx", "knife.vy", "support.x",
                 "support.y", "rod.F", "shaft.tau"],
        start=0.0, stop=0.4, step=1e-3, rel_tol=1e-6,
        speed=10.0 * math.pi,  # 300 rpm, drive.n's default: two crank turns in 0.4 s
        # S, D, C and beta against the NumPy geometry (circle-line intersection, not eq. 5)
        check=lambda result: disc_knife_closed_form.mismatches(result, disc_knife_closed_form.Params(),
                                                               rtol=1e-9),
    ),
    "SewingTable": Reference(
        outputs=["table.x", "table.v", "table.a", "cam.theta", "cam.F", "cam.sigma_H", "shaft.tau"],
        start=0.0, stop=1.2, step=0.002, rel_tol=1e-6,
        speed=100 * math.pi / 30,  # 100 rpm, the nominal speed: two turns in 1.2 s
        # table x, v, a against the NumPy cyclogram of sewing-table.md
        check=lambda result: closed_form_sewing.mismatches_table(result, rtol=1e-9),
    ),
    "Perforators": Reference(
        outputs=["table.x", "perforators.s", "perforators.v", "lever.gamma", "roller.F", "table.F",
                 "shaft.tau"],
        start=0.0, stop=1.2, step=0.002, rel_tol=1e-6,
        speed=100 * math.pi / 30,
        # table.x, perforators.s (the needle law of x_t) and shaft.tau = -table.F*dx_t/dphi
        check=lambda result: closed_form_sewing.mismatches_perforators(result, rtol=1e-9),
    ),
    "LegacyNeedleDrive": Reference(
        outputs=["perforators.s", "perforators.v", "rocker.psi", "lever3.theta", "cam.theta",
                 "rocker.w", "roller.F", "roller.sigma_H", "shaft.tau"],
        start=0.0, stop=1.2, step=0.002, rel_tol=1e-6,
        speed=100 * math.pi / 30,  # 100 rpm, the nominal speed: two turns in 1.2 s
        # the needle law, the chain's angles (NumPy circle intersections) and shaft.tau as the
        # roller's moment on the rocker
        check=lambda result: legacy_closed_form.mismatches(result, rtol=1e-9),
    ),
    "MainShaft": Reference(
        outputs=["shaft.phi", "shaft.w", "shaft.a", "motor.tau", "motor.s", "shaft.tau_load"],
        start=0.0, stop=3.0, step=0.01, rel_tol=1e-6,
        speed=0.0,  # it drives the shaft: a start-up from rest under constant loads
        check=lambda result: main_shaft_reference.mismatches(result, rtol=1e-6),
        inputs=main_shaft_reference.LOAD,
    ),
}


def make(mid: str, write: bool) -> list[str]:
    ref = MODELS[mid]
    ex = Extracted.of(FMU_DIR / f"{mid}.fmu")
    with tempfile.TemporaryDirectory() as tmp:
        tmp_paths = {k: Path(tmp) / p.name for k, p in cross_check_paths(mid).items()}
        n = int(round((ref.stop - ref.start) / ref.step)) + 1
        t = np.linspace(ref.start, ref.stop, n)
        if ref.inputs is None:
            signals = shaft_input(t, ref.speed * t, np.full_like(t, ref.speed), np.zeros_like(t))
            names = SHAFT_INPUTS
        else:
            names = list(ref.inputs)
            signals = np.zeros(t.shape, dtype=[("time", np.float64)] + [(n, np.float64) for n in names])
            signals["time"] = t
            for n, x in ref.inputs.items():
                signals[n] = x
        write_csv(tmp_paths["in"], signals, names)
        write_ref_opt(tmp_paths["opt"], ref.start, ref.stop, ref.step, ref.rel_tol)

        result = simulate_cross_check(ex, tmp_paths, ref.outputs,
                                      extra=SHAFT_INPUTS if ref.inputs is None else ())
        problems = []
        if ref.inputs is None:
            try:
                check_no_input_lag(result, lambda tt: ref.speed * tt)
            except AssertionError as e:
                problems.append(str(e))
        problems += ref.check(result)
        if problems:
            return problems
        write_csv(tmp_paths["ref"], result, ref.outputs)
        if write:
            for key, dest in cross_check_paths(mid).items():
                dest.parent.mkdir(parents=True, exist_ok=True)
                shutil.copyfile(tmp_paths[key], dest)
                print(f"wrote {dest} ({sum(1 for _ in open(dest)) - (key != 'opt')} rows)")
    return []


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("models", nargs="*", help=f"modelIdentifiers (default: {', '.join(MODELS)})")
    ap.add_argument("--check", action="store_true", help="simulate and compare only, write nothing")
    args = ap.parse_args(argv)
    failed = False
    for mid in args.models or list(MODELS):
        if mid not in MODELS:
            print(f"{mid}: no reference set-up in {Path(__file__).name} (known: {', '.join(MODELS)})")
            failed = True
            continue
        if not (FMU_DIR / f"{mid}.fmu").is_file():
            print(f"{mid}: {FMU_DIR / (mid + '.fmu')} missing: run `cargo run --release -- build`")
            failed = True
            continue
        problems = make(mid, write=not args.check)
        if problems:
            failed = True
            print(f"{mid}: the FMU disagrees with the closed form; nothing written:")
            for p in problems:
                print(f"  {p}")
        elif args.check:
            print(f"{mid}: agrees with the closed form")
    Extracted.cleanup()
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
