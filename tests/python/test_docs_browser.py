"""Every FMU's documentation page, as a reader sees it in a real browser (issue 16): Debian's
headless Chromium renders `documentation/index.html` of every built FMU and scene FMU at a desktop
width (1280 px) and a phone width (390 px), and the page must not be wider than the window (no
element reaching past it), every image must load, and every link must lead to an anchor of the
page or a file inside the FMU's documentation (none to ../shared or to spec files a user does not
have). The page must also read in the designer's order: a picture and the questions before the
variable table.

Chromium: $CHROMIUM, else `chromium` on the PATH (tests/run installs Debian's package).
"""

from __future__ import annotations

import re
import zipfile
from pathlib import Path

import pytest

from browser import Browser, chromium, problems
from harness import FMU_DIR, ROOT

SCENE_FMU_DIR = ROOT / "out" / "scenes"
FMUS = sorted(FMU_DIR.glob("*.fmu")) + sorted(SCENE_FMU_DIR.glob("*.fmu"))
WIDTHS = (1280, 390)


@pytest.fixture(scope="module")
def browser():
    if not chromium():
        pytest.fail("no Chromium: install Debian's chromium (apt-get install chromium; tests/run "
                    "does) or name one in $CHROMIUM")
    with Browser() as b:
        yield b


def unpacked(fmu: Path, tmp_path: Path) -> Path:
    """The FMU's documentation/ folder, unpacked; its index.html."""
    with zipfile.ZipFile(fmu) as z:
        for name in z.namelist():
            if name.startswith("documentation/"):
                z.extract(name, tmp_path)
    page = tmp_path / "documentation" / "index.html"
    assert page.is_file(), f"{fmu.name} has no documentation/index.html"
    return page


def test_there_are_fmus_and_scenes():
    assert list(FMU_DIR.glob("*.fmu")), f"no FMU in {FMU_DIR}: run `cargo run --release -- build`"
    assert list(SCENE_FMU_DIR.glob("*.fmu")), \
        f"no scene FMU in {SCENE_FMU_DIR}: run `cargo run --release -- scene`"


@pytest.mark.parametrize("path", FMUS, ids=[p.stem for p in FMUS])
def test_page_fits_the_window_loads_its_images_and_links_inside(path, tmp_path, browser):
    fmu = path
    page = unpacked(fmu, tmp_path)
    found = []
    for width in WIDTHS:
        m = browser.measure(page, width)
        found += [f"{width} px: {p}" for p in problems(page, m)]
        assert m["images"] or fmu.parent == SCENE_FMU_DIR, "a mechanism's page has figures"
    assert not found, f"{fmu.name}:\n" + "\n".join(found)


@pytest.mark.parametrize("path", sorted(FMU_DIR.glob("*.fmu")),
                         ids=[p.stem for p in sorted(FMU_DIR.glob("*.fmu"))])
def test_page_reads_in_the_designers_order(path, tmp_path, browser):
    fmu = path
    page = unpacked(fmu, tmp_path)
    m = browser.measure(page, 1280)
    html = page.read_text()
    at = {s: html.find(s) for s in ('id="what"', 'id="questions"', 'id="variables"')}
    assert all(i >= 0 for i in at.values()), at
    assert at['id="what"'] < at['id="questions"'] < at['id="variables"']
    # the picture within the first screen and a half, not after the table
    assert m["firstFigureTop"] is not None and m["firstFigureTop"] < 1300, m["firstFigureTop"]
    # every output a question names has its row; no number with 17 digits
    for anchor in re.findall(r'href="#(v-[^"]+)"', html):
        assert anchor in m["ids"], anchor
    assert not re.search(r"\d\.\d{12,}", re.sub(r"<style>.*?</style>", "", html, flags=re.S)), \
        "a value printed with all its digits"


def test_the_checks_find_what_they_look_for(tmp_path, browser):
    """A page with each fault: a table too wide for a phone, an image that is not there, links
    to a missing anchor, to a missing file and out of the FMU (what the old pages were checked
    for, so that a pass means something)."""
    page = tmp_path / "index.html"
    page.write_text(
        '<!DOCTYPE html><html><head><meta name="viewport" content="width=device-width">'
        '</head><body><table><tr>' + "<td>column</td>" * 40 + '</tr></table>'
        '<img src="missing.png" width="80" height="50">'
        '<a href="#nowhere">a</a><a href="gone.html">b</a>'
        '<a href="../shared/spec/dynamics.md">c</a><a href="#here" id="here">d</a>'
        '</body></html>')
    found = "\n".join(problems(page, browser.measure(page, 390)))
    for want in ("px wide in a 390 px viewport", "<table", "image 'missing.png' did not load",
                 "'#nowhere': no such anchor", "'gone.html': no such file",
                 "'../shared/spec/dynamics.md': outside the FMU's documentation"):
        assert want in found, f"{want!r} not in\n{found}"
    assert "#here" not in found
