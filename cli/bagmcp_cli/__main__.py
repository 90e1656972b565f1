"""``python -m bagmcp_cli`` runs the ``bagmcp`` command."""

import sys

from bagmcp_cli.main import main

sys.exit(main())
