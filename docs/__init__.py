"""The documentation pages (docs/*.md), shipped in the wheel as `sheetkin.docs` (pyproject maps
this folder to that package): `sheetkin docs` lists them and `sheetkin docs PAGE` prints one. The
site is built from the same pages by MkDocs (mkdocs.yml)."""
