"""The three-knife trimmer at N cycles per minute: how hard do the knives and their rods work,
and what torque must the motor give?

One cycle is one turn of the main shaft: each Geneva drive indexes its cross once and its knife
makes one stroke (paper 003's drive; the two side knives in phase, the front knife half a turn
later). Runs the machine as it is exported, out/ssp/ThreeKnifeTrimmer.ssp (the main-shaft drive
with its motor, gear and flywheel, and the three knife drives), with FMPy's SSP runner. The
drive's gear is set so that N rpm is the main shaft's synchronous speed, and the shaft starts at
N rpm; the machine runs `--cycles` cycles and the answers are read over the last one.

    python examples/trimmer.py --cpm 30 --out out/examples

Build first (from the checkout): `cargo run --release -- build` and `cargo run --release -- ssp`.
Prints the answers and writes <out>/trimmer_<N>cpm.png.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

from machine import last_turn, run_machine, write_plot

SSP = Path(__file__).resolve().parents[1] / "out" / "ssp" / "ThreeKnifeTrimmer.ssp"
KNIVES = ["side_left", "side_right", "front"]


def answer(cpm: float, cycles: int) -> tuple[dict, dict]:
    """The machine's run at `cpm` cycles per minute and the figures of its last cycle."""
    r = run_machine(SSP, cpm, cycles)
    t = last_turn(r)
    motor = r["drive.motor.tau"][t]
    w = r["drive.shaft.w"][t]
    figures = {
        "running speed, cycles/min": float(w.mean() * 30 / math.pi),
        "speed fluctuation delta": float((w.max() - w.min()) / w.mean()),
        "peak motor torque, N.m": float(np.abs(motor).max()),
        "RMS motor torque, N.m": float(math.sqrt((motor ** 2).mean())),
        "peak main-shaft torque, N.m": float(np.abs(r["drive.shaft.tau_load"][t]).max()),
    }
    for k in KNIVES:
        figures[f"{k}: peak cutting force, N"] = float(r[f"{k}.knife.F_cut"][t].max())
        figures[f"{k}: peak rod force, N"] = float(np.abs(r[f"{k}.rod.F"][t]).max())
        figures[f"{k}: peak Geneva contact force, N"] = float(np.abs(r[f"{k}.geneva.F"][t]).max())
    return r, figures


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cpm", type=float, default=30.0, help="cycles per minute = main-shaft rpm (nominal 30)")
    ap.add_argument("--cycles", type=int, default=4, help="cycles to run (answers: the last)")
    ap.add_argument("--out", type=Path, default=Path("out/examples"), help="folder for the plot")
    a = ap.parse_args(argv)
    if not (math.isfinite(a.cpm) and 1.0 <= a.cpm <= 120.0):
        ap.error(f"--cpm {a.cpm}: give the cycles per minute (main-shaft rpm), from 1 to 120")
    if a.cycles < 2:
        ap.error(f"--cycles {a.cycles}: at least 2 (the first settles the start)")
    if not SSP.is_file():
        ap.error(f"{SSP} is missing: run `cargo run --release -- build` and "
                 "`cargo run --release -- ssp` in the checkout first")
    r, fig = answer(a.cpm, a.cycles)
    print(f"Three-knife trimmer at {a.cpm:g} cycles/min nominal "
          f"(running {fig['running speed, cycles/min']:.2f}, delta = {fig['speed fluctuation delta']:.4f}):")
    for k in KNIVES:
        print(f"  {k} knife: cutting force peak {fig[f'{k}: peak cutting force, N'] / 1e3:.2f} kN, "
              f"rod force peak {fig[f'{k}: peak rod force, N'] / 1e3:.2f} kN, "
              f"Geneva contact peak {fig[f'{k}: peak Geneva contact force, N'] / 1e3:.1f} kN")
    print(f"  main-shaft torque of the three drives: peak {fig['peak main-shaft torque, N.m'] / 1e3:.2f} kN.m")
    print(f"  motor torque: peak {fig['peak motor torque, N.m']:.1f} N.m, RMS {fig['RMS motor torque, N.m']:.1f} N.m")
    t = last_turn(r)
    png = write_plot(
        a.out / f"trimmer_{a.cpm:g}cpm.png",
        f"Three-knife trimmer at {a.cpm:g} cycles/min: the last cycle",
        r["deg"][t],
        [("rod force rod.F, kN", [("side_left, side_right (in phase)", r["side_left.rod.F"][t] / 1e3),
                                  ("front", r["front.rod.F"][t] / 1e3)], True),
         ("main-shaft torque, kN.m", [("the three drives", r["drive.shaft.tau_load"][t] / 1e3)], True),
         ("motor torque, N.m", [("at the motor shaft", r["drive.motor.tau"][t])], False)])
    print(f"  plot: {png}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
