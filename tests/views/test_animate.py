"""sheetkin.views.drawing and `sheetkin animate`: what is drawn is where compute() puts it."""
from __future__ import annotations

import json
import math
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from helpers.scenes import SHORT

import sheetkin
from sheetkin.cli.commands import main
from sheetkin.kinematics import geometry
from sheetkin.views import drawing
from sheetkin.views.animate import animate, html_page

ROOT = Path(__file__).resolve().parents[2]
WB = ROOT / "workbooks"


@pytest.fixture(scope="module")
def short(tmp_path_factory):
    p = tmp_path_factory.mktemp("short") / "short.toml"
    p.write_text(SHORT)
    return p


def _shapes(frame, role):
    return [s for s in frame if s.role == role]


def test_structure_links_hold_their_points():
    st = geometry.structure(sheetkin.load_scene(WB / "shaper.toml"))
    assert st.members[1] == ("O", "A") and st.members[3] == ("B", "C") and st.members[4] == ("C", "D")
    assert st.pivots == ("B", "O")
    assert [(b.link, b.at) for b in st.blocks] == [(2, "A"), (5, "D")]


@pytest.mark.parametrize("name", ["fourbar", "crank_slider", "shaper", "slotted_lever"])
def test_links_are_drawn_between_the_computed_points(name):
    """Every link's outline has the computed points of that link as vertices, at every frame,
    and a link of two joints keeps its length (an identity the solver must satisfy)."""
    scene = sheetkin.load_scene(WB / f"{name}.toml")
    angles = geometry.revolution(scene, 12)
    pic = drawing.picture(scene, angles)
    df = sheetkin.compute(scene, angles)
    st = geometry.structure(scene)
    for i, frame in enumerate(pic.frames):
        links = _shapes(frame, "link")
        drawn = [k for k, pts in st.members.items() if len(pts) >= 2]
        assert len(links) == len(drawn)
        for k, shape in zip(drawn, links, strict=False):
            pts = np.array([geometry.point_xy(scene, df.iloc[i:i + 1], p)[0] for p in st.members[k]])
            for v in shape.xy:       # each vertex is one of the link's points
                assert np.min(np.hypot(*(pts - v).T)) < 1e-12
        crank = links[0].xy
        assert math.isclose(np.hypot(*(crank[0] - crank[1])), scene.crank.length, rel_tol=1e-12)


def test_blocks_sit_on_their_guides():
    """Crank-slider: the block is centred on B and turned along the guide (0 deg); shaper:
    the block A lies on the slot line through B at phi_3."""
    scene = sheetkin.load_scene(WB / "crank_slider.toml")
    pic = drawing.picture(scene, [0, 70, 200])
    df = sheetkin.compute(scene, [0, 70, 200])
    for i, frame in enumerate(pic.frames):
        (block,) = _shapes(frame, "block")
        assert np.allclose(block.xy.mean(axis=0), [df.x_B[i], df.y_B[i]], atol=1e-12)
        edge = block.xy[1] - block.xy[0]
        assert abs(math.atan2(edge[1], edge[0])) < 1e-12
    scene = sheetkin.load_scene(WB / "shaper.toml")
    angles = [248.2617, 100.0, 10.0]
    pic = drawing.picture(scene, angles)
    df = sheetkin.compute(scene, angles)
    for i, frame in enumerate(pic.frames):
        (slot,) = _shapes(frame, "slot")
        a, b = slot.xy
        u = (b - a) / np.hypot(*(b - a))
        for p in ("A", "B"):
            rel = geometry.point_xy(scene, df.iloc[i:i + 1], p)[0] - a
            assert abs(rel[0] * u[1] - rel[1] * u[0]) < 1e-12     # on the line
        assert math.isclose(math.degrees(math.atan2(u[1], u[0])) % 360, df.phi_3[i], abs_tol=1e-9)


def test_scotch_yoke_blocks_turn_along_their_own_lines():
    """RPP declares its parts: the yoke's block (link 3) at K slides on the frame guide (0
    deg), the block A (link 2) in the yoke's slot (90 deg), drawn through K and A."""
    scene = sheetkin.load_scene(WB / "scotch_yoke.toml")
    angles = [20.0, 135.0, 250.0]
    pic = drawing.picture(scene, angles)
    df = sheetkin.compute(scene, angles)
    st = geometry.structure(scene)
    assert [(b.link, b.at, b.guide.link) for b in st.blocks] == [(3, "K", 0), (2, "A", 3)]
    for i, frame in enumerate(pic.frames):
        at = {p: geometry.point_xy(scene, df.iloc[i:i + 1], p)[0] for p in ("A", "K")}
        for block, (p, deg) in zip(_shapes(frame, "block"), (("K", 0.0), ("A", 90.0)), strict=True):
            assert np.allclose(block.xy.mean(axis=0), at[p], atol=1e-12)
            edge = block.xy[1] - block.xy[0]
            assert math.isclose(math.degrees(math.atan2(edge[1], edge[0])) % 180, deg, abs_tol=1e-9)
        (slot,) = _shapes(frame, "slot")
        a, b = slot.xy
        u = (b - a) / np.hypot(*(b - a))
        for p in ("A", "K"):
            rel = at[p] - a
            assert abs(rel[0] * u[1] - rel[1] * u[0]) < 1e-12     # on the slot's line


def test_svg_is_to_scale_and_paths_follow_compute():
    """The crank pin's path is a circle in the picture (equal scale): every vertex of it is
    L1 * pixels-per-metre from the pivot."""
    scene = sheetkin.load_scene(WB / "fourbar.toml")
    pic = drawing.picture(scene)
    px = drawing._Px(pic.bounds, 400)
    trace = max((s for s in pic.background if s.role == "trace"), key=lambda s: np.ptp(s.xy[:, 0]))
    o = px(np.array([scene.frame["O"]]))[0]
    r = np.hypot(*(px(trace.xy) - o).T)
    assert np.allclose(r, scene.crank.length * px.s, rtol=1e-9)
    doc = drawing.svg(pic, 0, 400)
    assert doc.startswith("<svg") and doc.count("<polyline") >= len(scene.moving_joints)


def test_gaps_and_toggles_are_marked(short):
    scene = sheetkin.load_scene(short)
    pic = drawing.picture(scene, [0.0, 30.0, 180.0])
    assert any("cannot assemble for crank angles 104.48..255.52" in n for n in pic.notes)
    gap = [s for s in pic.background if s.role == "trace_gap"]
    assert gap                           # the crank pin's path through the gap, in red
    phi = np.degrees(np.arctan2(*np.concatenate([g.xy for g in gap])[:, ::-1].T)) % 360
    assert ((phi > 104.4) & (phi < 255.6)).all()
    assert pic.captions[2] == "phi_1 = 180 deg: cannot assemble"
    assert _shapes(pic.frames[2], "link") and len(_shapes(pic.frames[2], "link")) == 1   # the crank alone
    # just inside the assembling side of the gap's edge the group is near a toggle
    edge = 104.4775
    pic = drawing.picture(scene, [edge])
    assert "near a toggle (group 1)" in pic.captions[0]
    # on the paths, the positions with |det_g1| below the threshold are circled: B there
    fine = sheetkin.compute(scene, np.linspace(100.0, edge, 40), allow_gaps=True)
    pic = drawing.picture(scene, [edge], fine=fine)
    marks = [s for s in pic.background if s.role == "toggle"]
    near = fine[fine["det_g1"].abs() < 0.01]
    assert len(marks) == 2 * len(near) > 0                     # the group's moving joints A and B
    assert np.allclose(marks[-1].xy[0], [near["x_B"].iloc[-1], near["y_B"].iloc[-1]])
    assert any(n.startswith("group 1: |det_g1| < 0.01") for n in pic.notes)


def test_gif_frames_size_and_scale(tmp_path):
    scene = sheetkin.load_scene(WB / "fourbar.toml")
    out = tmp_path / "m.gif"
    seen = []
    pic = animate(scene, out, frames=8, size=200, vectors=True, progress=lambda i, n: seen.append((i, n)))
    from PIL import Image
    im = Image.open(out)
    assert im.n_frames == 8 and im.width == 200
    x0, y0, x1, y1 = pic.bounds
    assert abs((im.height - 40) - 200 * (y1 - y0) / (x1 - x0)) <= 2      # equal scale
    assert seen[-1] == (8, 8)
    assert any(s.role == "vector" for s in pic.frames[0])


def test_html_page_is_self_contained(short, tmp_path):
    scene = sheetkin.load_scene(short)
    pic = drawing.picture(scene, geometry.revolution(scene, 6))
    page = html_page(pic, fps=5, size=300)
    assert not re.search(r"(src|href)\s*=|https?://", page)          # nothing fetched
    data = json.loads(re.search(r"const D = (\{.*?\});\n", page).group(1))
    assert len(data["frames"]) == 6 and data["captions"][3].endswith("cannot assemble")
    assert "id=\"play\"" in page and "type=\"range\"" in page


@pytest.mark.parametrize("lang, words", [
    ("ru", ("пауза", "механизм", "положение", "град", ": не собирается", "не собирается при углах кривошипа")),
    ("uk", ("пауза", "механізм", "положення", "град", ": не збирається", "не збирається при кутах кривошипа")),
    ("en", ("pause", "the mechanism", "position", "deg", ": cannot assemble", "cannot assemble for crank angles")),
])
def test_html_page_speaks_its_language(short, tmp_path, lang, words):
    """Issue 22: the controls (play/pause, the slider's and canvas's labels), the captions
    and the notes in ru, uk or en; `sheetkin animate` defaults to ru, as the books."""
    out = tmp_path / f"{lang}.html"
    assert main(["animate", str(short), "-o", str(out), "--allow-gaps", "--frames", "6", "--lang", lang]) == 0
    page = out.read_text(encoding="utf-8")
    assert f'<html lang="{lang}">' in page
    data = json.loads(re.search(r"const D = (\{.*?\});\n", page).group(1))
    assert data["words"]["pause"] == words[0] and f'type="button">{words[0]}</button>' in page
    assert f'aria-label="{words[1]}"' in page and f'aria-label="{words[2]}"' in page
    assert re.match(r"phi_1 = \S+ (\S+?)(:|$)", data["captions"][0])[1] == words[3]
    assert data["captions"][3].endswith(words[4]) and words[5] in page
    visible = re.sub(r"<script>.*?</script>|<style>.*?</style>|<[^>]+>", " ", page, flags=re.S)
    visible = visible.replace(sheetkin.load_scene(short).title, " ")          # the scene's own title
    english = {"play", "pause", "position", "mechanism", "deg", "cannot", "assemble", "crank", "angles", "near",
               "toggle", "group", "velocity", "drawing", "variant", "speed"}
    said = {w.lower() for w in re.findall(r"[A-Za-z]+", visible + " ".join(data["captions"]) + data["words"]["play"])}
    assert bool(said & english) == (lang == "en"), sorted(said & english)
    if lang == "ru":                     # the default
        assert main(["animate", str(short), "-o", str(tmp_path / "d.html"), "--allow-gaps", "--frames", "6"]) == 0
        assert (tmp_path / "d.html").read_text(encoding="utf-8") == page


def test_cli_animate(short, tmp_path, capsys):
    assert main(["animate", str(short), "-o", str(tmp_path / "a.gif")]) == 3
    assert "use --allow-gaps" in capsys.readouterr().err
    assert main(["animate", str(short), "-o", str(tmp_path / "a.html"), "--allow-gaps", "--frames", "4"]) == 0
    err = capsys.readouterr().err
    assert "4 positions" in err and "warning: group 1 (RRR A-B-O1) cannot assemble" in err
    assert main(["animate", str(short), "-o", str(tmp_path / "a.mp4")]) == 2
    assert "expected a file name ending in .gif" in capsys.readouterr().err
    assert not (tmp_path / "a.mp4").exists()


def test_importing_the_drawing_does_not_import_matplotlib():
    code = "import sheetkin.views.animate, sheetkin.views.drawing, sys; print('matplotlib' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT,
                         env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"})
    assert out.stdout.strip() == "False", out.stderr
