"""The HTML validation report in a real browser (headless Chromium): what a teacher sees."""
from __future__ import annotations

import re

import pytest
from browser import HINT, chrome, chromium_paths, demo_class
from conftest import _require

from sheetkin.cli.commands import main


@pytest.fixture(scope="module")
def page(tmp_path_factory):
    paths = _require(chromium_paths(), HINT)
    d = tmp_path_factory.mktemp("class")
    demo_class(d / "submissions")
    html = d / "report.html"
    assert main(["validate", str(d / "submissions"), "--html", str(html), "--progress", "never"]) == 2
    driver = chrome(*paths)
    driver.get(html.as_uri())
    yield driver, html.read_text(encoding="utf-8")
    driver.quit()


def _column(driver, k):
    from selenium.webdriver.common.by import By
    return [tr.find_elements(By.TAG_NAME, "td")[k].text.rsplit("/", 1)[-1]
            for tr in driver.find_elements(By.CSS_SELECTOR, "#summary tbody tr")]


def test_the_table_sorts_on_a_header_click(page):
    from selenium.webdriver.common.by import By
    driver, _ = page
    headers = driver.find_elements(By.CSS_SELECTOR, "#summary th button")
    names = [h.text for h in headers]
    assert names[:5] == ["student", "group", "variant", "score", "result"] and "missing rows" in names
    files = names.index("file")
    headers[files].click()
    assert _column(driver, files) == ["ivanov.xlsx", "notes.xlsx", "petrova.xlsx", "sidorov.xlsx"]
    headers[files].click()
    assert _column(driver, files) == ["sidorov.xlsx", "petrova.xlsx", "notes.xlsx", "ivanov.xlsx"]
    th = headers[files].find_element(By.XPATH, "..")
    assert th.get_attribute("aria-sort") == "descending"
    score = names.index("score")
    headers[score].click()                       # numbers sort as numbers: 95 before 100
    got = [s for s in _column(driver, score) if s]
    assert got == sorted(got, key=float) and got[0] != got[-1]


def test_a_students_details_open_with_wrong_cells_and_picture(page):
    from selenium.webdriver.common.by import By
    driver, _ = page
    link = driver.find_element(By.LINK_TEXT, "Sidorov A.")
    target = driver.find_element(By.ID, link.get_attribute("data-open"))
    assert target.get_property("open") is False
    link.click()
    assert target.get_property("open") is True
    text = target.text
    assert "likely cause: omega_3" in text and "wrong from i = 0 (phi_1 = 0 deg)" in text
    assert len(target.find_elements(By.CSS_SELECTOR, "td.wrong")) == 3 * 13    # omega_3, vx_S3, vy_S3
    svg = target.find_element(By.TAG_NAME, "svg")
    assert svg.size["width"] > 200 and "i = 0 (phi_1 = 0 deg)" in svg.text


def test_no_console_errors_and_nothing_fetched(page):
    driver, source = page
    driver.refresh()
    errors = [e for e in driver.get_log("browser") if e["level"] in ("SEVERE", "ERROR")]
    assert errors == []
    refs = re.findall(r"(?:src|href)\s*=\s*['\"]([^'\"]*)", source)
    assert refs and all(r.startswith(("#", "data:")) for r in refs), refs
    assert not re.search(r"https?://(?!www\.w3\.org/2000/svg)", source)
