"""``python -m teamsim``: the same command-line interface as the ``teamsim`` script."""

from teamsim.cli import main

raise SystemExit(main())
