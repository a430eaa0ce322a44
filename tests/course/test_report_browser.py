"""The HTML validation report in a real browser (headless Chromium): what a teacher sees."""
from __future__ import annotations

import re
from pathlib import Path

import pytest
from helpers.browser import HINT, ROOT, chrome, chromium_paths, demo_class
from helpers.programs import require

from sheetkin.cli.commands import main

RU: dict[str, Path] = {}


@pytest.fixture(scope="module")
def page(tmp_path_factory):
    paths = require(chromium_paths(), HINT)
    d = tmp_path_factory.mktemp("class")
    demo_class(d / "submissions")
    html = d / "report.html"
    assert main(["validate", "--lang", "en", str(d / "submissions"), "--html", str(html), "--progress", "never"]) == 2
    # the same class in the books' own language (Russian: no --lang)
    RU["page"] = d / "ru.html"
    assert main(["validate", str(d / "submissions"), "--html", str(RU["page"]), "--progress", "never"]) == 2
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


def test_the_class_at_a_glance_opens_the_page_in_the_books_language(page):
    """Issue 22: the Russian page (the books' language by default, <html lang="ru">) opens
    with the class: the rows the class got wrong, each with its share of books as a bar as
    long as the share, in the lecture's order, then the distribution of scores; only then
    the list of students. The author shown is the student, never the scheme's author."""
    from selenium.webdriver.common.by import By
    driver, _ = page
    src = driver.current_url
    driver.get(RU["page"].as_uri())
    try:
        assert driver.execute_script("return document.documentElement.lang") == "ru"
        glance = driver.find_element(By.ID, "class")
        summary = driver.find_element(By.ID, "summary")
        assert glance.location["y"] < summary.location["y"]
        rows = driver.find_elements(By.CSS_SELECTOR, "#class-rows tr[data-row]")
        names = [r.get_attribute("data-row") for r in rows]
        # sidorov's omega_3 and the rows fed by it, in the sheet's order; 1 of 3 usable books
        assert names[0] == "omega_3" and {"vx_S3", "vy_S3"} <= set(names)
        import sheetkin
        from sheetkin.sheet.workbook import sheet_rows
        order = [r.name for r in sheet_rows(sheetkin.load_scene(ROOT / "workbooks" / "fourbar.toml")).rows]
        assert names == sorted(names, key=order.index)
        widths = [r.find_element(By.CLASS_NAME, "bar").size["width"] for r in rows]
        shares = [float(r.get_attribute("data-share")) for r in rows]
        assert shares[0] == pytest.approx(1 / 3, abs=1e-3)
        assert all(abs(w / widths[0] - s / shares[0]) < 0.05 for w, s in zip(widths, shares, strict=True))
        bins = driver.find_elements(By.CSS_SELECTOR, "#class-scores tr[data-bin]")
        assert sum(int(b.get_attribute("data-count")) for b in bins) == 4       # every book, unusable: 0
        assert "Группа одним взглядом" in glance.text and "доля неверных" in glance.text
        heads = [h.text for h in driver.find_elements(By.CSS_SELECTOR, "#summary th button")]
        assert heads[:3] == ["студент", "группа", "вариант"]
        body = driver.find_element(By.TAG_NAME, "body").text
        assert "sheetkin example" not in body and "Sidorov A." in body
    finally:
        driver.get(src)


def test_the_russian_page_of_a_class_with_held_copies_fits_a_laptop_screen(tmp_path):
    """Issue 34: the page fits a 1,366 px screen in Russian, whose words are the longest: a
    class issued with a class list, a held copy ("100.0 (отложено для проверки)"), a book
    handed in empty (its missing rows listed), long file names (measured 1,396 px before)."""
    import shutil
    paths = require(chromium_paths(), HINT)
    cl = tmp_path / "class.csv"              # a Russian Excel's class list
    cl.write_bytes("Фамилия;Имя;Адрес электронной почты\nИванов;Иван;iv@x.ru\nПетрова;Анна;pe@x.ru\n"
                   "Сидоров;Пётр;si@x.ru\nКузнецов;Олег;ku@x.ru\n".encode("cp1251"))
    out = tmp_path / "cls"
    assert main(["variants", str(ROOT / "workbooks" / "fourbar.toml"), "--class-list", str(cl), "-n", "3",
                 "--out", str(out), "--seed", "1"]) == 0
    subs = tmp_path / "sub"
    subs.mkdir()
    teacher = out / "teacher"
    shutil.copy(teacher / "fourbar-01-key.xlsx", subs / "ivanov.xlsx")
    shutil.copy(teacher / "fourbar-01-key.xlsx", subs / ("Кузнецов_Олег_лабораторная_работа_1_кинематика_шарнирно-"
                                                        "рычажного_механизма_окончательный_вариант.xlsx"))
    shutil.copy(next((out / "students").glob("fourbar-02-*")), subs / "petrova.xlsx")
    shutil.copy(teacher / "fourbar-03-key.xlsx", subs / "sidorov.xlsx")
    html = tmp_path / "ru.html"
    main(["validate", *map(str, sorted(subs.iterdir())), "--roster", str(teacher / "roster.csv"), "--class-list",
          str(cl), "--grades", str(tmp_path / "grades.csv"), "--html", str(html), "--lang", "ru",
          "--progress", "never"])
    assert "отложено для проверки" in html.read_text(encoding="utf-8")
    driver = chrome(*paths, width=1366, height=800)
    try:
        driver.get(html.as_uri())
        wide, window = driver.execute_script("return [document.documentElement.scrollWidth, window.innerWidth]")
    finally:
        driver.quit()
    assert wide <= window, f"the page is {wide} px wide in a {window} px window"
