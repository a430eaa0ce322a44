"""Render every picture of the README: a printed page of the four-bar's workbook, its
charts page, the live drawing at position 4, one animation per bundled mechanism
(workbooks/*.toml) and the validation report of a small class in Chromium.

    PYTHONPATH=. python tests/helpers/render_pictures.py [OUTDIR]      (default: workbooks/img)

LibreOffice prints the recalculated workbook to PDF, pdftoppm turns pages into PNG;
`sheetkin animate` draws the GIFs (36 frames, 320 px wide); headless Chromium (selenium)
takes the report's screenshot. Needs what tests/setup.sh and the test extras install.
"""
from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

TESTS = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(TESTS))           # run as a script: the helpers package is in tests/
from helpers.libreoffice import pdf_to_png, render_pdf  # noqa: E402

ROOT = TESTS.parent


def pdf_pages(pdf: Path) -> int:
    out = subprocess.run(["pdfinfo", str(pdf)], capture_output=True, text=True, check=True).stdout
    return int(next(line.split()[1] for line in out.splitlines() if line.startswith("Pages:")))


def render_animations(outdir: Path) -> list[Path]:
    """workbooks/NAME.toml -> OUTDIR/NAME.gif, as `sheetkin animate NAME.toml -o NAME.gif`."""
    sys.path.insert(0, str(ROOT))
    from sheetkin.cli.commands import main
    out = []
    for scene in sorted((ROOT / "workbooks").glob("*.toml")):
        gif = outdir / f"{scene.stem}.gif"
        if main(["animate", str(scene), "-o", str(gif), "--frames", "36", "--size", "320",
                 "--progress", "never"]) != 0:
            raise SystemExit(f"render_pictures: sheetkin animate {scene} failed")
        out.append(gif)
    return out


def render(outdir: Path) -> list[Path]:
    """The workbook's pictures (PNG)."""
    outdir.mkdir(parents=True, exist_ok=True)
    return render_sheets(outdir) + [render_drawing(outdir)]


def render_all(outdir: Path) -> list[Path]:
    """Every picture of the README."""
    return render(outdir) + render_animations(outdir) + [render_report(outdir)]


def render_report(outdir: Path) -> Path:
    """A validation report of a small class (tests/helpers/browser.py's demo_class) as headless
    Chromium shows it, one student's details open."""
    from helpers.browser import chrome, chromium_paths, demo_class
    paths = chromium_paths()
    if paths is None:
        raise SystemExit("render_pictures: chromium, chromedriver and selenium are needed for the report "
                         "(bash tests/setup.sh; pip install -e '.[test]')")
    sys.path.insert(0, str(ROOT))
    from selenium.webdriver.common.by import By

    from sheetkin.cli.commands import main
    with tempfile.TemporaryDirectory() as tmp:
        folder = demo_class(Path(tmp) / "submissions")
        html = Path(tmp) / "report.html"
        import contextlib
        import io
        with contextlib.redirect_stdout(io.StringIO()):
            main(["validate", str(folder), "--html", str(html), "--progress", "never"])
        # the page names the files as given: show them relative to the class's folder
        html.write_text(html.read_text(encoding="utf-8").replace(str(folder) + "/", ""), encoding="utf-8")
        driver = chrome(*paths, width=1100, height=1150)
        try:
            driver.get(html.as_uri())
            driver.find_elements(By.CSS_SELECTOR, "#summary th button")[3].click()      # by score
            driver.find_element(By.LINK_TEXT, "Sidorov A.").click()
            driver.execute_script("window.scrollTo(0, 0)")
            out = outdir / "report.png"
            driver.save_screenshot(str(out))
        finally:
            driver.quit()
    return out


def _crop(png: Path, dst: Path, top: float = 0.0, bottom: float = 1.0, pad: int = 12) -> Path:
    """Copy the non-white part of a band (fractions of the height) of a page image."""
    from PIL import Image, ImageChops
    im = Image.open(png).convert("RGB")
    band = im.crop((0, int(top * im.height), im.width, int(bottom * im.height)))
    box = ImageChops.difference(band, Image.new("RGB", band.size, "white")).getbbox()
    if box:
        band = band.crop((max(0, box[0] - pad), max(0, box[1] - pad),
                          min(band.width, box[2] + pad), min(band.height, box[3] + pad)))
    band.save(dst)
    return dst


def render_drawing(outdir: Path, position: int = 4) -> Path:
    """The four-bar's workbook with the charts sheet's position cell set to `position`:
    the top of its charts page (the live drawing and the trajectories)."""
    sys.path.insert(0, str(ROOT))
    import sheetkin
    from sheetkin.sheet.workbook import build_workbook
    scene_path = ROOT / "workbooks" / "fourbar.toml"
    wb = build_workbook(sheetkin.load_scene(scene_path), scene_text=scene_path.read_text(encoding="utf-8"))
    wb.worksheets[1]["B1"] = position
    with tempfile.TemporaryDirectory() as tmp:
        book = Path(tmp) / "fourbar-drawing.xlsx"
        wb.save(book)
        pdf = render_pdf(book, Path(tmp))
        last = pdf_pages(pdf)
        page = pdf_to_png(pdf, Path(tmp) / "drawing", dpi=170, first_page=last, last_page=last)[0]
        return _crop(page, outdir / "fourbar-drawing.png", 0.0, 0.42)


def render_sheets(outdir: Path) -> list[Path]:
    with tempfile.TemporaryDirectory() as tmp:
        pdf = render_pdf(ROOT / "workbooks" / "fourbar.xlsx", Path(tmp))
        last = pdf_pages(pdf)
        sheet = pdf_to_png(pdf, Path(tmp) / "sheet", dpi=110, first_page=1, last_page=1)[0]
        charts = pdf_to_png(pdf, Path(tmp) / "charts", dpi=90, first_page=last, last_page=last)[0]
        targets = [outdir / "fourbar-sheet.png", outdir / "fourbar-charts.png"]
        for src, dst in zip((sheet, charts), targets, strict=False):
            shutil.copyfile(src, dst)
    return targets


if __name__ == "__main__":
    for p in render_all(Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "workbooks" / "img"):
        print(p)
