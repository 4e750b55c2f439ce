"""``python -m urdftk`` runs the command line."""

import sys

from urdftk.cli import main

sys.exit(main())
