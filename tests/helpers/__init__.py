"""Helpers the tests share: scenes, workbooks as students make them, the command line as a
test calls it, the external engines (LibreOffice, Gnumeric, Chromium), and row look-ups.

Imported as `helpers.NAME`: tests/ is on sys.path because pytest puts the folder of the
root conftest.py there (tests/ has no __init__.py: the rootdir-based "prepend" import
mode), so no `pythonpath` list of test folders is needed.
"""
