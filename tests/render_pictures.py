"""Render every picture of the README: a page of the four-bar's workbook and its charts,
and one animation per bundled mechanism (workbooks/*.toml).

    python tests/render_pictures.py [OUTDIR]      (default: workbooks/img)

LibreOffice prints the recalculated workbook to PDF, pdftoppm turns pages into PNG;
`sheetkin animate` draws the GIFs (36 frames, 320 px wide).
Needs what tests/setup.sh installs.
"""
from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from libreoffice import pdf_to_png, render_pdf  # noqa: E402

ROOT = HERE.parent


def pdf_pages(pdf: Path) -> int:
    out = subprocess.run(["pdfinfo", str(pdf)], capture_output=True, text=True, check=True).stdout
    return int(next(line.split()[1] for line in out.splitlines() if line.startswith("Pages:")))


def render_animations(outdir: Path) -> list[Path]:
    """workbooks/NAME.toml -> OUTDIR/NAME.gif, as `sheetkin animate NAME.toml -o NAME.gif`."""
    sys.path.insert(0, str(ROOT))
    from sheetkin.cli import main
    out = []
    for scene in sorted((ROOT / "workbooks").glob("*.toml")):
        gif = outdir / f"{scene.stem}.gif"
        if main(["animate", str(scene), "-o", str(gif), "--frames", "36", "--size", "320",
                 "--progress", "never"]) != 0:
            raise SystemExit(f"render_pictures: sheetkin animate {scene} failed")
        out.append(gif)
    return out


def render(outdir: Path) -> list[Path]:
    outdir.mkdir(parents=True, exist_ok=True)
    return render_sheets(outdir) + render_animations(outdir)


def render_sheets(outdir: Path) -> list[Path]:
    with tempfile.TemporaryDirectory() as tmp:
        pdf = render_pdf(ROOT / "workbooks" / "fourbar.xlsx", Path(tmp))
        last = pdf_pages(pdf)
        sheet = pdf_to_png(pdf, Path(tmp) / "sheet", dpi=110, first_page=1, last_page=1)[0]
        charts = pdf_to_png(pdf, Path(tmp) / "charts", dpi=90, first_page=last, last_page=last)[0]
        targets = [outdir / "fourbar-sheet.png", outdir / "fourbar-charts.png"]
        for src, dst in zip((sheet, charts), targets):
            shutil.copyfile(src, dst)
    return targets


if __name__ == "__main__":
    for p in render(Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "workbooks" / "img"):
        print(p)
