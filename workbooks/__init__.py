"""The bundled example scenes, shipped in the wheel as `sheetkin.examples` (pyproject maps
this folder to that package): `sheetkin examples DIR` writes them out. The workbooks beside
them (*.xlsx) are made from them and stay in the repository."""
