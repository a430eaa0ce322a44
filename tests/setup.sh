#!/usr/bin/env bash
# Installs what the tests need besides Python packages, from Debian packages:
#   LibreOffice Calc headless (soffice): recalculates the workbooks sheetkin writes;
#   poppler-utils (pdftoppm, pdftotext): renders and reads the printed pages;
#   chromium and chromium-driver: the HTML report tested in a real browser (selenium);
#   gnumeric (ssconvert): the third spreadsheet engine the workbooks are recalculated in;
#   python3-uno: drives LibreOffice (with Debian's /usr/bin/python3) to edit books as students do.
# Idempotent and a quick no-op when all are on PATH. Needs root and apt-get (Debian/Ubuntu).
# Usage: bash tests/setup.sh
set -euo pipefail

me="tests/setup.sh"
pkgs=()
command -v soffice >/dev/null 2>&1 || pkgs+=(libreoffice-calc-nogui)
command -v pdftoppm >/dev/null 2>&1 || pkgs+=(poppler-utils)
{ command -v chromium >/dev/null 2>&1 || command -v chromium-browser >/dev/null 2>&1; } || pkgs+=(chromium)
command -v chromedriver >/dev/null 2>&1 || pkgs+=(chromium-driver)
command -v ssconvert >/dev/null 2>&1 || pkgs+=(gnumeric)
[ -x /usr/bin/python3 ] && /usr/bin/python3 -c "import uno" >/dev/null 2>&1 || pkgs+=(python3-uno)

if [ "${#pkgs[@]}" -eq 0 ]; then
    echo "$me: nothing to do, soffice ($(command -v soffice)), pdftoppm ($(command -v pdftoppm))," \
         "chromium and chromedriver ($(command -v chromedriver)), ssconvert and python3-uno are installed"
    exit 0
fi
if ! command -v apt-get >/dev/null 2>&1; then
    echo "$me: ERROR: need ${pkgs[*]} but apt-get is not available;" \
         "install LibreOffice Calc (soffice on PATH), poppler-utils (pdftoppm), Chromium and its" \
         "chromedriver yourself" >&2
    exit 1
fi
if [ "$(id -u)" -ne 0 ]; then
    echo "$me: ERROR: need root to apt-get install ${pkgs[*]}; run: sudo bash $me" >&2
    exit 1
fi

log="$(mktemp)"
trap 'rm -f "$log"' EXIT
export DEBIAN_FRONTEND=noninteractive
if ! { apt-get update -qq && apt-get install -y -qq --no-install-recommends "${pkgs[@]}"; } >"$log" 2>&1; then
    cat "$log" >&2
    echo "$me: ERROR: apt-get install ${pkgs[*]} failed (output above)" >&2
    exit 1
fi
for exe in soffice pdftoppm chromedriver ssconvert; do
    if ! command -v "$exe" >/dev/null 2>&1; then
        echo "$me: ERROR: installed ${pkgs[*]} but $exe is still not on PATH ($PATH)" >&2
        exit 1
    fi
done
echo "$me: installed ${pkgs[*]} with apt-get ($(soffice --version 2>/dev/null | head -n 1))"
