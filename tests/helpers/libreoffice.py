"""The tests import the LibreOffice harness as `libreoffice`; it lives in the package
(sheetkin/xlsx/libreoffice.py) because `sheetkin bench` uses it too."""
from sheetkin.xlsx.libreoffice import (  # noqa: F401
    SETUP_HINT,
    is_error,
    pdf_to_png,
    read_values,
    recalculate,
    render_pdf,
    soffice_path,
)
