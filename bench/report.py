"""Puts the peer benchmark's figures together (bench/run): per-step medians of both hosts, the
ratios and goals of issue 8, .fmu sizes, heap per instance, the machine. Prints markdown and
writes it to out/bench/report.md.

    python3 bench/report.py --dir out/bench
"""
import argparse
import json
import os
import platform
import statistics
from pathlib import Path

GOALS = "FFI overhead <= 1.2x; <= 1.5x the C floor (native); PythonFMU >= 100x ours (native); " \
        "ours <= 1.10x the floor under FMPy; .fmu <= 1 MB; <= 64 KB heap per instance"


def fmt_ns(ns):
    return f"{ns / 1000:.2f} us" if ns >= 10_000 else f"{ns:.1f} ns"


def machine():
    model = "?"
    for line in Path("/proc/cpuinfo").read_text().splitlines():
        if line.startswith("model name"):
            model = line.split(":", 1)[1].strip()
            break
    return f"{os.cpu_count()} CPUs (nproc), {model}, {platform.system()} {platform.release()}"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--dir", default="out/bench")
    ap.add_argument("--fmus", default="out/fmus")
    a = ap.parse_args()
    d = Path(a.dir)
    rows = json.loads((d / "native.json").read_text()) + json.loads((d / "fmpy.json").read_text())
    heap = json.loads((d / "heap.json").read_text())
    med = {(r["host"], r["fmu"], r["level"]): r for r in rows}

    def key(host, fmu, level):
        if fmu == "floor":
            level = "kinetostatic"  # the floor has no levels
        if fmu == "bare":
            host = "native"  # the bare call is Rust, in the native host's process
        return (host, fmu, level)

    def get(host, fmu, level):
        return med[key(host, fmu, level)]["ns_per_step"]

    def ratio(host, a_fmu, b_fmu, level):
        """Median over the rounds of a/b within each round: the two were measured moments apart,
        so a burst of load from elsewhere on the machine cancels out of the ratio."""
        a_r = med[key(host, a_fmu, level)]["rounds"]
        b_r = med[key(host, b_fmu, level)]["rounds"]
        if len(a_r) != len(b_r):  # different hosts: medians
            return get(host, a_fmu, level) / get(host, b_fmu, level)
        return statistics.median(x / y for x, y in zip(a_r, b_r))

    out = []
    out.append("### Per communication step (median; set 1 input, doStep, get 19 Real values)\n")
    out.append("Ratios are the median over the rounds of the ratio within each round "
               "(ours / bare under FMPy: FMPy's step over the bare Rust call).\n")
    out.append("| host | level | bare Rust call | ours (GenevaKnifeDrive) | PythonFMU peer | C floor "
               "| ours / bare (FFI) | ours / floor | PythonFMU / ours |")
    out.append("| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    verdict = []
    for host in ["native", "fmpy"]:
        for level in ["kinematic", "kinetostatic"]:
            bare = get("native", "bare", level)
            ours, py, floor = (get(host, f, level) for f in ["ours", "pythonfmu", "floor"])
            r_bare = ratio(host, "ours", "bare", level)
            r_floor = ratio(host, "ours", "floor", level)
            r_py = ratio(host, "pythonfmu", "ours", level)
            out.append(f"| {'native (Rust, C ABI)' if host == 'native' else 'FMPy 0.3.32'} | {level} "
                       f"| {fmt_ns(bare)} | {fmt_ns(ours)} | {fmt_ns(py)} | {fmt_ns(floor)} "
                       f"| {r_bare:.2f}x | {r_floor:.2f}x | {r_py:.0f}x |")
            if host == "native":
                verdict.append((f"FFI overhead ours/bare <= 1.2x ({level})", r_bare <= 1.2,
                                f"{r_bare:.2f}x"))
                # (ours - bare) / floor, from the two robust ratios
                layer = r_floor * (1.0 - 1.0 / r_bare)
                verdict.append((f"ours/C floor <= 1.5x, native ({level})", r_floor <= 1.5,
                                f"{r_floor:.2f}x; ours' FMI layer alone (ours - bare) "
                                f"= {layer:.1f}x the floor"))
                verdict.append((f"PythonFMU/ours >= 100x, native ({level})", r_py >= 100,
                                f"{r_py:.0f}x"))
            else:
                verdict.append((f"ours/floor <= 1.10x under FMPy ({level})", r_floor <= 1.10,
                                f"{r_floor:.3f}x"))
    out.append("")
    out.append("Spread (p10 .. p90 of the rounds): " + "; ".join(
        f"{r['host']} {r['fmu']} {r['level'][:5]} {fmt_ns(r['p10'])}..{fmt_ns(r['p90'])}"
        for r in rows))
    out.append("")
    out.append("### Size and memory\n")
    out.append("| FMU | .fmu size | heap per instance |")
    out.append("| --- | ---: | ---: |")
    sizes = {"ours": Path(a.fmus) / "GenevaKnifeDrive.fmu",
             "pythonfmu": d / "GenevaKnifeDrivePy.fmu", "floor": d / "Floor.fmu"}
    for fmu, path in sizes.items():
        size = path.stat().st_size
        hs = "; ".join(f"{h['bytes_per_instance']} B ({h['method']})" for h in heap if h["fmu"] == fmu)
        out.append(f"| {fmu} | {size / 1024:.0f} KiB ({size} B) | {hs} |")
        if fmu == "ours":
            verdict.append((".fmu <= 1 MB", size <= 1_000_000, f"{size / 1e6:.3f} MB"))
            worst = max(h["bytes_per_instance"] for h in heap if h["fmu"] == "ours")
            verdict.append(("heap <= 64 KB per instance", worst <= 65536, f"{worst} B"))
    out.append("")
    out.append("### Goals\n")
    for name, ok, value in verdict:
        out.append(f"- {'met' if ok else 'MISSED'}: {name}: {value}")
    out.append("")
    out.append(f"Machine: {machine()}.")
    text = "\n".join(out)
    print(text)
    (d / "report.md").write_text(text + "\n")


if __name__ == "__main__":
    main()
