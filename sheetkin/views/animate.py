"""`sheetkin animate`: the mechanism over a revolution as a GIF or a self-contained HTML page.

Both draw sheetkin.views.drawing's shapes: the GIF through matplotlib's animation writer with
Pillow, the page with a small inline script on a canvas (the frames' coordinates are
embedded as JSON; nothing is fetched, so it works offline). matplotlib is imported only
when a GIF or PNG is drawn.
"""
from __future__ import annotations

import dataclasses
import json
import math
import sys
import tempfile
from pathlib import Path

import numpy as np

from sheetkin.errors import UsageError
from sheetkin.files import Output, write_file
from sheetkin.kinematics.geometry import revolution
from sheetkin.kinematics.scene import Scene
from sheetkin.messages import message
from sheetkin.messages import say as said

from .drawing import STYLES, Picture, picture

FORMATS = (".gif", ".html", ".png")
# Caps (docs/reliability.md; `sheetkin animate` refuses more in one line): frames every 0.1
# deg, a drawing of at most 4000 px a side (a GIF frame is width x height bytes), and a
# frame rate a GIF can hold (its delays are hundredths of a second).
MAX_FRAMES = 3600
MAX_SIZE = 4000
MIN_FPS, MAX_FPS = 0.1, 100.0
# A GIF's frames are kept until its shared palette is made (about 11 bytes a pixel): frames x
# width x height at most this (about 265 frames at 320 px; 990 frames took 1.7 GB and 6 min)
MAX_GIF_PIXELS = 40_000_000


class AnimationError(UsageError):
    """An animation past its caps: one line. A UsageError: animate()'s parameters (frames,
    size, fps, the output's name) are `sheetkin animate`'s options, and the message names them."""


def check_caps(frames: int, fps: float, size: int) -> None:
    if not 1 <= frames <= MAX_FRAMES:
        raise AnimationError(f"--frames {frames}: expected 1 to {MAX_FRAMES:,}")
    if not 1 <= size <= MAX_SIZE:
        raise AnimationError(f"--size {size}: expected 1 to {MAX_SIZE:,} pixels")
    if not MIN_FPS <= fps <= MAX_FPS:        # also NaN
        raise AnimationError(f"--fps {fps}: expected {MIN_FPS:g} to {MAX_FPS:g} frames per second")


def fitted_size(pic: Picture, size: int) -> int:
    """The width to draw at: `size`, or less for a tall mechanism, so the height (at equal
    scale) stays within MAX_SIZE."""
    x0, y0, x1, y1 = pic.bounds
    ratio = (y1 - y0) / (x1 - x0) if x1 > x0 else 1.0
    if not math.isfinite(ratio) or ratio <= 0:
        return size
    return max(1, min(size, int(MAX_SIZE / ratio)))


def animation_picture(scene: Scene, frames: int = 36, *, vectors: bool = False, labels: bool = True,
                      allow_gaps: bool = False, toggle_threshold: float = 0.01) -> Picture:
    """`frames` positions over one revolution from phi0 (the way the crank turns)."""
    return picture(scene, revolution(scene, frames), vectors=vectors, labels=labels,
                   allow_gaps=allow_gaps, toggle_threshold=toggle_threshold)


# --------------------------------------------------------------------------- matplotlib
def _pt(px: float) -> float:
    return 0.75 * px              # CSS px -> typographic points at 96 dpi


def draw_shapes(ax, shapes) -> list:
    """Add the shapes to a matplotlib Axes; returns the artists (to remove them later)."""
    from matplotlib.patches import FancyArrowPatch, Polygon
    out = []
    for s in shapes:
        stroke, width, fill, dash = STYLES[s.role]
        ls = (0, tuple(float(x) for x in dash.split(","))) if dash else "-"
        z = {"trace": 1, "trace_gap": 1, "hatch": 2, "ground": 2, "guide": 2, "slot": 3, "link": 4,
             "block": 5, "joint": 6, "point": 6, "toggle": 3, "vector": 7}.get(s.role, 8)
        if s.kind == "text":
            out.append(ax.text(s.xy[0, 0], s.xy[0, 1], s.text, color=stroke, fontsize=8, zorder=z,
                               style="italic" if s.role == "link_label" else "normal"))
        elif s.kind == "dot":
            face = "none" if s.role == "toggle" else fill
            out += ax.plot(s.xy[:, 0], s.xy[:, 1], "o", ms=5 if s.role != "point" else 3.5, mfc=face,
                           mec=stroke, mew=_pt(width), zorder=z)
        elif s.kind == "polygon":
            out.append(ax.add_patch(Polygon(s.xy, closed=True, fc=fill or "none", ec=stroke,
                                            lw=_pt(width), zorder=z)))
        elif s.kind == "arrow":
            out.append(ax.add_patch(FancyArrowPatch(s.xy[0], s.xy[1], arrowstyle="-|>", mutation_scale=9,
                                                    color=stroke, lw=_pt(width), zorder=z)))
        else:
            out += ax.plot(s.xy[:, 0], s.xy[:, 1], color=stroke, lw=_pt(width), ls=ls, zorder=z)
    return out


def _figure(pic: Picture, size: int):
    import matplotlib
    matplotlib.use("Agg", force=False) if matplotlib.get_backend().lower() != "agg" else None
    import matplotlib.pyplot as plt
    x0, y0, x1, y1 = pic.bounds
    h = size * (y1 - y0) / (x1 - x0)
    dpi = 100
    fig = plt.figure(figsize=(size / dpi, (h + 40) / dpi), dpi=dpi)
    ax = fig.add_axes((0, 22 / (h + 40), 1, h / (h + 40)))
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("equal")          # a circle stays round
    ax.set_axis_off()
    fig.text(0.01, 1 - 4 / (h + 40), pic.title, va="top", fontsize=8)
    cap = fig.text(0.01, 4 / (h + 40), "", va="bottom", fontsize=7, color="#444444")
    draw_shapes(ax, pic.background)
    return fig, ax, cap


def write_png(pic: Picture, path, position: int = 0, size: int = 480) -> None:
    import matplotlib.pyplot as plt
    fig, ax, cap = _figure(pic, size)
    draw_shapes(ax, pic.frames[position])
    cap.set_text(pic.captions[position])
    fig.savefig(path, dpi=100)
    plt.close(fig)


def write_gif(pic: Picture, path, fps: float = 12, size: int = 320, progress=None) -> None:
    """The frames as an animated GIF (matplotlib's FuncAnimation, Pillow's writer).
    progress(i, n) is called after each frame."""
    import matplotlib.pyplot as plt
    from matplotlib.animation import FuncAnimation, PillowWriter
    fig, ax, cap = _figure(pic, size)
    current: list = []

    def update(i):
        for a in current:
            a.remove()
        current[:] = draw_shapes(ax, pic.frames[i])
        cap.set_text(pic.captions[i])
        return current

    class SharedPalette(PillowWriter):
        """Pillow's writer, but every frame on one 32-colour palette without dithering:
        a line drawing needs no more, and the GIF is about half the size."""

        def finish(self):
            frames = [f.convert("RGB") for f in getattr(self, "_frames", [])]
            if not frames:
                return super().finish()
            from PIL import Image
            # the palette of the first and the middle frame side by side
            a, b = frames[0], frames[len(frames) // 2]
            both = Image.new("RGB", (a.width * 2, a.height), "white")
            both.paste(a, (0, 0))
            both.paste(b, (a.width, 0))
            pal = both.quantize(colors=32)
            small = [f.quantize(palette=pal, dither=Image.Dither.NONE) for f in frames]
            small[0].save(self.outfile, save_all=True, append_images=small[1:],
                          duration=int(round(1000 / self.fps)), loop=0, optimize=True)

    anim = FuncAnimation(fig, update, frames=len(pic.frames), blit=False)
    try:
        # matplotlib's stub types fps as int; the writer takes any fps (0.1 to 100 here)
        anim.save(str(path), writer=SharedPalette(fps=fps), dpi=100,  # type: ignore[arg-type]
                  progress_callback=(lambda i, n: progress(i + 1, n)) if progress else None)
    finally:
        plt.close(fig)


# --------------------------------------------------------------------------- HTML
def _shape_json(s) -> list:
    return [s.kind, s.role, np.round(s.xy, 6).tolist(), s.text]


# the page's own words (its controls, captions and notes), one table a language: the
# Picture says them in English (sheetkin.views.drawing), the page in `lang`
PAGE_WORDS: dict[str, dict[str, str]] = {
    "en": {"play": "play", "pause": "pause", "mechanism": "the mechanism", "position": "position", "deg": "deg",
           "variant": "variant", "speed": "speed"},
    "ru": {"play": "пуск", "pause": "пауза", "mechanism": "механизм", "position": "положение", "deg": "град",
           "variant": "вариант", "speed": "скорость"},
    "uk": {"play": "пуск", "pause": "пауза", "mechanism": "механізм", "position": "положення", "deg": "град",
           "variant": "варіант", "speed": "швидкість"},
}
def say(text: str, lang: str) -> str:
    """A caption, a note or the title of a Picture (English) in `lang` (ru, uk, en): the
    drawing's messages of sheetkin.messages."""
    if lang not in PAGE_WORDS:
        raise ValueError(f"lang must be one of {', '.join(PAGE_WORDS)}, got {lang!r}")
    return said(text, lang, "drawing")


_PAGE = """<!doctype html>
<html lang="{lang}"><head><meta charset="utf-8"><title>{title}</title>
<style>body{{font-family:sans-serif;margin:1em}}canvas{{border:1px solid #ccc;display:block}}
#bar{{margin:.4em 0;display:flex;gap:.6em;align-items:center}}#pos{{flex:1;max-width:{width}px}}
.note{{color:#555;font-size:90%}}</style></head><body>
<h3>{title}</h3>
<canvas id="c" width="{width}" height="{height}" aria-label="{w[mechanism]}"></canvas>
<div id="bar"><button id="play" type="button">{w[pause]}</button>
<input id="pos" type="range" min="0" max="{last}" value="0" aria-label="{w[position]}">
<label>{w[speed]} <select id="speed"><option value="0.25">0.25&times;</option><option value="0.5">0.5&times;</option>
<option value="1" selected>1&times;</option><option value="2">2&times;</option></select></label>
<span id="cap"></span></div>
{notes}
<script>
"use strict";
const D = {data};
const cv = document.getElementById("c"), g = cv.getContext("2d");
const [x0, y0, x1, y1] = D.bounds, s = cv.width / (x1 - x0);
const px = p => [(p[0] - x0) * s, (y1 - p[1]) * s];
function draw(list) {{
  for (const [kind, role, xy, text] of list) {{
    const [stroke, width, fill, dash] = D.styles[role];
    g.strokeStyle = stroke; g.lineWidth = width; g.setLineDash(dash ? dash.split(",").map(Number) : []);
    const p = xy.map(px);
    if (kind === "text") {{ g.fillStyle = stroke; g.font = (role === "link_label" ? "italic " : "") + "11px sans-serif";
      g.fillText(text, p[0][0], p[0][1]); continue; }}
    if (kind === "dot") {{ g.beginPath(); g.arc(p[0][0], p[0][1], role === "point" ? 2.5 : 3.5, 0, 2 * Math.PI);
      if (role !== "toggle") {{ g.fillStyle = fill; g.fill(); }} g.stroke(); continue; }}
    g.beginPath(); g.moveTo(p[0][0], p[0][1]);
    for (const q of p.slice(1)) g.lineTo(q[0], q[1]);
    if (kind === "polygon") {{ g.closePath(); if (fill) {{ g.fillStyle = fill; g.fill(); }} }}
    g.stroke();
    if (kind === "arrow") {{ const a = Math.atan2(p[1][1] - p[0][1], p[1][0] - p[0][0]);
      g.beginPath(); g.moveTo(p[1][0], p[1][1]);
      g.lineTo(p[1][0] - 7 * Math.cos(a - 0.4), p[1][1] - 7 * Math.sin(a - 0.4));
      g.lineTo(p[1][0] - 7 * Math.cos(a + 0.4), p[1][1] - 7 * Math.sin(a + 0.4));
      g.closePath(); g.fillStyle = stroke; g.fill(); }}
  }}
}}
const pos = document.getElementById("pos"), cap = document.getElementById("cap"), btn = document.getElementById("play");
let i = 0, timer = null;
function show(k) {{ i = k; pos.value = k; g.clearRect(0, 0, cv.width, cv.height);
  g.fillStyle = "#fff"; g.fillRect(0, 0, cv.width, cv.height);
  draw(D.background); draw(D.frames[k]);
  cap.textContent = "i = " + k + " / " + (D.frames.length - 1) + ": " + D.captions[k]; }}
const speed = document.getElementById("speed");
function play() {{
  clearInterval(timer);
  timer = setInterval(() => show((i + 1) % D.frames.length), 1000 / (D.fps * Number(speed.value)));
  btn.textContent = D.words.pause;
}}
speed.addEventListener("change", () => {{ if (timer) play(); }});
function pause() {{ clearInterval(timer); timer = null; btn.textContent = D.words.play; }}
btn.addEventListener("click", () => timer ? pause() : play());
pos.addEventListener("input", () => {{ pause(); show(Number(pos.value)); }});
show(0); play();
</script></body></html>
"""


# the canvas of an HTML animation: its shortest link at least SHORTEST_PX long (labels
# apart), within MAX_W x MAX_H, MARGIN_PX around everything drawn (arrows, labels)
SHORTEST_PX, LEAST_PX, MAX_W, MAX_H, MARGIN_PX, LABEL_PX = 90.0, 560.0, 1100.0, 760.0, 16.0, 40.0


def canvas_bounds(pic: Picture, size: int) -> tuple[list[float], int, int]:
    """Bounds (model units) and the canvas's width and height in px, sized to the
    mechanism: every shape of every frame inside (vectors and labels too: a fixed 320 px
    cut the shaper's arrows and piled its labels), the shortest link SHORTEST_PX long or
    the width `size` or the larger side LEAST_PX, whichever is largest, within MAX_W x MAX_H."""
    pts = [s.xy for f in [pic.background, *pic.frames] for s in f if len(s.xy)]
    xy = np.vstack(pts) if pts else np.array([pic.bounds[:2], pic.bounds[2:]])
    x0, y0 = np.nanmin(xy, axis=0)
    x1, y1 = np.nanmax(xy, axis=0)
    w, h = max(x1 - x0, 1e-9), max(y1 - y0, 1e-9)
    links = [np.hypot(*np.diff(s.xy, axis=0).T).min() for s in pic.frames[0] if s.role == "link" and len(s.xy) > 1]
    shortest = min([v for v in links if v > 0] or [w])
    scale = max(size / w, SHORTEST_PX / shortest, LEAST_PX / max(w, h))
    scale = min(scale, (MAX_W - 2 * MARGIN_PX - LABEL_PX) / w, (MAX_H - 2 * MARGIN_PX) / h)
    m, lab = MARGIN_PX / scale, LABEL_PX / scale
    bounds = [float(x0 - m), float(y0 - m), float(x1 + m + lab), float(y1 + m)]
    return bounds, int(round((bounds[2] - bounds[0]) * scale)), int(round((bounds[3] - bounds[1]) * scale))


def html_page(pic: Picture, fps: float = 12, size: int = 480, lang: str = "en") -> str:
    """A self-contained page: the frames' coordinates as JSON, drawn on a canvas by an
    inline script, with play/pause and a position slider (positions named i = 0, 1 ...,
    as the sheet names its columns); its controls, captions and notes in `lang`."""
    import html
    words = PAGE_WORDS[lang] if say("", lang) == "" else {}
    bounds, width, height = canvas_bounds(pic, size)
    data = {"bounds": bounds, "fps": fps, "styles": STYLES, "captions": [say(c, lang) for c in pic.captions],
            "words": {k: words[k] for k in ("play", "pause")},
            "background": [_shape_json(s) for s in pic.background],
            "frames": [[_shape_json(s) for s in f] for f in pic.frames]}
    notes = "".join(f"<p class='note'>{html.escape(say(n, lang))}</p>" for n in pic.notes)
    # "</" would end the script element early: JSON may escape the slash
    blob = json.dumps(data, separators=(",", ":"), ensure_ascii=False).replace("</", "<\\/")
    return _PAGE.format(title=html.escape(say(pic.title, lang)), width=width, height=height,
                        last=len(pic.frames) - 1, notes=notes, data=blob, lang=lang,
                        w={k: html.escape(v) for k, v in words.items()})


def animate(scene: Scene, out, *, frames: int = 36, fps: float = 12, size: int = 320,
            vectors: bool = False, labels: bool = True, allow_gaps: bool = False,
            toggle_threshold: float = 0.01, progress=None, lang: str = "en") -> Picture:
    """Write `out` (.gif, .html, or .png: the first position) and return the Picture; an
    .html page speaks `lang` (ru, uk, en)."""
    suffix = Path(out).suffix.lower()
    if suffix not in FORMATS:
        raise AnimationError(f"{out}: expected a file name ending in {', '.join(FORMATS)}")
    check_caps(frames, fps, size)
    pic = animation_picture(scene, frames, vectors=vectors, labels=labels, allow_gaps=allow_gaps,
                            toggle_threshold=toggle_threshold)
    fitted = fitted_size(pic, size)
    if fitted < size:
        pic.notes.append(message("drawn_narrower", w=fitted, s=size, m=MAX_SIZE))
        size = fitted
    if suffix == ".html":
        write_file(out, html_page(pic, fps, size, lang))
        return pic
    if suffix == ".gif":
        x0, y0, x1, y1 = pic.bounds
        height = size * (y1 - y0) / (x1 - x0) + 40
        pixels = len(pic.frames) * size * height
        if pixels > MAX_GIF_PIXELS:
            raise AnimationError(f"{out}: {len(pic.frames):,} frames of {size} x {height:.0f} px are "
                                 f"{pixels / 1e6:,.0f} million pixels; a GIF may hold at most "
                                 f"{MAX_GIF_PIXELS / 1e6:,.0f} million (use fewer --frames or a smaller "
                                 "--size, or an .html page)")
    # matplotlib and Pillow write by name (the suffix names the format): into a temporary
    # file beside the output, renamed when complete; a device or a FIFO gets its bytes after
    target = Output(out, suffix=".part" + suffix)
    dest = target.tmp
    try:
        with tempfile.TemporaryDirectory(prefix="sheetkin-animate-") as scratch:
            dest = target.tmp or str(Path(scratch) / ("out" + suffix))
            drawn = dataclasses.replace(pic, title=say(pic.title, lang), captions=[say(c, lang) for c in pic.captions])
            if suffix == ".gif":
                write_gif(drawn, dest, fps, size, progress)
            else:
                write_png(drawn, dest, 0, size)
            if target.tmp is None:
                target.file.write(Path(dest).read_bytes())
        target.commit()
    except OSError as e:
        target.abandon()
        if not e.filename or e.filename in (target.tmp, dest):
            # a full disk met by matplotlib or Pillow: named by the output, not "stdout" nor the .part
            raise OSError(e.errno, e.strerror or str(e), str(out)) from None
        raise
    except BaseException:
        target.abandon()
        raise
    return pic


def stderr_progress(label: str):
    """A progress(i, n) that rewrites one line on stderr."""
    def report(i: int, n: int):
        sys.stderr.write(f"\r{label}: frame {i}/{n}")
        if i == n:
            sys.stderr.write("\n")
        sys.stderr.flush()
    return report
