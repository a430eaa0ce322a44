"""`sheetkin compute`'s output: the table, CSV, JSON and parquet, written block by block.

CSV is written by polars, block by block (issue 24: 2x faster than our own formatter on the
same arrays; its notation, the shortest decimal that reads back as the same double, is
in docs/output-formats.md); JSON's numbers are formatted in bulk by sheetkin.views.floatfmt
(Python's repr, byte for byte what json.dumps writes). Positions are computed and written in
blocks of compute.BLOCK, so 1e7 positions stream at bounded memory. Never "nan" or "inf":
a value that is not a finite number is an empty cell in CSV, null in JSON and parquet, "-"
in the table; where the group assembles (outside --allow-gaps' gaps) a warning names the
columns and crank angles.
"""
from __future__ import annotations

import io
import json
import math
import shutil
import sys
from dataclasses import dataclass, field
from typing import BinaryIO, cast

import numpy as np

from sheetkin.files import Output
from sheetkin.kinematics.scene import Scene, SceneError
from sheetkin.kinematics.table import (
    BLOCK,
    AngleRange,
    AssemblyError,
    Block,
    assembly_gaps,
    compute_blocks,
    failing,
    table_names,
    unit,
)

from .floatfmt import WIDTH, repr_slots

FORMATS = ("table", "csv", "json", "parquet")

_SHOWN = 8                       # crank angles listed in a warning before " ..."
# --dynamics: positions where the energy balance misses by more than this share of its terms
# are named (next to a toggle the reactions grow without bound and lose their digits)
BALANCE_TOL = 1e-9


# --------------------------------------------------------------------------- the warnings
@dataclass
class Notes:
    """What the warnings need, gathered block by block (a few angles each, not all)."""
    groups: int
    toggles: dict = field(default_factory=dict)           # group -> first angles flagged
    failing: list = field(default_factory=list)           # angles of failing positions (arrays)
    undefined: dict = field(default_factory=dict)         # column -> [count, first angles]
    balance_max: float = 0.0
    balance_bad: list = field(default_factory=list)
    balance_undefined: list = field(default_factory=list)

    def add(self, names: list[str], blk: Block, dynamics: bool):
        phi = blk.phi
        for i, label in enumerate(blk.labels):
            if not label:
                continue
            at = phi[blk.codes == i]
            for g in label.split(","):
                seen = self.toggles.setdefault(int(g), [])
                if len(seen) <= _SHOWN:
                    seen.extend(at[:_SHOWN + 1 - len(seen)].tolist())
        if blk.fail.any():
            self.failing.append(phi[blk.fail])
        ok = ~blk.fail
        bad = ~np.isfinite(blk.table) & ok
        if bad.any():
            for j in np.flatnonzero(bad.any(axis=1)).tolist():
                entry = self.undefined.setdefault(names[j], [0, []])
                entry[0] += int(bad[j].sum())
                if len(entry[1]) <= _SHOWN:
                    entry[1].extend(phi[bad[j]][:_SHOWN + 1 - len(entry[1])].tolist())
        if dynamics and "balance" in names:
            row = {n: blk.table[j] for j, n in enumerate(names)}
            terms = sum(np.abs(row[c]) for c in ("P_bal", "P_ext", "U_t", "T_t") if c in row)
            with np.errstate(invalid="ignore", divide="ignore"):
                rel = np.abs(row["balance"]) / (terms + 1e-300)
            if np.isfinite(rel).any() or (rel == np.inf).any():
                self.balance_max = max(self.balance_max, float(np.nanmax(rel, initial=0.0)))
            for sink, where in ((self.balance_bad, rel > BALANCE_TOL),
                                (self.balance_undefined, ~np.isfinite(rel) & ok)):
                if len(sink) <= _SHOWN:
                    sink.extend(phi[where][:_SHOWN + 1 - len(sink)].tolist())

    def warnings(self, scene: Scene) -> list[str]:
        out = []
        if self.failing:
            gaps = assembly_gaps(scene, np.concatenate(self.failing))
            out.append("; ".join(map(str, gaps)) + " (those positions are marked assembled = false)")
        for g in sorted(self.toggles):
            out.append(f"group {g} is near a toggle position (|det_g{g}| small: velocities and "
                       f"accelerations lose accuracy) at crank angles {_listed(self.toggles[g], ' ...')} deg")
        for what, angles in ((f"the energy balance misses by up to {self.balance_max:.1e} of its terms",
                              self.balance_bad),
                             ("the reactions and M_bal are undefined (a toggle: the group's "
                              "determinant is 0)", self.balance_undefined)):
            if angles:
                out.append(f"{what} at crank angles {_listed(angles, ', ...')} deg (near a toggle "
                           "the reactions grow without bound and lose their digits)")
        if self.undefined:
            cols = ", ".join(f"{n} ({c} position{'s' if c > 1 else ''})"
                             for n, (c, _) in list(self.undefined.items())[:_SHOWN])
            more = " ..." if len(self.undefined) > _SHOWN else ""
            first = next(iter(self.undefined.values()))[1]
            out.append(f"no finite value in {cols}{more}, first at crank angles {_listed(first, ' ...')} "
                       "deg (written as empty cells in CSV, null in JSON and parquet)")
        return out


def _listed(angles, ellipsis: str) -> str:
    return ", ".join(f"{a:g}" for a in angles[:_SHOWN]) + (ellipsis if len(angles) > _SHOWN else "")


# --------------------------------------------------------------------------- bulk text
def _cells(values: np.ndarray, null: bytes) -> np.ndarray:
    """(positions, columns * WIDTH) uint8: the numbers' repr, `null` where not finite."""
    n, k = values.shape
    slots, finite = repr_slots(values.reshape(-1))
    if null and not finite.all():
        slots[~finite, :len(null)] = np.frombuffer(null, np.uint8)
    return slots.reshape(n, k * WIDTH)


def _labels(texts: list[bytes], codes: np.ndarray) -> np.ndarray:
    """(positions, width) uint8 of texts[codes], 0-padded to a multiple of 8 bytes."""
    return _padded(texts).view(np.uint8)[codes]


def _assemble(n: int, pieces: list) -> bytes:
    """Rows of pieces (constant bytes, the same in every row; (n, w) uint8 arrays; or
    _Keyed runs) into text, the 0 bytes of unused slots dropped. Every piece is padded to
    whole 8-byte words and copied as uint64: a row is ~160 words, not ~1300 bytes."""
    words = []
    for p in pieces:
        if isinstance(p, bytes):
            p = _padded([p])
        elif not isinstance(p, _Keyed):
            assert p.shape[-1] % 8 == 0
            p = p.view(np.uint64)           # a column slice: its rows are contiguous
        words.append(p)
    total = sum(w.shape[1] for w in words)
    rows = np.empty((n, total), np.uint64)
    at = 0
    for w in words:
        width = w.shape[1]
        if isinstance(w, _Keyed):
            w.put(rows[:, at:at + width])
        else:
            rows[:, at:at + width] = w
        at += width
    return rows.tobytes().translate(None, b"\0")


def _padded(texts: list[bytes]) -> np.ndarray:
    """(len(texts), words) uint64: each text 0-padded to the longest's whole words."""
    width = -(-max(1, max(map(len, texts))) // 8) * 8
    table = np.zeros((len(texts), width), np.uint8)
    for i, t in enumerate(texts):
        table[i, :len(t)] = np.frombuffer(t, np.uint8)
    return table.view(np.uint64)


class _Keyed:
    """A run of k constant keys, each followed by its column's cells ((n, k * WIDTH)
    uint8): JSON's `"name": value` pairs, copied in two strided assignments instead of 2k
    (the keys padded to one width; the padding is dropped with the other 0 bytes)."""

    def __init__(self, keys: list[bytes], cells: np.ndarray):
        self.keys, self.cells = _padded(keys), cells.view(np.uint64)
        self.k, self.kw = self.keys.shape
        self.shape = (cells.shape[0], self.k * (self.kw + WIDTH // 8))

    def put(self, rows: np.ndarray):
        run = rows.reshape(rows.shape[0], self.k, -1)
        run[:, :, :self.kw] = self.keys
        run[:, :, self.kw:] = self.cells.reshape(rows.shape[0], self.k, -1)


class _Text:
    """CSV and JSON: the same row of pieces, with the format's separators."""

    def __init__(self, fmt: str, names: list[str], n_det: int, gaps: bool, title: str):
        self.fmt, self.names, self.n_det, self.gaps, self.title = fmt, names, n_det, gaps, title
        self.main = len(names) - n_det
        self.columns = names[:self.main] + (["assembled"] if gaps else []) + names[self.main:] + ["near_toggle"]
        self.first = True

    def head(self) -> bytes:
        if self.fmt == "csv":
            return ",".join(self.columns).encode() + b"\n"
        units = {c: unit(c) for c in self.columns if unit(c)}
        text = json.dumps({"title": self.title, "units": units, "positions": None}, indent=1)
        return text[:text.rindex("null")].encode() + b"["

    def rows(self, blk: Block) -> bytes:
        return self._csv(blk) if self.fmt == "csv" else self._json(blk)

    def _csv(self, blk: Block) -> bytes:
        """The block's rows, each ending in "\\n", written by polars (issue 24: 1.7-4x faster
        than our formatter on the same arrays): numbers in polars' shortest round-trip
        notation (docs/output-formats.md), an empty cell where a value is not finite."""
        import polars as pl  # only here: the table and JSON do not need it
        columns: dict[str, pl.Series] = {}
        for j, name in enumerate(self.names):
            if j == self.main and self.gaps:    # "assembled" between the main columns and det_g*
                truth = pl.Series("assembled", ["False", "True"])      # as pandas wrote it
                columns["assembled"] = truth.gather((~blk.fail).astype(np.uint32))
            v = blk.table[j] + 0.0          # -0.0 + 0.0 is 0.0: a CSV says 0.0, never -0.0
            finite = np.isfinite(v)
            columns[name] = pl.Series(name, v if finite.all() else np.where(finite, v, np.nan), nan_to_null=True)
        labels = pl.Series("near_toggle", [t or None for t in blk.labels], dtype=pl.String)
        columns["near_toggle"] = labels.gather(blk.codes.astype(np.uint32))
        out = io.BytesIO()
        pl.DataFrame(columns).write_csv(out, include_header=False, line_terminator="\n", null_value="")
        self.first = False
        return out.getvalue()

    def _json(self, blk: Block) -> bytes:
        """A record as json.dumps(indent=1) lays it out, null where there is no value."""
        n = blk.table.shape[1]
        values = np.ascontiguousarray(blk.table.T)
        cells = _cells(values, b"null")
        keys = [(b',\n  {\n   ' if j == 0 else b',\n   ') + json.dumps(name).encode() + b": "
                for j, name in enumerate(self.names)]
        cut = self.main * WIDTH
        pieces: list[bytes | np.ndarray | _Keyed] = [_Keyed(keys[:self.main], cells[:, :cut])]
        if self.gaps:
            pieces += [b',\n   "assembled": ', _labels([b"false", b"true"], (~blk.fail).astype(np.intp))]
        if self.main < len(keys):
            pieces.append(_Keyed(keys[self.main:], cells[:, cut:]))
        pieces += [b',\n   "near_toggle": ', _labels([json.dumps(t).encode() for t in blk.labels], blk.codes),
                   b"\n  }"]
        text = _assemble(n, pieces)
        if self.first:
            text = text[1:]                  # no comma before the first record
        self.first = False
        return text

    def tail(self, warnings: list[str]) -> bytes:
        if self.fmt == "csv":
            return b""
        w = json.dumps({"warnings": warnings}, indent=1)
        return b"\n ],\n " + w[w.index('"warnings"'):].encode() + b"\n"


# --------------------------------------------------------------------------- the table
def fmt_cell(v, scale: float = 0.0) -> str:
    """Six significant digits; round-off noise (below 1e-12 of the row's largest) shows as 0."""
    if isinstance(v, str):
        return v
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "-"
    if isinstance(v, (bool, np.bool_)):
        return "yes" if v else "NO"
    if abs(v) <= 1e-12 * scale:
        v = 0.0
    return f"{v + 0.0:.6g}"


def fmt_row(values) -> list[str]:
    nums = [abs(v) for v in values if isinstance(v, float) and math.isfinite(v)]
    scale = max(nums, default=0.0)
    return [fmt_cell(v, scale) for v in values]


def format_table(title: str, columns: dict, width: int | None = None) -> str:
    """Quantities as rows, positions as columns (like the lecture's workbook), paged to
    width. columns: name -> list of values, phi_1 first."""
    width = width or shutil.get_terminal_size((120, 24)).columns
    names = [c for c in columns if c != "phi_1"]
    label_w = max(len(c) for c in columns) + 2
    unit_w = max(len(unit(c)) for c in columns) + 2
    col_w = 13
    n = len(columns["phi_1"])
    per_page = max(1, (width - label_w - unit_w) // col_w)
    lines = [title] if title else []
    for start in range(0, n, per_page):
        stop = min(n, start + per_page)
        lines.append("")
        lines.append("phi_1".ljust(label_w) + "deg".ljust(unit_w) +
                     "".join(t.rjust(col_w) for t in fmt_row(columns["phi_1"][start:stop])))
        lines.append("-" * (label_w + unit_w + col_w * (stop - start)))
        for name in names:
            lines.append(name.ljust(label_w) + unit(name).ljust(unit_w) +
                         "".join(t.rjust(col_w) for t in fmt_row(columns[name][start:stop])))
    return "\n".join(lines) + "\n"


def _table_text(scene: Scene, names, n_det, gaps, blocks) -> str:
    main = len(names) - n_det
    cols: dict[str, list] = {name: [] for name in names[:main]}
    if gaps:
        cols["assembled"] = []
    cols.update({name: [] for name in names[main:]})
    cols["near_toggle"] = []
    for blk in blocks:
        for j, name in enumerate(names):
            cols[name].extend(blk.table[j].tolist())
        if gaps:
            cols["assembled"].extend((~blk.fail).tolist())
        cols["near_toggle"].extend(blk.labels[c] for c in blk.codes.tolist())
    return format_table(scene.title, cols)


# --------------------------------------------------------------------------- parquet
def _parquet_writer(path: str | BinaryIO):
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        raise SceneError("--format parquet needs pyarrow: pip install 'sheetkin[parquet]' "
                         "(or pip install pyarrow)") from None
    state = {}

    def write(names, n_det, gaps, blk):
        main = len(names) - n_det
        cols, fields = [], []
        for j, name in enumerate(names):
            if j == main and gaps:
                cols.append(pa.array(~blk.fail))
                fields.append("assembled")
            v = blk.table[j]
            cols.append(pa.array(v, mask=~np.isfinite(v)))
            fields.append(name)
        cols.append(pa.DictionaryArray.from_arrays(pa.array(blk.codes.astype(np.int32)),
                                                    pa.array(blk.labels, pa.string())).cast(pa.string()))
        fields.append("near_toggle")
        table = pa.Table.from_arrays(cols, names=fields)
        if "w" not in state:
            state["w"] = pq.ParquetWriter(path, table.schema)
        state["w"].write_table(table)

    def close():
        if "w" in state:
            state["w"].close()
    return write, close


# --------------------------------------------------------------------------- the command
class _Target:
    """Where the output goes: stdout, or sheetkin.files.Output (a new or regular file, also
    behind a link, written beside its final name and renamed when complete; a device or a
    FIFO written as it is)."""

    def __init__(self, path: str | None):
        self.path, self.tmp, self.out = path, None, None
        if path is None:
            sys.stdout.flush()
            self.file = getattr(sys.stdout, "buffer", None) or _TextSink(sys.stdout)
            return
        self.out = Output(path)
        self.file, self.tmp = self.out.file, self.out.tmp

    def commit(self):
        if self.out is None:
            self.file.flush()
        else:
            self.out.commit()

    def abandon(self):
        if self.out is not None:
            self.out.abandon()


class _TextSink:
    """A text stream without a binary buffer (io.StringIO, some embedders) taking bytes."""

    def __init__(self, stream):
        self.stream = stream

    def write(self, data: bytes):
        self.stream.write(data.decode("utf-8"))

    def flush(self):
        self.stream.flush()


def write_compute(scene: Scene, phi, fmt: str, output: str | None, *, analogs=False,
                  dynamics=False, allow_gaps=False, toggle_threshold=None,
                  block: int = BLOCK) -> list[str]:
    """Compute at the angles phi (array or AngleRange) and write them in `fmt` to output
    (a path, or stdout), block by block; returns the warnings (already in a JSON output).
    Raises AssemblyError before writing anything if some position fails without allow_gaps."""
    names = table_names(scene, analogs, dynamics)
    n_det = len(scene.groups)
    fail = failing(scene, phi, block)          # decides the columns; refuses before writing
    if fail.any() and not allow_gaps:
        angles = phi.take(0, len(phi)) if isinstance(phi, AngleRange) else np.asarray(phi)
        found = assembly_gaps(scene, angles[fail])
        raise AssemblyError("; ".join(map(str, found)) +
                            f" ({int(fail.sum())} of {fail.size} positions; use --allow-gaps to keep the rest)")
    gaps = bool(fail.any())
    del fail
    if fmt == "parquet" and output is None:
        raise SceneError("--format parquet writes a file: give -o FILE.parquet")
    notes = Notes(len(scene.groups))
    kw = dict(analogs=analogs, dynamics=dynamics, block=block)
    if toggle_threshold is not None:
        kw["toggle_threshold"] = toggle_threshold

    def blocks():
        for blk in compute_blocks(scene, phi, **kw):
            notes.add(names, blk, dynamics)
            yield blk

    # (parquet without an output was refused above)
    write = _parquet_writer(cast(str, output)) if fmt == "parquet" else None     # pyarrow missing: before any file
    target = _Target(output)
    try:
        if fmt == "parquet":
            # pyarrow writes to the temporary file by name; to a device or a FIFO through
            # the open file (it writes sequentially)
            # parquet has an output (refused above without): an Output's file, never stdout
            file = cast(BinaryIO, target.file)
            write, close = _parquet_writer(target.tmp if target.tmp is not None else file)
            if target.tmp is not None:
                file.close()
            for blk in blocks():
                write(names, n_det, gaps, blk)
            close()
            warnings = notes.warnings(scene)
        elif fmt == "table":
            text = _table_text(scene, names, n_det, gaps, list(blocks()))
            warnings = notes.warnings(scene)
            target.file.write(text.encode())
        else:
            writer = _Text(fmt, names, n_det, gaps, scene.title)
            stream = blocks()
            first = writer.rows(next(stream))     # a failure in the first block writes nothing
            target.file.write(writer.head())
            target.file.write(first)
            del first
            for blk in stream:
                target.file.write(writer.rows(blk))
            warnings = notes.warnings(scene)
            target.file.write(writer.tail(warnings))
        target.commit()
    except BaseException as e:
        target.abandon()
        if isinstance(e, OSError) and not isinstance(e, BrokenPipeError) and not e.filename and output:
            # a write error (a full disk) has no file name of its own: name the output
            raise OSError(e.errno, e.strerror or str(e), output) from None
        raise
    return warnings
