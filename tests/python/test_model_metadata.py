"""Who made an FMU, its version, on which terms and when (issue 16): FMPy reads author,
version, copyright, license, generationTool and generationDateAndTime from every built FMU and
scene FMU; the date is the commit's (SOURCE_DATE_EPOCH when set), so a commit builds the same
bytes.
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


def build_date() -> str | None:
    """The date the build stamps: SOURCE_DATE_EPOCH, else the checkout's commit (None: no git)."""
    secs = os.environ.get("SOURCE_DATE_EPOCH")
    if secs is None:
        try:
            secs = subprocess.run(["git", "-C", str(ROOT), "log", "-1", "--format=%ct"],
                                  capture_output=True, text=True, check=True).stdout.strip()
        except (OSError, subprocess.CalledProcessError):
            return None
    return datetime.fromtimestamp(int(secs), timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")


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
    date = build_date()
    if date is not None:
        assert md.generationDateAndTime == date
    else:
        datetime.strptime(md.generationDateAndTime, "%Y-%m-%dT%H:%M:%SZ")
