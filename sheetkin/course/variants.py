"""`sheetkin variants`: N distinct variants of one scheme for a class (issue 13).

A variant is the scene with other given data: by default each length, coordinate and
offset (the input rows in metres) whose scene value is not zero varies within +-BAND
(10 %) of it, on a teacher's grid (STEPS: lengths to the millimetre); --vary NAME=LO..HI
sets a range for any given value that the scene file holds (Fi_t0, gamma_g2, m_3 ...).
Candidates are drawn at random (seeded) and kept when the mechanism stays what it is:

  * every group assembles at every position of the sheet and over a whole revolution of
    the crank, one degree apart (the crank turns fully);
  * every link keeps its kind of motion (turns fully or rocks: a crank-rocker stays a
    crank-rocker, Grashof's class is kept);
  * every group's toggle measure |det| (solver.Solution.det: the determinant of its
    velocity system over its lengths, for RRR the sine of the transmission angle) is at
    least MIN_DET at all those positions, far from a toggle;
  * it differs from every variant kept before in at least one given value by MARGIN of
    that value's range (2 % of the scene's value for the default band), and never by less
    than one grid step.

Which scene key an input row comes from is found by changing each number of the scene
file once and seeing which rows follow (no per-kind table: a new group kind works as it is).
"""
from __future__ import annotations

import contextlib
import copy
import json
import math
import os
import random
import re
import shutil
import sys
import tempfile
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from sheetkin.kinematics.caps import load_toml
from sheetkin.kinematics.scene import Scene, SceneError, one_line, parse_scene
from sheetkin.kinematics.solver import solve
from sheetkin.messages import message
from sheetkin.sheet.workbook import build_workbook

from .caches import scene_rows
from .identity import ASSIGNMENT_FILE, assignment_text
from .issued import KEY_FILE, ROSTER_FILE, given_values, new_key, roster_text, seal

BAND = 0.10                 # default range: the scene's value +- 10 %
MIN_DET = 0.25              # |det| at every position; RRR: transmission angle >= 14.5 deg
MARGIN = 0.10               # of a value's range: two variants differ by this in some value
TRIES = 200                 # candidates drawn per variant asked for
MAX_VARIANTS = 1000         # a class, or a whole year's; not a million workbooks by a typo
REVOLUTION_DEG = 1.0        # the full-turn check's step
STEPS = {"m": 0.001, "deg": 1.0, "rad/s": 0.1, "rad/s^2": 0.1}   # the grid a teacher prints
SIGNIFICANT = 3             # other units (kg, N, kg m^2): three significant digits


@dataclass(frozen=True)
class Param:
    """A given value that can vary: its input row name(s), unit, where the scene file holds
    it (a path of keys and indices), and its scene value."""
    names: tuple[str, ...]
    unit: str
    path: tuple
    base: float

    @property
    def name(self) -> str:
        return self.names[0]


@dataclass(frozen=True)
class Range:
    param: Param
    lo: float
    hi: float
    step: float

    def grid(self) -> tuple[int, int]:
        return math.ceil(self.lo / self.step - 1e-9), math.floor(self.hi / self.step + 1e-9)

    @property
    def margin(self) -> float:
        return max(MARGIN * (self.hi - self.lo), self.step)


@dataclass
class Variant:
    id: str
    text: str               # the scene file
    scene: Scene
    values: dict[str, float]   # the varied values (by Param.name)


# --------------------------------------------------------------------------- TOML out
_BARE = re.compile(r"^[A-Za-z0-9_-]+$")


def _key(k: str) -> str:
    return k if _BARE.match(k) else json.dumps(k, ensure_ascii=False)


def _value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{_key(k)} = {_value(x)}" for k, x in v.items()) + " }"
    if isinstance(v, list):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    raise TypeError(f"no TOML for {type(v).__name__}")


def dump_toml(data: dict, header: str = "") -> str:
    """A scene document as TOML text (the subset scenes use: top-level keys, [tables],
    [[arrays of tables]], inline tables and arrays inside them)."""
    out = [f"# {line}" for line in header.splitlines()]
    tables = [(k, v) for k, v in data.items() if isinstance(v, dict)]
    arrays = [(k, v) for k, v in data.items() if isinstance(v, list) and v and all(isinstance(x, dict) for x in v)]
    special = {k for k, _ in tables} | {k for k, _ in arrays}
    out += [f"{_key(k)} = {_value(v)}" for k, v in data.items() if k not in special]
    for k, v in tables:
        out += ["", f"[{_key(k)}]"] + [f"{_key(a)} = {_value(b)}" for a, b in v.items()]
    for k, items in arrays:
        for item in items:
            out += ["", f"[[{_key(k)}]]"] + [f"{_key(a)} = {_value(b)}" for a, b in item.items()]
    return "\n".join(out) + "\n"


def _leaves(node, path=()):
    """(path, number) of every number in the document, in file order."""
    if isinstance(node, dict):
        for k, v in node.items():
            yield from _leaves(v, path + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from _leaves(v, path + (i,))
    elif isinstance(node, (int, float)) and not isinstance(node, bool):
        yield path, node


def _set(data, path, value):
    node = data
    for k in path[:-1]:
        node = node[k]
    node[path[-1]] = value


# --------------------------------------------------------------------------- what can vary
def parameters(text: str, source: str = "<scene>") -> list[Param]:
    """The scene file's numbers that are given data of the workbook, in input-block order."""
    data = load_toml(text, source)
    scene = parse_scene(text, source)
    base = given_values(scene)
    units = {r.name: r.unit for r in scene_rows(scene) if r.kind == "input"}
    found = []
    for path, v in _leaves(data):
        if path[0] == "synthesis":
            continue
        probe = copy.deepcopy(data)
        _set(probe, path, float(v) * 1.01 + 0.0123)      # a value no row holds by chance
        try:
            moved = given_values(parse_scene(dump_toml(probe), source))
        except SceneError:
            continue                                      # an index, a count, a branch: not a given value
        names = tuple(n for n in base if n in moved and moved[n] != base[n])
        if names:
            found.append(Param(names, units[names[0]], path, float(base[names[0]])))
    order = list(base)
    return sorted(found, key=lambda p: order.index(p.name))


def _step(unit: str, lo: float, hi: float) -> float:
    if unit in STEPS:
        return STEPS[unit]
    top = max(abs(lo), abs(hi)) or 1.0
    return 10.0 ** (math.floor(math.log10(top)) - (SIGNIFICANT - 1))


_VARY = re.compile(r"^\s*([A-Za-z][A-Za-z0-9_]*)\s*=\s*(\S+?)\s*\.\.\s*(\S+)\s*$")


def ranges(params: list[Param], vary: Sequence[str] = ()) -> list[Range]:
    """The default band around each non-zero length/coordinate, and every --vary range."""
    by_name = {n: p for p in params for n in p.names}
    chosen: dict[str, tuple[float, float]] = {}
    for spec in vary:
        m = _VARY.match(spec)
        lo = hi = math.nan
        if m:
            with contextlib.suppress(ValueError):
                lo, hi = float(m.group(2)), float(m.group(3))
        if not m or not (math.isfinite(lo) and math.isfinite(hi)) or lo > hi:
            raise SceneError(one_line(f"--vary {spec}: expected NAME=LO..HI with numbers LO <= HI "
                                      "(e.g. L2=0.45..0.55)"))
        if m.group(1) not in by_name:
            raise SceneError(one_line(message("vary_no_given_value", v=spec, name=repr(m.group(1)),
                                              list=", ".join(n for p in params for n in p.names)), 2000))
        if by_name[m.group(1)].name in chosen:     # the last one silently won
            raise SceneError(one_line(f"--vary {spec}: {m.group(1)} is given a range twice"))
        chosen[by_name[m.group(1)].name] = (lo, hi)
    out = []
    for p in params:
        if p.name in chosen:
            lo, hi = chosen[p.name]
        elif p.unit == "m" and p.base != 0.0:
            lo, hi = sorted((p.base * (1 - BAND), p.base * (1 + BAND)))
        else:
            continue
        r = Range(p, lo, hi, _step(p.unit, lo, hi))
        a, b = r.grid()
        if a > b:
            raise SceneError(one_line(f"--vary {p.name}={lo:g}..{hi:g}: no value on its grid "
                                      f"(steps of {r.step:g} {p.unit})"))
        out.append(r)
    return out


# --------------------------------------------------------------------------- acceptable?
def _turns(c, s) -> int:
    """Whole turns of a link over the crank's revolution (0: it rocks)."""
    a = np.unwrap(np.arctan2(s, c))
    return int(round((a[-1] - a[0]) / (2 * np.pi)))


def revolution(scene: Scene) -> np.ndarray:
    """The sheet's crank angles and a whole turn one degree apart, the way the crank turns."""
    c = scene.crank
    sign = -1.0 if c.step_deg < 0 else 1.0
    turn = c.phi0_deg + sign * np.arange(0.0, 360.0 + REVOLUTION_DEG / 2, REVOLUTION_DEG)
    return np.concatenate([turn, np.asarray(scene.crank_angles_deg(), dtype=float)])


def assess(scene: Scene, min_det: float = MIN_DET) -> tuple[str, tuple]:
    """("", the links' turns) when the mechanism assembles everywhere on a revolution and
    is far from toggles; else (reason, ())."""
    phi = revolution(scene)
    with np.errstate(all="ignore"):
        sol = solve(scene, phi)
    for i, bad in sol.failed.items():
        if np.any(bad):
            at = phi[np.argmax(bad)]
            return f"group {i} cannot assemble at phi_1 = {at:g} deg", ()
    for i, det in sol.det.items():
        d = np.abs(np.broadcast_to(det, phi.shape))
        if not np.all(np.isfinite(d)) or np.min(d) < min_det:
            k = int(np.argmin(np.where(np.isfinite(d), d, -1)))
            return f"group {i}'s |det| is {d[k]:.3g} < {min_det:g} at phi_1 = {phi[k]:g} deg", ()
    n = len(phi) - scene.crank.positions           # the revolution's part of phi
    turns = tuple(_turns(np.broadcast_to(r.c, phi.shape)[:n], np.broadcast_to(r.s, phi.shape)[:n])
                  for _, r in sorted(sol.links.items()))
    return "", turns


def _distinct(values: dict[str, float], kept: list[Variant], rngs: list[Range]) -> bool:
    return all(any(abs(values[r.param.name] - v.values[r.param.name]) >= r.margin * (1 - 1e-9) for r in rngs)
               for v in kept)


# --------------------------------------------------------------------------- making them
def make_variants(text: str, source: str, n: int, seed: int, vary: Sequence[str] = (),
                  min_det: float = MIN_DET) -> list[Variant]:
    """N acceptable, distinct variants of the scene `text` (the module's docstring), or a
    SceneError (one line) saying why there are fewer."""
    if n > MAX_VARIANTS:
        raise SceneError(f"-n {n}: at most {MAX_VARIANTS} variants at a time (two workbooks each)")
    scene = parse_scene(text, source)
    reason, turns = assess(scene, min_det)
    if reason:
        raise SceneError(one_line(f"{source}: the scheme itself is not fit for variants: {reason} "
                                  f"(variants need a crank that turns fully, |det| >= {min_det:g})"))
    params = parameters(text, source)
    rngs = ranges(params, vary)
    if not rngs:
        raise SceneError(one_line(f"{source}: nothing to vary (no non-zero length or coordinate); "
                                  "give ranges with --vary NAME=LO..HI"))
    data = load_toml(text, source)
    data.pop("synthesis", None)      # the design data of the scene's own lengths, not a variant's
    rng = random.Random(seed)
    kept: list[Variant] = []
    width = max(2, len(str(n)))
    stem = Path(source).stem
    rejected = {"assembly or toggle": 0, "type of motion": 0, "too close to another": 0}
    for _ in range(TRIES * n):
        if len(kept) == n:
            break
        values = {}
        for r in rngs:
            a, b = r.grid()
            values[r.param.name] = _on_grid(rng.randint(a, b), r.step)
        if not _distinct(values, kept, rngs):
            rejected["too close to another"] += 1
            continue
        doc = copy.deepcopy(data)
        for r in rngs:
            _set(doc, r.param.path, values[r.param.name])
        vid = f"{stem}-{len(kept) + 1:0{width}d}"
        doc["title"] = f"{scene.title} (variant {vid})"
        body = dump_toml(doc, f"variant {vid} of {Path(source).name}: sheetkin variants --seed {seed}")
        try:
            cand = parse_scene(body, f"{vid}.toml")
        except SceneError:
            rejected["assembly or toggle"] += 1
            continue
        why, t = assess(cand, min_det)
        if why:
            rejected["assembly or toggle"] += 1
            continue
        if t != turns:
            rejected["type of motion"] += 1
            continue
        kept.append(Variant(vid, body, cand, values))
    if len(kept) < n:
        bands = ", ".join(f"{r.param.name} {r.lo:g}..{r.hi:g}" for r in rngs)
        raise SceneError(one_line(
            f"{source}: only {len(kept)} acceptable variant{'' if len(kept) == 1 else 's'} "
            f"of the {n} asked for in {TRIES * n} tries "
            f"within {bands} (rejected: " + ", ".join(f"{v} {k}" for k, v in rejected.items())
            + "); widen the ranges with --vary NAME=LO..HI or ask for fewer with -n", 2000))
    return kept


def _on_grid(k: int, step: float) -> float:
    """k steps, printed as the teacher prints them (0.001 * 140 -> 0.14, not 0.14000000000000001)."""
    decimals = max(0, -math.floor(math.log10(step)) + 1)
    return float(f"{k * step:.{decimals}f}")


# --------------------------------------------------------------------------- writing them
# with a class list, the students' own books (one each) go to this folder of --out, the one
# to upload, and everything else to TEACHER_FOLDER (keys, scenes, roster, assignment, the
# key, the generic exercises), never uploaded: issue 34, a folder of 16 exercises for 8
# students handed out both. Without a class list all is in --out, as before (and a class
# issued before this layout, roster.csv directly in --out, is read as it was).
STUDENTS_FOLDER = "students"
TEACHER_FOLDER = "teacher"


def teacher_folder(out: str | Path, class_list: bool) -> Path:
    """Where `variants` writes the roster, the key, assignment.csv and the books of each
    variant: out/TEACHER_FOLDER with a class list, else out itself."""
    return Path(out) / TEACHER_FOLDER if class_list else Path(out)


def file_names(vid: str) -> dict[str, str]:
    return {"exercise": f"{vid}-exercise.xlsx", "key": f"{vid}-key.xlsx", "scene": f"{vid}.toml"}


def write_variants(variants: list[Variant], out: str | Path, *, force: bool = False, lang: str = "ru",
                   charts: bool = True, note=None, class_list=None, kept: list | None = None) -> Path:
    """Write the variants' scenes, exercise and key workbooks, roster.csv and the teacher's
    key in `out`; with a class list (classlist.ClassList) each student's own exercise in
    out/STUDENTS_FOLDER (the folder to hand out), and all the rest, with assignment.csv
    (assign()), in out/TEACHER_FOLDER (teacher_folder: never uploaded).
    Refuses to overwrite a file unless force. An issued
    class's roster, key and assignment are never overwritten: with force they are renamed
    beside the new ones, dated (roster-20261126-113000.csv, .sheetkin-key-20261126-113000),
    and `validate` still checks the books sealed with the older keys (their names are
    appended to `kept`). Returns the roster."""
    top = Path(out)
    people = assign(variants, class_list) if class_list is not None else []
    out = teacher_folder(top, class_list is not None)
    targets = ([out / ROSTER_FILE, out / KEY_FILE, out / ASSIGNMENT_FILE]
               + [out / f for v in variants for f in file_names(v.id).values()]
               + [top / STUDENTS_FOLDER / exercise for _, _, _, exercise in people])
    if not force:
        for t in targets:
            if t.exists():
                raise SceneError(one_line(message("exists_refusing", f=t)))
    for folder in (top, out, top / STUDENTS_FOLDER):
        if folder.exists() and not folder.is_dir():
            raise SceneError(one_line(message("out_not_folder", f=folder)))
    out.mkdir(parents=True, exist_ok=True)
    if people:
        (top / STUDENTS_FOLDER).mkdir(exist_ok=True)
    done = keep_issued(out)
    if kept is not None:
        kept += done
    key_hex = new_key()
    key = bytes.fromhex(key_hex)
    written: list[Path] = []
    try:
        _write_issue(variants, out, key, lang, charts, note, class_list, people, written, top / STUDENTS_FOLDER)
        # the key last: a run that fails before it (a full disk) leaves no key that would
        # make the rerun refuse ("exists") or check books against a key nobody received
        _atomic(out / KEY_FILE, key_hex + "\n", private=True)
    except BaseException:
        _undo(out, written, done)
        raise
    return out / ROSTER_FILE


def _write_issue(variants, out: Path, key: bytes, lang: str, charts: bool, note, class_list, people,
                 written: list[Path], students: Path) -> None:
    """The scenes, books, assignment and roster of write_variants in `out`, the students'
    own books in `students` (each path appended to `written` once it is there)."""
    def atomic(path: Path, text: str) -> None:
        _atomic(path, text)
        written.append(path)

    def book(path: Path, wb) -> None:
        _atomic_book(path, wb)
        written.append(path)
    names = list(given_values(variants[0].scene))
    rows = []
    for k, v in enumerate(variants, 1):
        files = file_names(v.id)
        atomic(out / files["scene"], v.text)
        mark = (v.id, seal(key, v.id, v.text))
        for which, is_exercise in (("exercise", True), ("key", False)):
            wb = build_workbook(v.scene, lang=lang, exercise=is_exercise, scene_text=v.text, issued=mark,
                                charts=charts)
            book(out / files[which], wb)
        rows.append((v.id, files, given_values(v.scene)))
        if note:
            note(k, v)
    by_id = {v.id: v for v in variants}
    for name, ident, vid, exercise in people:
        v = by_id[vid]
        wb = build_workbook(v.scene, lang=lang, exercise=True, scene_text=v.text,
                            issued=(vid, seal(key, vid, v.text, ident)), charts=charts)
        _seal_student(wb, name, ident)
        book(students / exercise, wb)
    if people:
        atomic(out / ASSIGNMENT_FILE, assignment_text(class_list.id_header, people))
    atomic(out / ROSTER_FILE, roster_text(names, rows))


def _undo(out: Path, written: list[Path], kept: list[Path]) -> None:
    """After a failed run: the files it wrote removed, and the issued roster, key and
    assignment it had kept dated (keep_issued) back under their names, so that the folder
    is as before and the same command can be run again."""
    for path in written:
        with contextlib.suppress(OSError):
            path.unlink()
    for dated in kept:
        for name in (ROSTER_FILE, KEY_FILE, ASSIGNMENT_FILE):
            base = name.rpartition(".")[0] if not name.startswith(".") else name
            if dated.name.startswith(base + "-"):
                with contextlib.suppress(OSError):
                    if (out / name).exists() and os.path.samefile(dated, out / name):
                        dated.unlink()           # a hard link to the very file: rename() would do nothing
                    else:
                        os.replace(dated, out / name)
                break


MAX_CLASS_SIZE = 2_000      # students one `variants --class-list` issues books to (a year's course)


def check_class_size(class_list) -> None:
    """A class list of more students than MAX_CLASS_SIZE is one line, before any variant is
    made (100,000 students took hours and 4.5 GB)."""
    n = len({p.ident for p in class_list.people})
    if n > MAX_CLASS_SIZE:
        raise SceneError(one_line(f"{class_list.path}: --class-list names {n:,} students; `variants` issues books "
                                  f"to at most {MAX_CLASS_SIZE:,} at a time (split the list by group)"))


def assign(variants: list[Variant], class_list) -> list[tuple[str, str, str, str]]:
    """(name, identifier, variant id, exercise file) for each student of the class list, in
    the list's order: the k-th student (from 0) gets variant k mod N. More students than
    variants is allowed (a variant is then shared, each student's book sealed with their
    own identity); a student listed twice (one identifier) gets one variant."""
    check_class_size(class_list)
    out: list[tuple[str, str, str, str]] = []
    seen: set[str] = set()
    files: set[str] = set()         # the exercise files' names, casefolded
    for person in class_list.people:
        if person.ident in seen:
            continue
        seen.add(person.ident)
        v = variants[len(out) % len(variants)]
        stem = f"{v.id}-{_file_part(person.name)}"
        exercise, n = f"{stem}-exercise.xlsx", 2
        while exercise.casefold() in files:            # two students of one name
            exercise, n = f"{stem}-{n}-exercise.xlsx", n + 1
        files.add(exercise.casefold())
        out.append((person.name, person.ident, v.id, exercise))
    if not out:
        raise SceneError(one_line(message("class_list_no_student", f=class_list.path)))
    return out


def _file_part(name: str) -> str:
    """A student's name as part of a file name: letters, digits and - kept, spaces _."""
    return re.sub(r"[^\w-]+", "_", name, flags=re.UNICODE).strip("_")[:60] or "student"


def _seal_student(wb, name: str, ident: str) -> None:
    """The student's name in their own cell of the exercise (D1, the name cell since the
    language merge; the row `student` is gone), and their identifier beside the seal
    (scene!B3:C3, under it)."""
    from sheetkin.sheet.workbook import SCENE_SHEET

    from .issued import STUDENT_LABEL, STUDENT_ROW
    ws = wb.worksheets[0]
    ws.cell(1, 4).value = name
    ws.cell(1, 4).data_type = "s"
    sc = wb[SCENE_SHEET]
    for col, value in ((2, STUDENT_LABEL), (3, ident)):
        sc.cell(STUDENT_ROW, col).value = value
        sc.cell(STUDENT_ROW, col).data_type = "s"


def keep_issued(out: Path) -> list[Path]:
    """Rename an issued class's roster, key and assignment in `out` to dated names beside
    them (never overwritten, never deleted); returns the new names."""
    import datetime
    stamp = datetime.datetime.now().strftime("%Y%m%d-%H%M%S")
    kept = []
    for name in (ROSTER_FILE, KEY_FILE, ASSIGNMENT_FILE):
        old = out / name
        if not old.exists():
            continue
        base, dot, ext = name.rpartition(".") if not name.startswith(".") else (name, "", "")
        n = 1
        while True:
            dated = out / (f"{base}-{stamp}{'-' + str(n) if n > 1 else ''}{dot}{ext}")
            if not dated.exists():
                break
            n += 1
        try:
            os.link(old, dated)            # the very file (its permissions too); the new one replaces the name
        except OSError:
            try:
                shutil.copy2(old, dated)   # a file system without hard links
            except OSError as e:
                raise SceneError(one_line(f"{old}: cannot keep it as {dated.name} ({e.strerror or e}); "
                                          "nothing issued was changed")) from None
        kept.append(dated)
    return kept


def _atomic(path: Path, text: str, private: bool = False) -> None:
    _atomic_bytes(path, text.encode("utf-8"), private)


def _atomic_book(path: Path, wb) -> None:
    import io
    buf = io.BytesIO()
    wb.save(buf)
    _atomic_bytes(path, buf.getvalue())


def _atomic_bytes(path: Path, data: bytes, private: bool = False) -> None:
    """Write to a temporary file beside `path`, then rename: a reader never sees half a file.
    An OSError names `path`, not the temporary file (a read-only folder once said
    "out/..sheetkin-key.almuqx0p.tmp: Read-only file system")."""
    try:
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    except OSError as e:
        raise OSError(e.errno, e.strerror, str(path)) from None
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        if not private:
            os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        err = sys.exc_info()[1]
        if isinstance(err, OSError):
            raise OSError(err.errno, err.strerror, str(path)) from None
        raise
