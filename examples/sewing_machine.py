"""The thread-sewing machine at N rpm: does the perforators' roller stay on its ramp, and what
torque does the main shaft need with the sewing table and the perforators riding on it?

Runs the machine as it is exported, out/ssp/ThreadSewingMachine.ssp (the main-shaft drive with
its motor, gear and flywheel; the cam-driven sewing table; the perforator drive on the table,
its force on the table wired into the table), with FMPy's SSP runner. The drive's gear is set so
that N rpm is the main shaft's synchronous speed, and the shaft starts at N rpm; the machine then
runs `--turns` shaft turns and the answers are read over the last one.

    python examples/sewing_machine.py --rpm 100 --out out/examples

Build first (from the checkout): `cargo run --release -- build` and `cargo run --release -- ssp`.
Prints the answers and writes <out>/sewing_machine_<N>rpm.png.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

from machine import last_turn, run_machine, write_plot

SSP = Path(__file__).resolve().parents[1] / "out" / "ssp" / "ThreadSewingMachine.ssp"


def answer(rpm: float, turns: int) -> tuple[dict, dict]:
    """The machine's run at `rpm` (nominal) and the figures of its last shaft turn."""
    r = run_machine(SSP, rpm, turns)
    t = last_turn(r)
    f = r["perforators.roller.F"][t]
    phi = r["deg"][t]
    tau = r["drive.shaft.tau_load"][t]
    motor = r["drive.motor.tau"][t]
    w = r["drive.shaft.w"][t]
    i_min = int(f.argmin())
    figures = {
        "running speed, rpm": float(w.mean() * 30 / math.pi),
        "speed fluctuation delta": float((w.max() - w.min()) / w.mean()),
        "smallest ramp contact force, N": float(f.min()),
        "at shaft angle, deg": float(phi[i_min]),
        "roller lifts off": bool(f.min() < 0.0),
        "peak main-shaft torque, N.m": float(abs(tau).max()),
        "mean main-shaft torque, N.m": float(tau.mean()),
        "RMS main-shaft torque, N.m": float(math.sqrt((tau ** 2).mean())),
        "peak motor torque, N.m": float(abs(motor).max()),
        "RMS motor torque, N.m": float(math.sqrt((motor ** 2).mean())),
    }
    return r, figures


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rpm", type=float, default=100.0, help="main-shaft speed, rpm (nominal 100)")
    ap.add_argument("--turns", type=int, default=6, help="shaft turns to run (answers: the last)")
    ap.add_argument("--out", type=Path, default=Path("out/examples"), help="folder for the plot")
    a = ap.parse_args(argv)
    if not (math.isfinite(a.rpm) and 1.0 <= a.rpm <= 600.0):
        ap.error(f"--rpm {a.rpm}: give the main-shaft speed in rpm, from 1 to 600")
    if a.turns < 2:
        ap.error(f"--turns {a.turns}: at least 2 (the first settles the start)")
    if not SSP.is_file():
        ap.error(f"{SSP} is missing: run `cargo run --release -- build` and "
                 "`cargo run --release -- ssp` in the checkout first")
    r, fig = answer(a.rpm, a.turns)
    print(f"Thread-sewing machine at {a.rpm:g} rpm nominal "
          f"(running {fig['running speed, rpm']:.2f} rpm, delta = {fig['speed fluctuation delta']:.4f}):")
    if fig["roller lifts off"]:
        print(f"  the perforators' roller LIFTS OFF its ramp: the ramp would have to pull with "
              f"{-fig['smallest ramp contact force, N']:.1f} N at shaft angle "
              f"{fig['at shaft angle, deg']:.1f} deg; stiffen the spring (spring.M0, spring.kt) or slow down")
    else:
        print(f"  the roller stays on its ramp: lift-off margin {fig['smallest ramp contact force, N']:.1f} N "
              f"(smallest contact force, at shaft angle {fig['at shaft angle, deg']:.1f} deg)")
    print(f"  main-shaft torque of table + perforators: peak {fig['peak main-shaft torque, N.m']:.1f} N.m, "
          f"mean {fig['mean main-shaft torque, N.m']:.2f} N.m, RMS {fig['RMS main-shaft torque, N.m']:.1f} N.m")
    print(f"  motor torque: peak {fig['peak motor torque, N.m']:.2f} N.m, "
          f"RMS {fig['RMS motor torque, N.m']:.2f} N.m")
    t = last_turn(r)
    png = write_plot(
        a.out / f"sewing_machine_{a.rpm:g}rpm.png",
        f"Thread-sewing machine at {a.rpm:g} rpm: the last shaft turn",
        r["deg"][t],
        [("ramp contact force roller.F, N", [("perforators", r["perforators.roller.F"][t])], True),
         ("torque, N.m", [("main shaft (table + perforators)", r["drive.shaft.tau_load"][t]),
                          ("motor (at the motor shaft)", r["drive.motor.tau"][t])], False)])
    print(f"  plot: {png}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
