"""The binaries of the other platforms run here and compute what linux64 computes (issue 15).

- win64: every FMU (the five full ones and tailored scenes, which read resources/scene.toml) is
  simulated as a win64-only FMU under Wine through FMPy's remoting
  (`simulate_fmu(..., remote_platform='win64')`: FMPy's Linux client starts its Windows server
  under `wine64`, which loads binaries/win64/<id>.dll), and the project's C host
  (tests/c_host/host.c, built with MinGW-w64) runs the scenes with a resource location that has
  a drive letter (file:///Z:/...): the path a Windows host passes, which the binary once turned
  into /Z:/... and so missed scene.toml.
- aarch64-linux: the C host built for aarch64 runs every FMU and the scenes under qemu-user.
Each run is compared with the same experiment on linux64: equal to rounding (the C libraries'
math functions may differ in the last bit: MinGW's against glibc's, glibc's aarch64 code against
its x86-64 code). At the elastodynamic level a last-bit difference can move a step of the adaptive
integrator, which then ends within its error control: there the outputs agree to the integration
tolerance (solver.rtol, 1e-6), not to rounding.

Also the unload of the caches on both platforms (tests/unload.rs does it for linux64): the C
host loads, steps, frees and unloads each binary again and again and reads the heap in use.

Wine is prepared by tests/wine/prepare (target/wine: a prefix with a stand-in
bcryptprimitives.dll, and the `wine64` command FMPy's remoting calls); tests/run installs Wine,
qemu-user and the cross compilers (Debian packages).
"""

from __future__ import annotations

import io
import json
import os
import re
import shutil
import subprocess
import sys
import tomllib
import zipfile
from pathlib import Path

import numpy as np
import pytest

from harness import FMU_DIR, ROOT, Extracted, fmu_paths

C_HOST = ROOT / "tests" / "c_host" / "host.c"
SCENE_FMU_DIR = ROOT / "out" / "scenes"
WINE_DIR = ROOT / "target" / "wine"
STOP, STEP = 2.0, 0.01
# Equal to rounding: every sample within this fraction of its column's largest magnitude.
RTOL = 1e-12
# The elastodynamic level: both runs are solutions of the adaptive integrator within its error
# control (solver.rtol = 1e-6), which may pick different steps after a last-bit difference; they
# agree to its tolerance (measured: 3e-8 between win64 and linux64, GenevaKnifeDrive's chain).
ODE_RTOL = 1e-6
# Tailored scenes run on every platform: an elastodynamic one (the ODE inside the step) and a
# constant-speed kinematic one; both read resources/scene.toml.
SCENES = ["GenevaKnifeDrive_chain_dynamics", "SewingTable_table_travel"]
# What a load/unload cycle may leave allocated: the host's and the loader's own bookkeeping
# (tests/unload.rs: the caches were 11-12 KB per cycle).
UNLOAD_BYTES = 1024


def subjects() -> list[Path]:
    return fmu_paths() + [SCENE_FMU_DIR / f"{s}.fmu" for s in SCENES]


def alone(ex: Extracted) -> dict:
    """Start values that let the FMU run without inputs: constant speed (drive.mode = 2),
    unless it drives itself (MainShaft) or is a scene (its drive is in scene.toml)."""
    if "drive.mode" in ex.vars and ex.vars["shaft.phi"].causality == "input":
        return {"drive.mode": 2}
    return {}


def tolerance(ex: Extracted) -> float:
    """RTOL, or ODE_RTOL for a scene at the elastodynamic level."""
    scene = Path(ex.dir) / "resources" / "scene.toml"
    if scene.is_file() and tomllib.loads(scene.read_text()).get("fidelity") == "elastodynamic":
        return ODE_RTOL
    return RTOL


def compare(label: str, got, want, names, rtol: float) -> float:
    """Asserts equality to `rtol` of each column's largest magnitude; returns the largest
    difference relative to its column."""
    worst = 0.0
    for n in names:
        a, b = np.asarray(got[n], dtype=float), np.asarray(want[n], dtype=float)
        assert a.shape == b.shape, f"{label}: {n}: {a.shape} rows against {b.shape}"
        scale = max(np.abs(b).max(), 1e-300)
        d = np.abs(a - b).max() / scale
        worst = max(worst, d)
        assert d <= rtol, f"{label}: {n} differs by {d:.3g} of its largest magnitude"
    return worst


DIFFERENCES: dict[str, float] = {}


@pytest.fixture(scope="session", autouse=True)
def _record_differences():
    """Writes the measured differences to out/platforms/differences.txt (for BENCHMARKS.md)."""
    yield
    if DIFFERENCES:
        out = ROOT / "out" / "platforms"
        out.mkdir(parents=True, exist_ok=True)
        lines = [f"{k}\t{v:.3g}" for k, v in sorted(DIFFERENCES.items())]
        (out / "differences.txt").write_text("\n".join(lines) + "\n")


@pytest.fixture(scope="session")
def wine() -> Path:
    """tests/wine/prepare's folder; its bin/ (the `wine64` command) goes first on PATH."""
    subprocess.run([str(ROOT / "tests" / "wine" / "prepare"), str(WINE_DIR)], check=True)
    path = os.environ.get("PATH", "")
    os.environ["PATH"] = f"{WINE_DIR / 'bin'}{os.pathsep}{path}"
    yield WINE_DIR
    os.environ["PATH"] = path


def build(compiler: str, exe: Path, *libs: str) -> Path:
    assert shutil.which(compiler), f"{compiler} is needed (tests/run installs it)"
    subprocess.run([compiler, "-std=c99", "-Wall", "-Wextra", "-Werror", "-O1", "-o", str(exe),
                    str(C_HOST), *libs], check=True)
    return exe


@pytest.fixture(scope="session")
def host_native(tmp_path_factory) -> Path:
    return build("gcc", tmp_path_factory.mktemp("host") / "host", "-ldl")


@pytest.fixture(scope="session")
def host_win64(tmp_path_factory) -> Path:
    return build("x86_64-w64-mingw32-gcc", tmp_path_factory.mktemp("host") / "host.exe")


@pytest.fixture(scope="session")
def host_aarch64(tmp_path_factory) -> Path:
    return build("aarch64-linux-gnu-gcc", tmp_path_factory.mktemp("host") / "host", "-ldl")


QEMU = ["qemu-aarch64", "-L", "/usr/aarch64-linux-gnu"]


def wine_path(p: Path) -> str:
    """`p` as Wine's programs see it: drive Z: is the root of the Linux file system."""
    return "Z:" + str(p).replace("/", "\\")


def run_host(runner: list[str], host: Path, *args: str, timeout=600) -> str:
    proc = subprocess.run([*runner, str(host), *args], capture_output=True, text=True,
                          timeout=timeout)
    assert proc.returncode == 0, proc.stderr[-4000:]
    return proc.stdout


def host_table(runner, host, fmu_dir: str, ex: Extracted):
    assign = [f"{k}={v}" for k, v in alone(ex).items()]
    out = run_host(runner, host, fmu_dir, str(STOP), str(STEP), *assign)
    return np.genfromtxt(io.StringIO(out), delimiter=",", names=True, deletechars="")


def ids(paths):
    return [p.stem for p in paths]


# ---- win64 under Wine -------------------------------------------------------------------------

def win64_only(fmu: Path, folder: Path) -> Path:
    """A copy of `fmu` with binaries/win64 as its only binaries (what FMPy's remoting is for)."""
    out = folder / fmu.name
    with zipfile.ZipFile(fmu) as src, zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as dst:
        for item in src.infolist():
            if item.filename.startswith("binaries/") and not item.filename.startswith("binaries/win64/"):
                continue
            dst.writestr(item, src.read(item.filename))
    return out


# One simulation per Python process: FMPy's remoting client library is unloaded at the end of
# simulate_fmu while a thread of it still waits for the server, which crashes the process that
# runs the next simulation.
REMOTE = """
import json, sys
import numpy as np
from fmpy import simulate_fmu
np.save(sys.argv[3], simulate_fmu(sys.argv[1], remote_platform="win64", **json.loads(sys.argv[2])))
"""


def simulate_remotely(fmu: Path, kw: dict, result: Path):
    """simulate_fmu(fmu, remote_platform='win64', **kw) in a fresh Python process."""
    proc = subprocess.run([sys.executable, "-c", REMOTE, str(fmu), json.dumps(kw), str(result)],
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, (proc.stdout + proc.stderr)[-4000:]
    return np.load(result)


@pytest.mark.parametrize("path", subjects(), ids=ids(subjects()))
def test_win64_under_wine_through_fmpy_remoting_equals_linux64(path, wine, tmp_path):
    assert path.is_file(), f"{path} missing: run tests/run (or `cargo run --release -- build` and `-- scene`)"
    ex = Extracted.of(path)
    names = ex.outputs(types=("Real", "Integer", "Boolean", "Enumeration"))
    kw = dict(fmi_type="CoSimulation", start_time=0.0, stop_time=STOP, output_interval=STEP,
              start_values=alone(ex), output=names)
    want = ex.simulate(**kw)
    got = simulate_remotely(win64_only(path, tmp_path), kw, tmp_path / "result.npy")
    assert len(got) == len(want) == round(STOP / STEP) + 1
    DIFFERENCES[f"win64 (FMPy remoting) {path.stem}"] = compare(path.stem, got, want, names, tolerance(ex))


@pytest.mark.parametrize("scene", SCENES)
def test_win64_c_host_finds_scene_resources_through_a_drive_letter(scene, wine, host_win64,
                                                                   host_native):
    """host.exe passes file:///Z:/.../resources; the tailored FMU must read its scene.toml there
    (before, the path became /Z:/... and fmi2Instantiate refused the scene's GUID)."""
    ex = Extracted.of(SCENE_FMU_DIR / f"{scene}.fmu")
    want = host_table([], host_native, ex.dir, ex)
    got = host_table([str(WINE_DIR / "bin" / "wine64")], host_win64, wine_path(Path(ex.dir)), ex)
    names = [n for n in want.dtype.names if n != "time"]
    assert got.dtype.names == want.dtype.names
    DIFFERENCES[f"win64 (C host, file:///Z:/) {scene}"] = compare(scene, got, want, names, tolerance(ex))


@pytest.mark.parametrize("path", fmu_paths(), ids=ids(fmu_paths()))
def test_win64_unload_releases_the_caches(path, wine, host_win64):
    """DllMain at DLL_PROCESS_DETACH frees what the binary keeps (the Linux binaries do it from
    .fini_array); before, each FreeLibrary cycle left about 12 KB."""
    ex = Extracted.of(path)
    out = run_host([str(WINE_DIR / "bin" / "wine64")], host_win64, "--unload-cycles", "100",
                   wine_path(Path(ex.dir)), str(STEP), str(STEP))
    per_cycle = float(re.match(r"(-?[0-9.]+) bytes", out).group(1))
    DIFFERENCES[f"win64 unload, bytes per cycle {path.stem}"] = per_cycle
    assert per_cycle < UNLOAD_BYTES, out


# ---- aarch64-linux under qemu-user ------------------------------------------------------------

@pytest.mark.parametrize("path", subjects(), ids=ids(subjects()))
def test_aarch64_c_host_under_qemu_equals_linux64(path, host_aarch64, host_native):
    assert path.is_file(), f"{path} missing: run tests/run"
    ex = Extracted.of(path)
    want = host_table([], host_native, ex.dir, ex)
    got = host_table(QEMU, host_aarch64, ex.dir, ex)
    names = [n for n in want.dtype.names if n != "time"]
    assert got.dtype.names == want.dtype.names
    assert len(got) == round(STOP / STEP) + 1
    DIFFERENCES[f"aarch64 (C host, qemu) {path.stem}"] = compare(path.stem, got, want, names, tolerance(ex))


@pytest.mark.parametrize("path", fmu_paths(), ids=ids(fmu_paths()))
def test_aarch64_unload_releases_the_caches(path, host_aarch64):
    ex = Extracted.of(path)
    out = run_host(QEMU, host_aarch64, "--unload-cycles", "100", ex.dir, str(STEP), str(STEP))
    per_cycle = float(re.match(r"(-?[0-9.]+) bytes", out).group(1))
    DIFFERENCES[f"aarch64 unload, bytes per cycle {path.stem}"] = per_cycle
    assert per_cycle < UNLOAD_BYTES, out
