"""Headless Chromium for the tests (Debian's chromium and chromium-driver, installed by
tests/setup.sh; selenium from the test extras), and a small class of students' workbooks
for the validation report."""
from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync"]
HINT = "chromium/chromedriver/selenium not found: run `bash tests/setup.sh` and pip install -e '.[test]'"


def chromium_paths() -> tuple[str, str] | None:
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    driver = shutil.which("chromedriver")
    try:
        import selenium  # noqa: F401
    except ImportError:
        return None
    return (browser, driver) if browser and driver else None


def chrome(browser: str, driver: str, width: int = 1200, height: int = 1000):
    """A headless Chromium with a fresh profile; its console log is readable
    (driver.get_log('browser'))."""
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    opts = webdriver.ChromeOptions()
    for a in FLAGS + [f"--user-data-dir={tempfile.mkdtemp(prefix='sheetkin-chromium-')}",
                      f"--window-size={width},{height}"]:
        opts.add_argument(a)
    opts.binary_location = browser
    opts.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    return webdriver.Chrome(service=Service(driver), options=opts)


def demo_class(folder: Path) -> Path:
    """Four submissions: two correct (four-bar, shaper), one with omega_3's sign flipped in
    every column, one that is not a workbook."""
    import openpyxl
    folder.mkdir(parents=True, exist_ok=True)

    def book(stem, student, change=None):
        wb = openpyxl.load_workbook(ROOT / "workbooks" / f"{stem}.xlsx")
        ws = wb.worksheets[0]
        rows = {ws.cell(r, 1).value: r for r in range(1, ws.max_row + 1)}
        ws["D1"] = student                  # the student's own cells (rows 1-2), not the scene's author
        ws["D2"] = "ГИ-21"
        if change:
            change(ws, rows)
        return wb

    def flip_omega_3(ws, rows):
        for k in range(13):
            c = ws.cell(rows["omega_3"], 5 + k)
            c.value = "=-(" + c.value[1:] + ")"
    book("fourbar", "Ivanov I.").save(folder / "ivanov.xlsx")
    book("shaper", "Petrova A.").save(folder / "petrova.xlsx")
    book("fourbar", "Sidorov A.", flip_omega_3).save(folder / "sidorov.xlsx")
    (folder / "notes.xlsx").write_text("not a workbook", encoding="utf-8")
    return folder
