from sheetkin.cli import run

run()
