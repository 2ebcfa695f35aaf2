"""pytest set-up of the FMU tests: which FMUs there are, and each one extracted once.

The FMUs are those `cargo run --release -- build` wrote to out/fmus/ (tests/run builds them
first). Without any, every test that needs one fails and says how to build them.
"""

from __future__ import annotations

import pytest

from harness import FMU_DIR, Extracted, fmu_paths

BUILD_HINT = "run `cargo run --release -- build` (or tests/run) first"


def pytest_generate_tests(metafunc):
    """Tests taking `fmu` run once per FMU in out/fmus/ (id = modelIdentifier)."""
    if "fmu" in metafunc.fixturenames:
        paths = fmu_paths()
        if paths:
            metafunc.parametrize("fmu", paths, ids=[p.stem for p in paths])
        else:  # one failing case rather than silently collecting nothing
            metafunc.parametrize("fmu", [None], ids=["no-FMU-built"])


@pytest.fixture
def extracted(fmu) -> Extracted:
    if fmu is None:
        pytest.fail(f"no FMU in {FMU_DIR}: {BUILD_HINT}")
    return Extracted.of(fmu)


@pytest.fixture(scope="session")
def geneva() -> Extracted:
    path = FMU_DIR / "GenevaKnifeDrive.fmu"
    if not path.is_file():
        pytest.fail(f"{path} is missing: {BUILD_HINT}")
    return Extracted.of(path)


@pytest.fixture(scope="session", autouse=True)
def _cleanup_extracted():
    yield
    Extracted.cleanup()


def pytest_report_header(config):
    paths = fmu_paths()
    return f"FMUs under test ({FMU_DIR}): {', '.join(p.name for p in paths) or 'none'}"
