"""Who made an FMU, its version, on which terms and when (issue 16): FMPy reads author,
version, copyright, license, generationTool and generationDateAndTime from every built FMU and
scene FMU; the date is that of the commit built (SOURCE_DATE_EPOCH when set), so a commit builds
the same bytes (tests/cli.rs checks the bytes and the date of the checkout's commit).
"""

from __future__ import annotations

import os
import subprocess
import tomllib
from datetime import datetime, timezone

import pytest
from fmpy import read_model_description

from harness import FMU_DIR, ROOT

CARGO = tomllib.loads((ROOT / "Cargo.toml").read_text())
VERSION = CARGO["workspace"]["package"]["version"]
LICENSE = CARGO["workspace"]["package"]["license"]
FMUS = sorted(FMU_DIR.glob("*.fmu")) + sorted((ROOT / "out" / "scenes").glob("*.fmu"))


def stamp(secs) -> str:
    return datetime.fromtimestamp(int(secs), timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")


def build_dates() -> set[str] | None:
    """The dates a build may stamp: SOURCE_DATE_EPOCH's, else those of the checkout's commits
    (the FMUs may have been built at an earlier one); None without git."""
    secs = os.environ.get("SOURCE_DATE_EPOCH")
    if secs is not None:
        return {stamp(secs)}
    try:
        log = subprocess.run(["git", "-C", str(ROOT), "log", "--format=%ct"],
                             capture_output=True, text=True, check=True).stdout.split()
    except (OSError, subprocess.CalledProcessError):
        return None
    return {stamp(s) for s in log}


def test_there_are_fmus():
    assert FMUS, f"no FMU in {FMU_DIR}: run `cargo run --release -- build` first"


@pytest.mark.parametrize("path", FMUS, ids=[p.stem for p in FMUS])
def test_description_names_author_version_license_and_date(path):
    md = read_model_description(str(path))
    assert md.author == "the bindery-fmu authors"
    assert md.version == VERSION
    assert md.copyright == "Copyright the bindery-fmu authors"
    assert md.license == LICENSE
    assert md.generationTool == f"bindery-fmu {VERSION}"
    datetime.strptime(md.generationDateAndTime, "%Y-%m-%dT%H:%M:%SZ")
    dates = build_dates()
    if dates is not None:
        assert md.generationDateAndTime in dates, "not the date of a commit of this checkout"


def test_one_build_one_date():
    dates = {read_model_description(str(p)).generationDateAndTime for p in FMU_DIR.glob("*.fmu")}
    assert len(dates) == 1, dates
