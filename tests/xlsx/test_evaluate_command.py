"""`sheetkin evaluate` and sheetkin.evaluate_frame: the headless values of a workbook."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import sheetkin
from sheetkin.cli.commands import main

WORKBOOKS = Path(__file__).resolve().parents[2] / "workbooks"


@pytest.mark.parametrize("stem", sorted(p.stem for p in WORKBOOKS.glob("*.toml")))
def test_evaluate_frame_equals_the_solver(stem):
    """Rows = names, columns = positions; the accepted values are the solver's."""
    scene = sheetkin.load_scene(WORKBOOKS / f"{stem}.toml")
    df = sheetkin.evaluate_frame(WORKBOOKS / f"{stem}.xlsx")
    ref = sheetkin.compute(scene)
    assert list(df.columns) == list(range(1, scene.crank.positions + 1))
    for name in sheetkin.column_names(scene):
        got, exp = df.loc[name].to_numpy(dtype=float), ref[name].to_numpy()
        d = np.abs(got - exp)
        if name.startswith("phi_"):
            d = np.minimum(d, 360 - d)
        assert np.all(d <= 1e-9 * np.maximum(1, np.abs(exp))), name


def test_evaluate_command_formats(tmp_path, capsys):
    book = str(WORKBOOKS / "fourbar.xlsx")
    assert main(["evaluate", book]) == 0
    table = capsys.readouterr().out
    assert any(line.startswith("omega_3") and "-5.13142" in line for line in table.splitlines())
    assert main(["evaluate", book, "--format", "csv", "-o", str(tmp_path / "v.csv")]) == 0
    assert (tmp_path / "v.csv").read_text().splitlines()[0].startswith("name,1,2,")
    assert main(["evaluate", book, "--format", "json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["rows"]["asm_g1"] == [True] * 13 and len(data["rows"]["x_B"]) == 13
    assert main(["evaluate", book, "--sheet", "nope"]) == 2
    assert "no sheet 'nope'" in capsys.readouterr().err


def test_csv_is_the_csv_writers_row_for_row(tmp_path):
    """rows_csv joins number-only rows itself (issue 32, item 5): the same bytes as the
    csv module's writer, names that need quoting and mixed rows included."""
    import csv
    import io

    import openpyxl

    from sheetkin.xlsx.evaluator import evaluate, rows_csv, rows_table
    wb = openpyxl.Workbook()
    ws = wb.active
    names = ["plain", "a,b", 'say "hi"', "two\nlines", "mixed", "tiny", "zeros", "zeros too"]
    # each distinct number's repr is made once (issue 32): 0.0 and -0.0 are one key there,
    # so rows of both signs, each first in one row, and numbers repeated across rows
    signed = {"zeros": [-0.0, 0.0, 2.5, -0.0], "zeros too": [0.0, -0.0, 0.0, 1e-300 * 5]}
    for r, name in enumerate(names, start=5):
        ws.cell(r, 1, name)
        for c in range(5, 9):
            ws.cell(r, c, signed[name][c - 5] if name in signed else
                    f"=SIN({c}*{r})/7" if name != "tiny" else 1e-300 * c)
    ws.cell(9, 6, "text")
    ws.cell(9, 7, "=1>0")
    ws.cell(9, 8, None)
    path = tmp_path / "names.xlsx"
    wb.save(path)
    book = evaluate(path)
    names_got, data, width = rows_table(book)
    assert names_got == names
    ref = io.StringIO()
    w = csv.writer(ref, lineterminator="\n")
    w.writerow(["name", *range(1, width + 1)])
    for name, row in zip(names_got, data, strict=True):
        w.writerow([name, *("" if v is None else v for v in row)])
    assert rows_csv(book) == ref.getvalue()
    assert '\n"a,b",' in ref.getvalue() and '\n"two\nlines",' in ref.getvalue()
    assert "\nzeros,-0.0,0.0,2.5,-0.0\n" in ref.getvalue() and "\nzeros too,0.0,-0.0,0.0,5e-300\n" in ref.getvalue()
