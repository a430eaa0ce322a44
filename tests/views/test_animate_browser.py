"""`sheetkin animate -o page.html` in headless Chromium: it plays, pauses, and the slider
shows the chosen position; nothing is fetched and the console stays clean."""
from __future__ import annotations

import re
from pathlib import Path

import pytest
from helpers.browser import HINT, chrome, chromium_paths
from helpers.programs import require

from sheetkin.cli.commands import main

WB = Path(__file__).resolve().parents[2] / "workbooks"


@pytest.fixture(scope="module")
def driver(tmp_path_factory):
    paths = require(chromium_paths(), HINT)
    page = tmp_path_factory.mktemp("anim") / "shaper.html"
    assert main(["animate", str(WB / "shaper.toml"), "-o", str(page), "--frames", "12", "--fps", "20",
                 "--vectors", "--lang", "en"]) == 0
    d = chrome(*paths, width=700, height=800)
    d.get(page.as_uri())
    yield d
    d.quit()


def test_play_pause_and_slider(driver):
    import time

    from selenium.webdriver.common.by import By
    cap = driver.find_element(By.ID, "cap")
    button = driver.find_element(By.ID, "play")
    assert button.text == "pause"                 # it plays on opening
    seen = {cap.text}
    for _ in range(20):
        time.sleep(0.05)
        seen.add(cap.text)
    assert len(seen) > 2                          # the frames change
    button.click()
    assert button.text == "play"
    frozen = cap.text
    time.sleep(0.3)
    assert cap.text == frozen                     # paused
    slider = driver.find_element(By.ID, "pos")
    driver.execute_script("arguments[0].value = 6; arguments[0].dispatchEvent(new Event('input'))", slider)
    assert cap.text.startswith("i = 6 / 11: phi_1 = 68.26 deg")     # positions from i = 0; 248.2617 - 6 * 30
    # the canvas is drawn: some pixels are not white
    drawn = driver.execute_script(
        "const c = document.getElementById('c'), d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;"
        "let n = 0; for (let k = 0; k < d.length; k += 4) if (d[k] < 200) n++; return n;")
    assert drawn > 500


def test_console_is_clean(driver):
    errors = [e for e in driver.get_log("browser") if e["level"] in ("SEVERE", "ERROR")]
    assert errors == []


@pytest.mark.parametrize("lang, play, pause, deg", [("ru", "пуск", "пауза", "град"), ("uk", "пуск", "пауза", "град")])
def test_controls_in_the_students_language(tmp_path, lang, play, pause, deg):
    """Issue 22: the page in Russian (the default) and Ukrainian, as a browser shows it: the
    button, the caption under the slider; a screenshot kept for a look."""
    from selenium.webdriver.common.by import By
    paths = require(chromium_paths(), HINT)
    page = tmp_path / f"shaper-{lang}.html"
    args = ["animate", str(WB / "shaper.toml"), "-o", str(page), "--frames", "12", "--vectors"]
    assert main(args + (["--lang", lang] if lang != "ru" else [])) == 0
    d = chrome(*paths, width=760, height=760)
    try:
        d.get(page.as_uri())
        button = d.find_element(By.ID, "play")
        assert button.text == pause
        button.click()
        assert button.text == play
        slider = d.find_element(By.ID, "pos")
        d.execute_script("arguments[0].value = 6; arguments[0].dispatchEvent(new Event('input'))", slider)
        cap = d.find_element(By.ID, "cap").text
        assert cap.startswith(f"i = 6 / 11: phi_1 = 68.26 {deg}"), cap
        assert not re.search(r"\b(deg|play|pause|position)\b", d.find_element(By.TAG_NAME, "body").text)
        assert d.execute_script("return document.documentElement.lang") == lang
        speed = d.find_element(By.ID, "speed")
        assert speed.find_element(By.XPATH, "..").text.startswith({"ru": "скорость", "uk": "швидкість"}[lang])
        button.click()                                             # plays again, four times slower
        d.execute_script("arguments[0].value = '0.25'; arguments[0].dispatchEvent(new Event('change'))", speed)
        import time
        before = d.find_element(By.ID, "cap").text
        time.sleep(0.15)                                           # 12 fps x 0.25: a frame every 333 ms
        assert d.find_element(By.ID, "cap").text == before and button.text == pause
        button.click()
        d.save_screenshot(str(tmp_path / f"shaper-{lang}.png"))
        errors = [e for e in d.get_log("browser") if e["level"] in ("SEVERE", "ERROR")]
        assert errors == []
    finally:
        d.quit()
