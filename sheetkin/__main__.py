import sys

from sheetkin.cli.commands import main

sys.exit(main())
