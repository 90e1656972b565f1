"""``python -m bagmcp_gateway`` runs the ``bagmcp`` command."""

import sys

from bagmcp_gateway.cli import main

sys.exit(main())
